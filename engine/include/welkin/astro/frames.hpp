// Observer frames: a WGS84 site, true-of-date equatorial -> topocentric horizontal (ENU, azimuth
// from north through east), diurnal parallax, annual + diurnal aberration, refraction.
//
//   using namespace welkin::astro;
//   Site site{glm::radians(52.5), glm::radians(13.4), 34.0};             // Berlin, 34 m
//   TimeScales ts = timeScales(UtcInstant::parse("2026-06-21T21:00:00Z"));
//   ObserverFrame f = observerFrame(site, ts, Path::Fast);               // once per instant
//   // A body from its apparent geocentric RA/Dec of date and distance (m):
//   Topocentric moon = topocentric(f, raRad, decRad, 3.8e8);
//   double alt = moon.altitudeRad;            // refracted; moon.altitudeGeometricRad without
//   // A star (ICRS direction) through the full pipeline (aberration, precession-nutation, ...):
//   Topocentric vega = topocentricFromIcrs(f, directionFromRaDec(ra2000, dec2000));
//
// Conventions: ENU = (x east, y north, z up); azimuth in [0, 2 pi) from north through east;
// altitude in [-pi/2, pi/2]. At the zenith/nadir the azimuth is degenerate (returned as 0):
// compare directions on the sphere there. Refraction uses the Site's pressure and temperature;
// pressure 0 switches it off.
#pragma once
#include <welkin/astro/earth.hpp>

#include <glm/glm.hpp>

namespace welkin::astro {

/// Speed of light, m/s; astronomical unit, m; WGS84 ellipsoid; Earth rotation rate, rad/s.
inline constexpr double kSpeedOfLight = 299792458.0;
inline constexpr double kAstronomicalUnit = 149597870700.0;
inline constexpr double kWgs84A = 6378137.0;
inline constexpr double kWgs84F = 1.0 / 298.257223563;
inline constexpr double kEarthRotationRate = 7.292115855306589e-5;

/// An observer on the WGS84 ellipsoid.
struct Site {
    double latitudeRad = 0;     ///< geodetic latitude, rad, [-pi/2, pi/2], north positive
    double longitudeRad = 0;    ///< rad, [-pi, pi] (values up to +-2 pi accepted), east positive
    double heightMeters = 0;    ///< above the ellipsoid, m, [-1e4, 1e8]
    double pressureHpa = 1013.25;  ///< surface pressure, hPa, [0, 2000]; 0 = no refraction
    double temperatureC = 10;      ///< surface temperature, deg C, [-100, 100]
};

/// Throws welkin::Error naming the field and its range if `site` is out of range or not finite.
void validate(const Site& site);

/// Geocentric position of the site in the Earth-fixed (ITRS, polar motion neglected) frame, m.
glm::dvec3 siteItrs(const Site& site);
/// Rotation from the Earth-fixed frame to the site's ENU frame: v_enu = M * v_itrs.
glm::dmat3 itrsToEnu(const Site& site);

/// Everything needed to place sources for one site and instant (compute once per frame).
struct ObserverFrame {
    Site site;
    TimeScales time;
    Path path = Path::Fast;
    EarthOrientation earth;                 ///< precession-nutation, sidereal time
    glm::dmat3 trueOfDateToEnu{1.0};        ///< v_enu = M * v_tod (site, GAST)
    glm::dmat3 icrsToEnu{1.0};              ///< trueOfDateToEnu * earth.celestialToTrueOfDate
    glm::dvec3 sitePositionTod{0.0};        ///< geocentric site position, true-of-date axes, m
    glm::dvec3 siteVelocityTod{0.0};        ///< its velocity from the Earth's rotation, m/s
    glm::dvec3 earthVelocityIcrs{0.0};      ///< Earth's barycentric velocity / c, ICRS axes
    glm::dvec3 observerVelocityIcrs{0.0};   ///< earthVelocityIcrs + site velocity / c (ICRS axes)
    glm::dvec3 sunFromEarthIcrs{0.0};       ///< Sun -> Earth unit vector, ICRS (Fast: Keplerian)
    double sunDistanceAu = 1.0;             ///< Sun-Earth distance, au
    double lastRad = 0;                     ///< local apparent sidereal time, rad [0, 2 pi)
    double lmstRad = 0;                     ///< local mean sidereal time, rad [0, 2 pi)
};
/// Builds the frame. Fast: analytic Earth velocity (Keplerian Earth-Moon barycentre, Jupiter and
/// Saturn reflex, circular Moon: 0.002" of aberration vs eraEpv00); Precise: eraEpv00. Throws
/// welkin::Error for an invalid site.
ObserverFrame observerFrame(const Site& site, const TimeScales& ts, Path path);
/// The same with the Earth orientation's series reused through `cache` (earthOrientation()).
ObserverFrame observerFrame(const Site& site, const TimeScales& ts, Path path, EarthSeriesCache* cache);

/// Earth's barycentric velocity divided by c, ICRS axes (Fast: analytic; Precise: eraEpv00).
glm::dvec3 earthVelocity(const TimeScales& ts, Path path);

/// Annual (+ diurnal) aberration: natural direction `p` (unit, ICRS axes) seen by an observer with
/// velocity `velocityOverC` (ICRS axes). Fast: first order p + v renormalised (error < |v|^2 ~
/// 0.002"); Precise: eraAb (relativistic, with the Sun's distance).
glm::dvec3 aberrate(const glm::dvec3& p, const glm::dvec3& velocityOverC, Path path, double sunDistanceAu = 1.0);

/// Azimuth (from north through east, [0, 2 pi)) and altitude of an ENU vector (any length > 0).
struct Horizontal {
    double azimuthRad = 0;
    double altitudeRad = 0;
};
Horizontal horizontalFromEnu(const glm::dvec3& enu);
glm::dvec3 enuFromHorizontal(double azimuthRad, double altitudeRad);

/// Atmospheric refraction R (rad, >= 0) to add to a geometric (airless) altitude, for surface
/// pressure (hPa) and temperature (deg C). Above 25 deg: Green's A tan z + B tan^3 z with the
/// constants of ERFA's eraRefco (dry air, 0.55 um), agreeing with ERFA to < 0.1"; below 15 deg:
/// Saemundsson's formula scaled by (P / 1010) (283 / (273 + T)); blended smoothly between. Below
/// the horizon the argument is clamped so that R stays finite and monotonic: R(h) for h < -1 deg
/// decays smoothly to 0 at -5 deg and stays 0 below (no blow-up). Zero when pressure is 0.
/// Finite for every finite input.
double refraction(double geometricAltitudeRad, double pressureHpa, double temperatureC);
/// Inverse: the geometric altitude whose refracted altitude is `apparentAltitudeRad`
/// (refraction(h) + h = apparent). Accurate to 1e-10 rad where the map is invertible.
double geometricFromApparentAltitude(double apparentAltitudeRad, double pressureHpa, double temperatureC);
/// Refracted (apparent) altitude of a geometric altitude: h + refraction(h, P, T).
double apparentFromGeometricAltitude(double geometricAltitudeRad, double pressureHpa, double temperatureC);

/// A source as seen by the observer.
struct Topocentric {
    double azimuthRad = 0;            ///< from north through east, [0, 2 pi)
    double altitudeRad = 0;           ///< refracted (apparent) altitude (= geometric if P = 0)
    double altitudeGeometricRad = 0;  ///< airless altitude
    double distanceMeters = 0;        ///< topocentric distance, m (0 for sources at infinity)
    glm::dvec3 enu{0, 0, 1};          ///< unit vector to the refracted position, ENU
    glm::dvec3 enuGeometric{0, 0, 1}; ///< unit vector to the airless position, ENU
    double raTopocentricRad = 0;      ///< topocentric apparent RA of date (airless), rad
    double decTopocentricRad = 0;     ///< topocentric apparent Dec of date (airless), rad
};
/// A body from its apparent GEOCENTRIC right ascension / declination of date (true equator and
/// equinox; already containing annual aberration and light time) and its geocentric distance in
/// metres: adds diurnal parallax (exact vector subtraction; distance <= 0 or infinite = no
/// parallax) and refraction. Diurnal aberration (< 0.32") is not added here.
Topocentric topocentric(const ObserverFrame& frame, double raRad, double decRad, double distanceMeters);
/// A fixed source given by its ICRS (astrometric, catalogue) direction: aberration for the
/// observer's velocity (annual + diurnal), light deflection by the Sun (Precise path only),
/// precession-nutation, Earth rotation, site, refraction. This is the CPU reference of what
/// starMatrix + the star shader do (see stars.hpp).
Topocentric topocentricFromIcrs(const ObserverFrame& frame, const glm::dvec3& icrsDirection);

}  // namespace welkin::astro
