// The Moon's geocentric position from the ELP-2000/82 periodic terms of Meeus, Astronomical
// Algorithms (2nd ed.), ch. 47: 60 terms in longitude and distance, 60 in latitude, plus the
// additive terms for Venus, Jupiter and the flattening of the Earth. Accuracy about 10" in
// longitude and 4" in latitude against the full ELP-2000/82 near the present.
//
//   welkin::astro::MoonEcliptic m = welkin::astro::moonMeeus(tCenturiesTT);
//   // m.longitude, m.latitude: radians, mean ecliptic and equinox of date; m.distanceKm
//
// The longitude constant of the theory includes the light time (0.7"), so the result is the
// position the Moon is seen at from the geocentre, before nutation.
#pragma once

namespace welkin::astro {

namespace detail {
/// Table 47.A row: multiples of D, M, M', F; sum_l coefficient (1e-6 deg), sum_r (1e-3 km).
struct MoonTermLR {
    int d, m, mp, f;
    int l, r;
};
/// Table 47.B row: multiples of D, M, M', F; sum_b coefficient (1e-6 deg).
struct MoonTermB {
    int d, m, mp, f;
    int b;
};
extern const MoonTermLR kMoonLR[60];
extern const MoonTermB kMoonB[60];
}  // namespace detail

struct MoonEcliptic {
    double longitude = 0.0;   ///< rad, mean equinox of date, in [0, 2 pi)
    double latitude = 0.0;    ///< rad
    double distanceKm = 0.0;  ///< centre to centre, km
    double meanElongation = 0.0;  ///< D, rad (for phases)
    double ascendingNode = 0.0;   ///< mean longitude of the ascending node Omega, rad
    double argumentLatitude = 0.0;  ///< F, rad (for libration)
    double sunMeanAnomaly = 0.0;    ///< M, rad
    double moonMeanAnomaly = 0.0;   ///< M', rad
    double eccentricityFactor = 1.0;  ///< E = 1 - 0.002516 T - 0.0000074 T^2
};

/// `t`: Julian centuries of TT from J2000.0. Allocation-free.
MoonEcliptic moonMeeus(double t);

}  // namespace welkin::astro
