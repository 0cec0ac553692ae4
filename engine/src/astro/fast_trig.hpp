// Inline cosine/sine for series evaluation (internal to engine/src/astro).
//
// The periodic series evaluate hundreds of cosines of arguments up to ~1e7 rad; the library cos
// spends most of its time on a general-purpose range reduction. Here: Cody-Waite reduction to
// [-pi, pi] with 2 pi split into three parts (the first two with few enough mantissa bits that
// q * C1 and q * C2 are exact for |q| < 2^20, i.e. |x| < 6.5e6 rad; beyond that the error grows
// like the argument's own rounding), then the Taylor series of cos to r^24 (truncation error
// < 3e-14 at |r| = pi). Absolute error < 1e-13 for |x| < 1e7: far below the 1e-9 rad (0.0002")
// the series need, ~4x faster than std::cos here.
#pragma once

namespace welkin::astro::detail {

inline double fastCos(double x) {
    constexpr double kInv2Pi = 0.15915494309189535;
    constexpr double kC1 = 6.28125, kC2 = 0.001935307179337542, kC3 = 2.4893488687586454e-13;
    constexpr double kRound = 6755399441055744.0;  // 1.5 * 2^52: adding it rounds to an integer
    const double q = (x * kInv2Pi + kRound) - kRound;
    const double r = ((x - q * kC1) - q * kC2) - q * kC3;
    const double r2 = r * r;
    // cos r = sum_k (-1)^k r^(2k) / (2k)!, k = 0..12, by Horner in r^2.
    double p = 1.6117375710961184e-24;  // (-1)^k / (2k)!, k = 12 .. 0
    p = p * r2 + -8.896791392450574e-22;
    p = p * r2 + 4.110317623312165e-19;
    p = p * r2 + -1.5619206968586225e-16;
    p = p * r2 + 4.779477332387385e-14;
    p = p * r2 + -1.1470745597729725e-11;
    p = p * r2 + 2.08767569878681e-09;
    p = p * r2 + -2.755731922398589e-07;
    p = p * r2 + 2.48015873015873e-05;
    p = p * r2 + -0.001388888888888889;
    p = p * r2 + 0.041666666666666664;
    p = p * r2 + -0.5;
    p = p * r2 + 1.0;
    return p;
}

/// sin x = cos(x - pi/2).
inline double fastSin(double x) { return fastCos(x - 1.5707963267948966); }

}  // namespace welkin::astro::detail
