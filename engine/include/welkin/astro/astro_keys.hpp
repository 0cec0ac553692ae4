// SkyVars keys written by the astronomy generator, and the generator that writes them.
//
//   welkin::SkyVars vars = welkin::SkyVars::earth();
//   vars.set(welkin::astro::keys::precise, true);          // ERFA + full VSOP87 instead of series
//   welkin::astro::updateSkyVars(vars);                    // reads time.* and observer.* keys
//   glm::dvec3 sun = vars.get(welkin::keys::sunDirection); // ENU unit vector, refracted
//   double k = vars.get(welkin::astro::keys::moonIlluminatedFraction);
//   glm::dmat3 m = vars.get(welkin::astro::keys::starFrameRotation);  // ICRS -> ENU, this instant
//
// SkyProcessor registers an AstronomyGenerator (unless ProcessorOptions::astronomy is false): a
// processor-level generator that runs whenever the time or the observer changed, before every
// generator that reads what it writes. Directions are unit vectors in the world ENU frame
// (x east, y north, z up) towards the refracted (apparent) topocentric place.
#pragma once
#include <welkin/astro/bodies.hpp>
#include <welkin/element.hpp>
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
/// Solar and lunar eclipses on (default true). false: sun.eclipse_fraction and moon.eclipse_factor
/// stay 1 and the sky ignores the Moon's shadow (the same instant without the eclipse, to compare).
inline const Key<bool> eclipses{"astro.eclipses", "solar and lunar eclipses on (false: the same sky without them)"};

// --- Sun -------------------------------------------------------------------------------------
inline const Key<double> sunDistance{"sun.distance_m", Range{1.4e11, 1.6e11}, "observer-Sun distance, m"};
inline const Key<double> sunAngularRadius{"sun.angular_radius_rad", Range{0, 0.01}, "apparent angular radius of the Sun, rad"};
inline const Key<double> sunAzimuth{"sun.azimuth_rad", Range{0, 2 * welkin::keys::kPi}, "Sun azimuth from north through east, rad"};
inline const Key<double> sunAltitude{"sun.altitude_rad", Range{-welkin::keys::kPi / 2, welkin::keys::kPi / 2}, "Sun refracted altitude, rad"};

// --- Moon ------------------------------------------------------------------------------------
inline const Key<double> moonDistance{"moon.distance_m", Range{1e7, 1e9}, "observer-Moon distance, m (3.5e8 .. 4.1e8 on the ground)"};
/// The Moon's centre relative to the observer, ENU metres, in the apparent Sun's frame: the airless
/// position turned by the rotation that takes the Sun's airless direction to sun.direction, so the
/// Sun-Moon geometry (the shadow on the atmosphere, docs/eclipse.md) is the airless one.
inline const Key<glm::dvec3> moonPosition{"moon.position_m", Range{-1e9, 1e9}, "Moon's centre from the observer, ENU m (frame of the apparent Sun: refraction turns both alike)", "m"};
/// The Moon's mean radius, m (IAU).
inline constexpr double kMoonRadiusMeters = 1737400.0;
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
/// The part of moon.eclipse_factor (welkin::keys::moonEclipseFactor: the fraction of sunlight,
/// by luminance, reaching the Moon's disk, direct + refracted) that is the atmosphere's reddened
/// light refracted into the umbra (colour astro::umbraColour(), welkin/astro/eclipses.hpp),
/// [0, 1]; 0 outside the umbra. Written by the astronomy (astro::moonShadowLight()), read by
/// atmosphere.lights.
inline const Key<double> moonEclipseRefracted{"moon.eclipse_refracted", Range{0, 1}, "part of moon.eclipse_factor refracted into the umbra by the Earth's air (reddened)"};

// --- Star frame (for the Stars element: one rotation per frame on the GPU) ----------------------
/// Rotation ICRS (J2000 axes) -> observer ENU at this instant (bias-precession-nutation, Earth
/// rotation, site): v_enu = M * v_icrs. Refraction is not included.
inline const Key<glm::dmat3> starFrameRotation{"stars.frame_icrs_to_enu", Range{-1, 1}, "rotation ICRS (J2000) -> observer ENU"};
/// Observer's velocity / c in ICRS axes (annual + diurnal aberration): p_apparent = normalize(p + v).
inline const Key<glm::dvec3> starFrameAberration{"stars.frame_aberration", Range{-1e-3, 1e-3}, "observer velocity / c, ICRS axes"};
/// Epoch of the frame: Julian years of TT since J2000.0 (proper motion: p0 + years * pm).
inline const Key<double> starFrameEpochYears{"stars.frame_epoch_years", Range{-1e4, 1e4}, "epoch, Julian years of TT since J2000.0", "a"};

// --- Planets (Mercury .. Neptune) ----------------------------------------------------------------
/// Key for a planet's ENU unit vector ("planet.mars.direction") or magnitude ("planet.mars.magnitude").
const Key<glm::dvec3>& planetDirection(Body planet);
const Key<double>& planetMagnitude(Body planet);
const Key<double>& planetAngularDiameter(Body planet);  // "planet.<name>.angular_diameter_rad"

}  // namespace welkin::astro::keys

namespace welkin::astro {

/// Fraction of a limb-darkened disk's flux left visible when another disk covers part of it
/// (small-angle, flat geometry): the source of angular radius `sourceRadiusRad`, the occulting
/// disk of `occulterRadiusRad`, their centres `separationRad` apart. Limb darkening
/// I(mu) = I(1) (1 - u (1 - mu)) with u = `limbDarkening` (the Sun in the visible: 0.6). [0, 1].
/// The rings of the source the occulter's limb does not cut are integrated in closed form, the
/// band it cuts with `bandNodes` (>= 1) cosine-spaced rings (analytic arc per ring): 128 keep the
/// fraction within 1e-4 of itself, thin crescents near the contacts included; the sky's GPU pass
/// and its CPU twin (generators::cpu::eclipseFraction) use 24.
double eclipseVisibleFraction(double sourceRadiusRad, double occulterRadiusRad, double separationRad, double limbDarkening = 0.6,
                              int bandNodes = 128);

/// Computes every body for the time (keys::timeJdUtc) and observer (observer.*) in `vars`, on the
/// path chosen by astro.precise, and writes welkin::keys::sunDirection / moonDirection and the keys
/// above, and the eclipses: sun.eclipse_fraction (the Sun's flux not hidden by the Moon, from their
/// topocentric airless directions and radii) and moon.eclipse_factor / moon.eclipse_refracted
/// (the sunlight reaching the Moon's disk past the Earth's shadow: astro::moonShadowLight). Declares astro.precise (false) and the refraction keys (1013.25 hPa, 10 C) if absent.
///
/// `ephemeris`: an Ephemeris kept across calls (the generator's), so that its VSOP87 reuse
/// (Ephemeris::kVsopReuseDays) applies from frame to frame; null: a fresh one.
void updateSkyVars(SkyVars& vars, Ephemeris* ephemeris = nullptr);

/// updateSkyVars() as a generator ("astronomy"): inputs time.jd_utc, observer.*, astro.*;
/// outputs the Sun, Moon, planets and the star frame. Its stats: Sun and Moon az/alt, the Moon's
/// phase and illuminated fraction.
class AstronomyGenerator final : public Generator {
public:
    AstronomyGenerator();

private:
    void doRun(SkyVars& vars, const Logger& log) override;
    void doDeclare(SkyVars& vars) override;
    void doStats(nlohmann::json& root) const override;
    double sunEclipse_ = 1, moonEclipse_ = 1;
    double sunAz_ = 0, sunAlt_ = 0, moonAz_ = 0, moonAlt_ = 0, moonPhase_ = 0, moonFraction_ = 0;
    bool precise_ = false;
    bool ran_ = false;
    Ephemeris ephemeris_;  // kept across runs: the planets' series are summed once per 5 simulated minutes
};

}  // namespace welkin::astro
