// Clouds: a volumetric cumulus layer (a spherical shell between clouds.bottom_m and clouds.top_m,
// density from the weather map and the noise of generators/clouds) and a thin cirrus layer at
// clouds.cirrus_height_m, ray-marched per pixel and lit by the Sun and the Moon through the
// atmosphere's transmittance, with ambient light from the sky's irradiance; composited after the
// Sky (Layer::Clouds, not in the default set).
//
//   welkin::SkyProcessor p;                                   // the default set, then the clouds:
//   for (auto& n : welkin::elements::defaultElements()) p.add(welkin::elements::makeElement(n));
//   p.add(std::make_unique<welkin::elements::Clouds>());
//   p.vars().set(welkin::elements::cloudelemkeys::preset, std::string("overcast"));
//   p.vars().set(welkin::generators::cloudkeys::coverage, 0.7);   // overrides the preset's
//   p.renderFrame();
//   // welkin render ... --elements default,clouds --var clouds.preset=fair
//
// Presets (clouds.preset): `fair` (fair-weather cumulus), `overcast` (stratocumulus),
// `scattered-cirrus` (a few cumulus under much cirrus), `towering` (cumulus congestus and
// cumulonimbus towers, 1.2-8 km), `clear`. A preset supplies the value of
// every cloud key it names (coverage, layer heights, cirrus, scattering, rain, weather-map
// generation) that nobody else set: a key the host or `--var` sets keeps the set value, whatever
// the preset (the element declares those keys without a value; SkyVars::has() tells them apart).
// When the preset changes at run time, the keys the element wrote itself follow the new preset.
//
// Units: radiance cd/m^2, illuminance lux, heights m above the ground, scattering 1/m.
#pragma once
#include <welkin/element.hpp>
#include <welkin/generators/sky_luts.hpp>
#include <welkin/gl/objects.hpp>
#include <welkin/gl/projection_programs.hpp>

#include <array>
#include <string>
#include <vector>

namespace welkin::elements {

namespace cloudelemkeys {
inline const Key<std::string> preset{"clouds.preset", Choices{{"fair", "overcast", "scattered-cirrus", "towering", "clear"}}, "cloud preset: fair, overcast, scattered-cirrus, towering or clear (sets the cloud keys nobody set)"};
inline const Key<int> samples{"clouds.samples", Range{4, 512}, "ray-march samples per view ray through the cumulus layer"};
inline const Key<int> lightSamples{"clouds.light_samples", Range{1, 32}, "light-march samples from each sample towards the Sun or Moon (self-shadowing)"};
inline const Key<bool> reprojection{"clouds.reprojection", "the real-time path: the clouds in a direction-space cache refreshed over clouds.cache_frames frames, which every frame samples; off: every pixel every frame; unset: on when render.interactive (welkin view)"};
inline const Key<int> cacheFrames{"clouds.cache_frames", Range{1, 64}, "real-time path: frames that refresh the whole direction cache (1, 4, 16 or 64; a Bayer order)"};
inline const Key<bool> skyShadow{"clouds.sky_shadow", "the clouds' shadow on the atmosphere's in-scattering (crepuscular rays; the sky.shadow_loss_lut the Sky element subtracts)"};
inline const Key<int> cacheWidth{"clouds.cache_width", Range{64, 4096}, "azimuth texels of the real-time path's direction cache (its height is half)"};
}  // namespace cloudelemkeys

/// The values a preset gives the cloud keys (cloud_keys.hpp).
struct CloudPreset {
    std::string name;
    double coverage = 0;        ///< clouds.coverage [0, 1]
    double bottom = 2000;       ///< clouds.bottom_m
    double top = 3000;          ///< clouds.top_m
    double cirrusCoverage = 0;  ///< clouds.cirrus_coverage [0, 1]
    double cirrusHeight = 9000; ///< clouds.cirrus_height_m
    double scattering = 0.05;   ///< clouds.scattering_per_m (1/m)
    double detailScale = 1;     ///< clouds.detail_scale
    double rain = 0;            ///< clouds.rain_density [0, 1]
    int cloudCount = 60;        ///< clouds.cloud_count (weather-map generator)
    double sizeMin = 800;       ///< clouds.cloud_size_min_m
    double sizeMax = 3000;      ///< clouds.cloud_size_max_m
    double cloudType = 1;       ///< clouds.cloud_type (0 stratocumulus, 1 cumulus)
};
/// The preset named `name`; throws welkin::Error "clouds.preset: 'x' not one of fair, overcast,
/// scattered-cirrus, towering, clear".
const CloudPreset& cloudPreset(const std::string& name);
/// The preset names, in the order above.
std::vector<std::string> cloudPresetNames();

namespace cloudcpu {
/// Henyey-Greenstein phase function (1/sr) for cos(angle) nu and asymmetry g in (-1, 1).
double henyeyGreenstein(double nu, double g);
/// The cloud droplets' phase function: the fit of Jendersie & d'Eon 2023 ("An approximate Mie
/// scattering function for fog and cloud rendering") to Lorenz-Mie at droplet diameter 20 um
/// (r_eff 10 um), (1 - w_D) HG(g_peak) + w_D Draine(g_D, alpha_D).
inline constexpr double kDropletGPeak = 0.9946;       ///< the diffraction peak's HG asymmetry
inline constexpr double kDropletGDraine = 0.5938;     ///< the Draine lobe's g
inline constexpr double kDropletAlphaDraine = 27.11;  ///< the Draine lobe's alpha
inline constexpr double kDropletWDraine = 0.4982;     ///< the Draine lobe's weight w_D (delta-M: 1 - f)
/// The diffusion form's constants that no fit moves (clouds.cpp's shader defines and `welkin bench
/// cloud-fit` read these, one source): transport optical depth per scaled optical depth
/// (1 - g) / w_D with g 0.86 (the Mie droplets'); A, the slab's two extrapolation lengths
/// (transmission A / (s + A)); q, the exponent of the light's cos(zenith) (a deck's flux per area);
/// the cos(zenith) below which that factor stays constant.
inline constexpr double kDiffusionS = (1.0 - 0.86) / kDropletWDraine;
inline constexpr double kDiffusionA = 2.0;
inline constexpr double kDiffusionQ = 0.75;
inline constexpr double kDiffusionMuMin = 0.2;
/// The ambient's diffusion constants (ambientTransfer(): k scale, z the bottom's extrapolation
/// length in transport depth, h the net flux's share towards the lit side, c the thin-cloud onset
/// per unscaled optical depth): a least-squares fit to adding-doubling's fluxes alone
/// (skyelements/clouds/README.md, "Ambient"). `welkin bench cloud-fit` reads them too (its copy of
/// the transfer text needs them defined; it fits only the lights' constants).
struct AmbientTransferConstants {
    double k, z, h, c;
};
inline constexpr AmbientTransferConstants kAmbientTransfer{0.8, 1.4, 1.5, 0.2};
/// The fitted constants of the lights' transfer (lightTransfer(): its diffusion term's k, c, h, z
/// and the forward-peaked orders' w_m, g_m, m = 0..4), as `welkin bench cloud-fit` regenerates
/// them from the path tracer's slab radiances and adding-doubling's fluxes
/// (skyelements/clouds/README.md, "The fit"). c per unscaled optical depth.
struct LightTransferConstants {
    double k, c, h, z;
    double w[5], g[5];
};
/// The committed fit: `welkin bench cloud-fit --paths 60000 --seed 1` (2026-11-27, 263 s).
inline constexpr LightTransferConstants kLightTransferFit{0.63055, 0.1100, 0.5282, 2.1264,
                                                          {0.7765, 0.5273, 0.5273, 0.5273, 0.5273},
                                                          {0.9925, 0.6025, 0.4535, 0.4535, 0.4535}};
/// The droplets' phase function (1/sr) at cos(scattering angle) nu in [-1, 1]: the diffraction
/// peak, the forward lobe and the backward rise (asymmetry 0.88). Integrates to 1.
double cloudPhase(double nu);
/// The delta-M scaled phase function (1/sr): the Draine lobe alone (the peak's share of the
/// extinction treated as unscattered). Integrates to 1.
double scaledPhase(double nu);
/// The light transfer of the real-time clouds (skyelements/clouds/README.md, "Model"): the in-scattered
/// radiance per lux of a light and per unit scaled extinction w_D sigma (1/sr) at a point with
/// scaled optical depths tauL towards the light and tauB away from it (>= 0), cos(scattering
/// angle) nu and the light's cos(zenith) muL in [-1, 1]: the single scattering
/// scaledPhase(nu) e^(-tauL), the forward-peaked low orders forwardTransfer(nu, tauL) and a
/// diffusion term along the light axis,
/// k/pi max(muL, 0.2)^q (1 - e^(-c (tauL + tauB) / w_D)) max(sB + z + h nu, 0) / (sL + sB + A),
/// s = (1 - 0.86) tau / w_D (the transport optical depth, g 0.86 the Mie droplets'), the constants
/// fitted to the path tracer's slab radiances and adding-doubling's fluxes (skyelements/clouds/README.md).
double lightTransfer(double nu, double tauL, double tauB, double muL);
/// lightTransfer()'s diffusion term alone (1/sr per lux and per unit scaled extinction).
double lightDiffusion(double nu, double tauL, double tauB, double muL);
/// The transfer table's correction of the diffusion term's angular shape (dimensionless, 0.25-4):
/// the ratio of a slab's multiply scattered radiance at a depth inside it (adding-doubling's,
/// azimuth-averaged) to the diffusion term's, quadrilinear in log2 tauAxis (the slab's unscaled
/// optical depth along the light's axis, 1-256, clamped), muL (0.2-1, clamped), depthFrac (the
/// depth from the lit face over the slab's, tauL / (tauL + tauB), [0, 1]) and the view ray's
/// cos(zenith) muV in [-1, 1] (> 0 looking up: the light going down). Written by `welkin bench cloud-table`
/// (clouds_transfer_table.shared.glsl; skyelements/clouds/README.md, "Transfer table").
double diffusionShape(double muV, double tauAxis, double muL, double depthFrac);
/// What the march uses: lightTransfer() with its diffusion term times
/// diffusionShape(muV, (tauL + tauB) / w_D, muL, tableDepth(muV, tauL, tauB, deck)); muV the view
/// ray's cos(zenith), deck in [0, 1] (deckness(): 0 a cumulus, the table at the face the light
/// leaves by; 1 a wide deck, at the sample's own depth).
double lightTransferTable(double nu, double muV, double tauL, double tauB, double muL, double deck = 0.0);
/// How much the cloud around a sample is a deck, in [0, 1]: (tauWidth - tauAxis) / (tauWidth +
/// tauAxis) clamped, tauWidth the scaled depth across the cloud (finiteBackDepth()'s), tauAxis the
/// scaled depth along the light's axis through the sample (tauL + tauB): 0 for a cloud no wider than
/// it is deep along the light, -> 1 for a sheet far wider (skyelements/clouds/README.md, "The transfer table").
double deckness(double tauWidth, double tauAxis);
/// The depth fraction (0 the lit face, 1 the far one) at which lightTransferTable() reads the
/// table: mix(face, tauL / (tauL + tauB), deck), face = clamp(0.5 + 4 muV, 0, 1) (the far face
/// looking up, the lit one looking down).
double tableDepth(double muV, double tauL, double tauB, double deck);
/// The depth to the far side for a cloud of finite width (scaled optical depths >= 0): tauB, the
/// depth to the cloud's far side along the light's axis, and tauWidth, the depth across the cloud
/// through the sample perpendicular to the light (horizontal, both ways), combined harmonically,
/// tauB tauWidth / (tauB + tauWidth): the light diffusing in a cumulus leaks out through its sides
/// too. In a deck (tauWidth >> tauB) it is tauB; 0 where either is 0. What the march passes to
/// lightTransferTable() as tauB (skyelements/clouds/README.md, "Finite clouds").
double finiteBackDepth(double tauB, double tauWidth);
/// The cosine between the light and the normal of the cloud face it entered through: the scaled
/// depth to the sky above the sample, tauUp (marched through the density), over the scaled depth
/// towards the light, tauL, clamped to [max(muL, 0), 1] (in a deck tauUp = muL tauL: muL; a side
/// facing the light: 1), blended back to muL by e^(-kDiffusionS tauL) (the face is remembered over
/// about one transport optical depth). What the march passes to lightTransferTable() as muL
/// (skyelements/clouds/README.md, "The lit face").
double litFaceCosine(double tauUp, double tauL, double muL);
/// The transfer table's 9 x 5 x 5 x 17 values, [tauAxis][muL][depth][muV] (diffusionShape()'s nodes).
const double* diffusionShapeTable();
inline constexpr int kShapeTauN = 9, kShapeMuLN = 5, kShapeDepthN = 5, kShapeMuVN = 17;
/// The forward-peaked low orders of lightTransfer() (1/sr per lux and per unit scaled
/// extinction): sum over m = 0..4 of w_m tauL^m e^(-tauL) / m! HG(nu, g_m), the light scattered m
/// times at small angles on its way in (Poisson's share at scaled depth tauL >= 0) sent towards
/// the view by a lobe that widens with the order; m = 0 the diffraction peak's wings that delta-M
/// counts as unscattered. Fitted to the path tracer's slab radiances (skyelements/clouds/README.md).
double forwardTransfer(double nu, double tauL);
/// The share of the Draine lobe's scattering into the forward hemisphere, integral over nu in
/// [0, 1] of 2 pi scaledPhase(nu) (0.938; checked by the tests): what a particle lit by a uniform
/// hemisphere sends along the hemisphere's axis, per unit radiance.
inline constexpr double kDraineForwardFraction = 0.938;
/// The diffusivity factor (Elsasser 1942): diffuse light through an optical depth tau is
/// attenuated about as a beam through 1.66 tau.
inline constexpr double kDiffusivity = 1.66;
/// The ambient light's transfer (skyelements/clouds/README.md, "Ambient"): the in-scattered radiance per lux of
/// horizontal illuminance arriving as a uniform hemisphere of radiance E/pi from one side of the
/// layer (the sky from above, the ground from below) and per unit scaled extinction (1/sr), at a
/// point with scaled vertical optical depths tauN to that side and tauF to the other (>= 0), nu the
/// cosine between the view ray and the direction towards the lit side, in [-1, 1]:
/// (1/pi) (1/2 + (F - 1/2) nu) e^(-1.66 tauN) (single scattering, F = kDraineForwardFraction)
/// plus lightTransfer()'s diffusion term at the slant transport depths 1.66 s, times 2 / (1 + q)
/// (its mu^q averaged over a diffuse field's mu, per horizontal lux). Fluxes of slabs of
/// tau 3-100 within 0.86-1.16x (T) and 0.87-1.09x (R) of adding-doubling's for diffuse light.
double ambientTransfer(double nu, double tauN, double tauF);
/// Energy-conserving integration of one step (Hillaire 2016, "Physically based sky, atmosphere
/// and cloud rendering in Frostbite", eq. at §5.6.3): the radiance in-scattered over a step of
/// length dt with source S (cd/m^2 per m) and extinction sigmaT (1/m): (S - S e^-sigmaT dt)/sigmaT.
double integrateStep(double source, double sigmaT, double dt);
/// The longest light march and march to a cloud's far side (m; to the shell's exit if nearer).
inline constexpr double kMarchMaxM = 3000.0;
/// Steps of the march to a cloud's far side (generators::cpu::cloudDepthAlong along -l, x1.5
/// growth over kMarchMaxM) for clouds.light_samples = lightSamples: half as many, at least 2 (the
/// far side's depth enters only the diffusion term, smoothly; the light's sets the beam's e^-tauL).
int backSamples(int lightSamples);
/// Two-stream transmission (direct + diffuse) of a conservative-scattering slab of optical
/// depth tau and asymmetry g (Bohren 1987, "Multiple scattering of light and some of its
/// observable consequences", Am. J. Phys. 55, 524: T = 1 / (1 + 0.75 (1 - g) tau) at normal
/// incidence, diffuse illumination).
double twoStreamTransmission(double tau, double g);
/// The elevation (rad, < 0) below which a light of angular radius `radius` (rad) lights no point
/// of a cumulus layer whose top is `layerTopM` above a planet of radius `planetRadiusM` that the
/// view march from height `observerM` (m, >= 0) reaches: the atmosphere's transmittance to a
/// light is exactly 0 at radius r once the light's cos(zenith) is below -sqrt(r^2 - R^2)/r -
/// (R/r) radius (atm_lightAboveHorizon's smoothed horizon), at most -sin(theta_top) - radius in
/// the layer (theta_x = acos(R / (R + x)), the horizon's dip at height x); a straight ray that
/// misses the ground reaches points at central angles up to theta_obs + theta_top from the
/// observer, whose zenith tilts by as much. So: -(asin(sin(theta_top) + radius) + theta_obs +
/// theta_top) less 1e-3 rad for float rounding. Below it the light's march is dropped from the
/// shader (Clouds' CLD_LIGHTS variants): its term was exactly zero.
double lightDarkElevation(double planetRadiusM, double observerM, double layerTopM, double radius);
}  // namespace cloudcpu

class Clouds final : public SkyElement {
public:
    Clouds();
    /// The photometry of the last frame that computed it (lux): horizontal global, direct (the
    /// Sun's beam through the clouds), diffuse (sky + clouds), and the clear-sky values. The
    /// transmittances along the rays to the Sun and the Moon are also written into the engine keys
    /// lights.sun_cloud_transmittance and lights.moon_cloud_transmittance (SkyLighting reads them).
    struct Photometry {
        double global = 0, direct = 0, diffuse = 0;
        double clearGlobal = 0, clearDirect = 0, clearDiffuse = 0;
        double sunTransmittance = 1;  ///< the clouds' transmittance along the ray to the Sun
        double moonTransmittance = 1;  ///< the clouds' transmittance along the ray to the Moon
        bool valid = false;
        /// The ground's global illuminance under the clouds (luminance, lux) that lights their
        /// bases (albedo 0.2): the photometry's fixed point on the ground (equals `global` for an
        /// observer on the ground).
        double groundLux = 0;
    };
    const Photometry& photometry() const { return photometry_; }
    /// True if the last render() drew (coverage > 0 or cirrus coverage > 0).
    bool drew() const { return drew_; }

private:
    void doInit(InitContext& ctx) override;
    void doUpdate(const FrameContext& ctx) override;
    void doRender(const FrameContext& ctx) override;
    /// ScenePass::Surfaces: the clouds' shadows over the host's scene (clouds_scene.frag.glsl).
    void doApplyToScene(const FrameContext& ctx, ScenePass pass) override;
    void doResize(int w, int h) override;
    void doRelease() override;
    void doStats(nlohmann::json& root) const override;
    void doValidateOptions(const SkyVars& vars) const override;

    void applyPreset(SkyVars& v);
    void bindResources(const FrameContext& ctx);
    void setUniforms(const gl::Program& p, const FrameContext& ctx) const;
    void computePhotometry(const FrameContext& ctx);
    gl::ProgramBuilder recipe(bool stats, bool reproject, int lights) const;
    /// The lights the march computes (CLD_LIGHTS: bit 0 the Sun, bit 1 the Moon): those that light
    /// the layer (cloudcpu::lightDarkElevation) and, for the Moon, carry at least 1e-4 of the
    /// Sun's light at the observer (setUniforms zeroes it otherwise).
    int marchedLights(const SkyVars& v) const;
    void renderCached(const FrameContext& ctx);

    generators::SkyLuts luts_;
    // One program per CLD_LIGHTS variant (marchedLights), compiled on first use: a SIMD machine
    // runs a branch whenever one lane takes it (llvmpipe runs every branch), so a light switched
    // off by a uniform still cost its march; a variant without it costs nothing.
    std::array<gl::ProjectionPrograms, 4> programs_;
    std::array<gl::Program, 4> statsProgram_;
    gl::Buffer atmUbo_, cloudUbo_;
    gl::Texture2D statsTex_;
    gl::Framebuffer statsFbo_;
    Photometry photometry_;
    glm::dvec3 groundE_{0.0};  // the ground's global illuminance under the clouds, lux per channel (the bases' light from below)
    std::vector<double> photometryInputs_;
    struct PhotometryLast {  // the moving inputs of the last photometry pass (compared by tolerance)
        glm::dvec3 sunDir{0.0}, moonDir{0.0}, sunE{0.0}, moonE{0.0}, skyE{0.0};
        glm::dvec2 offset{0.0};
    } photometryLast_;
    int photometryAge_ = 0;   // frames since the last photometry pass
    int photometryRuns_ = 0;  // photometry passes since construction (tests count them)
    // Real time: a photometry refresh spread over frames, one stats pass (a march of the 16 x 16
    // hemisphere and its read-back) a frame: the ground with no light from below, the ground lit
    // by the clear sky, then (an observer above 1 m) the observer's height. The photometry shown
    // is the last complete one until the last pass (issue 22 items 4-5).
    struct PhotometryPass {
        glm::dvec3 meanL{0.0};
        double meanT = 0, sunT = 1, moonT = 1;
    };
    struct PhotometryStaged {
        int next = 0;  // the next pass: 0 none under way, 1 the ground lit by the clear sky, 2 at the observer's height
        glm::dvec3 sunD{0.0}, moonD{0.0}, diffuseE{0.0}, clearG{0.0}, ground{0.0};
        double hObs = 0;
        PhotometryPass p0, p1;
    } staged_;
    int photometryPassesLast_ = 0;  // stats passes in the last render()
public:
    /// Real time: a photometry pass that only the lights' motion, their illuminances or the wind
    /// asked for runs at most once in this many frames (skyelements/clouds/README.md, "Time running").
    static constexpr int kPhotometryFrames = 8;
    /// Photometry passes run since construction (a refresh spread over frames counts once, at its start).
    int photometryRuns() const { return photometryRuns_; }
    /// Stats passes (each a march of the photometry's hemisphere with a read-back) in the last
    /// render(): 2 or 3 for a whole photometry, at most 1 in real time once one is valid.
    int photometryPassesLastFrame() const { return photometryPassesLast_; }
    /// Real time: a photometry refresh is under way (its passes spread over frames).
    bool photometryPending() const { return staged_.next > 0; }
    /// The direction cache's work in the last render() (counted, not timed): Bayer phases of
    /// 1/cache_frames of its texels each that were marched (cache_frames: a whole fill; 1: the
    /// running refresh, or one phase of a refill after a jump; 0: no real-time path).
    int cachePhasesLastFrame() const { return cachePhasesLast_; }
    /// Refills after a jump of the Sun started so far, and whether one is under way.
    int cacheJumpRefills() const { return cacheJumpRefills_; }
    bool cacheRefilling() const { return backPhase_ >= 0; }
    /// The drawn direction cache's radiance and transmittance texels (RGBA16F read back as float;
    /// tests: a cache refilled over frames against one filled whole).
    std::vector<float> readCache(bool transmittance) const { return (transmittance ? cacheT_ : cacheL_).readRgbaFloat(); }

private:
    bool drew_ = false;
    // The real-time path (clouds.reprojection): the direction cache (radiance, transmittance),
    // its fill and display programs, the phase of the next partial refresh, and the inputs of the
    // last full fill (a change of any refills it at once).
    gl::Program scenePass_;  // applyToScene()'s shadow pass
    gl::Texture2D cacheL_, cacheT_;
    int cacheRadianceUnit_ = 0, cacheTransmittanceUnit_ = 0;  // private texture units (SkyElement::textureUnit)
    std::array<gl::Program, 4> cacheFill_;
    gl::ProjectionPrograms cacheShow_;
    int cachePhase_ = 0;
    std::vector<double> cacheInputs_;
    // The refill after a jump of the Sun: the second pair of textures, the next Bayer phase to
    // march into them (-1: none under way).
    gl::Texture2D backL_, backT_;
    int backPhase_ = -1;
    int cachePhasesLast_ = 0;
    int cacheJumpRefills_ = 0;
    // Preset bookkeeping: per preset-driven key, the version after the element last wrote it (0:
    // never written by the element).
    std::string appliedPreset_;
    std::vector<std::pair<std::string, uint64_t>> written_;
};

}  // namespace welkin::elements
