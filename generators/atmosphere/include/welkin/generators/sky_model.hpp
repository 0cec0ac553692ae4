// The real-time sky model: the atmosphere as the GPU passes see it (SkyModel), the quality
// presets (SkyQuality), the LUT parameterisations and the double-precision CPU twins of every
// GPU pass (namespace welkin::generators::cpu). The GLSL twin of this file is
// generators/atmosphere/shaders/atmosphere.glsl: every function here has a GLSL function of the same name
// and the same math (float), so a GPU texel can be checked against its CPU twin. The optical
// functions and LUT parameterisations are one text for both, atmosphere.shared.glsl, which
// sky_model.cpp compiles as C++ (docs/architecture.md, "One source").
//
//   auto model = welkin::generators::SkyModel::fromVars(vars);        // or SkyModel::earthClear()
//   auto q = welkin::generators::SkyQuality::preset(1);              // medium
//   auto T = welkin::generators::cpu::transmittanceLut(model, q);    // 256x64, double
//   glm::dvec3 t = T.sample(welkin::generators::transmittanceUv(model, r, mu, q.transmittance));
//
// Geometry convention (Bruneton 2017): a point is described by its distance r to the planet's
// centre (metres) and a ray by mu = cos(view zenith angle); the Sun by mu_s = cos(solar zenith
// angle at the point) and nu = cos(angle between view ray and Sun). Heights h = r - bottomRadius
// are carried separately where precision matters (r^2 - R^2 is computed as h (2R + h)).
//
// Colour: "RGB" mode treats each linear-sRGB channel as one wavelength band. Scattering and
// absorption coefficients are per channel (1/m) and the light source's top-of-atmosphere
// illuminance is given per channel in lux with Y = 0.2126 R + 0.7152 G + 0.0722 B equal to its
// total illuminance, so every radiance comes out directly in cd/m^2 (linear sRGB).
#pragma once
#include <welkin/vars.hpp>

#include <glm/glm.hpp>

#include <array>
#include <functional>
#include <memory>
#include <vector>

namespace welkin::generators {

/// One layer of a density profile (Bruneton 2017): d(h) = expTerm exp(expScale h) +
/// linearTerm h + constantTerm, clamped to [0, 1]; h in metres above the ground.
struct DensityLayer {
    double width = 0.0;         ///< thickness of the layer, m (the top layer ignores it)
    double expTerm = 0.0;       ///< 1
    double expScale = 0.0;      ///< 1/m (e.g. -1/8000 for Rayleigh)
    double linearTerm = 0.0;    ///< 1/m
    double constantTerm = 0.0;  ///< 1
};

/// Two layers: layers[0] below layers[0].width, layers[1] above.
struct DensityProfile {
    std::array<DensityLayer, 2> layers{};
    double density(double h) const;
    /// exp(-h / scaleHeight) everywhere.
    static DensityProfile exponential(double scaleHeightM);
    /// A tent: 0 at centre -/+ halfWidth, 1 at centre (ozone).
    static DensityProfile tent(double centreM, double halfWidthM);
};

/// The atmosphere as the real-time passes see it. SI units.
struct SkyModel {
    double bottomRadius = 6360e3;  ///< ground sphere radius, m
    double topRadius = 6420e3;     ///< top of the atmosphere, m (> bottomRadius); as Atmosphere::earthClear()
    glm::dvec3 rayleighScattering{5.802e-6, 13.558e-6, 33.1e-6};  ///< 1/m at density 1
    DensityProfile rayleighDensity = DensityProfile::exponential(8000.0);
    glm::dvec3 mieScattering{3.996e-6};  ///< 1/m at density 1
    glm::dvec3 mieExtinction{4.440e-6};  ///< 1/m at density 1
    DensityProfile mieDensity = DensityProfile::exponential(1200.0);
    double mieG = 0.8;   ///< Mie asymmetry, (-1, 1)
    int miePhase = 1;    ///< 0 Henyey-Greenstein, 1 Cornette-Shanks
    glm::dvec3 absorptionExtinction{0.650e-6, 1.881e-6, 0.085e-6};  ///< ozone, 1/m at density 1
    DensityProfile absorptionDensity = DensityProfile::tent(25e3, 15e3);
    glm::dvec3 groundAlbedo{0.3};  ///< Lambertian, [0, 1]
    /// Sun's illuminance at the top of the atmosphere per linear-sRGB channel, lux (Y = total).
    glm::dvec3 solarIlluminance{1.32e5, 1.27e5, 1.24e5};
    double sunAngularRadius = 0.004675;  ///< rad

    /// Hillaire 2020 / Bruneton 2017 Earth parameters (used until an atmosphere is in SkyVars).
    static SkyModel earthClear() { return {}; }
    /// From the atmosphere description in SkyVars (generators/atmosphere.hpp) if present, else
    /// earthClear().
    static SkyModel fromVars(const SkyVars& vars);
    /// Throws welkin::Error naming the member and range.
    void validate() const;

    glm::dvec3 scatteringRayleigh(double h) const { return rayleighScattering * rayleighDensity.density(h); }
    glm::dvec3 scatteringMie(double h) const { return mieScattering * mieDensity.density(h); }
    glm::dvec3 extinction(double h) const;
};

/// Per-pass sizes and sample counts of one quality preset.
struct SkyQuality {
    int transmittanceW = 256, transmittanceH = 64;  ///< texels
    int transmittanceSteps = 64;                    ///< trapezoid samples along each ray
    int multiScatteringMuS = 64;                    ///< texels along mu_s (multiple-scattering LUTs)
    int multiScatteringSize = 16;                   ///< texels along the height
    int multiScatteringDirections = 64;             ///< sphere directions per texel
    int multiScatteringSteps = 20;                  ///< samples per direction
    /// Directional multiple scattering: the incident radiance field (single scattering with its
    /// phase functions plus Hillaire's isotropic higher orders) at each (h, mu_s) projected on
    /// spherical harmonics l <= shBands and convolved with the Rayleigh/Mie phase functions per
    /// view direction (exact second order up to the truncation). Off: Hillaire's isotropic
    /// approximation.
    bool directionalMs = true;
    /// SH bands L of the directional field, [cpu::kShMinBands, cpu::kShMaxBands] = [2, 6]: 15
    /// coefficients at L = 4 (low, medium), 28 at L = 6 (high, reference). Every view-ray sample
    /// reads that many texels; L = 6 holds the aerosols' forward-scattered second order better
    /// (measured in skyelements/sky/README.md).
    int shBands = 4;
    int shDirections = 128;                         ///< gathered directions per SH texel
    /// Second pass of the directional field (0 or 1; more acts as 1): the incident field is gathered again, its
    /// orders >= 2 now from the first pass's SH (directional) instead of Hillaire's isotropic
    /// Psi, which is left to orders >= 4 of a view ray. Costs one more SH pass, whose rays are
    /// marched like view rays (15 SH fetches per sample): hence its own, smaller, counts.
    int shIterations = 0;
    int shIterationDirections = 64;  ///< gathered directions per texel in the second pass
    int shIterationSteps = 12;       ///< samples per direction in the second pass
    int skyViewW = 192, skyViewH = 108;             ///< texels (azimuth x latitude)
    int skyViewSteps = 32;                          ///< samples per ray
    int aerialSize = 32;                            ///< texels per side of the volume
    int aerialSteps = 2;                            ///< samples per distance slice
    double aerialMaxDistance = 100e3;               ///< m, last slice
    int raymarchSteps = 48;                         ///< per-pixel ray march (space, reference)
    bool halfFloat = false;                         ///< fp16 LUTs (else fp32)
    /// The pixel shader reads one sky-view texture with the Mie phase function baked in at each
    /// texel's own angle to the light (one texture fetch and no phase per pixel), instead of two
    /// (smooth + Mie without phase, the phase evaluated at the pixel's exact angle: a sharper
    /// aureole). Measured cost and error in skyelements/sky/README.md.
    bool bakedMiePhase = true;
    bool perPixel = false;                          ///< ray-march every pixel (reference)
    int irradianceAzimuth = 32, irradianceZenith = 16;  ///< hemisphere quadrature
    /// While the light moves, the Sun- (Moon-) dependent tables are built at elevations on a grid
    /// (this step up to 4 deg of elevation, growing above to keyframeCoarseStepRad), each over
    /// `keyframeChunks` frames and kept, and the tables in between interpolated (Catmull-Rom in
    /// log radiance; light_keyframes.hpp; measured in skyelements/sky/README.md). rad.
    double keyframeStepRad = 0.0175;
    double keyframeCoarseStepRad = 0.0524;  ///< rad (3 deg)
    int keyframeChunks = 8;
    /// The first time the light moves, build every grid table from -20 deg up at once (a
    /// one-time cost: skyelements/sky/README.md "While time runs"), so time running then costs only the
    /// per-frame mix. The presets set it; off, the grid tables are built along the light's path.
    bool keyframePrefill = false;
    /// 0 low, 1 medium, 2 high, 3 reference. Throws welkin::Error outside [0, 3].
    static SkyQuality preset(int quality);
    /// A tiny preset for [gl] tests on llvmpipe.
    static SkyQuality tiny();
};

/// A 2-D table of RGB doubles sampled like a GL texture with GL_LINEAR and GL_CLAMP_TO_EDGE
/// (texel centres at (i + 0.5) / size). Rows bottom-up as GL stores them.
struct Lut2D {
    int width = 0, height = 0;
    std::vector<glm::dvec3> texels;
    glm::dvec3& at(int x, int y) { return texels[size_t(y) * width + x]; }
    const glm::dvec3& at(int x, int y) const { return texels[size_t(y) * width + x]; }
    glm::dvec3 sample(glm::dvec2 uv) const;
};

// --- Parameterisations (identical in atmosphere.glsl) ------------------------------------------
/// Texture coordinate of x in [0, 1] so that 0 and 1 fall on the first and last texel centres.
double texCoordFromUnit(double x, int size);
double unitFromTexCoord(double u, int size);

/// Transmittance LUT: (r, mu) <-> uv (Bruneton 2017, dense near the horizon).
glm::dvec2 transmittanceUv(const SkyModel& m, double h, double mu, int w, int hgt);
/// Inverse: returns (h, mu).
glm::dvec2 transmittanceHMu(const SkyModel& m, glm::dvec2 uv, int w, int hgt);
/// Multiple-scattering LUT: (h, mu_s) <-> uv.
glm::dvec2 multiScatteringUv(const SkyModel& m, double h, double muS, int w, int hgt);
glm::dvec2 multiScatteringHMuS(const SkyModel& m, glm::dvec2 uv, int w, int hgt);
/// Sky-view LUT at height h: (cos view zenith mu, azimuth from the light in [0, pi]) <-> uv.
/// Latitude is dense at the horizon (square-root law in sin(theta/2) on each side of the
/// horizon, whose texel rows never mix: the upper half is sampled with v clamped to its own
/// rows); azimuth u = sin(azimuth / 2). Both need only square roots per pixel (no acos, atan).
glm::dvec2 skyViewUv(const SkyModel& m, double h, double mu, double azimuth, int w, int hgt);
/// The same from the cosine of the azimuth (what a pixel shader has: no atan).
glm::dvec2 skyViewUvCos(const SkyModel& m, double h, double mu, double cosAzimuth, int w, int hgt);
/// sin(theta_H / 2), theta_H the zenith angle of the observer's horizon at height h.
double skyViewHorizonS(const SkyModel& m, double h);
/// Inverse: returns (mu, azimuth).
glm::dvec2 skyViewMuAz(const SkyModel& m, double h, glm::dvec2 uv, int w, int hgt);

// --- Phase functions ----------------------------------------------------------------------------
double rayleighPhase(double nu);
/// Henyey-Greenstein (kind 0) or Cornette-Shanks (kind 1), normalised over the sphere.
double miePhase(double nu, double g, int kind);

namespace cpu {
// --- Geometry (stable for rays grazing the ground) -----------------------------------------------
double distanceToTop(const SkyModel& m, double h, double mu);
double distanceToBottom(const SkyModel& m, double h, double mu);
bool rayIntersectsGround(const SkyModel& m, double h, double mu);
/// Height after travelling t along (h, mu).
double heightAt(const SkyModel& m, double h, double mu, double t);

/// Transmittance LUT texel values computed directly (the CPU twin of transmittance_lut.glsl).
glm::dvec3 transmittanceToTop(const SkyModel& m, double h, double mu, int steps);
Lut2D transmittanceLut(const SkyModel& m, const SkyQuality& q);
/// Transmittance to the top of the atmosphere from the LUT, and to the light with the planet's
/// soft shadow (disk of the given angular radius).
glm::dvec3 transmittanceFromLut(const SkyModel& m, const Lut2D& T, double h, double mu);
glm::dvec3 transmittanceToLight(const SkyModel& m, const Lut2D& T, double h, double muS, double angularRadius);

/// Multiple-scattering LUT (Hillaire 2020): per unit illuminance, isotropic multiple
/// scattering transfer Psi_ms(h, mu_s).
glm::dvec3 multiScatteringTexel(const SkyModel& m, const SkyQuality& q, const Lut2D& T, double h, double muS);
Lut2D multiScatteringLut(const SkyModel& m, const SkyQuality& q, const Lut2D& T);

/// Spherical harmonics of the incident radiance field: the real SH of bands l <= L that are even
/// about the light's vertical plane (cos(m phi) terms, m = 0..l): (L + 1)(L + 2) / 2 coefficients,
/// stored at index l (l + 1) / 2 + m. L = SkyQuality::shBands in [kShMinBands, kShMaxBands].
constexpr int kShMinBands = 2;
constexpr int kShMaxBands = 6;
constexpr int shCoefficients(int bands) { return (bands + 1) * (bands + 2) / 2; }
constexpr int kShMaxCoefficients = shCoefficients(kShMaxBands);  // 28
using ShCoefficients = std::array<glm::dvec3, kShMaxCoefficients>;
/// The fields the view-ray marches read for scattering orders >= 2.
struct MsField {
    Lut2D psi;                   ///< Hillaire's Psi_ms (isotropic), per lux
    int bands = 4;               ///< SH bands L of `sh`
    std::vector<Lut2D> sh;       ///< shCoefficients(bands) SH coefficient tables of the incident field
    /// Sky irradiance on the (horizontal) ground per lux of the light, over mu_s at the ground
    /// (width = psi's, height 1, u as multiScatteringUv at h = 0). Empty: the ground is lit by
    /// the direct light only.
    Lut2D ground;
    bool directional = false;    ///< use sh (else psi)
};
/// How a view-ray sample convolves the SH field with the phase functions (Funk-Hecke), for L
/// bands: band l of the field is scaled by rayleigh[l] (Rayleigh's Legendre moments: 1, 0, 1/10,
/// 0 ...) and by mie[l] = (Lambda_l - f) w_l for the aerosols, where Lambda_l = 2 pi int p(t)
/// P_l(t) dt is the Mie phase function's Legendre moment, f = kDeltaScale Lambda_(L+1) the
/// delta-M forward fraction (`forward`: that part of the Mie scattering stays in the beam) and
/// w_l = exp(-c l^2) a Gaussian window against ringing (c = 0.48 / L^2: 0.03 at L = 4).
struct PhaseMoments {
    std::array<double, kShMaxBands + 2> lambda{};  ///< Mie Lambda_0 .. Lambda_(kShMaxBands + 1)
    std::array<double, kShMaxBands + 1> mie{};     ///< Mie band factors (0 beyond `bands`)
    std::array<double, kShMaxBands + 1> rayleigh{};  ///< Rayleigh band factors
    double forward = 0.0;                          ///< delta-M fraction f of the Mie scattering
};
PhaseMoments phaseMoments(const SkyModel& m, int bands);
/// The kShMaxCoefficients real SH basis functions (l <= kShMaxBands, m >= 0, normalised over the
/// sphere, no Condon-Shortley phase: Y00 = 0.282095, Y10 = 0.488603 z, Y11 = 0.488603 x, ...) at a
/// unit vector in the local frame (x horizontal towards the light, z up); y enters only squared.
std::array<double, kShMaxCoefficients> shBasis(double x, double z);
/// Ground texel: the sky's irradiance on a horizontal surface at the ground, per lux of the
/// light at mu_s, gathered over q.shDirections directions of the upper hemisphere (single
/// scattering with the phase functions plus Hillaire's isotropic higher orders along each ray).
glm::dvec3 groundIrradianceTexel(const SkyModel& m, const SkyQuality& q, const Lut2D& T, const Lut2D& psi, double muS);
/// Irradiance of the ground (direct light plus sky light) per lux of the light at mu_s (the
/// ground's radiance is groundAlbedo / pi times this). `ground` may be empty (direct only).
glm::dvec3 groundIrradiance(const SkyModel& m, const Lut2D& T, const Lut2D& ground, double muS, double lightAngularRadius);
/// SH texel: the projection of the incident radiance field at (h, mu_s), per lux (the ground
/// lit by `ground`, as groundIrradiance()).
/// The first q.shBands coefficients are set, the others 0.
ShCoefficients shTexel(const SkyModel& m, const SkyQuality& q, const Lut2D& T, const Lut2D& psi, const Lut2D& ground, double h,
                       double muS);
/// SH texel of the second pass (q.shIterations): the projection of the incident field whose
/// every gathered ray is marched like a view ray through `prev` (integrate()).
ShCoefficients shIterationTexel(const SkyModel& m, const SkyQuality& q, const Lut2D& T, const MsField& prev, double h,
                                double muS);
/// Ground texel of the second pass: the sky's irradiance on the ground with every gathered ray
/// marched like a view ray through `prev` (q.shIterationDirections over the upper hemisphere).
glm::dvec3 groundIrradianceIterationTexel(const SkyModel& m, const SkyQuality& q, const Lut2D& T, const MsField& prev,
                                          double muS);
/// Builds psi (and ground and sh if q.directionalMs, iterated q.shIterations times).
MsField msField(const SkyModel& m, const SkyQuality& q, const Lut2D& T);
/// In-scattered radiance per lux of orders >= 2 at a point (h, mu, mu_s, nu), for the given
/// Rayleigh and Mie scattering coefficients there.
glm::dvec3 msInscatter(const SkyModel& m, const MsField& f, const PhaseMoments& moments, double h, double mu, double muS,
                       double nu, const glm::dvec3& sR, const glm::dvec3& sM);

/// Result of a ray march: radiance per unit light illuminance, split into the phase-applied
/// part (Rayleigh single, multiple scattering, ground) and Mie single scattering without its
/// phase function; plus the transmittance along the marched segment.
struct Scattering {
    glm::dvec3 smooth{0.0};
    glm::dvec3 mieNoPhase{0.0};
    glm::dvec3 transmittance{1.0};
    bool hitGround = false;
};
/// March from height h along mu (light at mu_s, nu) for at most maxDistance metres, with
/// `steps` samples spaced quadratically from the origin when `quadratic`, else densest at the
/// ray's lowest point. groundMode: -1 from the geometry, 0 never hits, 1 hits the ground.
Scattering integrate(const SkyModel& m, const Lut2D& T, const MsField& MS, double h, double mu, double muS, double nu,
                     double maxDistance, int steps, bool quadratic, double lightAngularRadius, int groundMode = -1);
/// The aerial-perspective volume's march over the distance slice [t0, t1] (m) of a ray from
/// height h (mu, mu_s, nu; the Sun's angular radius), `substeps` midpoint samples through air no
/// lower than the ground when `groundAir`: adds the in-scattered radiance per lux to L and
/// multiplies the exact and delta-M transmittances thr, thrD (the GPU pass's text, aerialTexel()).
void aerialSlice(const SkyModel& m, const Lut2D& T, const MsField& MS, double h, double mu, double muS, double nu, double t0,
                 double t1, int substeps, bool groundAir, glm::dvec3& L, glm::dvec3& thr, glm::dvec3& thrD);
/// Total radiance per unit illuminance along a ray (smooth + mie * phase).
glm::dvec3 radiance(const SkyModel& m, const Scattering& s, double nu);

/// The multiple-scattering model's weight along a view ray at cosine `nu` to the Sun: the orders
/// >= 2 take mix(f, f + D, w) (docs/eclipse.md). A ray near the shadow's axis gathers, through
/// the forward peak of the aerosol's phase function, light scattered in the air along the axis,
/// as dark as the point itself; through the rest of the scattering (Rayleigh's, the aerosol's
/// broad part) and across the axis, the kernel's average. w = 1 - F (1 - sin(angle to the Sun)),
/// F = min(1, the delta-M forward fraction x the aerosol's share of the scattering at the ground
/// / kEclipseForwardShare). Runs atmosphere.shared.glsl's atm_eclMsAxisWeight().
double eclipseMsAxisWeight(const SkyModel& m, double forwardFraction, double nu);
/// The forward peak's share of the scattering at the ground above which the gathered light near
/// the axis is taken as all from along it: 0.16, that of atmosphere::Atmosphere::earthClear()
/// (aerosol 86 % of the scattering, delta-M fraction 0.187), whose sky the weight sin(angle) fitted
/// (docs/eclipse.md); SkyModel::earthClear() (aerosol 23 %) has 0.043. (The shared text writes
/// the literal 0.16; a test checks the two agree.)
inline constexpr double kEclipseForwardShare = 0.16;

/// The full weight along a view ray at cosines `nu` (to the Sun), `mu` (to the zenith) with the
/// Sun at `muS` (docs/eclipse.md, "One model at three places"): the axis' share F x G(the Sun's
/// elevation) (the shadowed column along the axis: 0 with the Sun at the zenith, 0.22 with it 81.8 deg
/// up, >= 0.99 below 56 deg), towards the Sun the lesser of sin(angle) and the view's offset from the umbra's
/// footprint along the Sun's azimuth; on hazy air (eclipseHaze() H > 0) the sunward power
/// raised and F' = max(F, H) there, times mix(1, R, H), R the sunlit ring's directional gather at
/// `cosRing` (cos(elevation) |sin(azimuth from the Sun)|, in [0, 1]), its lobe scaled by the
/// umbra's elongation on the air; away from the Sun no axis term (w' = 1); times the low views' gain
/// (kEclipseLowView*, larger than 1: the orders >= 2 take max(mix(f, f + D, w), 0)). Runs atm_eclMsWeight().
double eclipseMsWeight(const SkyModel& m, double forwardFraction, double nu, double mu, double muS, double cosRing);
/// How hazy the air is for the eclipse's weight, in [0, 1]: 0 up to 1.1 x kEclipseHazeClearMie
/// (the aerosol's scattering at the ground, green, 1/m), 1 from 4 x. Runs atm_eclHaze().
double eclipseHaze(const SkyModel& m);
/// atmosphere::Atmosphere::earthClear()'s aerosol scattering at the ground, green (measured
/// 7.514e-5 /m), rounded: the haze measure's unit. The shared text writes the literals of these
/// constants; a test checks they agree.
inline constexpr double kEclipseHazeClearMie = 7.5e-5;
/// The rate at which the shadowed column along the axis (air mass X = 1 / sin(the Sun's
/// elevation)) takes the light gathered near the axis: G = 1 - exp(-rate (X - 1)).
inline constexpr double kEclipseColumnRate = 23.6;
/// The umbra's elongation at which the hazy ring's lobe is half on: E = (X-1)^2 / ((X-1)^2 + this^2).
inline constexpr double kEclipseRingElongation = 2.26;
/// Towards the Sun: the weight of the view's cosine to the zenith in its offset from the umbra's
/// footprint along the Sun's azimuth, sqrt(cosRing^2 + (this mu X)^2), X = 1 / max(muS, 0.05).
inline constexpr double kEclipseFootprintMu = 0.47;
/// Towards the Sun: the power of s (times 1 + kEclipseHazeSunwardPower H).
inline constexpr double kEclipseSunwardPower = 0.85;
/// The sunward power's extra factor at H = 1.
inline constexpr double kEclipseHazeSunwardPower = 0.40;
/// The share of the kernel's light that reaches the shadowed hazy air (R averaged over the sphere).
inline constexpr double kEclipseHazeRingShare = 0.50;
/// The asymmetry of the ring's smoothed lobe.
inline constexpr double kEclipseHazeRingG = 0.4;
/// The low views' gain (docs/eclipse.md, "The ring of directions"): the weight times
/// 1 + gain (1 + haze H) (x e^(1 - x))^power, x = mu / kEclipseLowViewMu: views some 20 deg up
/// gather the bright horizon's ring through the forward scattering more than the kernel's average
/// gives (largest at mu = kEclipseLowViewMu, 1 at the horizon's rim and near the zenith).
inline constexpr double kEclipseLowViewGain = 0.88;
/// The low views' gain's extra factor at H = 1 (less on hazy air).
inline constexpr double kEclipseLowViewHaze = -0.23;
/// The view's sine of elevation where the low views' gain peaks.
inline constexpr double kEclipseLowViewMu = 0.34;
/// The low views' gain's power (its width in elevation).
inline constexpr double kEclipseLowViewPower = 2.1;

/// The eclipse's multiple-scattering field (docs/eclipse.md, "Multiple scattering"): in the
/// plane through the observer perpendicular to the shadow's axis (unit basis e1, horizontal, and
/// e2), a grid of D = (the Sun's visible fraction averaged over the air around a point, weighted
/// by a kernel whose mass beyond a distance r falls as exp(-r / L)) minus (the fraction at the
/// point). The orders >= 2 at p are the clear sky's times clamp(f(p) + D(p), 0, 1); D is 0 off the
/// grid (far from the umbra the fraction varies slowly and the average equals it). Built on the
/// CPU (eclipseMsTable(), ~10 ms); the GPU samples the same grid as a texture.
struct EclipseMsTable {
    glm::dvec3 e1{1.0, 0.0, 0.0}, e2{0.0, 1.0, 0.0};  ///< unit ENU, perpendicular to the shadow's axis
    glm::dvec2 centre{0.0};       ///< the grid's centre (the axis' crossing of the plane), m in (e1, e2)
    double halfExtentMeters = 0;  ///< the grid covers centre +- this on both axes, m (0: no table, D = 0)
    int n = 0;                    ///< texels per side
    std::vector<float> d;         ///< D, row-major [e2][e1], texel centres at -half + (i + 0.5) * 2 half / n
    /// D at the point p (ENU m from the observer), bilinear between texel centres (as the GPU's
    /// linear filter with clamp to edge), 0 outside the grid.
    double sample(const glm::dvec3& p) const;
};
/// A solar eclipse's geometry for the shadow on the air (docs/eclipse.md): positions in ENU
/// metres from the observer (the frame of the apparent Sun, moon.position_m).
struct EclipseGeometry {
    glm::dvec3 moonPos{0.0};    ///< the Moon's centre
    double moonRadius = 1737400.0;  ///< m
    glm::dvec3 sunPos{0.0};     ///< the Sun's centre
    double sunRadius = 6.957e8;     ///< m
    const EclipseMsTable* ms = nullptr;  ///< the multiple-scattering field (null: orders >= 2 take the point's own fraction)
    /// >= 0: the orders >= 2's weight w along the ray forced to this value instead of the model's
    /// (fitting: the radiance is linear in w, so two marches give it for every w). CPU only.
    double msWeightOverride = -1.0;
};
/// The multiple-scattering kernel's length L for the geometry `g` (m; docs/eclipse.md, "The
/// kernel's length"): kEclipseMsLengthMeters x (e / kEclipseMsEdgeMeters)^kEclipseMsEdgePower, e the
/// observer's distance inside the umbra's edge on the plane perpendicular to the shadow's axis (the
/// umbra's radius there minus the observer's distance from the axis), at least
/// kEclipseMsEdgeMinMeters (the partial phases, outside the umbra). The kernel's tail is not
/// exp(-r / L): the nearer the sunlit air, the shorter the exponential that matches it.
/// Burgos 31 km (e = 46 km), Reykjavik 28 km (9 km), Luxor 33 km (114 km), partial phases 24 km.
double eclipseMsLength(const EclipseGeometry& g);
/// L at kEclipseMsEdgeMeters inside the umbra's edge, m.
inline constexpr double kEclipseMsLengthMeters = 31.5e3;
/// The edge distance of the reference length, m.
inline constexpr double kEclipseMsEdgeMeters = 50e3;
/// How L grows with the distance from the umbra's edge.
inline constexpr double kEclipseMsEdgePower = 0.07;
/// The least edge distance L uses (outside the umbra: the partial phases, annular), m.
inline constexpr double kEclipseMsEdgeMinMeters = 1e3;
/// Visible fraction of a limb-darkened disk (u = 0.6) of angular radius rs behind a dark disk of
/// radius ro, centres d apart (rad), [0, 1]: the rings the dark disk's limb does not cut in closed
/// form, the cut band with `rings` nodes (24: the GPU's; within 0.1 % of the fraction itself, thin
/// crescents near the contacts included).
double eclipseFraction(double rs, double ro, double d, int rings = 24);
/// At point p (m from the observer): x the Sun's visible fraction there, y the multiple-scattering
/// model's factor clamp(x + g.ms->sample(p), 0, 1). Twin of atm_eclipseAt().
glm::dvec2 eclipseAt(const EclipseGeometry& g, const glm::dvec3& p, int rings = 24);
/// Builds the multiple-scattering field for the geometry `g` (its `ms` is ignored): kernel length
/// `lengthMeters` (L, > 0; eclipseMsLength(g)), `n` x `n` texels (>= 8) over +- `halfExtentMeters`
/// around the shadow's axis. `verticalMeters`: the spread of the air around a point in height (the
/// kernel's extent across the horizontal layer), m.
EclipseMsTable eclipseMsTable(const EclipseGeometry& g, double lengthMeters, int n = 128, double halfExtentMeters = 600e3,
                              double verticalMeters = 4e3);
/// eclipseMsTable() in pieces, so that EclipseSkyLut can spread the table's CPU work over frames
/// (docs/eclipse.md, "Frame cost"): the same arithmetic in the same order in units of work (a
/// chunk of the radial fraction, of the fraction's grid, one line of one blur pass, the fourth
/// Gaussian, D), so the finished table is bit for bit eclipseMsTable()'s (which runs this).
///
///     cpu::EclipseMsTableBuilder b(g, cpu::eclipseMsLength(g));
///     while (!b.finished()) b.advance(b.totalWork() / 8);  // e.g. an eighth a frame
///     cpu::EclipseMsTable t = b.take();
class EclipseMsTableBuilder {
public:
    /// The arguments as eclipseMsTable()'s (same ranges; throws on the same).
    EclipseMsTableBuilder(const EclipseGeometry& g, double lengthMeters, int n = 128, double halfExtentMeters = 600e3,
                          double verticalMeters = 4e3);
    ~EclipseMsTableBuilder();
    EclipseMsTableBuilder(EclipseMsTableBuilder&&) noexcept;
    EclipseMsTableBuilder& operator=(EclipseMsTableBuilder&&) noexcept;
    /// The whole table's work and the work done so far, in blur taps (a radial fraction counted as
    /// ~500 taps: their CPU time's ratio).
    double totalWork() const { return totalWork_; }
    double workDone() const { return work_; }
    /// Units of work: all, and done.
    int units() const { return units_; }
    int unitsDone() const { return next_; }
    bool finished() const { return next_ >= units_; }
    /// One unit of work (nothing once finished).
    void step();
    /// Units until at least `work` more is done or the table is finished.
    void advance(double work);
    /// The finished table (throws if not finished); the builder is spent.
    EclipseMsTable take();

private:
    struct State;
    double unitWork(int u) const;
    std::unique_ptr<State> s_;
    EclipseMsTable t_;
    int units_ = 0, next_ = 0;
    double totalWork_ = 0, work_ = 0;
};
/// integrate() for the Sun at unit ENU `sunDir`, along unit ENU `viewDir` from the observer at
/// height h (inside the atmosphere), every point seeing the Moon's shadow: single scattering and
/// the directly lit ground by eclipseAt().x, the sky's light on the ground by eclipseAt().y, orders
/// >= 2 by x + (y - x) w, w the weight of eclipseMsWeight() for this ray (or g.msWeightOverride)
/// (docs/eclipse.md). Twin of integrateScattering() with ATM_ECLIPSE.
Scattering integrateEclipse(const SkyModel& m, const Lut2D& T, const MsField& MS, double h, const glm::dvec3& viewDir,
                            const glm::dvec3& sunDir, const EclipseGeometry& g, int steps, bool quadratic, double lightAngularRadius,
                            int groundMode = -1);

/// One sky-view texel: RGB = smooth part, and the Mie part (two textures on the GPU).
struct SkyViewTexel {
    glm::dvec3 smooth{0.0};
    glm::dvec3 mie{0.0};
};
SkyViewTexel skyViewTexel(const SkyModel& m, const SkyQuality& q, const Lut2D& T, const MsField& MS, double h, double muS,
                          glm::dvec2 uv, double lightAngularRadius);
/// Radiance per lux from sky-view LUTs (values without kLutScale) for a view (mu, azimuth from
/// the light, nu): the twin of skyViewSample() in atmosphere.glsl (halves never blended).
glm::dvec3 skyViewSample(const SkyModel& m, const Lut2D& smooth, const Lut2D& mie, double h, double mu, double az, double nu);
/// Sky radiance (cd/m^2) seen from height h (clamped into the atmosphere) in direction
/// `viewDir` with the light at `lightDir` (both unit ENU vectors), for a light of illuminance
/// `E` (lux per channel), marching every ray (CPU reference for tests).
glm::dvec3 skyRadiance(const SkyModel& m, const Lut2D& T, const MsField& MS, double h, const glm::dvec3& viewDir,
                       const glm::dvec3& lightDir, const glm::dvec3& E, int steps, double lightAngularRadius);
}  // namespace cpu

}  // namespace welkin::generators
