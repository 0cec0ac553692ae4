// SecantCache: a series' last full evaluation and the secant to the one before, so that nearby
// instants are extrapolated instead of summed again (the Ephemeris' frame-to-frame reuse of the
// planets' VSOP87, the Moon's series and the Earth's nutation and CIO locator).
//
//   welkin::astro::SecantCache<3> cache;
//   std::array<double, 3> v;
//   if (!cache.reuse(t, span, v)) {     // t and span in one unit (e.g. TT centuries from J2000)
//       v = fullSeries(t);              // the costly evaluation
//       cache.record(t, span, v);
//   }
//
// reuse() answers only after two full evaluations within `span` of each other, and only for a
// `t` within `span` of the last: then value + slope (t - tLast). The error of a secant over D
// extrapolated by dt is at most 0.5 |f''| dt (dt + D); each user states its own bound from its
// series' |f''| and span. Fields marked as angles (radians) are unwrapped when the slope is taken
// and reduced to [0, 2 pi) when extrapolated, as series that reduce their angles return them.
#pragma once
#include <array>
#include <cmath>
#include <cstddef>
#include <numbers>

namespace welkin::astro {

template <std::size_t N>
struct SecantCache {
    bool valid = false;     ///< `value` holds a full evaluation at `t`
    bool hasSlope = false;  ///< `slope` is the secant from the evaluation before (within the span)
    double t = 0;           ///< the instant of the last full evaluation (the caller's unit)
    std::array<double, N> value{};  ///< the last full evaluation
    std::array<double, N> slope{};  ///< per unit of t
    std::array<bool, N> angle{};    ///< fields that are angles in radians, reduced to [0, 2 pi)

    /// Writes the extrapolation at `tNow` into `out` and returns true when the cache may answer
    /// (a slope is known and |tNow - t| <= span); otherwise returns false and leaves `out`.
    bool reuse(double tNow, double span, std::array<double, N>& out) const {
        if (!valid || !hasSlope || !(std::fabs(tNow - t) <= span)) return false;
        constexpr double kTwoPi = 2.0 * std::numbers::pi;
        for (std::size_t i = 0; i < N; ++i) {
            out[i] = value[i] + slope[i] * (tNow - t);
            if (angle[i]) out[i] -= kTwoPi * std::floor(out[i] / kTwoPi);
        }
        return true;
    }

    /// Records a full evaluation `v` at `tNow`; the slope is kept when the last full evaluation
    /// lies within `span` of it (and at another instant).
    void record(double tNow, double span, const std::array<double, N>& v) {
        constexpr double kTwoPi = 2.0 * std::numbers::pi;
        const double dt = tNow - t;
        hasSlope = valid && dt != 0.0 && std::fabs(dt) <= span;
        if (hasSlope)
            for (std::size_t i = 0; i < N; ++i) {
                double d = v[i] - value[i];
                if (angle[i]) d -= kTwoPi * std::round(d / kTwoPi);
                slope[i] = d / dt;
            }
        valid = true;
        t = tNow;
        value = v;
    }
};

}  // namespace welkin::astro
