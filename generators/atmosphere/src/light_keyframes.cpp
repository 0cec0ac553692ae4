// LightKeyframes: the schedule of light-dependent tables while the light moves (see the header).
#include <welkin/error.hpp>
#include <welkin/generators/detail/light_keyframes.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>

namespace welkin::generators {

LightKeyframes::LightKeyframes() : LightKeyframes(Options{}) {}
LightKeyframes::LightKeyframes(Options o) { setOptions(o); }

void LightKeyframes::setOptions(Options o) {
    if (!(o.stepRad > 0.0) || o.chunks < 1 || o.slots < 6 || !(o.stillMuS >= 0.0) || o.stillRuns < 1 || o.prefillChunksPerRun < 0) {
        char buf[260];
        std::snprintf(buf, sizeof buf,
                      "LightKeyframes: step %g rad, %d chunks, %d slots, still %g, still runs %d, prefill chunks per run %d: need step > 0, chunks >= 1, slots >= 6, still >= 0, still runs >= 1, prefill chunks per run >= 0",
                      o.stepRad, o.chunks, o.slots, o.stillMuS, o.stillRuns, o.prefillChunksPerRun);
        throw Error(buf);
    }
    const bool same = o.stepRad == o_.stepRad && o.coarseStepRad == o_.coarseStepRad && o.fineTopRad == o_.fineTopRad &&
                      o.chunks == o_.chunks && o.slots == o_.slots && !nodes_.empty();
    o_ = o;
    if (!same) {
        nodes_ = makeGrid(o);
        slots_.clear();
        reset();
    }
}

std::vector<double> LightKeyframes::makeGrid(const Options& o) {
    // stepRad from -pi/2 up to fineTopRad, then a step growing by half the elevation gained, up
    // to coarseStepRad; 0 and +-pi/2 are grid points.
    const double half = 0.5 * std::numbers::pi;
    std::vector<double> below;
    for (int j = 1; j * o.stepRad < half - 1e-9; ++j) below.push_back(-j * o.stepRad);
    below.push_back(-half);
    std::vector<double> nodes(below.rbegin(), below.rend());
    for (double e = 0.0; e < half - 1e-9;) {
        nodes.push_back(e);
        const double s = std::clamp(o.stepRad + 0.5 * (e - o.fineTopRad), o.stepRad, std::max(o.stepRad, o.coarseStepRad));
        if (half - (e + s) < 0.5 * s) break;  // no point within half a step of the zenith but the zenith
        e += s;
    }
    nodes.push_back(half);
    return nodes;
}

int LightKeyframes::locate(double e) const {
    auto it = std::upper_bound(nodes_.begin(), nodes_.end(), e);
    return std::clamp(int(it - nodes_.begin()) - 1, 0, int(nodes_.size()) - 2);
}

double LightKeyframes::spacing(int k) const {
    k = std::clamp(k, 0, int(nodes_.size()) - 2);
    return nodes_[size_t(k) + 1] - nodes_[size_t(k)];
}

void LightKeyframes::reset() {
    for (Slot& s : slots_) s = Slot{};
    building_ = -1;
    pending_ = false;
    haveLast_ = false;
    dir_ = 0;
    anchorRuns_ = 0;
    lastPlan_ = Plan{};
    prefilled_ = false;
    prefillQueue_.clear();
    buildingFill_ = false;
    runsSinceReset_ = 0;
}

LightKeyframes::Prefill LightKeyframes::nextPrefill() {
    if (o_.prefillChunksPerRun > 0) return {};  // spread: plan() builds the queue
    while (!prefillQueue_.empty()) {
        const int k = prefillQueue_.back();
        prefillQueue_.pop_back();
        if (findGrid(k, false) >= 0) continue;  // built or being built meanwhile
        if (adopt(k) >= 0) continue;            // preloaded: complete now
        const int s = victim({-1, -1, -1, -1}, false);
        if (s < 0) return {};
        slots_[size_t(s)] = Slot{nodes_[size_t(k)], k, o_.chunks, run_};
        return {s, std::sin(nodes_[size_t(k)])};
    }
    return {};
}

int LightKeyframes::preload(int k) {
    if (k < 0 || k >= int(nodes_.size()) || findGrid(k, false) >= 0) return -1;
    for (const Slot& s : slots_)
        if (s.cached && s.grid == k) return -1;
    int v = -1;
    for (int i = 0; i < int(slots_.size()) && v < 0; ++i)
        if (i != building_ && slots_[size_t(i)].done < 0 && !slots_[size_t(i)].cached) v = i;
    if (v < 0) {
        if (int(slots_.size()) >= o_.slots) return -1;
        slots_.push_back(Slot{});
        v = int(slots_.size()) - 1;
    }
    slots_[size_t(v)] = Slot{nodes_[size_t(k)], k, -1, run_, true};
    return v;
}

int LightKeyframes::adopt(int k) {
    for (int i = 0; i < int(slots_.size()); ++i) {
        Slot& s = slots_[size_t(i)];
        if (s.cached && s.grid == k && s.done < 0) {
            s.cached = false;
            s.done = o_.chunks;
            s.used = run_;
            ++adopted_;
            return i;
        }
    }
    return -1;
}

bool LightKeyframes::hasGrid(int k) const {
    for (const Slot& s : slots_)
        if (s.grid == k && (s.done >= 0 || s.cached)) return true;
    return false;
}

double LightKeyframes::slotMuS(int i) const { return std::sin(slots_.at(size_t(i)).e); }

int LightKeyframes::gridTables() const {
    int n = 0;
    for (const Slot& s : slots_) n += s.grid != kNoGrid && s.done == o_.chunks;
    return n;
}

std::array<double, 4> LightKeyframes::catmullRom(double t) {
    const double t2 = t * t, t3 = t2 * t;
    return {0.5 * (-t3 + 2.0 * t2 - t), 0.5 * (3.0 * t3 - 5.0 * t2 + 2.0), 0.5 * (-3.0 * t3 + 4.0 * t2 + t), 0.5 * (t3 - t2)};
}

int LightKeyframes::find(double e, double tol, bool completeOnly) const {
    int best = -1;
    double bestD = tol;
    for (int i = 0; i < int(slots_.size()); ++i) {
        const Slot& s = slots_[size_t(i)];
        if (s.done < 0 || (completeOnly && s.done != o_.chunks)) continue;
        double d = std::abs(s.e - e);
        if (d <= bestD) best = i, bestD = d;
    }
    return best;
}

int LightKeyframes::findGrid(int k, bool completeOnly) const {
    for (int i = 0; i < int(slots_.size()); ++i) {
        const Slot& s = slots_[size_t(i)];
        if (s.grid == k && s.done >= 0 && (!completeOnly || s.done == o_.chunks)) return i;
    }
    return -1;
}

int LightKeyframes::victim(const std::array<int, 4>& keep, bool exactTable) {
    auto kept = [&](int i) { return i == building_ || std::find(keep.begin(), keep.end(), i) != keep.end(); };
    for (int i = 0; i < int(slots_.size()); ++i)
        if (!kept(i) && slots_[size_t(i)].done < 0 && !slots_[size_t(i)].cached) return i;
    // An exact table replaces another exact table (they are transient: a light at rest, a jump)
    // before it takes a new slot; a grid table takes a new slot while under the cap.
    int v = -1;
    if (exactTable)
        for (int i = 0; i < int(slots_.size()); ++i)
            if (!kept(i) && slots_[size_t(i)].grid == kNoGrid && (v < 0 || slots_[size_t(i)].used < slots_[size_t(v)].used)) v = i;
    if (v >= 0) return v;
    if (int(slots_.size()) < o_.slots) {
        slots_.push_back(Slot{});
        return int(slots_.size()) - 1;
    }
    for (int i = 0; i < int(slots_.size()); ++i)
        if (!kept(i) && (v < 0 || slots_[size_t(i)].used < slots_[size_t(v)].used)) v = i;
    return v;
}

void LightKeyframes::show(Plan& p, double e, double eTol) const {
    auto one = [&](int s) {
        p.slot = {s, -1, -1, -1};
        p.weight = {1.0, 0.0, 0.0, 0.0};
        p.count = 1;
    };
    if (int x = find(e, eTol, true); x >= 0) {
        one(x);
        p.exact = true;
        return;
    }
    const int k = locate(e);
    const double t = std::clamp((e - nodes_[size_t(k)]) / spacing(k), 0.0, 1.0);
    const int s1 = findGrid(k, true), s2 = findGrid(k + 1, true);
    if (s1 >= 0 && s2 >= 0) {
        const int s0 = findGrid(k - 1, true), s3 = findGrid(k + 2, true);
        if (s0 >= 0 && s3 >= 0) {
            p.slot = {s0, s1, s2, s3};
            p.weight = catmullRom(t);
            p.count = 4;
            p.cubic = true;
        } else {
            p.slot = {s1, s2, -1, -1};
            p.weight = {1.0 - t, t, 0.0, 0.0};
            p.count = 2;
        }
        return;
    }
    // The builder is late: the two complete tables nearest e, extrapolated along their trend (at
    // most one spacing beyond either).
    int n1 = -1, n2 = -1;
    for (int i = 0; i < int(slots_.size()); ++i) {
        const Slot& s = slots_[size_t(i)];
        if (s.done != o_.chunks) continue;
        const double d = std::abs(s.e - e);
        if (n1 < 0 || d < std::abs(slots_[size_t(n1)].e - e)) n2 = n1, n1 = i;
        else if (n2 < 0 || d < std::abs(slots_[size_t(n2)].e - e)) n2 = i;
    }
    one(n1);
    // Two tables closer than half a spacing would amplify their differences: the nearest alone.
    const double sp = spacing(locate(e));
    if (n2 >= 0 && std::abs(slots_[size_t(n2)].e - e) <= 3.0 * sp && std::abs(slots_[size_t(n2)].e - slots_[size_t(n1)].e) >= 0.5 * sp) {
        const double tt = std::clamp((e - slots_[size_t(n1)].e) / (slots_[size_t(n2)].e - slots_[size_t(n1)].e), -1.0, 2.0);
        p.slot = {n1, n2, -1, -1};
        p.weight = {1.0 - tt, tt, 0.0, 0.0};
        p.count = 2;
    }
}

LightKeyframes::Plan LightKeyframes::plan(double muS) {
    if (!(muS >= -1.0 && muS <= 1.0)) {
        char buf[96];
        std::snprintf(buf, sizeof buf, "LightKeyframes::plan(): cos zenith %g not in [-1, 1]", muS);
        throw Error(buf);
    }
    ++run_;
    const double e = std::asin(muS);
    const int k = locate(e);
    const double step = spacing(k);  // the grid's local spacing
    // Moved: more than the generator's own tolerance since the last run. At rest: within it of
    // one elevation for stillRuns runs.
    // A light drifting by less than that per run still leaves its anchor elevation: that gives
    // the direction of motion too.
    const bool moved = !haveLast_ || std::abs(muS - std::sin(lastE_)) > o_.stillMuS;
    if (haveLast_ && moved) dir_ = e > lastE_ ? 1 : -1;
    rate_ = haveLast_ ? std::abs(e - lastE_) : 0.0;
    lastE_ = e;
    haveLast_ = true;
    if (anchorRuns_ > 0 && std::abs(muS - std::sin(anchorE_)) <= o_.stillMuS) {
        ++anchorRuns_;
    } else {
        if (anchorRuns_ > 0 && !moved) dir_ = e > anchorE_ ? 1 : -1;
        anchorE_ = e;
        anchorRuns_ = 1;
    }
    const bool still = anchorRuns_ > o_.stillRuns;
    // The light moves for the first time since the reset: every grid table from prefillLowRad
    // up, nearest the light first (as many as the slots hold beside the 4 the cubic needs).
    // (A jump of more than two grid steps, a new time, is not time running: no prefill.)
    ++runsSinceReset_;
    if (o_.prefill && !prefilled_ && runsSinceReset_ > 1 && anchorRuns_ == 1 && rate_ <= 2.0 * step) {
        prefilled_ = true;
        std::vector<int> ks;
        for (int i = 0; i < int(nodes_.size()); ++i)
            if (nodes_[size_t(i)] >= o_.prefillLowRad - 1e-9) ks.push_back(i);
        std::stable_sort(ks.begin(), ks.end(), [&](int a, int b) { return std::abs(nodes_[size_t(a)] - e) > std::abs(nodes_[size_t(b)] - e); });
        const size_t cap = size_t(std::max(0, o_.slots - 6));
        if (ks.size() > cap) ks.erase(ks.begin(), ks.begin() + std::ptrdiff_t(ks.size() - cap));
        prefillQueue_ = std::move(ks);  // popped from the back: nearest first
        // A grid table half built along the path is built whole with the others instead (when
        // the prefill is built whole; spread, it is finished first).
        if (o_.prefillChunksPerRun == 0 && building_ >= 0 && slots_[size_t(building_)].grid != kNoGrid && slots_[size_t(building_)].e >= o_.prefillLowRad - 1e-9) {
            slots_[size_t(building_)].done = -1;
            building_ = -1;
        }
    }
    // An elevation change up to stillMuS (in e, at the horizon where it is largest) counts as none.
    const double eTol = std::max(1e-12, std::asin(std::min(o_.stillMuS, 1.0)));
    Plan p;

    // Interactive (Options::adoptOnJump): the preloaded grid tables around the light are shown
    // at once, a jump included; the exact table follows once the light rests.
    if (o_.adoptOnJump) {
        for (int c = k - 1; c <= k + 2; ++c)
            if (c >= 0 && c < int(nodes_.size()) && findGrid(c, false) < 0) adopt(c);
        // An exact table half built for where the light rested is of no use once it has left
        // (and the pace rule below would finish it at once after a jump): abandoned.
        if (building_ >= 0 && slots_[size_t(building_)].grid == kNoGrid && std::abs(muS - std::sin(slots_[size_t(building_)].e)) > o_.stillMuS) {
            slots_[size_t(building_)].done = -1;
            building_ = -1;
            buildingFill_ = false;
        }
    }
    // First run, a jump, or after reset(): a table at exactly e, built now.
    if (find(e, 2.0 * step, true) < 0) {
        if (building_ >= 0 && std::abs(slots_[size_t(building_)].e - e) > 2.0 * step) {
            slots_[size_t(building_)].done = -1;  // far from the light now: abandoned
            if (buildingFill_) prefillQueue_.push_back(slots_[size_t(building_)].grid);  // queued again
            building_ = -1;
            buildingFill_ = false;
        }
        const int s = victim({-1, -1, -1, -1}, true);
        slots_[size_t(s)] = Slot{e, kNoGrid, o_.chunks, run_};
        p.build = s;
        p.buildMuS = muS;
        p.chunkBegin = 0;
        p.chunkEnd = o_.chunks;
        p.slot = {s, -1, -1, -1};
        p.weight = {1.0, 0.0, 0.0, 0.0};
        p.count = 1;
        p.exact = true;
        pending_ = building_ >= 0 || (o_.prefillChunksPerRun > 0 && !prefillQueue_.empty());
        lastPlan_ = p;
        shownE_ = e;
        return p;
    }

    // A moving light adopts the preloaded tables around it at once (they cost nothing now).
    if (!still && dir_ != 0)
        for (int c = k - 2; c <= k + 3; ++c)
            if (c >= 0 && c < int(nodes_.size()) && findGrid(c, false) < 0) adopt(c);
    const std::array<int, 4> needed = {findGrid(k - 1, false), findGrid(k, false), findGrid(k + 1, false), findGrid(k + 2, false)};
    // What to build: a still light wants its exact table; a moving one the grid tables the cubic
    // needs (nearest its direction of motion first), then the next one ahead.
    const bool spread = o_.prefillChunksPerRun > 0;
    // A moving light waits for a grid table of its own while a fill table is being built: the
    // fill table is then finished at the light's pace.
    bool pathWaiting = false;
    if (spread && buildingFill_ && !still && dir_ != 0)
        for (int c : {k - 1, k, k + 1, k + 2})
            if (c >= 0 && c < int(nodes_.size()) && findGrid(c, false) < 0) pathWaiting = true;
    if (building_ < 0 && (spread || prefillQueue_.empty())) {  // (a prefill built whole builds the grid this run)
        double target = NAN;
        int grid = kNoGrid;
        if (still || (dir_ == 0 && !o_.adoptOnJump)) {  // (adoptOnJump: the exact table only once the light rests)
            if (find(e, eTol, true) < 0) target = e;
        } else {
            const std::array<int, 5> cands = dir_ > 0 ? std::array<int, 5>{k + 1, k, k + 2, k - 1, k + 3}
                                                      : std::array<int, 5>{k, k + 1, k - 1, k + 2, k - 2};
            for (int c : cands)
                if (c >= 0 && c < int(nodes_.size()) && findGrid(c, false) < 0) {
                    if (adopt(c) >= 0) continue;  // preloaded: complete now, the next one
                    target = nodes_[size_t(c)];
                    grid = c;
                    break;
                }
        }
        // Nothing the light needs: the spread prefill's next table, the queued one nearest the
        // light (the light has moved since the queue was sorted).
        bool fill = false;
        while (spread && !std::isfinite(target) && !prefillQueue_.empty()) {
            auto it = std::min_element(prefillQueue_.begin(), prefillQueue_.end(), [&](int a, int b) {
                return std::abs(nodes_[size_t(a)] - e) < std::abs(nodes_[size_t(b)] - e);
            });
            const int c = *it;
            prefillQueue_.erase(it);
            if (findGrid(c, false) >= 0) continue;  // built or being built meanwhile
            if (adopt(c) >= 0) continue;            // preloaded: complete now
            target = nodes_[size_t(c)];
            grid = c;
            fill = true;
        }
        if (std::isfinite(target)) {
            const int s = victim(needed, grid == kNoGrid);
            if (s >= 0) {
                slots_[size_t(s)] = Slot{target, grid, 0, run_};
                building_ = s;
                buildingFill_ = fill;
            }
        }
    }
    if (building_ >= 0) {
        Slot& b = slots_[size_t(building_)];
        // Chunks per run: enough to be complete before the light, at its last rate, needs the
        // table (at least one; two once it is needed already).
        const int remaining = o_.chunks - b.done;
        int perRun = 1;
        if (rate_ > 0.0) {
            // Grid point m is among the cubic's four once the light passes m - 2 (rising) or m + 2.
            const int last = int(nodes_.size()) - 1;
            const double needAt = b.grid == kNoGrid ? b.e : nodes_[size_t(std::clamp(b.grid - 2 * dir_, 0, last))];
            const double ahead = (needAt - e) * dir_;
            const double framesLeft = ahead > 0.0 ? std::floor(ahead / rate_) : 0.0;
            perRun = framesLeft >= 1.0 ? int(std::ceil(remaining / framesLeft)) : 2;
        }
        // Keeping pace: one grid table per grid spacing the light travels (with a quarter more
        // for the turns); late (its bracketing pair incomplete): the rest within 4 runs.
        if (rate_ > 0.0) perRun = std::max(perRun, int(std::ceil(1.25 * o_.chunks * rate_ / step)));
        const bool late = findGrid(k, true) < 0 || findGrid(k + 1, true) < 0;
        if (late && !still) perRun = std::max(perRun, (remaining + 3) / 4);
        if (spread) {
            // The budget: a fill table not (yet) among those the light needs gets the budget; one
            // it needs, no more than the budget or the pace that keeps up with the light.
            const int pace = rate_ > 0.0 ? int(std::ceil(1.25 * o_.chunks * rate_ / step)) : 1;
            const bool needs = b.grid != kNoGrid && b.grid >= k - 1 && b.grid <= k + 2;
            if (buildingFill_ && !needs) perRun = pathWaiting ? std::max(o_.prefillChunksPerRun, pace) : o_.prefillChunksPerRun;
            else perRun = std::min(perRun, std::max(o_.prefillChunksPerRun, pace));
        }
        perRun = std::clamp(perRun, 1, remaining);
        p.build = building_;
        p.buildMuS = std::sin(b.e);
        p.chunkBegin = b.done;
        p.chunkEnd = std::min(b.done + perRun, o_.chunks);
        b.done = p.chunkEnd;
        b.used = run_;
        if (b.done == o_.chunks) building_ = -1, buildingFill_ = false;
    }

    // What to show (this run's completed build included).
    show(p, e, eTol);
    for (int i = 0; i < p.count; ++i) slots_[size_t(p.slot[size_t(i)])].used = run_;
    // Work remains while a table is half built, or while a light not shown exactly may yet come
    // to rest (the runs that count its stillness: cheap, Plan::unchanged).
    pending_ = building_ >= 0 || !p.exact || (spread && !prefillQueue_.empty());
    // Unchanged: the same tables, none of them written this run, and the light within stillMuS
    // of the elevation last mixed (the staleness the generator's input tolerance accepts anyway).
    // A build into a slot that is not shown (the background fill of sky.keyframe_budget, a grid
    // table ahead of the light) leaves the shown mix as it is: it is not re-mixed or republished.
    bool buildShown = false;
    for (int i = 0; i < p.count; ++i) buildShown = buildShown || p.slot[size_t(i)] == p.build;
    for (int i = 0; i < lastPlan_.count; ++i) buildShown = buildShown || lastPlan_.slot[size_t(i)] == p.build;
    if ((p.build < 0 || !buildShown) && lastPlan_.count == p.count && std::abs(muS - std::sin(shownE_)) <= o_.stillMuS) {
        bool same = true;
        for (int i = 0; i < p.count; ++i) same = same && p.slot[size_t(i)] == lastPlan_.slot[size_t(i)];
        p.unchanged = same;
    }
    if (!p.unchanged) shownE_ = e;
    lastPlan_ = p;
    return p;
}

}  // namespace welkin::generators
