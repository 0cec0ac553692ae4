// LightKeyframes: which tables a light-dependent LUT builds, and which it shows, while the light's
// elevation changes (time running). CPU bookkeeping only; the generators own the textures.
//
//   welkin::generators::LightKeyframes kf({.stepRad = 0.0175, .coarseStepRad = 0.0524, .chunks = 6, .slots = 64});
//   auto plan = kf.plan(muS);                  // once per run, muS the light's cos zenith
//   if (plan.build >= 0)                       // build chunks [chunkBegin, chunkEnd) of the table
//       buildRows(plan.build, plan.buildMuS, plan.chunkBegin, plan.chunkEnd);  // into slot `build`
//   show(plan.slot, plan.weight, plan.count);  // sum of weight[i] x slot[i] (in log radiance)
//   if (kf.pending()) runAgain();              // more to do next frame even if muS stays
//
// A table is a function of the light's elevation e (and of the observer's height and the
// atmosphere, whose change calls reset()). Tables are kept in slots: grid tables at elevations
// on a grid (stepRad below fineTopRad, growing to coarseStepRad above), built once and kept for as long as the atmosphere and height stay (a
// cache over the whole elevation range, filled where the light goes, least recently used evicted
// beyond `slots`), and exact tables (at the light's own elevation: the first run, a jump, a
// light at rest). Each table is built over `chunks` runs into its own slot and shown only once
// complete (double buffering). A run shows:
//   * a complete exact table at e, alone;
//   * else, with e between grid points k and k+1 and the grid tables k-1 .. k+2 complete, the
//     Catmull-Rom cubic through the four (uniform in the grid index; weights summing to 1);
//   * else, with k and k+1 complete, the linear mix of the two;
//   * else (the builder is late: the first runs of a motion, or a turn) the two complete tables
//     nearest e, extrapolated along their trend (at most one spacing beyond either), or one alone.
// What is built next while the light moves: the missing grid tables of the four the cubic needs,
// nearest the light's direction of motion first, then the next one ahead; each at enough chunks
// per run to be complete before the light needs it (at its last rate). A still light (a run whose
// cos zenith has stayed within Options::stillMuS of one elevation for Options::stillRuns runs) has
// a table at exactly e built, so a still sky converges to the exact table. When no complete table lies within 2 steps of e (the
// first run, a jump, after reset()) one is built at exactly e at once.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace welkin::generators {

class LightKeyframes {
public:
    struct Options {
        double stepRad = 0.0175;  ///< grid step in elevation up to fineTopRad (the twilight and low Sun), rad (> 0)
        /// Above fineTopRad the step grows by half the elevation gained, up to this (the
        /// sky changes slowly with a high light); <= stepRad: a uniform grid. rad.
        double coarseStepRad = 0.0;
        double fineTopRad = 0.07;  ///< rad
        int chunks = 6;           ///< parts of one table (at least one built per run; more when the light would reach it first), >= 1
        int slots = 64;           ///< tables kept at most (the memory cap), >= 6
        /// A change of cos zenith up to this since the last run counts as a still light (the
        /// generator's input tolerance: it already accepts that much staleness), >= 0.
        double stillMuS = 0.0;
        /// A light counts as at rest (its exact table is built) once it has stayed within
        /// stillMuS of one elevation for this many runs, >= 1. A slowly drifting light (time
        /// running at 1 s/s moves the Sun's cos zenith by up to 7e-5 per second) is not at rest:
        /// it is shown through the grid tables, and building exact tables it drifts away from
        /// would cost a table build every few hundred milliseconds for nothing.
        int stillRuns = 1;
        /// The first run in which the light moves (after a reset) queues every grid table from
        /// prefillLowRad up to the zenith, to be built whole at once (nextPrefill()): a one-time
        /// cost (skyelements/sky/README.md), after which time running costs only the per-frame mix. Off: the
        /// grid tables are built along the light's path, a few chunks per run.
        bool prefill = false;
        /// Spreads the prefill over runs (0: the whole queue at once through nextPrefill()).
        /// Above 0, plan() itself builds the queued grid tables, nearest the light first, one
        /// table at a time and at most this many chunks per run, after the tables the light
        /// needs; and a table the light needs is then built at most max(this, the chunks that
        /// keep pace with the light's last rate) per run (while it is late the nearest
        /// complete tables are shown). nextPrefill() then returns none. Chunks per run, >= 0.
        int prefillChunksPerRun = 0;
        double prefillLowRad = -0.3490658503988659;  ///< rad (-20 deg: below, the Sun's scattered light is negligible)
        /// A first run or a jump adopts the preloaded grid tables around the light (preload():
        /// the disk cache, or the whole grid built at load in an interactive session) and shows
        /// their cubic instead of building a table at exactly its elevation at once; the exact
        /// table follows once the light has rested (stillRuns), a chunk per run. Off: a first
        /// run and a jump build their exact table whole (what a still render shows).
        bool adoptOnJump = false;
    };
    /// A grid table to build whole now (Options::prefill).
    struct Prefill {
        int slot = -1;  ///< -1: none left
        double muS = 0.0;
    };
    struct Plan {
        /// Slots shown: sum of weight[i] x table slot[i], i < count (count in [1, 4], weights sum to 1).
        std::array<int, 4> slot{-1, -1, -1, -1};
        std::array<double, 4> weight{0, 0, 0, 0};
        int count = 0;
        int build = -1;      ///< slot to build into this run (-1: none); may be a new one (== slotCount() - 1)
        double buildMuS = 0.0;
        int chunkBegin = 0, chunkEnd = 0;  ///< chunks of the table to build now, [begin, end) of Options::chunks
        bool exact = false;  ///< what is shown is a table at exactly this run's elevation
        bool cubic = false;  ///< shown through the Catmull-Rom cubic of four grid tables
        /// What is shown equals the previous run's (same tables and weights, no build): the
        /// generator may keep its shown table instead of mixing it again.
        bool unchanged = false;
    };

    LightKeyframes();
    explicit LightKeyframes(Options o);
    const Options& options() const { return o_; }
    /// Changes the options (a different step, chunk or slot count empties every slot).
    void setOptions(Options o);
    /// Forgets every table (the observer's height, the atmosphere or the quality changed). The
    /// slots stay allocated (their textures are reused).
    void reset();
    /// Plans one run at the light's cos zenith `muS` in [-1, 1]. The chunks it returns count as
    /// built: build them in this run before showing.
    Plan plan(double muS);
    /// Work remains (a table half built, or a still light not yet shown exactly).
    bool pending() const { return pending_; }
    /// The next queued prefill table (Options::prefill with prefillChunksPerRun 0), counted as
    /// built: build all of it before the next plan(). Call until it returns slot -1.
    Prefill nextPrefill();
    /// A grid table kept outside the schedule (read from a disk cache, SkyViewLut): returns the
    /// slot whose texture the caller fills now with grid point k's table (-1: k has a table
    /// already, or no slot is free). The table is not shown and nothing is planned around it
    /// until the schedule would build grid point k (the light's path, the prefill): then it is
    /// adopted as complete in place of the build (adoptedTables()). A first run or a jump still
    /// builds its exact table, so what a frame shows differs from the uncached schedule's only in
    /// which grid tables are complete when. reset() forgets preloaded tables too.
    int preload(int k);
    /// Preloaded tables adopted since construction (instead of being built).
    int adoptedTables() const { return adopted_; }
    /// Grid point k has a table (complete, being built, or preloaded).
    bool hasGrid(int k) const;
    /// Grid point of slot i's table (-1: an exact table or an empty slot).
    int slotGrid(int i) const {
        const Slot& s = slots_.at(std::size_t(i));
        return s.grid == kNoGrid || (s.done < 0 && !s.cached) ? -1 : s.grid;
    }
    /// Cos zenith of slot i's table, and whether it is complete.
    double slotMuS(int i) const;
    bool complete(int i) const { return slots_.at(std::size_t(i)).done == o_.chunks; }
    /// Slots in use so far (grows up to Options::slots; the generators allocate textures to match).
    int slotCount() const { return int(slots_.size()); }
    /// Complete grid tables held.
    int gridTables() const;
    /// Grid tables still queued by the prefill (not yet begun).
    int prefillQueued() const { return int(prefillQueue_.size()); }

    /// Catmull-Rom weights of p0..p3 at t in [0, 1] between p1 and p2 (uniform knots).
    static std::array<double, 4> catmullRom(double t);
    /// The grid's elevations (ascending, from -pi/2 to pi/2), rad.
    const std::vector<double>& grid() const { return nodes_; }
    /// The grid of these options (Options::stepRad, coarseStepRad, fineTopRad).
    static std::vector<double> makeGrid(const Options& o);

private:
    static constexpr int kNoGrid = INT32_MIN;
    struct Slot {
        double e = 0.0;       // elevation, rad
        int grid = kNoGrid;   // grid index k (e = k step) or kNoGrid for an exact table
        int done = -1;        // chunks built; -1 empty
        uint64_t used = 0;    // last run that showed or built it
        bool cached = false;  // holds grid table `grid`, preloaded, not adopted yet (done -1)
    };
    int adopt(int k);  // a preloaded table of grid point k made complete (its slot), or -1
    int find(double e, double tol, bool completeOnly) const;
    int findGrid(int k, bool completeOnly) const;
    int victim(const std::array<int, 4>& keep, bool exactTable);
    void show(Plan& p, double e, double eTol) const;
    int locate(double e) const;  // k with nodes_[k] <= e < nodes_[k + 1] (clamped)
    double spacing(int k) const;  // nodes_[k + 1] - nodes_[k] (clamped)
    Options o_;
    std::vector<double> nodes_;
    std::vector<Slot> slots_;
    int building_ = -1;
    bool pending_ = false;
    bool haveLast_ = false;
    double lastE_ = 0.0;
    int dir_ = 0;  // -1, 0, +1: direction of the last motion
    double rate_ = 0.0;  // elevation change of the last run, rad
    double anchorE_ = 0.0;  // elevation the light has stayed near (within stillMuS) ...
    int anchorRuns_ = 0;    // ... for this many runs
    Plan lastPlan_;         // the previous run's plan (Plan::unchanged)
    double shownE_ = 0.0;   // elevation of the last mixed (not unchanged) plan
    bool prefilled_ = false;         // the prefill was queued since the last reset
    int runsSinceReset_ = 0;
    std::vector<int> prefillQueue_;  // grid indices still to build whole
    bool buildingFill_ = false;      // building_ was taken from the prefill queue (spread prefill)
    uint64_t run_ = 0;
    int adopted_ = 0;
};

}  // namespace welkin::generators
