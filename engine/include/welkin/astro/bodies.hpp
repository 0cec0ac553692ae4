// The Sun, the Moon and the planets Mercury .. Neptune as seen by an observer: apparent places,
// horizontal coordinates, distances, sizes, brightness, phase, and the Moon's orientation.
//
//   using namespace welkin::astro;
//   TimeScales ts = timeScales(UtcInstant::parse("2026-06-21T21:00:00Z"));
//   ObserverFrame f = observerFrame(Site{glm::radians(52.5), glm::radians(13.4), 34.0}, ts, Path::Fast);
//   BodyState moon = computeBody(Body::Moon, f);       // moon.topo.altitudeRad, moon.magnitude, ...
//   Ephemeris eph;                                      // every frame: all nine bodies at once,
//   eph.update(f);                                      // allocation-free on the Fast path
//   double sunAlt = eph[Body::Sun].topo.altitudeRad;
//
// Paths (chosen by the ObserverFrame's path, i.e. the SkyVars key astro.precise):
// - Fast: Earth and planets from VSOP87B truncated in code (vsop87.hpp), the Moon from Meeus
//   ch. 47 (elp.hpp), light time from the planet's velocity, annual aberration, IAU 2006 /
//   2000B precession-nutation (earth.hpp). Measured against Precise in docs/astronomy-bodies.md.
// - Precise: the Sun from ERFA eraEpv00 (1900-2100; the full VSOP87 Earth outside that span,
//   where eraEpv00's fit degrades), the Moon from eraMoon98, the planets from the full VSOP87B
//   series of kstars-data with light time iterated to convergence, relativistic aberration (eraAb),
//   IAU 2006/2000A precession-nutation.
// Both: apparent geocentric place -> diurnal parallax -> refraction (frames.hpp). Light deflection
// by the Sun (< 0.02" except within a few degrees of it) and diurnal aberration (< 0.32") are not
// applied to bodies.
//
// Validity: dates in years [-2000, +6000] (the span VSOP87 is published for); outside it
// computeBody throws welkin::Error. Accuracy degrades away from 1900-2100 (measured numbers in
// docs/astronomy-bodies.md). All angles are radians, distances metres.
#pragma once
#include <welkin/astro/frames.hpp>

#include <array>
#include <string>
#include <string_view>

namespace welkin::astro {

enum class Body { Sun, Moon, Mercury, Venus, Mars, Jupiter, Saturn, Uranus, Neptune };
inline constexpr int kBodyCount = 9;
inline constexpr std::array<Body, kBodyCount> kAllBodies = {Body::Sun,     Body::Moon,   Body::Mercury,
                                                            Body::Venus,   Body::Mars,   Body::Jupiter,
                                                            Body::Saturn,  Body::Uranus, Body::Neptune};

/// Lower-case name: "sun", "moon", "mercury", ...
const char* bodyName(Body b);
/// Inverse of bodyName (case-insensitive); throws welkin::Error listing the accepted names.
Body parseBody(std::string_view name);

/// Mean radius used for the apparent diameter, metres (equatorial for the planets: IAU 2015).
double bodyRadiusMeters(Body b);

/// Everything about one body at one instant for one observer.
struct BodyState {
    Body body = Body::Sun;
    double raRad = 0;                 ///< apparent geocentric right ascension, true equinox of date, [0, 2 pi)
    double decRad = 0;                ///< apparent geocentric declination, true equator of date
    double distanceMeters = 0;        ///< geocentric distance (of the light-time corrected position), m
    double heliocentricDistanceAu = 0;  ///< Sun-body distance, au (0 for the Sun)
    Topocentric topo;                 ///< azimuth, altitude (refracted and geometric), topocentric distance, ENU
    double angularDiameterRad = 0;    ///< apparent (topocentric) angular diameter, rad
    double magnitude = 0;             ///< visual magnitude V
    double phaseAngleRad = 0;         ///< Sun-body-Earth angle, [0, pi] (0 for the Sun)
    double illuminatedFraction = 1;   ///< (1 + cos phase) / 2, [0, 1]
    double brightLimbAngleRad = 0;    ///< position angle of the bright limb's midpoint, from north through east, [0, 2 pi)
    // Moon only (zero for other bodies): optical libration (Meeus ch. 53, with the physical
    // libration terms) and the position angle of the Moon's rotation axis.
    double librationLonRad = 0;       ///< libration in longitude l, rad
    double librationLatRad = 0;       ///< libration in latitude b, rad
    double axisAngleRad = 0;          ///< position angle P of the axis (north pole), from north through east, rad
    glm::dvec3 directionIcrs{0, 0, 1};  ///< apparent geocentric direction, unit vector, ICRS (GCRS) axes
};

/// One body (computes the Sun too where the body's phase needs it). Throws welkin::Error outside
/// years [-2000, 6000] or if the Precise path's VSOP87 files are missing.
BodyState computeBody(Body body, const ObserverFrame& frame);

/// Per-frame evaluation of all nine bodies, sharing the Earth's and the Sun's position.
class Ephemeris {
public:
    /// Recomputes every body for `frame` (no allocation on the Fast path).
    void update(const ObserverFrame& frame);
    const BodyState& operator[](Body b) const { return states_[static_cast<int>(b)]; }
    const std::array<BodyState, kBodyCount>& states() const { return states_; }

    /// TT span (days) within which update() on the Fast path extrapolates a planet's (and the
    /// Earth's) VSOP87 coordinates and the Moon's series linearly from their last two full
    /// evaluations (their secant, both within the span): 5 minutes, an error below 0.015" for the
    /// planets and 0.05" for the Moon (tested against full evaluations in [astro]), far below the
    /// truncated series' own (about 1" and 10"). With time running, the series are summed twice
    /// per 5 minutes of simulated time instead of every frame; an update far from the last one
    /// (time jumped, or scattered instants) costs one full evaluation as before.
    static constexpr double kVsopReuseDays = 300.0 / 86400.0;
    /// (Internal) the last full VSOP87 evaluation of one VsopPlanet.
    /// Fields L, B (rad), R (au); t in TT Julian millennia from J2000.
    struct VsopCache : SecantCache<3> {
        glm::dvec3 lightRate{0.0};  ///< evaluate()'s rates at the last full evaluation (light time)
    };

    /// (Internal) the last full evaluation of the Moon's series (moonMeeus) and its slope.
    /// MoonEcliptic's fields in order (the angles among them reduced to [0, 2 pi)); t in TT
    /// Julian centuries from J2000.
    struct MoonCache : SecantCache<9> {
        MoonCache() { angle = {true, false, false, true, true, true, true, true, false}; }
    };

    /// The Earth orientation's series reuse (observerFrame(..., &earthSeries())), kept with the
    /// bodies' so that one Ephemeris carries all of the astronomy's frame-to-frame reuse.
    EarthSeriesCache& earthSeries() { return earth_; }

private:
    std::array<BodyState, kBodyCount> states_{};
    EarthSeriesCache earth_{};
    std::array<VsopCache, 8> vsop_{};  ///< per VsopPlanet, Mercury .. Neptune (Earth included)
    MoonCache moon_{};
};

/// Years accepted by the ephemerides (inclusive), as decimal years.
inline constexpr double kEphemerisFirstYear = -2000.0;
inline constexpr double kEphemerisLastYear = 6000.0;

/// Visual magnitude models (exposed for tests). Distances in au, phase angle in degrees.
namespace magnitude {
/// Mallama & Hilton (2018) for the planets; `subLatitudeDeg` is the Saturnicentric latitude of
/// Earth and Sun combined as in the paper (Saturn's rings), or the planetographic sub-latitude
/// (Uranus); `year` for Neptune's secular brightening. Outside a formula's phase-angle range the
/// nearest valid formula is used (never NaN).
double planet(Body b, double r, double delta, double phaseDeg, double subLatitudeDeg = 0.0, double year = 2000.0);
/// The Moon: V = 0.21 + 5 log10(r delta) + 0.026 |phase| + 4e-9 phase^4 (r, delta in au), the
/// classical lunar phase law (Allen), V = -12.74 at full Moon at mean distance.
double moon(double r, double delta, double phaseDeg);
/// The Sun: -26.74 + 5 log10(delta).
double sun(double delta);
/// Illuminance outside the atmosphere of a source of visual magnitude `m`, lux:
/// 2.54e-6 x 10^(-0.4 m) (the V = 0 zero point: 10^(-0.4 x 13.99) lux; Allen, 4th ed., 15.1).
double illuminanceLux(double m);
/// Luminance of a surface brightness `magPerArcsec2` (V mag/arcsec^2, finite), cd/m^2: the
/// illuminance of that magnitude per arcsec^2 (2.3504e-11 sr); 22.0 gives 1.71e-4 cd/m^2.
double surfaceBrightnessCdM2(double magPerArcsec2);
/// Its inverse: V mag/arcsec^2 of a luminance `cdM2` (> 0).
double surfaceBrightnessMag(double cdM2);
/// The natural night sky's zenith at a dark site, V mag/arcsec^2 (airglow, zodiacal light and
/// starlight together; Leinert et al. 1998): the Stars' default background floor and Bortle
/// class 1 of the night sky.
inline constexpr double kDarkSkyZenithMag = 22.0;
}  // namespace magnitude

}  // namespace welkin::astro
