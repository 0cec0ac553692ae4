// Planet: the Sun's disk, the Moon and the planets at their apparent places, from the astronomy
// keys and the shared lights, in every projection.
//
//   processor.add(welkin::elements::makeElement("planet"));   // after the stars, before the Sky
//   processor.add(welkin::elements::makeElement("sky"));      // its transmittance reddens them once
//   processor.vars().set(welkin::elements::planetkeys::sizeFactor, 3.0);   // artistic, Moon + planets
//   // command line: welkin render --var planet.bodies=moon,jupiter --var planet.earthshine=false
//   // one body from C++ (element names are unique in a processor):
//   processor.add(std::make_unique<welkin::elements::Planet>(std::vector{welkin::astro::Body::Moon}, "moon"));
//
// Model (skyelements/planet/README.md has the sources, the tests and the cost):
//  - Each body is a screen quad around its apparent direction (welkin_clipFromDirection); the
//    fragment shader casts the pixel's view direction at the body's sphere, supersampling (4 x 4)
//    the pixels within 1.5 pixels of the limb, so the disk's integral is exact to a fraction of
//    a pixel whatever the projection. A disk under 2 pixels across (the Sun, the Moon; 3 for the
//    planets) is drawn instead as the Stars' Gaussian PSF (FWHM 2 px)
//    whose integral is the body's illuminance, so the flux is right resolved or not.
//    With render.point_sources = perceptual an unresolved planet is culled or drawn as the eye
//    sees it over the sky behind it (welkin/point_source.hpp), its peak under its disk's mean.
//  - Sun: mean radiance lights.sun_disk_radiance (unreddened, cd/m^2) with the limb darkening
//    I(mu)/I(1) = mu^a(lambda), a = -0.023 + 0.292 / lambda[um] (Hestroffer & Magnan 1998, A&A
//    333, 338: a fit to the measured centre-to-limb profiles of Pierce & Slaughter 1977 and
//    Neckel & Labs 1994), per sRGB channel at 612 / 549 / 465 nm; I(1) = mean (a + 2) / 2.
//  - Moon: the albedo (moon_4k.jpg) and normal (moon_normals.png) maps of stellarium-data,
//    equirectangular, selenographic longitude 0 at the centre, east to the right, north up (the
//    normals in tangent space: R east, G south, B up);
//    oriented by the libration (the sub-Earth point (l, b)) and the axis' position angle P turned
//    into the local vertical by the parallactic angle q. Lit by the Sun seen from the Moon (from
//    the Sun's and Moon's directions and distances) with Hapke's 1966 Lommel-Seeliger law and
//    opposition surge (as in Jensen et al. 2001, "A physically-based night sky model", SIGGRAPH):
//    L ~ A B(g) S(g) cos i / (cos i + cos e), g = 0.6. Calibrated every frame by a CPU integral of
//    that model over the disk (moonDiskIntegral) so that the disk-integrated illuminance is
//    lights.moon_illuminance (the astronomy's moon.magnitude: one brightness law). Earthshine:
//    the Earth as a Lambert sphere of Bond albedo 0.30 (geometric 0.20; earthshine measurements,
//    Goode et al. 2001, Qiu et al. 2003) at its phase seen from the Moon (pi - the Moon's phase
//    angle), coloured (0.88, 0.96, 1.00) (Mueller et al. 2012). Lunar eclipse: per surface point
//    the fraction of the Sun's disk not hidden by the Earth, whose radius is enlarged for its
//    atmosphere by Danjon's 1.01, plus in the umbra a reddened refracted light of 1e-4 .. 2e-5 of
//    sunlight (Danjon L ~ 2): astro::earthShadowLight's model and constants
//    (welkin/astro/eclipses.hpp), which moon.eclipse_factor averages over the disk.
//  - Solar eclipse (planet.corona): the K+F corona (Baumbach's profile, coronaRelativeRadiance,
//    times the disk's mean radiance and the Sun's transmittance), additive, drawn before the Sun
//    while the Moon overlaps it, flattened towards the Sun's poles (taken as the ecliptic's) by
//    planet.corona_flattening; the dark Moon drawn over both. The diamond ring near C2/C3: the
//    uncovered sliver's glare at the limb point farthest from the Moon's centre. Baily's beads
//    (planet.limb_profile): the dark Moon's limb drawn with a limb profile (lunarLimbHeightMeters).
//  - Planets (Mercury .. Neptune): illuminance 2.54e-6 lx x 10^(-0.4 m) (planet.<name>.magnitude,
//    the Stars' convention), colour from B-V (Allen's Astrophysical Quantities, 4th ed., 12.3:
//    Mercury 0.93, Venus 0.82, Mars 1.36, Jupiter 0.83, Saturn 1.04, Uranus 0.56, Neptune 0.41)
//    through the Stars' black-body colour; a Lambert sphere lit from the Sun when resolved
//    (disk integral of the same illuminance; Saturn's rings are not drawn, their light is in the
//    disk).
//  - Extinction: left to a later element that attenuates (the Sky; FrameContext::attenuatedLater),
//    else lights.sun_transmittance / lights.moon_transmittance, and for a planet the atmosphere's
//    transmittance towards its altitude.
//  - Occlusion: disks are opaque (transmittance 1 - coverage; the Moon covers the stars and the
//    Sun); PSFs are transparent. Drawn Sun, planets, then the Moon.
#pragma once
#include <welkin/astro/bodies.hpp>
#include <welkin/astro/lunar_limb.hpp>
#include <welkin/element.hpp>
#include <welkin/gl/objects.hpp>
#include <welkin/gl/text.hpp>
#include <welkin/gl/projection_programs.hpp>

#include <glm/glm.hpp>

#include <array>

#include <optional>
#include <string>
#include <vector>

namespace welkin::elements {

namespace planetkeys {
inline const Key<std::string> bodies{"planet.bodies", "bodies drawn: a comma list of sun, moon, mercury .. neptune, or 'all' or 'none'"};
inline const Key<double> sizeFactor{"planet.size_factor", Range{0.1, 100}, "artistic enlargement of the Moon and the planets (1 = true size; the flux is kept: the surface brightness drops by its square)", "1"};
inline const Key<bool> earthshine{"planet.earthshine", "the Moon's night side is lit by the Earth"};
inline const Key<bool> eclipse{"planet.eclipse", "the Earth's shadow on the Moon (lunar eclipses)"};
inline const Key<std::string> moonTexture{"planet.moon_texture", "the Moon's albedo map: equirectangular, longitude 0 at the centre ('' = uniform grey)"};
/// Names beside the bodies drawn (an education overlay: the engine's text, welkin/gl/text.hpp).
inline const Key<bool> labels{"planet.labels", "names beside the bodies drawn"};
/// With planet.labels, the visual magnitude after the name ("Mars -2.2"): the astronomy's
/// `planet.NAME.magnitude`, moon.magnitude, the Sun's -26.74 + 5 log10(distance / au); one decimal.
inline const Key<bool> labelMagnitude{"planet.label_magnitude", "with planet.labels, the visual magnitude after each name (\"Mars -2.2\")"};
/// Label size, px (0: the image's shorter side / 64, at least 11 px).
inline const Key<double> labelSize{"planet.label_size_px", Range{0, 256}, "label em height, px (0: shorter image side / 64, >= 11)", "px"};
/// Label luminance, cd/m^2 (default 2e-3: ~10x a dark site's night sky, read at night, lost in a
/// day sky like ink on a chart; 0: 0.8 of the manual exposure's white, exposure.ev100).
inline const Key<double> labelLuminance{"planet.label_luminance_cd_m2", Range{0, 1e9}, "label luminance (0: 0.8 of the manual exposure's white)", "cd/m^2"};
inline const Key<std::string> moonNormals{"planet.moon_normals", "the Moon's tangent-space normal map, same layout ('' = a smooth sphere)"};
/// The solar corona around the Sun while the Moon overlaps it (coronaRelativeRadiance()).
inline const Key<bool> corona{"planet.corona", "the solar corona and the diamond ring while the Moon covers the Sun (solar eclipses)"};
/// The lunar limb's mountains and valleys on the dark Moon during a solar eclipse (Baily's beads:
/// lunarLimbHeightMeters()).
inline const Key<bool> limbProfile{"planet.limb_profile", "the lunar limb's mountains and valleys on the dark Moon in a solar eclipse (Baily's beads)"};
/// The corona's flattening (its solar-cycle shape): an isophote's equatorial radius over its polar
/// one minus 1, Ludendorff's index a + b: ~0.3 at solar minimum, ~0.05 at maximum; 0 = round.
inline const Key<double> coronaFlattening{"planet.corona_flattening", Range{0, 0.5}, "the corona's flattening (Ludendorff a+b): ~0.3 at solar minimum, ~0.05 at maximum"};
}  // namespace planetkeys

inline constexpr const char* kMoonTexturePath = "/usr/share/stellarium/textures/moon_4k.jpg";
inline constexpr const char* kMoonNormalsPath = "/usr/share/stellarium/textures/moon_normals.png";

/// The K+F corona's radiance over the mean radiance of the solar disk at `rSolarRadii` (>= 1) from
/// the Sun's centre, in the solar equator's direction: out to 6 solar radii Baumbach's (1937) fit as
/// given in Allen's Astrophysical Quantities (4th ed., 14.5), 1e-6 (0.0532 r^-2.5 + 1.425 r^-7 +
/// 2.565 r^-17): 1.3e-6 at 1.1, 1.05e-7 at 1.5, 1.2e-8 at 2, 6.0e-10 at 6 solar radii; beyond, the
/// F corona's measured power law (Lamy et al. 2022: r^-2.33 along the equator, r^-2.55 towards the
/// poles) continuing it from its value at 6, faded to 0 between 20 and kCoronaExtentSolarRadii
/// (planet_corona.shared.glsl). Towards the poles r is stretched by 1 + flattening sin^2(position
/// angle from the equator) (planet.corona_flattening).
double coronaRelativeRadiance(double rSolarRadii, double flattening = 0.0, double sinFromEquator = 0.0);
/// Radius, in solar radii, out to which the corona is drawn (the profile reaches 0 there, faded
/// from 20 solar radii, where it is 3.7e-11 of the disk's radiance: below the totality sky near
/// the Sun, docs/eclipse.md "The corona's edge").
inline constexpr double kCoronaExtentSolarRadii = 30.0;
/// The diamond ring: while 0 < sun.eclipse_fraction < this, the last sliver of photosphere also
/// spreads kDiamondGlare of its light into a Gaussian glare of sigma = the Sun's radius (the eye's
/// or the lens' veiling glare: an assumed, not a measured, PSF).
inline constexpr double kDiamondRingFraction = 0.01;
inline constexpr double kDiamondGlare = 0.1;

/// The lunar limb's profile (the engine's astronomy: welkin/astro/lunar_limb.hpp, which the
/// contacts of findSolarEclipses() use too).
using astro::kLimbProfileRmsMeters;
using astro::kLimbProfileSamples;
using astro::lunarLimbHeightMeters;
using astro::lunarLimbProfileMeters;

/// Limb-darkening exponent a(lambda) of I(mu)/I(1) = mu^a (Hestroffer & Magnan 1998), lambda in
/// nm, [300, 2000].
double sunLimbExponent(double wavelengthNm);
/// The exponents of the sRGB channels (612, 549, 465 nm).
glm::dvec3 sunLimbExponents();
/// Hapke's (1966) opposition surge B(g) x phase function S(g) (Jensen et al. 2001), g the phase
/// angle in [0, pi] (rad), compaction 0.6.
double hapkePhase(double phaseRad);
/// Lambert sphere's integral phase function [sin a + (pi - a) cos a] / pi, a in [0, pi].
double lambertPhase(double phaseRad);
/// Earthshine: the Earth's illuminance on the Moon over the Sun's, for the Moon's phase angle
/// (rad) and the Earth-Moon distance (m): p (R_earth / d)^2 Phi_Lambert(pi - phase), p = 0.20.
double earthshineRatio(double moonPhaseRad, double earthMoonDistanceM);
/// Fraction of a disk of angular radius rs (the Sun) not hidden by a disk of radius re (the
/// Earth) at centre distance d (all rad, small angles), [0, 1].
double visibleSunFraction(double rs, double re, double d);

/// The Moon's orientation and lighting for one instant, from the keys (world ENU frame).
struct MoonGeometry {
    glm::dvec3 centre{0, 0, 1};   ///< unit direction to the Moon's centre
    glm::dmat3 axes{1.0};         ///< selenographic axes in ENU: lon 0 / lat 0, lon 90 E, north pole
    glm::dvec3 sunFromMoon{0, 0, 1};  ///< unit direction from the Moon to the Sun
    double phaseRad = 0;          ///< Sun-Moon-observer angle
    double angularRadius = 0;     ///< apparent, as drawn (size factor applied), rad
    double earthMoonDistanceM = 3.844e8;
};
MoonGeometry moonGeometry(const SkyVars& vars, double sizeFactor = 1.0);
/// Position angle (from the zenith direction towards the left on the sky, i.e. east of an
/// upright view, rad) of a unit `dir` seen around the unit `centre` in the local vertical frame.
double verticalPositionAngle(const glm::dvec3& centre, const glm::dvec3& dir);

/// An albedo and normal map as the CPU integral samples them (equirect, longitude 0 at the
/// centre): albedo in [0, 1], normals as the map's tangent-space (east, south, up) vectors.
/// Empty = uniform.
struct MoonMaps {
    int width = 0, height = 0;
    std::vector<float> albedo;      ///< width x height, top row north
    std::vector<glm::vec3> normal;  ///< width x height (empty: smooth)
    double albedoAt(double lonRad, double latRad) const;
    glm::dvec3 normalAt(double lonRad, double latRad) const;
};
/// Integral over the Moon's disk of A B(g) cos i / (cos i + cos e) dOmega (sr; the model the
/// shader draws, without eclipse and earthshine) on an n x n grid over the disk.
double moonDiskIntegral(const MoonGeometry& g, const MoonMaps& maps, int n = 128);

class Planet final : public SkyElement {
public:
    /// The bodies named by planet.bodies.
    Planet();
    /// These bodies only (planet.bodies is then ignored), e.g. one instance per body, each with
    /// its own element name (a processor's element names are unique); the other options
    /// (planet.size_factor, ...) are shared keys.
    explicit Planet(std::vector<astro::Body> bodies, std::string name = "planet");

    /// Bodies drawn by the last frame (disk or PSF): those whose quads meet the image (a body
    /// off the image costs no GL call).
    int drawn() const { return drawn_; }
    /// The Moon's calibration of the last frame that drew it: radiance = scale x albedo x shading
    /// (cd/m^2).
    double moonScale() const { return moonScale_; }
    /// The maps as the calibration integral samples them (after init, if the Moon is drawn).
    const MoonMaps& moonMaps() const { return maps_; }

private:
    explicit Planet(std::string name);
    void doInit(InitContext& ctx) override;
    void doRender(const FrameContext& ctx) override;
    void doRelease() override;
    void doStats(nlohmann::json& root) const override;
    void doValidateOptions(const SkyVars& vars) const override;
    void loadMoonMaps(const std::string& albedoPath, const std::string& normalPath, const Logger& log);
    glm::dvec3 transmittanceTowards(const SkyVars& v, double altitudeRad) const;

    std::optional<std::vector<astro::Body>> own_;
    gl::ProjectionPrograms programs_;
    gl::Texture2D albedoTex_, normalTex_;
    int moonAlbedoUnit_ = 0, moonNormalUnit_ = 0;  // private texture units (SkyElement::textureUnit)
    MoonMaps maps_;
    std::string loadedAlbedo_, loadedNormals_;
    bool mapsLoaded_ = false;
    int drawn_ = 0;
    double moonScale_ = 0;
    double moonIlluminanceLux_ = 0;
    bool coronaDrawn_ = false, diamondRing_ = false;  // this frame (stats: sun.corona_drawn, sun.diamond_ring)
    bool moonDrawn_ = false;
    double integral_ = 0, integralKey_[7] = {};
    bool integralValid_ = false;
    gl::Font font_;  // loaded on the first frame with planet.labels
    gl::TextBatch labelBatch_;
    int labelsDrawn_ = 0;
};

}  // namespace welkin::elements
