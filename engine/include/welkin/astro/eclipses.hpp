// Solar and lunar eclipses: the local circumstances of solar eclipses for an observer (contacts,
// maximum, magnitude, obscuration), lunar eclipses with their contacts and magnitudes, and the
// Earth's shadow model that the Moon's light in a lunar eclipse follows (one source of truth for
// moon.eclipse_factor, lights.moon_illuminance and the Planet element's per-pixel shadow).
//
//   using namespace welkin::astro;
//   Site burgos{glm::radians(42.34), glm::radians(-3.70), 860.0};
//   auto from = UtcInstant::parse("2026-08-01T00:00:00Z"), to = UtcInstant::parse("2026-09-01T00:00:00Z");
//   for (const SolarEclipseLocal& e : findSolarEclipses(burgos, from, to, Path::Fast))
//       std::cout << toString(e.type) << " max " << e.maximum.time.toIso() << " mag " << e.magnitude;
//   for (const LunarEclipse& e : findLunarEclipses(burgos, from, to, Path::Fast)) ...
//
// Conventions (as in Espenak & Meeus, Five Millennium Canon of Solar / Lunar Eclipses, NASA
// TP-2006-214141 and TP-2009-214172):
// - Solar: topocentric airless directions of the Sun and the Moon; the Moon's radius k = 0.2725076
//   Earth equatorial radii for the first and last contacts (C1, C4) and k = 0.272281 for the inner
//   contacts (C2, C3), the magnitude and the obscuration. Magnitude = fraction of the Sun's
//   diameter covered at maximum; obscuration = fraction of its area covered.
// - Lunar: geocentric; the Earth's shadow enlarged by its atmosphere with Danjon's rule (the
//   Moon's parallax x 1.01 = 1 + 1/85 - 1/594): umbra radius 1.01 pi_M - s_S + pi_S, penumbra
//   1.01 pi_M + s_S + pi_S (this enlarges the umbra by about 1.7 %).
// Times: found by sampling every 4 min (solar) / 6 min (lunar) and refining (golden section for
// the maximum, bisection to 0.05 s for the contacts); their accuracy is that of the ephemeris (the
// Fast path's Moon, Meeus ch. 47, ~10" -> ~20 s on a contact).
#pragma once
#include <welkin/astro/bodies.hpp>
#include <welkin/time.hpp>

#include <optional>
#include <vector>

namespace welkin::astro {

/// One contact: its instant and the body's (Sun for solar, Moon for lunar eclipses) geometric
/// (airless) topocentric altitude then, radians.
struct EclipseContact {
    UtcInstant time;
    double altitudeRad = 0;
};

enum class SolarEclipseType { Partial, Annular, Total };
const char* toString(SolarEclipseType t);  // "partial", "annular", "total"

/// A solar eclipse as seen from one place.
struct SolarEclipseLocal {
    SolarEclipseType type = SolarEclipseType::Partial;
    EclipseContact c1, maximum, c4;        ///< first contact, maximum (least separation), last contact
    std::optional<EclipseContact> c2, c3;  ///< second/third contact (annular or total only)
    double magnitude = 0;                  ///< fraction of the Sun's diameter covered at maximum (> 1: total)
    double obscuration = 0;                ///< fraction of the Sun's disk area covered at maximum, [0, 1]
    double durationSeconds = 0;            ///< C3 - C2 (0 for a partial eclipse)
    double moonSunRatio = 0;               ///< apparent radius ratio Moon/Sun at maximum
    bool visible = false;                  ///< the Sun's upper limb is above the horizon at some time between C1 and C4
    /// C2 and C3 with the lunar limb's profile (welkin/astro/lunar_limb.hpp) on the Moon's mean
    /// radius: the instants the last Baily's bead vanishes and the first one appears (total), or
    /// the profiled limb wholly enters and starts to leave the Sun's disk (annular); to 0.05 s.
    /// Absent where the profile never covers the Sun (or never fits inside it).
    std::optional<EclipseContact> c2Limb, c3Limb;
    /// Unrounded differences (the EclipseContact times are printed to the second):
    double c2LimbShiftSeconds = 0;  ///< c2Limb - C2 of a smooth limb at the mean radius, s
    double c3LimbShiftSeconds = 0;  ///< c3Limb - C3 of a smooth limb at the mean radius, s
    double c2MeanShiftSeconds = 0;  ///< C2 of a smooth limb at the mean radius - c2 (the Canon's k), s
    double c3MeanShiftSeconds = 0;  ///< C3 of a smooth limb at the mean radius - c3, s
};

enum class LunarEclipseType { Penumbral, Partial, Total };
const char* toString(LunarEclipseType t);  // "penumbral", "partial", "total"

/// A lunar eclipse (geocentric circumstances) with the Moon's altitude at the site.
struct LunarEclipse {
    LunarEclipseType type = LunarEclipseType::Penumbral;
    EclipseContact p1, greatest, p4;           ///< penumbral contacts and greatest eclipse
    std::optional<EclipseContact> u1, u4;      ///< umbral (partial) contacts
    std::optional<EclipseContact> u2, u3;      ///< totality
    double umbralMagnitude = 0;                ///< fraction of the Moon's diameter in the umbra at greatest (< 0: none)
    double penumbralMagnitude = 0;             ///< same for the penumbra
    bool visible = false;                      ///< the Moon's upper limb is above the horizon at some time between P1 and P4
};

/// Solar eclipses with maximum in [from, to] seen from `site` (also those below the horizon;
/// see `visible`). Window at most 20 years. Throws welkin::Error for a bad site or window.
std::vector<SolarEclipseLocal> findSolarEclipses(const Site& site, const UtcInstant& from, const UtcInstant& to, Path path);
/// Lunar eclipses with greatest eclipse in [from, to]; `visible` and the altitudes for `site`.
std::vector<LunarEclipse> findLunarEclipses(const Site& site, const UtcInstant& from, const UtcInstant& to, Path path);

// --- The Earth's shadow and the Moon's light ------------------------------------------------------
/// Earth's equatorial radius, m (WGS84), and its enlargement for the shadow (Danjon: 1 + 1/85 - 1/594).
inline constexpr double kEarthEquatorialRadiusMeters = 6378137.0;
inline constexpr double kEarthShadowFactor = 1.01;
/// The Earth's radius as an occulter of the Sun in the shadow geometry, m.
inline constexpr double kEarthShadowRadiusMeters = kEarthShadowFactor * kEarthEquatorialRadiusMeters;
/// Sunlight refracted into the umbra by the Earth's atmosphere, as a fraction of the uneclipsed
/// sunlight's luminance: 1e-4 at the umbra's edge, 2e-5 at its centre, growing with depth^2
/// between them (a Danjon L ~ 2 eclipse: the totally eclipsed Moon 10 to 12 magnitudes below the
/// full Moon, the range usually quoted for dark-to-average eclipses).
inline constexpr double kUmbraRefractedCentre = 2e-5;
inline constexpr double kUmbraRefractedEdge = 1e-4;
/// Colour of that light, linear sRGB, luminance 1 (sunlight through ~40 air masses: red-orange).
glm::dvec3 umbraColour();
/// Fraction of the Sun's disk (uniform) left visible by a disk of radius `occulterRad` whose
/// centre is `separationRad` from the Sun's (radius `sunRad`): the lens formula, [0, 1]. The
/// Planet shader's planet_lensFraction() is the same formula.
double lensVisibleFraction(double sunRad, double occulterRad, double separationRad);

/// The sunlight reaching one point: `direct` = the Sun's visible fraction past the enlarged Earth,
/// `refracted` = the reddened light in the shadow (luminance fraction, colour umbraColour()).
struct ShadowLight {
    double direct = 1;
    double refracted = 0;
};
/// At a point `pointFromEarth` (metres, geocentric, any axes) with the Sun at `sunFromEarth`.
ShadowLight earthShadowLight(const glm::dvec3& pointFromEarth, const glm::dvec3& sunFromEarth);
/// Averaged over the Moon's disk as seen from the Earth (the Moon's centre at `moonFromEarth`,
/// radius bodyRadiusMeters(Moon)); uniform weights on a 12 x 12 grid inside the disk (the full
/// Moon has no limb darkening to speak of). 1 / 0 away from the shadow.
ShadowLight moonShadowLight(const glm::dvec3& moonFromEarth, const glm::dvec3& sunFromEarth);

}  // namespace welkin::astro
