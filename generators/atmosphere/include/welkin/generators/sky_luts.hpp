// The sky's LUT generators (Hillaire 2020 style, horizon-dense): each a GPU pass with a CPU
// double-precision twin in sky_model.hpp, each a welkin::Generator that runs only when its
// declared inputs changed, each shared between elements through SkyVars.
//
//   auto luts = welkin::generators::SkyLuts::obtain(vars);   // shared: one set per SkyVars
//   element.addGenerator(luts.transmittance); ...             // the processor runs them when due
//   // or by hand, with a context current:
//   luts.transmittance->runIfDue(vars, log);
//   welkin::TextureRef t = vars.get(welkin::generators::skykeys::transmittanceLut);
//
// Chain and inputs (a generator re-runs when any input's version changed):
//   TransmittanceLut      <- sky.atmosphere, sky.quality                       (256x64 medium)
//   MultiScatteringLut    <- sky.atmosphere, sky.quality, sky.transmittance_luts (32x32)
//   LightZenith           <- sun.direction, moon.direction, lights.moon_illuminance (CPU)
//   SkyViewLut (Sun)      <- ..., sky.multiscattering_luts, sky.sun_cos_zenith, observer.height_m
//   SkyViewLut (Moon)     <- ..., sky.moon_cos_zenith, sky.moon_lit, observer.height_m
//   AerialPerspectiveLut  <- ..., sky.sun_cos_zenith, observer.height_m          (32^3)
//   SkyIrradiance         <- the sky views, light illuminances, cos zeniths
// The Sun- and Moon-dependent tables depend on the light's elevation only (cos zenith, change
// tolerance kCosZenithTolerance; the azimuth from the light is applied per pixel). While the
// light moves they are built as keyframes at elevations on a grid (SkyQuality::keyframeStepRad),
// each over several frames into its own texture set and kept (a cache over the elevations the
// light visits), and the shown tables are blended from up to four complete keyframes each run
// (Catmull-Rom in elevation, LightKeyframes, light_keyframes.hpp): a generator with work left
// asks to run again (Generator::runAgain()).
// A generator that rewrites a texture in place republishes its key (SkyVars::publish), which
// bumps the key's version: its readers (which name the texture key as an input) run again.
// The sky-view and aerial-perspective values are radiance per lux of the light's illuminance
// (times kLutScale), so one LUT serves any light intensity and colour: multiply by the light's
// per-channel illuminance (sky.sun_illuminance / sky.moon_illuminance, lux) to get cd/m^2.
//
// Spectral mode (sky.wavelengths = N > 3, sky_spectral.hpp): every pass runs once per wavelength
// triple k with that triple's coefficients in the atmosphere block. The transmittance,
// multiple-scattering and SH LUTs keep one texture per triple (sky.*_luts, read by the passes
// after them); the sky views and the aerial-perspective volume are accumulated, through the
// triple's 3x3 matrix, into the same single RGB textures as in RGB mode, and
// sky.transmittance_lut holds the combined (solar-weighted) transmittance. So the Sky's per-pixel
// cost is unchanged and the LUT cost is about N/3 times RGB's.
#pragma once
#include <welkin/element.hpp>
#include <welkin/generators/detail/light_keyframes.hpp>
#include <welkin/generators/lights.hpp>
#include <welkin/generators/sky_model.hpp>
#include <welkin/generators/sky_spectral.hpp>
#include <welkin/gl/objects.hpp>

#include <algorithm>
#include <cmath>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace welkin::generators {

/// Stored LUT values are radiance per lux times this factor (keeps fp16 LUTs out of subnormals
/// for daylight and civil twilight).
inline constexpr double kLutScale = 1e4;

namespace skykeys {
/// Quality preset of the sky passes: -1 follows render.quality, else 0 low .. 3 reference (an
/// option of the Sky element). effectiveQuality() resolves it.
inline const EnumKey<int> quality{"sky.quality", {{"auto", -1}, {"low", 0}, {"medium", 1}, {"high", 2}, {"reference", 3}}, "sky quality preset: auto (follows render.quality), low, medium, high or reference (levels -1..3 in C++)"};
/// The Moon as a second light of the sky (an option of the Sky element).
inline const Key<bool> moonLight{"sky.moon", "the Moon lights the sky (false: Sun only)"};
/// The Sky's option: the aerial-perspective volume is built (for a host's geometry:
/// elements::AerialPerspective) only while this is true.
inline const Key<bool> aerialVolume{"sky.aerial_volume", "build the aerial-perspective volume for the host's geometry (AerialPerspective)"};
/// Once time runs, the Sky builds every keyframe table of the light's elevation grid in the
/// background (the prefill, skyelements/sky/README.md "While time runs"): at most this many parts of a table
/// per frame (a table has SkyQuality::keyframeChunks parts: 4 low, 12 medium, 48 high; one
/// medium part is ~3 ms on llvmpipe), beyond what keeping pace with the light needs. 0: the
/// whole prefill in the first frame in which the light moves (a freeze of seconds on llvmpipe).
/// Unset: kKeyframeBudgetDefault.
inline const Key<int> keyframeBudget{"sky.keyframe_budget", Range{0, 1000},
                                     "keyframe table parts built per frame in the background once time runs (0: all at the first moving frame)"};
/// The Sun's sky-view keyframe tables of the elevation grid (from -20 deg up) are written to the
/// disk cache (welkin::cacheDirectory(), folder sky-keyframes-<hash of the atmosphere, quality,
/// observer height, shaders and GL renderer>) as they are built, and read back into the GPU at
/// the first run of a later processor with the same hash (a one-time cost in that first frame,
/// measured in skyelements/sky/README.md), so that when time starts the grid is there and running costs only
/// the per-frame mix. Unset: true. false: neither read nor written.
inline const Key<bool> keyframeCache{"sky.keyframe_cache", "read and write the Sun's keyframe tables in the disk cache (skyelements/sky/README.md, While time runs)"};
inline const Key<TextureRef> transmittanceLut{"sky.transmittance_lut", "transmittance LUT (RGB, to the top of the atmosphere)"};
/// One texture per wavelength triple (RGB mode: one), for the passes after them; in spectral
/// mode sky.transmittance_lut is the combined one and sky.multiscattering_lut / sky.sh_lut are
/// triple 0's.
using TextureList = std::shared_ptr<const std::vector<TextureRef>>;
inline const Key<TextureList> transmittanceLuts{"sky.transmittance_luts", "transmittance LUT per wavelength triple"};
inline const Key<TextureList> multiScatteringLuts{"sky.multiscattering_luts", "multiple-scattering LUT per wavelength triple"};
inline const Key<TextureList> shLuts{"sky.sh_luts", "directional multiple-scattering LUT per wavelength triple"};
inline const Key<TextureRef> multiScatteringLut{"sky.multiscattering_lut", "multiple-scattering LUT (Hillaire Psi_ms)"};
inline const Key<TextureRef> shLut{"sky.sh_lut", "directional multiple scattering: SH l<=L of the incident field (2D array, layers 0..n-1) and the ground's sky irradiance (layer n, row 0)"};
inline const Key<TextureRef> sunViewLut{"sky.sun_view_lut", "sky-view LUT for the Sun: Rayleigh + multiple scattering + ground"};
inline const Key<TextureRef> sunViewMieLut{"sky.sun_view_mie_lut", "sky-view LUT for the Sun: Mie single scattering without phase"};
inline const Key<TextureRef> sunViewTotalLut{"sky.sun_view_total_lut", "sky-view LUT for the Sun: everything, Mie phase at the texel's angle"};
/// Transmittance observer -> top of the atmosphere along each sky-view latitude (1-D, N = 4 x the
/// sky view's height; 0 on the ground half), sampled with the sky view's v. Written with the Sun's view.
inline const Key<TextureRef> viewTransmittanceLut{"sky.view_transmittance_lut", "transmittance to the top along each sky-view latitude (1-D)"};
inline const Key<TextureRef> moonViewLut{"sky.moon_view_lut", "sky-view LUT for the Moon (smooth part)"};
inline const Key<TextureRef> moonViewMieLut{"sky.moon_view_mie_lut", "sky-view LUT for the Moon (Mie without phase)"};
inline const Key<TextureRef> moonViewTotalLut{"sky.moon_view_total_lut", "sky-view LUT for the Moon: everything, Mie phase at the texel's angle"};
/// The direct light's shadow on the in-scattering (optional; published by a shadow's generator,
/// e.g. the clouds' generators::CloudSkyShadow; absent: the sky is unshadowed and pays nothing).
/// The single scattering (and the directly lit ground) that the shadow removes, per lux of the
/// light x kLutScale, over absolute azimuth u = az / 2 pi (az from north through east; wrap
/// repeat) and the sky view's latitude v (skyViewUvS().y); the Sky element subtracts it from the
/// light's sky-view radiance. R: Rayleigh with its phase and the ground; Mie: without its phase.
inline const Key<TextureRef> shadowLossLut{"sky.shadow_loss_lut", "single scattering removed by the direct light's shadow (clouds): Rayleigh + ground, absolute azimuth"};
inline const Key<TextureRef> shadowLossMieLut{"sky.shadow_loss_mie_lut", "single scattering removed by the direct light's shadow: Mie without phase, absolute azimuth"};
/// Which light sky.shadow_loss_lut shadows: false the Sun, true the Moon.
inline const Key<bool> shadowLossMoon{"sky.shadow_loss_moon", "sky.shadow_loss_lut is the Moon's (false: the Sun's)"};
/// A solar eclipse's sky (EclipseSkyLut): the Sun's sky-view tables over the whole circle of
/// azimuth, u = az / 2 pi (az from north through east, wrap repeat), v the sky view's latitude
/// (skyViewUvS().y), every ray seeing the Moon's shadow; per lux of the Sun x kLutScale. R: Rayleigh
/// with its phase, multiple scattering and the ground; Mie: without its phase. id 0 while the
/// shadow is nowhere near the visible air (the Sky then reads the ordinary sky view: no cost).
inline const Key<TextureRef> eclipseViewLut{"sky.eclipse_view_lut", "solar eclipse: the Sun's sky view over absolute azimuth, in the Moon's shadow (id 0: no eclipse)"};
inline const Key<TextureRef> eclipseViewMieLut{"sky.eclipse_view_mie_lut", "solar eclipse: Mie single scattering without phase, absolute azimuth"};
inline const Key<TextureRef> eclipseViewTotalLut{"sky.eclipse_view_total_lut",
                                                 "solar eclipse: the Sun's sky view with the Mie phase at each texel's angle, absolute azimuth"};
inline const Key<TextureRef> aerialInscatter{"sky.aerial_inscatter", "aerial perspective volume: in-scattered radiance per lux x kLutScale"};
inline const Key<TextureRef> aerialTransmittance{"sky.aerial_transmittance", "aerial perspective volume: transmittance"};
/// Horizontal illuminance at the observer, lux: (global, direct, diffuse); Sun and Moon.
inline const Key<glm::dvec3> horizontalIlluminance{"sky.horizontal_illuminance", Range{0, 1e7}, "global, direct, diffuse horizontal illuminance, lux"};
/// Diffuse sky irradiance on a horizontal surface per channel (lux; an ambient term for hosts).
inline const Key<glm::dvec3> diffuseIrradiance{"sky.diffuse_irradiance", Range{0, 1e7}, "diffuse horizontal illuminance per channel, lux"};
/// Zenith luminance, cd/m^2.
inline const Key<double> zenithLuminance{"sky.zenith_luminance", Range{0, 1e9}, "zenith luminance, cd/m^2"};
/// The lights' elevations as the sky's tables see them (LightZenith): the sky views, the aerial
/// perspective and the irradiance depend on these, not on the full directions (the azimuth from
/// the light is applied per pixel), so a pure azimuth change rebuilds nothing.
inline const Key<double> sunCosZenith{"sky.sun_cos_zenith", Range{-1, 1}, "cos zenith of the Sun (sun.direction.z)"};
inline const Key<double> moonCosZenith{"sky.moon_cos_zenith", Range{-1, 1}, "cos zenith of the Moon (moon.direction.z)"};
inline const Key<bool> moonLit{"sky.moon_lit", "the Moon lights the sky (illuminance > 0)"};
}  // namespace skykeys

/// Change tolerance of the sky's tables on the lights' cos zenith: 2e-5 is 0.0011 deg of
/// elevation at the horizon (where a degree changes the twilight sky by up to ~x2, so at most
/// ~0.1 % of staleness; the Sun's disk is 0.53 deg wide) and less higher up.
inline constexpr double kCosZenithTolerance = 2e-5;
/// Below this cos zenith (-20 deg of elevation) a light's sky-view tables are black (SkyViewLut).
inline constexpr double kDarkBelowCosZenith = -0.342;
/// Runs a light must stay within kCosZenithTolerance of one elevation before its exact table is
/// built (LightKeyframes::Options::stillRuns): a third of a second at 60 frames per second, so a
/// Sun drifting at 1 s/s (up to 7e-5 in cos zenith per second) is shown through the grid tables.
inline constexpr int kKeyframeStillRuns = 20;
/// skykeys::keyframeBudget when unset: table parts per frame.
inline constexpr int kKeyframeBudgetDefault = 2;

/// Keyframe tables kept at most per light-dependent generator (LightKeyframes::Options::slots)
/// for a quality's grid (SkyQuality::keyframeStepRad, keyframeCoarseStepRad): its grid points
/// from -20 deg to +90 deg of elevation (deeper, the Sun's sky is below the night sky's airglow)
/// plus 6 (exact tables, margin); beyond, the least recently used are rebuilt when needed again.
/// `current`: keyframes whose grid is reused when it is this quality's (no grid is built: the
/// generators ask every frame).
inline int keyframeSlots(const SkyQuality& q, const LightKeyframes* current = nullptr) {
    const LightKeyframes::Options o{.stepRad = q.keyframeStepRad, .coarseStepRad = q.keyframeCoarseStepRad};
    const bool same = current && !current->grid().empty() && current->options().stepRad == o.stepRad &&
                      current->options().coarseStepRad == o.coarseStepRad && current->options().fineTopRad == o.fineTopRad;
    std::vector<double> fresh;
    if (!same) fresh = LightKeyframes::makeGrid(o);
    int n = 6;
    for (double e : same ? current->grid() : fresh) n += e >= -0.3491;
    return n;
}

/// Publishes the lights' cos zenith (skykeys::sunCosZenith, moonCosZenith) and whether the Moon
/// gives light (moonLit) from their directions and illuminance; CPU, microseconds. Shared.
class LightZenith final : public Generator {
public:
    LightZenith();
    static std::shared_ptr<LightZenith> obtain(SkyVars& vars);

private:
    void doRun(SkyVars& vars, const Logger& log) override;
};

/// The preset the sky passes use: sky.quality if >= 0, else render.quality (default medium).
int effectiveQuality(const SkyVars& vars);

/// std140 mirror of the WelkinAtmosphere block in atmosphere.glsl (binding 1).
struct AtmosphereBlock {
    glm::vec4 radii;
    glm::vec4 rayleigh;
    glm::vec4 mieScattering;
    glm::vec4 mieExtinction;
    glm::vec4 absorption;
    glm::vec4 groundAlbedo;
    glm::vec4 solarIlluminance;
    glm::vec4 shFactors;   ///< Mie band factors l = 1, 2; Rayleigh's l = 2; delta-M fraction f (cpu::PhaseMoments)
    glm::vec4 profiles[9];
    glm::vec4 shFactors2;  ///< Mie band factors l = 3 .. 6 (0 beyond the SH bands)
    /// The block for `m` with the SH convolution factors of `shBands` bands (SkyQuality::shBands).
    static AtmosphereBlock from(const SkyModel& m, int shBands);
};

/// Quality and model resolution shared by the sky generators.
class SkyGenerator : public Generator {
public:
    /// With `fixed`, the generator always uses that preset (tests); else sky.quality.
    void setFixedQuality(std::optional<SkyQuality> q) { fixed_ = q; }
    /// The preset used by the last run.
    const SkyQuality& quality() const { return q_; }
    const SkyModel& model() const { return model_; }
    /// The spectral sampling of the last run (null in RGB mode).
    const std::shared_ptr<const SpectralSampling>& spectral() const { return spectral_; }
    /// Frees GL resources (call with the context current before the context goes away).
    virtual void releaseGl() = 0;

protected:
    explicit SkyGenerator(std::string name);
    /// Resolves the model, quality and wavelengths from vars; uploads the atmosphere block
    /// (binding 1) of the RGB model (or of triple 0 in spectral mode).
    void prepare(SkyVars& vars);
    /// Number of passes: 1 in RGB mode, N/3 in spectral mode.
    int triples() const { return spectral_ ? spectral_->triples() : 1; }
    /// Uploads the atmosphere block of triple k (spectral mode; no-op in RGB mode).
    void useTriple(int k);
    /// Spectral mode: dst (+)= toRgb[k] * src over the whole texture (2D or 3D, same size;
    /// dst's format rgba16f or rgba32f); overwrite for k = 0, clamp at 0 after the last triple.
    void combine(const gl::Texture& src, const gl::Texture& dst, int k);
    void fullscreen() const;
    SkyModel model_;
    /// The atmosphere model_ was derived from (immutable, held so its address stays unique): the
    /// RGB conversion (through the CIE observer) runs only when it changes, not every run.
    std::shared_ptr<const atmosphere::Atmosphere> modelFor_;
    bool modelDefault_ = false;
    SkyQuality q_;
    std::optional<SkyQuality> fixed_;
    std::shared_ptr<const SpectralSampling> spectral_;
    gl::Buffer ubo_;
    gl::VertexArray vao_;
    gl::Program combine2D16_, combine2D32_, combine3D32_;
    void releaseCommon() {
        ubo_ = {};
        vao_ = {};
        combine2D16_ = {};
        combine2D32_ = {};
        combine3D32_ = {};
    }

private:
    void doRelease() override { releaseGl(); }
    void doDeclare(SkyVars& vars) override;
    std::shared_ptr<const atmosphere::Atmosphere> spectralFor_;  // cache key of spectral_
};

class TransmittanceLut final : public SkyGenerator {
public:
    TransmittanceLut();
    /// RGB mode: the LUT; spectral mode: the combined (solar-weighted) transmittance.
    const gl::Texture2D& texture() const { return tex_; }
    /// Spectral mode: triple k's LUT (k < N/3); RGB mode: texture().
    const gl::Texture2D& tripleTexture(int k) const { return spectral_ ? triples_.at(size_t(k)) : tex_; }
    void releaseGl() override;

private:
    void doRun(SkyVars& vars, const Logger& log) override;
    gl::Texture2D tex_;
    std::vector<gl::Texture2D> triples_;
    gl::Framebuffer fbo_;
    gl::Program prog_;
};

class MultiScatteringLut final : public SkyGenerator {
public:
    MultiScatteringLut();
    /// Triple k's LUT (spectral mode; k = 0 in RGB mode).
    const gl::Texture2D& texture(int k = 0) const { return k == 0 ? tex_ : more_.at(size_t(k - 1)); }
    void releaseGl() override;

private:
    void doRun(SkyVars& vars, const Logger& log) override;
    gl::Texture2D tex_;
    std::vector<gl::Texture2D> more_;  // triples 1.. (spectral mode)
    gl::Program prog_;
};

/// Directional multiple scattering (SkyQuality::directionalMs): SH l <= L (SkyQuality::shBands)
/// of the incident radiance field at (h, mu_s) in layers 0 .. n - 1 (n = cpu::shCoefficients(L):
/// 15 at L = 4, 28 at L = 6), and in layer n (row 0) the sky's irradiance on the ground over mu_s
/// (cpu::MsField::ground); read on texture unit 8 by the passes after it.
class ShLut final : public SkyGenerator {
public:
    ShLut();
    /// Triple k's published field (spectral mode; k = 0 in RGB mode): the second pass's when
    /// SkyQuality::shIterations > 0.
    const gl::Texture2DArray& texture(int k = 0) const;
    void releaseGl() override;

private:
    void doRun(SkyVars& vars, const Logger& log) override;
    std::vector<gl::Texture2DArray> first_;  ///< first pass, per triple
    std::vector<gl::Texture2DArray> iter_;   ///< second pass per triple (SkyQuality::shIterations)
    gl::Program prog_;
    gl::Program iterProg_;
    gl::Program iterGroundProg_;
    gl::Texture2D ground_;  ///< the sky's irradiance on the ground over mu_s (w x 1)
    gl::Framebuffer groundFbo_;
    gl::Program groundProg_;
};

enum class Light { Sun, Moon };

/// Sky-view LUT seen from the observer for one light: two textures (smooth part with phase,
/// Mie single scattering without phase), azimuth measured from the light, [0, pi].
class SkyViewLut final : public SkyGenerator {
public:
    explicit SkyViewLut(Light light);
    const gl::Texture2D& smoothTexture() const { return smooth_; }
    const gl::Texture2D& mieTexture() const { return mie_; }
    /// smooth + Mie x phase(angle of the texel's direction to the light).
    const gl::Texture2D& totalTexture() const { return total_; }
    /// Sun only: transmittance to the top along each latitude (1-D, see viewTransmittanceLut).
    const gl::Texture1D& viewTransmittanceTexture() const { return viewT_; }
    /// Height and light cos-zenith of the last run (h clamped into the atmosphere).
    double height() const { return h_; }
    double lightMuS() const { return muS_; }
    /// The tables built at given elevations and shown while the light moves (see
    /// light_keyframes.hpp), and the last run's plan.
    const LightKeyframes& keyframes() const { return keyframes_; }
    const LightKeyframes::Plan& lastPlan() const { return plan_; }
    /// Forgets every table: the next run builds one at exactly the light's elevation.
    void resetKeyframes() { keyframes_.reset(); }
    void releaseGl() override;

private:
    void doRun(SkyVars& vars, const Logger& log) override;
    Light light_;
    /// Shown tables (written by the blend pass); each keyframe slot: smooth and Mie with its
    /// framebuffer.
    gl::Texture2D smooth_, mie_, total_;
    // A keyframe: the six log radiances of a texel (smooth and Mie, RGB) packed at 21 bits each
    // into one RGBA32UI texel (light_blend.glsl), so the blend fetches one texel per table.
    struct Slot {
        gl::Texture2D packed;
    };
    // Where a keyframe is built (radiance, fp32) before it is packed: one for the table built
    // over several runs, one for tables built whole in one run (a jump, the prefill).
    struct Scratch {
        gl::Texture2D smooth, mie;
        gl::Framebuffer fbo;
    };
    std::vector<Slot> slots_;
    Scratch chunkScratch_, wholeScratch_;
    gl::Framebuffer showFbo_;
    gl::Program blendProg_;
    gl::Program toLogProg_;  // a complete keyframe packed (light_blend.glsl, KEYFRAME_PACK)
    LightKeyframes keyframes_;
    LightKeyframes::Plan plan_;
    bool shownOnce_ = false;  // the shown table holds a mix (Plan::unchanged may keep it)
    bool darkShown_ = false;  // the shown table is black (the light far below the horizon)
    bool shownBlack_ = false;  // the shown table was cleared black since it was allocated (valid content)
    std::vector<uint64_t> validFor_;  // input versions the keyframes were built with
    double viewTH_ = -1.0;
    uint64_t viewTVersion_ = 0;
    gl::Texture1D viewT_;  // Sun only: transmittance along each latitude (viewTransmittanceLut)
    gl::Program viewTProg_;
    gl::Texture2D smoothK_, mieK_, totalK_;  // spectral mode: one triple's pass, before combine()
    gl::Framebuffer fboK_;
    gl::Program prog_;
    int progBands_ = 0;  // SkyQuality::shBands prog_ was compiled for
    double h_ = 0.0, muS_ = 1.0;
    // The disk cache of the grid tables (skykeys::keyframeCache; Sun, RGB mode, prefill presets).
    bool preloadDue_ = true;     // the keyframes were reset: read the cache at the next lit run
    std::string cacheFolder_;    // this run's folder ("" : no cache)
    int cacheReads_ = 0, cacheWrites_ = 0;
    std::string cacheFolder(const SkyVars& vars) const;
    void preloadFromCache(const Logger& log);
    void writeToCache(int slot);
    // Interactive (render.interactive): the whole grid at the first run, the mix in halves.
    bool loadFilled_ = false;  // the grid was completed (read or built) at the first run
    int loadBuilt_ = 0;        // grid tables built at load (not found in the disk cache)
    int staleHalf_ = -1;       // the half of the shown table still at the previous run's mix (-1: none)
    int nextHalf_ = 0;         // the half the next half mix does
    double lastMixMuS_ = 2.0;  // cos zenith of the last mix
    int halfMixes_ = 0;
    // Interactive, the Moon while the Sun is up: its mix paced (kMoonDaylightMixEvery).
    uint64_t planGen_ = 0;           // plans that changed the shown table since pacing began
    uint64_t pacedGen_[2] = {0, 0};  // the plan each half was last mixed for
    int pacedRuns_ = 0;              // runs since the last paced half mix

public:
    /// A moving light's mix is done a half table per run (interactive) when the light has moved
    /// at most this far in elevation since the last mix (0.25 deg; time at 1440x moves the Sun
    /// by up to 0.2 deg per frame at 30 frames/s), rad.
    static constexpr double kHalfMixRad = 0.25 * 3.14159265358979323846 / 180.0;
    /// Interactive, the Moon while the Sun is above the horizon: one half of its table is mixed
    /// every this many runs (its sky is then below ~1e-4 of the Sun's).
    static constexpr int kMoonDaylightMixEvery = 4;
    /// Interactive: a table is built in at least SkyQuality::keyframeChunks x this many parts.
    static constexpr int kInteractiveChunkFactor = 4;
    /// Interactive: and in parts of at most this many texel-samples (texels x SkyQuality::skyViewSteps):
    /// 108 texels at medium (192 parts of its 192x108x32), 54 at high (911 parts), so that a part
    /// of a resting light's exact table (~0.2 ms at medium on llvmpipe, quiet) keeps the frame
    /// within 3 still frames at 512x256 (issue 22 item 4).
    static constexpr long kInteractivePartWork = 3456;
    /// The parts of a table in an interactive session: max(keyframeChunks x kInteractiveChunkFactor,
    /// ceil(W x H x steps / kInteractivePartWork)). Part c of n is the texels [c W H / n, (c + 1) W H / n)
    /// in row order (rows from the bottom), so parts cross rows; the texels are the same whatever the
    /// parts (each is computed from gl_FragCoord alone): a table built in parts is bit for bit the
    /// table built whole.
    static int interactiveChunks(const SkyQuality& q);
    /// Grid tables built whole at the first run of an interactive session (not in the disk cache).
    int loadBuiltTables() const { return loadBuilt_; }
    /// Runs whose mix covered only half of the table (interactive, a moving light).
    int halfMixes() const { return halfMixes_; }
    /// The half of the shown table (0: rows [0, H/2), 1: [H/2, H)) one run behind the light, -1: none.
    int staleHalf() const { return staleHalf_; }
    /// Tables read from and written to the disk cache (sky.keyframe_cache) since construction.
    int cacheReads() const { return cacheReads_; }
    int cacheWrites() const { return cacheWrites_; }
};

/// Aerial perspective volume, camera-independent: (azimuth from the Sun, horizon-dense
/// latitude, distance with quadratic slices up to SkyQuality::aerialMaxDistance). In-scattered
/// radiance per lux x kLutScale, and transmittance; Sun only.
class AerialPerspectiveLut final : public SkyGenerator {
public:
    AerialPerspectiveLut();
    const gl::Texture3D& inscatter() const { return inscatter_; }
    const gl::Texture3D& transmittance() const { return transmittance_; }
    const LightKeyframes& keyframes() const { return keyframes_; }
    const LightKeyframes::Plan& lastPlan() const { return plan_; }
    void resetKeyframes() { keyframes_.reset(); }
    void releaseGl() override;

private:
    void doRun(SkyVars& vars, const Logger& log) override;
    gl::Texture3D inscatter_, transmittance_;  // shown (blend pass)
    std::vector<gl::Texture3D> slots_;  // keyframes: log in-scattering (the transmittance is the shown one's)
    gl::Program blendProg_;
    gl::Program toLogProg_;
    LightKeyframes keyframes_;
    LightKeyframes::Plan plan_;
    bool shownOnce_ = false;
    std::vector<uint64_t> validFor_;
    gl::Texture3D inscatterK_, transmittanceK_;  // spectral mode: one triple's pass
    gl::Program prog_;
    int progBands_ = 0;  // SkyQuality::shBands prog_ was compiled for
};

/// The eclipse table is rebuilt when the shadow's axis has moved this far across the observer's
/// air since the last build (m; ~2 s of the shadow's motion): at >= 60 km, where the horizon sees
/// the umbra's edge, that is <= 2 deg, about one texel of the table's azimuth.
inline constexpr double kEclipseRebuildMeters = 2e3;
/// Rebuilds of the eclipse table are spread over this many frames (rows in bands), the old table
/// shown meanwhile; a jump of the shadow by more than kEclipseJumpMeters between two runs (time
/// set, not running) rebuilds it whole at once. (Before 2026-11-28 the jump was measured from the
/// table shown, so time running at 60x, ~1 km a frame, rebuilt it whole every ~50 frames.)
inline constexpr int kEclipseTimeSlices = 32;
/// With the frame's size known (EclipseSkyLut::setFramePixels: the Sky element sets it), the bands
/// are made thinner on small frames so that a band costs at most about half a frame: a band
/// texel (a ray march with the shadow at every step) costs llvmpipe ~7 us of CPU, a frame pixel of
/// the ordinary sky ~0.05 us (docs/eclipse.md, "Frame cost"), so a band holds at most
/// pixels / kEclipseBandPixelsPerTexel texels; at least kEclipseTimeSlices and at most
/// kEclipseMaxTimeSlices bands (tiles of rows and, beyond the table's height, of columns).
inline constexpr double kEclipseBandPixelsPerTexel = 300.0;
inline constexpr int kEclipseMaxTimeSlices = 512;
/// While time runs, a rebuild's multiple-scattering field (cpu::EclipseMsTableBuilder) is built in
/// runs of its own before the first band, each at most about a tenth of a frame: the table costs
/// about what the ordinary sky's frame of ~34,000 pixels costs (2.2 ms of CPU against 0.5-0.7 ms
/// for 160 x 90, docs/eclipse.md "Frame cost"), so EclipseSkyLut::fieldPiecesFor(pixels) =
/// ceil(kEclipseFieldPixels / pixels) pieces, at most kEclipseMaxFieldPieces (the builder's largest
/// unit of work is ~4 % of the table): 24 at 160 x 90, 6 at 320 x 180, 2 at 640 x 360, 1 (the
/// table in the first band's run, as before) at 1280 x 720. (A fifth of a frame, 170e3, measured
/// 1.32x and 1.44x a normal frame at 160 x 90 and 320 x 180: too near the 1.5x target.)
inline constexpr double kEclipseFieldPixels = 340e3;
inline constexpr int kEclipseMaxFieldPieces = 24;
/// The texture unit of the eclipse's multiple-scattering field (shares 9 with the SH pass's ground
/// input and the clouds' shadow map, gl::binding: never bound together with them).
inline constexpr int kEclipseMsFieldUnit = 9;
inline constexpr double kEclipseJumpMeters = 50e3;
/// The Sun's radius, m (IAU nominal).
inline constexpr double kSunRadiusMeters = 6.957e8;
/// The Moon's shadow on the air (docs/eclipse.md): while the shadow's penumbra can reach air that a
/// sky-view ray crosses (the Sun-Moon separation seen from the observer below the sum of their
/// radii plus the parallax of the farthest such air), the Sun's sky over the whole circle of
/// azimuth with every ray's points seeing their own Sun and Moon (eclipse_lut.glsl), rebuilt when
/// the shadow has moved kEclipseRebuildMeters (its multiple-scattering field in fieldPiecesFor()
/// runs, then bandsFor() bands over as many runs, the previous table shown meanwhile; built for
/// the shadow's position extrapolated to the run that will show it); publishes skykeys::eclipseViewLut (id 0 otherwise: nothing runs on the GPU). RGB mode only
/// (spectral mode: the ordinary sky view). Inputs: the Sun's direction and distance,
/// moon.position_m, astro.eclipses.
class EclipseSkyLut final : public SkyGenerator {
public:
    EclipseSkyLut();
    const gl::Texture2D& smoothTexture() const { return smooth_; }
    const gl::Texture2D& mieTexture() const { return mie_; }
    const gl::Texture2D& totalTexture() const { return total_; }
    /// Whether the last run built the tables (an eclipse near).
    bool active() const { return active_; }
    void releaseGl() override;
    /// The activation test: the Sun's apparent direction `sunDir`, its angular radius, the Moon's
    /// position from the observer (m), the farthest air a ray reaches (m).
    static bool shadowNear(const glm::dvec3& sunDir, double sunAngularRadius, const glm::dvec3& moonPos, double reachMeters);
    /// Binds the multiple-scattering field of the table now shown (texture unit
    /// kEclipseMsFieldUnit) and sets its uniforms on `p` (a program with ATM_ECLIPSE).
    void bindMsField(const gl::Program& p) const;
    /// The CPU field of the table now shown.
    const cpu::EclipseMsTable& msTable() const { return shownMs_; }
    /// Full rebuilds and time-sliced bands rendered so far (bench and tests).
    int rebuilds() const { return rebuilds_; }
    /// Whether a time-sliced rebuild is in progress (bands still to render).
    bool building() const { return nextBand_ >= 0; }
    /// Bands per rebuild while the shadow moves smoothly (default kEclipseTimeSlices; 1: every
    /// rebuild whole at once), [1, table height].
    void setTimeSlices(int n) {
        slices_ = std::max(n, 1);
        explicitSlices_ = true;
    }
    /// The frame's pixels (the Sky element's camera): unless setTimeSlices() fixed the bands,
    /// a rebuild is spread over bandsFor(pixels) bands (kEclipseBandPixelsPerTexel).
    void setFramePixels(long pixels) { framePixels_ = pixels; }
    /// The bands a rebuild of a W x H table takes for a frame of `pixels` (0: kEclipseTimeSlices).
    static int bandsFor(long pixels, int W, int H);
    /// The runs a rebuild's multiple-scattering field takes for a frame of `pixels` (0: 1), before
    /// the first band (kEclipseFieldPixels); 1: built in the first band's run.
    static int fieldPiecesFor(long pixels);
    /// Fixes the field's runs per rebuild (> 0; 0: fieldPiecesFor() the frame's pixels).
    void setFieldPieces(int n) { explicitFieldPieces_ = std::max(n, 0); }
    /// The field's runs of the rebuild in progress or the last one, and the runs spent on it so far
    /// (bench and tests); whether the rebuild in progress is still building its field.
    int fieldPiecesPerRebuild() const { return fieldPieces_; }
    int fieldRuns() const { return fieldRuns_; }
    bool buildingField() const { return msBuilder_.has_value(); }
    /// While time runs, a rebuild is built for the geometry it will be shown at (the shadow's
    /// motion per run, extrapolated over the rebuild's runs; default on). Off: the geometry of the
    /// run that starts it (the table then lags the shadow by the rebuild's runs).
    void setPredict(bool on) { predict_ = on; }
    /// How far the shadow of the table shown after the last run is from the run's own shadow, m
    /// (the table's lag or lead; the kEclipseRebuildMeters measure).
    double shownOffsetMeters() const { return shownOffset_; }
    /// The bands of the rebuild in progress or the last one, and the largest band's texels.
    int bandsPerRebuild() const { return buildBands_; }
    long largestBandTexels() const { return largestBand_; }
    /// Texels rendered by the bands of the last finished rebuild (W x H when they tile the table).
    long lastRebuildTexels() const { return lastBuildTexels_; }

private:
    void doRun(SkyVars& vars, const Logger& log) override;
    void renderBand(int x0, int x1, int y0, int y1);
    void renderTile(int k);  // band k of buildBands_
    gl::Texture2D smooth_, mie_, total_, backSmooth_, backMie_, backTotal_, msTex_, backMsTex_;
    gl::Framebuffer fbo_, backFbo_;
    gl::Program prog_;
    int progBands_ = 0;
    bool active_ = false, published_ = false;
    // The build in progress (the back tables) and the one shown.
    struct Build {
        glm::dvec3 sunDir{0.0}, moonPos{0.0};
        double h = 0.0, sunDist = 1.496e11;
    };
    Build shown_, building_, last_;
    bool haveLast_ = false, predict_ = true;
    double shownOffset_ = 0.0;
    cpu::EclipseMsTable shownMs_, buildingMs_;
    std::optional<cpu::EclipseMsTableBuilder> msBuilder_;  // the field of the rebuild in progress, while not finished
    int fieldPieces_ = 1, explicitFieldPieces_ = 0, fieldRuns_ = 0;
    int nextBand_ = -1;  // the next band of the build in progress; -1 none
    int slices_ = kEclipseTimeSlices, rebuilds_ = 0;
    bool explicitSlices_ = false;
    long framePixels_ = 0;
    int buildBands_ = kEclipseTimeSlices;
    long largestBand_ = 0, buildTexels_ = 0, lastBuildTexels_ = 0;
};
/// Horizontal illuminance at the observer (global/direct/diffuse, Sun and Moon) and the zenith
/// luminance, integrated on the GPU from the sky-view LUTs; read back (16 floats) only when an
/// input changed. Publishes skykeys::horizontalIlluminance, diffuseIrradiance, zenithLuminance.
class SkyIrradiance final : public SkyGenerator {
public:
    SkyIrradiance();
    void releaseGl() override;
    /// Per-channel diffuse illuminance from each light's LUT (lux), as last computed.
    glm::dvec3 sunDiffuse() const { return sunDiffuse_; }
    glm::dvec3 moonDiffuse() const { return moonDiffuse_; }

private:
    void doRun(SkyVars& vars, const Logger& log) override;
    gl::Program prog_, eclipseProg_;
    gl::Buffer out_;
    glm::dvec3 sunDiffuse_{0.0}, moonDiffuse_{0.0};
    float perLux_[24] = {};           // the GPU pass's results per lux of each light
    std::vector<uint64_t> gpuFor_;    // input versions of the last GPU pass
    bool eclipseRun_ = false;         // the last GPU pass used the eclipse table
};

namespace cpu {
/// CPU twin of one aerial-perspective texel (direction texel i, j; slice k): in-scattered
/// radiance per lux (without kLutScale) and transmittance from the observer to slice k's end.
struct AerialTexel {
    glm::dvec3 inscatter{0.0};
    glm::dvec3 transmittance{1.0};
};
AerialTexel aerialTexel(const SkyModel& m, const SkyQuality& q, const Lut2D& T, const MsField& MS, double h, double muS, int i,
                        int j, int k);
}  // namespace cpu

/// The shared set of sky generators of one SkyVars.
struct SkyLuts {
    std::shared_ptr<TransmittanceLut> transmittance;
    std::shared_ptr<MultiScatteringLut> multiScattering;
    std::shared_ptr<ShLut> sh;
    std::shared_ptr<SkyViewLut> sunView, moonView;
    std::shared_ptr<AerialPerspectiveLut> aerial;
    std::shared_ptr<SkyIrradiance> irradiance;
    std::shared_ptr<LightZenith> lightZenith;
    std::shared_ptr<EclipseSkyLut> eclipse;
    /// The instances stored in `vars` (created on first request).
    static SkyLuts obtain(SkyVars& vars);
    void releaseGl();
};

/// Hemisphere quadrature of a sky-view LUT on the CPU (twin of sky_irradiance.glsl): diffuse
/// horizontal illuminance per lux of the light (the LUT given as a function of (mu, azimuth)).
glm::dvec3 cpuDiffuseIrradiance(const SkyModel& m, const SkyQuality& q, double h, double muS,
                                const std::function<glm::dvec3(double mu, double az, double nu)>& radiancePerLux);

}  // namespace welkin::generators
