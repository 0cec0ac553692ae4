// Earth orientation: sidereal time, obliquity, nutation and the celestial (GCRS/J2000) to true
// equator and equinox of date rotation, each on the Fast or the Precise path.
//
//   using namespace welkin::astro;
//   TimeScales ts = timeScales(UtcInstant::parse("1987-04-10T19:21:00Z"));
//   double theta = gmst(ts, Path::Precise);                      // radians, [0, 2 pi)
//   glm::dmat3 npb = celestialToTrueOfDate(ts, Path::Fast);       // v_tod = npb * v_gcrs
//   EarthOrientation eo = earthOrientation(ts, Path::Fast);       // all of the above at once
//
// Fast path: IAU 2006 precession (Fukushima-Williams angles, including the frame bias), IAU 2000B
// nutation (77 luni-solar terms, fixed planetary offsets, IAU 2006 scaling), GMST from the Earth
// rotation angle (IAU 2006) and GAST the CIO way, ERA - EO, with the equation of the origins from
// the Fast matrix and the CIO locator s truncated to its luni-solar terms above 0.2 uas.
// Precise path: ERFA eraPnm06a (IAU 2006/2000A), eraGmst06, eraGst06 (from the same matrix),
// eraNut06a, eraObl06. Measured differences (tests/astro/test_frames.cpp): the Fast path is
// within 0.003" of the Precise path over 1900-2100 and at the years -2000 and +6000 (see
// docs/astronomy-time-and-frames.md).
// Polar motion is neglected (< 0.5", it needs IERS data that an offline renderer does not have).
#pragma once
#include <welkin/astro/secant_cache.hpp>
#include <welkin/astro/timescales.hpp>

#include <glm/glm.hpp>

namespace welkin::astro {

/// Nutation in longitude and obliquity, radians.
struct Nutation {
    double dpsi = 0;  ///< nutation in longitude, rad (|dpsi| < 20")
    double deps = 0;  ///< nutation in obliquity, rad (|deps| < 10")
};

/// Mean obliquity of the ecliptic of date (IAU 2006), radians. Same on both paths.
double meanObliquity(const TimeScales& ts);
/// Nutation (Fast: IAU 2000B; Precise: IAU 2006/2000A via eraNut06a), radians.
Nutation nutation(const TimeScales& ts, Path path);
/// Earth rotation angle (IAU 2000), radians in [0, 2 pi).
double earthRotationAngle(const TimeScales& ts);
/// Greenwich mean sidereal time (IAU 2006), radians in [0, 2 pi). Same formula on both paths.
double gmst(const TimeScales& ts, Path path);
/// Greenwich apparent sidereal time, radians in [0, 2 pi).
double gast(const TimeScales& ts, Path path);
/// Rotation from the GCRS (ICRS axes, "J2000") to the true equator and equinox of date, including
/// the frame bias, precession and nutation: v_tod = M * v_gcrs.
glm::dmat3 celestialToTrueOfDate(const TimeScales& ts, Path path);

/// Everything above at one instant, computed once (nutation is evaluated a single time).
struct EarthOrientation {
    glm::dmat3 celestialToTrueOfDate{1.0};  ///< v_tod = M * v_gcrs
    Nutation nutation;                      ///< rad
    double meanObliquity = 0;               ///< rad
    double trueObliquity = 0;               ///< meanObliquity + nutation.deps, rad
    double gmst = 0;                        ///< rad, [0, 2 pi)
    double gast = 0;                        ///< rad, [0, 2 pi)
};
EarthOrientation earthOrientation(const TimeScales& ts, Path path);

/// The Fast path's nutation and CIO-locator series reused between nearby instants (an Ephemeris
/// keeps one across frames): within kReuseDays of the last full evaluation their values are
/// extrapolated along the secant of the last two full evaluations (both within the span), as
/// Ephemeris does for the planets. Error: at most 0.5 |f''| dt (dt + D) for dt, D <= 5 minutes;
/// the series' fastest terms (13.66 and 9.13 days, |f''| summed < 0.1"/day^2) give < 2e-6",
/// against the IAU 2000B truncation's own 1 mas. Tested in [astro] against full evaluations.
/// Fields: dpsi, deps, s + XY/2 (rad); t in TT centuries from J2000.
struct EarthSeriesCache : SecantCache<3> {
    static constexpr double kReuseDays = 300.0 / 86400.0;  ///< 5 minutes of TT
};
/// earthOrientation() with its series reused through `cache` (Fast path; ignored on the Precise
/// path and when null).
EarthOrientation earthOrientation(const TimeScales& ts, Path path, EarthSeriesCache* cache);

/// Elementary rotations (right-handed frame rotations, as in ERFA: rotating the axes by +angle).
/// v' = rotationX(a) * v.
glm::dmat3 rotationX(double angleRad);
glm::dmat3 rotationY(double angleRad);
glm::dmat3 rotationZ(double angleRad);

/// Unit vector from right ascension / declination (rad) and back (ra in [0, 2 pi)).
glm::dvec3 directionFromRaDec(double raRad, double decRad);
void raDecFromDirection(const glm::dvec3& v, double& raRad, double& decRad);

}  // namespace welkin::astro
