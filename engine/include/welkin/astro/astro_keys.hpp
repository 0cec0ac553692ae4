// SkyVars keys written by the astronomy step each frame, and the function that writes them.
//
//   welkin::SkyVars vars = welkin::SkyVars::earth();
//   vars.set(welkin::astro::keys::precise, true);          // ERFA + full VSOP87 instead of series
//   welkin::astro::updateSkyVars(vars);                    // reads time.* and observer.* keys
//   glm::dvec3 sun = vars.get(welkin::keys::sunDirection); // ENU unit vector, refracted
//   double k = vars.get(welkin::astro::keys::moonIlluminatedFraction);
//
// SkyProcessor::deriveVariables() calls updateSkyVars() every frame. Directions are unit vectors in
// the world ENU frame (x east, y north, z up) towards the refracted (apparent) topocentric place.
#pragma once
#include <welkin/astro/bodies.hpp>
#include <welkin/keys.hpp>
#include <welkin/vars.hpp>

namespace welkin::astro::keys {

using welkin::Key;
using welkin::Range;

/// Which path computes positions: false = Fast series (default), true = Precise (ERFA, full VSOP87).
inline const Key<bool> precise{"astro.precise", "astronomy path: false fast series, true precise (ERFA, full VSOP87)"};
/// Surface pressure used for refraction, hPa, [0, 2000] (0 disables refraction).
inline const Key<double> refractionPressure{"astro.refraction_pressure_hpa", Range{0, 2000}, "pressure for refraction, hPa"};
/// Surface temperature used for refraction, deg C, [-100, 100].
inline const Key<double> refractionTemperature{"astro.refraction_temperature_c", Range{-100, 100}, "temperature for refraction, deg C"};

// --- Sun -------------------------------------------------------------------------------------
inline const Key<double> sunDistance{"sun.distance_m", Range{1.4e11, 1.6e11}, "observer-Sun distance, m"};
inline const Key<double> sunAngularRadius{"sun.angular_radius_rad", Range{0, 0.01}, "apparent angular radius of the Sun, rad"};
inline const Key<double> sunAzimuth{"sun.azimuth_rad", Range{0, 2 * welkin::keys::kPi}, "Sun azimuth from north through east, rad"};
inline const Key<double> sunAltitude{"sun.altitude_rad", Range{-welkin::keys::kPi / 2, welkin::keys::kPi / 2}, "Sun refracted altitude, rad"};

// --- Moon ------------------------------------------------------------------------------------
inline const Key<double> moonDistance{"moon.distance_m", Range{1e7, 1e9}, "observer-Moon distance, m (3.5e8 .. 4.1e8 on the ground)"};
inline const Key<double> moonAngularRadius{"moon.angular_radius_rad", Range{0, 0.2}, "apparent angular radius of the Moon, rad"};
inline const Key<double> moonAzimuth{"moon.azimuth_rad", Range{0, 2 * welkin::keys::kPi}, "Moon azimuth from north through east, rad"};
inline const Key<double> moonAltitude{"moon.altitude_rad", Range{-welkin::keys::kPi / 2, welkin::keys::kPi / 2}, "Moon refracted altitude, rad"};
inline const Key<double> moonPhaseAngle{"moon.phase_angle_rad", Range{0, welkin::keys::kPi}, "Sun-Moon-Earth angle, rad (0 full)"};
inline const Key<double> moonIlluminatedFraction{"moon.illuminated_fraction", Range{0, 1}, "illuminated fraction of the disc"};
inline const Key<double> moonBrightLimbAngle{"moon.bright_limb_angle_rad", Range{0, 2 * welkin::keys::kPi}, "position angle of the bright limb, from north through east, rad"};
inline const Key<double> moonLibrationLon{"moon.libration_lon_rad", Range{-0.2, 0.2}, "libration in longitude, rad"};
inline const Key<double> moonLibrationLat{"moon.libration_lat_rad", Range{-0.2, 0.2}, "libration in latitude, rad"};
inline const Key<double> moonAxisAngle{"moon.axis_angle_rad", Range{-welkin::keys::kPi, welkin::keys::kPi}, "position angle of the Moon's north pole, from north through east, rad"};
inline const Key<double> moonMagnitude{"moon.magnitude", Range{-14, 0}, "visual magnitude of the Moon"};
/// Parallactic angle q at the Moon: rotates the equatorial position angles above into the local
/// vertical frame (angle from the zenith direction towards east = position angle - q).
inline const Key<double> moonParallacticAngle{"moon.parallactic_angle_rad", Range{-welkin::keys::kPi, welkin::keys::kPi}, "parallactic angle at the Moon, rad"};

// --- Planets (Mercury .. Neptune) ----------------------------------------------------------------
/// Key for a planet's ENU unit vector ("planet.mars.direction") or magnitude ("planet.mars.magnitude").
const Key<glm::dvec3>& planetDirection(Body planet);
const Key<double>& planetMagnitude(Body planet);
const Key<double>& planetAngularDiameter(Body planet);  // "planet.<name>.angular_diameter_rad"

}  // namespace welkin::astro::keys

namespace welkin::astro {

/// Computes every body for the time (keys::timeJdUtc) and observer (observer.*) in `vars`, on the
/// path chosen by astro.precise, and writes welkin::keys::sunDirection / moonDirection and the keys
/// above. Declares astro.precise (false) and the refraction keys (1013.25 hPa, 10 C) if absent.
void updateSkyVars(SkyVars& vars);

}  // namespace welkin::astro
