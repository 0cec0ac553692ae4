// LightKeyframes: which tables a light-dependent LUT builds, and which it shows, while the light's
// elevation changes (time running). CPU bookkeeping only; the generators own the textures.
//
//   welkin::generators::LightKeyframes kf({.stepRad = 0.0175, .chunks = 6});
//   auto plan = kf.plan(muS);                  // once per run, muS the light's cos zenith
//   if (plan.build >= 0)                       // build chunks [chunkBegin, chunkEnd) of the table
//       buildRows(plan.build, plan.buildMuS, plan.chunkBegin, plan.chunkEnd);  // at buildMuS
//   show(plan.a, plan.b, plan.t);              // mix(slot a, slot b, t); b < 0: slot a alone
//   if (kf.pending()) runAgain();              // more to do next frame even if muS stays
//
// A table is a function of the light's elevation e (and of the observer's height and the
// atmosphere, whose change calls reset()). Tables are kept in a few slots at elevations on a grid
// of `stepRad` (plus exact ones, see below), each built over `chunks` runs into its own slot
// (double buffering: a slot is shown only once complete). A run shows the two complete slots
// that bracket e, interpolated in e (t in [0, 1]), or, while the next one is still being built,
// extrapolated from the two nearest (t in [-1, 2]). Which slot is built next: the grid point
// ahead of the light in its direction of motion, then the one behind, then the second ahead.
// When the light stops (a run whose cos zenith is within Options::stillMuS of the last run's) a
// table at exactly e is built
// (over `chunks` runs), so a still sky converges to the exact table; when no complete slot lies
// within 2 steps of e (the first run, a jump, after reset()) one is built at exactly e at once.
#pragma once

#include <cstdint>
#include <vector>

namespace welkin::generators {

class LightKeyframes {
public:
    struct Options {
        double stepRad = 0.0175;  ///< grid step in elevation, rad (> 0)
        int chunks = 6;           ///< parts of one table (at least one built per run; more when the light would reach it first), >= 1
        int slots = 4;            ///< tables kept, >= 3
        /// A change of cos zenith up to this since the last run counts as a still light (the
        /// generator's input tolerance: it already accepts that much staleness), >= 0.
        double stillMuS = 0.0;
    };
    struct Plan {
        int a = -1, b = -1;  ///< slots shown: mix(a, b, t); b < 0: a alone
        double t = 0.0;
        int build = -1;      ///< slot to build into this run (-1: none)
        double buildMuS = 0.0;
        int chunkBegin = 0, chunkEnd = 0;  ///< chunks of the table to build now, [begin, end) of Options::chunks
        bool exact = false;  ///< what is shown is a table at exactly this run's elevation
    };

    LightKeyframes();
    explicit LightKeyframes(Options o);
    const Options& options() const { return o_; }
    /// Changes the options (a different step or chunk count empties every slot).
    void setOptions(Options o);
    /// Forgets every table (the observer's height, the atmosphere or the quality changed).
    void reset();
    /// Plans one run at the light's cos zenith `muS` in [-1, 1]. The chunks it returns count as
    /// built: build them in this run before showing.
    Plan plan(double muS);
    /// Work remains (a table half built, or a still light not yet shown exactly).
    bool pending() const { return pending_; }
    /// Cos zenith of slot i's table, and whether it is complete.
    double slotMuS(int i) const;
    bool complete(int i) const { return slots_.at(size_t(i)).done == o_.chunks; }
    int slotCount() const { return int(slots_.size()); }

private:
    struct Slot {
        double e = 0.0;      // elevation, rad
        int done = -1;       // chunks built; -1 empty
        uint64_t used = 0;   // last run that showed or built it
    };
    int find(double e, double tol, bool completeOnly) const;
    int victim(int keepA, int keepB) const;
    Options o_;
    std::vector<Slot> slots_;
    int building_ = -1;
    bool pending_ = false;
    bool haveLast_ = false;
    double lastE_ = 0.0;
    int dir_ = 0;  // -1, 0, +1: direction of the last motion
    double rate_ = 0.0;  // elevation change of the last run, rad
    uint64_t run_ = 0;
};

}  // namespace welkin::generators
