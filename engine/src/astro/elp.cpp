// The Moon from Meeus ch. 47 (ELP-2000/82 main terms). Literate summary:
//   L' mean longitude, D mean elongation, M Sun's mean anomaly, M' Moon's mean anomaly, F argument
//   of latitude (degrees, polynomials in T centuries TT); E = 1 - 0.002516 T - 0.0000074 T^2
//   scales the terms in M (the decreasing eccentricity of the Earth's orbit), once per |multiple|.
//   lambda = L' + sum_l, beta = sum_b, Delta = 385000.56 km + sum_r.
#include <welkin/astro/elp.hpp>

#include "fast_trig.hpp"

#include <cmath>
#include <numbers>

namespace welkin::astro {

namespace {
constexpr double kDeg = std::numbers::pi / 180.0;
inline double reduceDeg(double x) {
    x = std::fmod(x, 360.0);
    return x < 0 ? x + 360.0 : x;
}
}  // namespace

MoonEcliptic moonMeeus(double T) {
    const double T2 = T * T, T3 = T2 * T, T4 = T3 * T;
    const double Lp = reduceDeg(218.3164477 + 481267.88123421 * T - 0.0015786 * T2 + T3 / 538841.0 - T4 / 65194000.0);
    const double D = reduceDeg(297.8501921 + 445267.1114034 * T - 0.0018819 * T2 + T3 / 545868.0 - T4 / 113065000.0);
    const double M = reduceDeg(357.5291092 + 35999.0502909 * T - 0.0001536 * T2 + T3 / 24490000.0);
    const double Mp = reduceDeg(134.9633964 + 477198.8675055 * T + 0.0087414 * T2 + T3 / 69699.0 - T4 / 14712000.0);
    const double F = reduceDeg(93.2720950 + 483202.0175233 * T - 0.0036539 * T2 - T3 / 3526000.0 + T4 / 863310000.0);
    const double A1 = reduceDeg(119.75 + 131.849 * T);
    const double A2 = reduceDeg(53.09 + 479264.290 * T);
    const double A3 = reduceDeg(313.45 + 481266.484 * T);
    const double E = 1.0 - 0.002516 * T - 0.0000074 * T2;
    const double E2 = E * E;

    const double d = D * kDeg, m = M * kDeg, mp = Mp * kDeg, f = F * kDeg;
    double sl = 0.0, sr = 0.0, sb = 0.0;
    for (const auto& t : detail::kMoonLR) {
        const double arg = t.d * d + t.m * m + t.mp * mp + t.f * f;
        const double e = t.m == 0 ? 1.0 : (t.m == 1 || t.m == -1) ? E : E2;
        sl += e * t.l * detail::fastSin(arg);
        if (t.r != 0) sr += e * t.r * detail::fastCos(arg);
    }
    for (const auto& t : detail::kMoonB) {
        const double arg = t.d * d + t.m * m + t.mp * mp + t.f * f;
        const double e = t.m == 0 ? 1.0 : (t.m == 1 || t.m == -1) ? E : E2;
        sb += e * t.b * detail::fastSin(arg);
    }
    // Additive terms: Venus (A1), Jupiter (A2), flattening of the Earth (L' - F).
    sl += 3958.0 * std::sin(A1 * kDeg) + 1962.0 * std::sin((Lp - F) * kDeg) + 318.0 * std::sin(A2 * kDeg);
    sb += -2235.0 * std::sin(Lp * kDeg) + 382.0 * std::sin(A3 * kDeg) + 175.0 * std::sin((A1 - F) * kDeg) +
          175.0 * std::sin((A1 + F) * kDeg) + 127.0 * std::sin((Lp - Mp) * kDeg) - 115.0 * std::sin((Lp + Mp) * kDeg);

    MoonEcliptic r;
    r.longitude = reduceDeg(Lp + sl * 1e-6) * kDeg;
    r.latitude = sb * 1e-6 * kDeg;
    r.distanceKm = 385000.56 + sr * 1e-3;
    r.meanElongation = d;
    r.argumentLatitude = f;
    r.sunMeanAnomaly = m;
    r.moonMeanAnomaly = mp;
    r.eccentricityFactor = E;
    r.ascendingNode = reduceDeg(125.0445479 - 1934.1362891 * T + 0.0020754 * T2 + T3 / 467441.0 - T4 / 60616000.0) * kDeg;
    return r;
}

}  // namespace welkin::astro
