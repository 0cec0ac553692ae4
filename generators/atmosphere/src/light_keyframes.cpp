// LightKeyframes: the schedule of light-dependent tables while the light moves (see the header).
#include <welkin/error.hpp>
#include <welkin/generators/light_keyframes.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>

namespace welkin::generators {

LightKeyframes::LightKeyframes() : LightKeyframes(Options{}) {}
LightKeyframes::LightKeyframes(Options o) { setOptions(o); }

void LightKeyframes::setOptions(Options o) {
    if (!(o.stepRad > 0.0) || o.chunks < 1 || o.slots < 3 || !(o.stillMuS >= 0.0)) {
        char buf[160];
        std::snprintf(buf, sizeof buf, "LightKeyframes: step %g rad, %d chunks, %d slots, still %g: need step > 0, chunks >= 1, slots >= 3, still >= 0",
                      o.stepRad, o.chunks, o.slots, o.stillMuS);
        throw Error(buf);
    }
    bool same = o.stepRad == o_.stepRad && o.chunks == o_.chunks && o.slots == o_.slots && !slots_.empty();
    o_ = o;
    if (!same) reset();
}

void LightKeyframes::reset() {
    slots_.assign(size_t(o_.slots), Slot{});
    building_ = -1;
    pending_ = false;
    haveLast_ = false;
    dir_ = 0;
}

double LightKeyframes::slotMuS(int i) const { return std::sin(slots_.at(size_t(i)).e); }

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

int LightKeyframes::victim(int keepA, int keepB) const {
    int v = -1;
    for (int i = 0; i < int(slots_.size()); ++i) {
        if (i == keepA || i == keepB || i == building_) continue;
        const Slot& s = slots_[size_t(i)];
        if (s.done < 0) return i;
        if (v < 0 || s.used < slots_[size_t(v)].used) v = i;
    }
    return v;
}

LightKeyframes::Plan LightKeyframes::plan(double muS) {
    if (!(muS >= -1.0 && muS <= 1.0)) {
        char buf[96];
        std::snprintf(buf, sizeof buf, "LightKeyframes::plan(): cos zenith %g not in [-1, 1]", muS);
        throw Error(buf);
    }
    ++run_;
    const double e = std::asin(muS);
    const double step = o_.stepRad;
    // Still: moved no more than the generator's own tolerance since the last run.
    const bool still = haveLast_ && std::abs(muS - std::sin(lastE_)) <= o_.stillMuS;
    if (haveLast_ && !still) dir_ = e > lastE_ ? 1 : -1;
    rate_ = haveLast_ && !still ? std::abs(e - lastE_) : 0.0;
    lastE_ = e;
    haveLast_ = true;
    // An elevation change up to stillMuS (in e, at the horizon where it is largest) counts as none.
    const double eTol = std::max(1e-12, std::asin(std::min(o_.stillMuS, 1.0)));
    Plan p;
    auto cosZ = [](double el) { return std::sin(el); };

    // First run, a jump, or after reset(): a table at exactly e, built now.
    if (find(e, 2.0 * step, true) < 0) {
        if (building_ >= 0 && std::abs(slots_[size_t(building_)].e - e) > 2.0 * step) {
            slots_[size_t(building_)].done = -1;  // far from the light now: abandoned
            building_ = -1;
        }
        int s = victim(-1, -1);
        slots_[size_t(s)] = Slot{e, o_.chunks, run_};
        p.build = s;
        p.buildMuS = cosZ(e);
        p.chunkBegin = 0;
        p.chunkEnd = o_.chunks;
        p.a = s;
        p.exact = true;
        pending_ = building_ >= 0;
        return p;
    }

    // The complete slots that bracket e (before this run's build).
    auto bracket = [&](int& lo, int& hi) {
        lo = hi = -1;
        for (int i = 0; i < int(slots_.size()); ++i) {
            const Slot& s = slots_[size_t(i)];
            if (s.done != o_.chunks) continue;
            if (s.e <= e + eTol && (lo < 0 || s.e > slots_[size_t(lo)].e)) lo = i;
            if (s.e >= e - eTol && (hi < 0 || s.e < slots_[size_t(hi)].e)) hi = i;
        }
    };
    int lo, hi;
    bracket(lo, hi);
    const bool late = !(lo >= 0 && hi >= 0 && slots_[size_t(hi)].e - slots_[size_t(lo)].e <= 2.5 * step);

    // What to build: a still light wants its exact table; a moving one the grid ahead of it.
    if (building_ < 0) {
        double target = NAN;
        if (still || dir_ == 0) {
            if (find(e, eTol, true) < 0) target = e;
        } else {
            const double g0 = std::floor(e / step) * step;
            const double ahead = dir_ > 0 ? g0 + step : g0, behind = dir_ > 0 ? g0 : g0 + step;
            const double cands[3] = {ahead, behind, ahead + dir_ * step};
            // A grid point is covered by a table within a quarter step of it, or (the one behind)
            // by any table between it and the light.
            auto covered = [&](double g) {
                if (find(g, 0.25 * step, false) >= 0) return true;
                if (g != behind) return false;
                for (const Slot& sl : slots_)
                    if (sl.done >= 0 && (sl.e - g) * (e - sl.e) >= 0.0) return true;
                return false;
            };
            for (double g : cands)
                if (std::abs(g) <= 0.5 * std::numbers::pi + 1e-9 && !covered(g)) {
                    target = std::clamp(g, -0.5 * std::numbers::pi, 0.5 * std::numbers::pi);
                    break;
                }
        }
        if (std::isfinite(target)) {
            int s = victim(lo, hi);
            if (s >= 0) {
                slots_[size_t(s)] = Slot{target, 0, run_};
                building_ = s;
            }
        }
    }
    if (building_ >= 0) {
        Slot& b = slots_[size_t(building_)];
        // Chunks per run: enough to finish before the light, at its last rate, reaches the table's
        // elevation (at least one); behind the light (extrapolating), twice that.
        const int remaining = o_.chunks - b.done;
        int perRun = 1;
        if (rate_ > 0.0) {
            const double ahead = (b.e - e) * dir_;
            const double framesLeft = ahead > 0.0 ? std::floor(ahead / rate_) : 0.0;
            perRun = framesLeft >= 1.0 ? int(std::ceil(remaining / framesLeft)) : 2;
        }
        if (late) perRun = std::max(perRun, 2);
        perRun = std::clamp(perRun, 1, remaining);
        p.build = building_;
        p.buildMuS = cosZ(b.e);
        p.chunkBegin = b.done;
        p.chunkEnd = std::min(b.done + perRun, o_.chunks);
        b.done = p.chunkEnd;
        b.used = run_;
        if (b.done == o_.chunks) building_ = -1;
    }

    // What to show (this run's completed build included).
    if (int x = find(e, eTol, true); x >= 0) {
        p.a = x;
        p.exact = true;
    } else {
        bracket(lo, hi);
        if (lo >= 0 && hi >= 0 && slots_[size_t(hi)].e - slots_[size_t(lo)].e <= 2.5 * step) {
            p.a = lo;
            p.b = hi;
            p.t = (e - slots_[size_t(lo)].e) / (slots_[size_t(hi)].e - slots_[size_t(lo)].e);
        } else {
            // The two complete slots nearest e, extrapolated along their trend (at most one
            // spacing beyond either).
            int n1 = -1, n2 = -1;
            for (int i = 0; i < int(slots_.size()); ++i) {
                const Slot& s = slots_[size_t(i)];
                if (s.done != o_.chunks) continue;
                double d = std::abs(s.e - e);
                if (n1 < 0 || d < std::abs(slots_[size_t(n1)].e - e)) n2 = n1, n1 = i;
                else if (n2 < 0 || d < std::abs(slots_[size_t(n2)].e - e)) n2 = i;
            }
            p.a = n1;
            if (n2 >= 0 && std::abs(slots_[size_t(n2)].e - e) <= 3.0 * step && slots_[size_t(n2)].e != slots_[size_t(n1)].e) {
                p.b = n2;
                p.t = std::clamp((e - slots_[size_t(n1)].e) / (slots_[size_t(n2)].e - slots_[size_t(n1)].e), -1.0, 2.0);
            }
        }
    }
    slots_[size_t(p.a)].used = run_;
    if (p.b >= 0) slots_[size_t(p.b)].used = run_;
    pending_ = building_ >= 0 || !p.exact;
    return p;
}

}  // namespace welkin::generators
