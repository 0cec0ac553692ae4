#include <welkin/check.hpp>
#include <welkin/elements/clouds.hpp>
#include <welkin/embedded/atmosphere_shaders.hpp>
#include <welkin/embedded/clouds_element_shaders.hpp>
#include <welkin/embedded/clouds_shaders.hpp>
#include <welkin/error.hpp>
#include <welkin/generators/atmosphere.hpp>
#include <welkin/generators/cloud_density.hpp>
#include <welkin/generators/cloud_keys.hpp>
#include <welkin/generators/cloud_noise.hpp>
#include <welkin/generators/cloud_shadow.hpp>
#include <welkin/generators/cloud_sky_shadow.hpp>
#include <welkin/generators/lights.hpp>
#include <welkin/generators/weather_map.hpp>
#include <welkin/gl/bindings.hpp>
#include <welkin/gl/shader.hpp>
#include <welkin/glsl_cpp.hpp>
#include <welkin/keys.hpp>

#include <epoxy/gl.h>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <numbers>

namespace welkin::elements {

using namespace welkin::generators;
namespace ck = welkin::generators::cloudkeys;

namespace {
constexpr double kPi = std::numbers::pi;
using namespace cloudcpu;  // the droplet constants
// The ambient's diffusion term (ambientTransfer(), fitted to adding-doubling's fluxes;
// skyelements/clouds/README.md): (k/pi) (2 / (1 + q)) (1 - e^(-c tau)) (sF + z + h nu) / (sN + sF + A),
// s the transport optical depth (1 - g) tau (g 0.86, the Mie droplets'), tau unscaled (the scaled
// depth / w_D). One source for these and bench cloud-fit's: clouds.hpp (cloudcpu::kAmbientTransfer,
// cloudcpu::kDiffusion*).
constexpr double kMsS = kDiffusionS;         // transport depth per scaled depth
constexpr double kMsK = kAmbientTransfer.k;  // scale
constexpr double kMsZ = kAmbientTransfer.z;  // the bottom's extrapolation length (transport depth)
constexpr double kMsA = kDiffusionA;         // the slab's two extrapolation lengths (transmission A / (s + A))
constexpr double kMsH = kAmbientTransfer.h;  // the net flux's share: anisotropy towards the lit side
constexpr double kMsC = kAmbientTransfer.c;  // thin-cloud onset per optical depth
constexpr double kMsQ = kDiffusionQ;         // exponent of the light's cos(zenith) (a deck's flux per area)
constexpr double kMsMuMin = kDiffusionMuMin;  // the cos(zenith) below which the factor stays constant
// The lights' transfer (lightTransfer()): the same diffusion form with its own scale, onset,
// extrapolation length and anisotropy, and the forward-peaked low orders forwardTransfer(), w_m
// tauL^m e^(-tauL) / m! HG(nu, g_m), m = 0..4, fitted together (Nelder-Mead on the log radiance)
// to the path tracer's radiance of conservative slabs (the droplets' Mie phase truncated at 3 deg,
// 60,000 paths a direction: tau 0.5, 1, 2, 4, 8, 16, 32; the Sun overhead and 60 deg from the
// zenith; 29 directions each, transmitted and reflected, 3.5-180 deg from the Sun) and to
// adding-doubling's fluxes (tau 3-100, mu0 1 and 0.5), skyelements/clouds/README.md "Light transport". The
// ambient keeps the constants above (its own fit against adding-doubling).
constexpr double kSunK = kLightTransferFit.k;  // scale
constexpr double kSunC = kLightTransferFit.c;  // thin-cloud onset per optical depth
constexpr double kSunH = kLightTransferFit.h;  // the net flux's share towards the light's direction
constexpr double kSunZ = kLightTransferFit.z;  // the bottom's extrapolation length (transport depth)
constexpr const double (&kFwW)[5] = kLightTransferFit.w;  // per order's share left
constexpr const double (&kFwG)[5] = kLightTransferFit.g;  // its lobe's asymmetry
// The ambient's diffusion term per horizontal lux of a diffuse hemisphere: mu^q / mu averaged
// over its cosine-weighted directions, int 2 mu mu^(q - 1) dmu = 2 / (1 + q).
constexpr double kMsAmbient = 2.0 / (1.0 + kMsQ);
// The view transmittance at which the march stops.
constexpr double kTransmittanceCut = 1e-3;

// Side of the photometry pass's grid of hemisphere directions (even: no direction on the
// concentric map's axes). 16 x 16 = 256 directions: the cosine-weighted mean of a sky of
// scattered cumulus converges to ~2 % (measured against 64 x 64 in the tests' overcast case).
constexpr int kStatsN = 16;
// Vertical optical depth of cirrus at relative density 1: thin cirrus 0.03-0.3, cirrus up to ~1-3
// (Sassen & Cho 1992, "Subvisual-thin cirrus lidar dataset", J. Appl. Meteor. 31: thin < 0.3).
constexpr float kCirrusTau = 0.3f;
// Longest march through the shell (m): a grazing ray crosses ~200 km of a 1 km layer; beyond
// ~60 km the air between hides cumulus almost entirely (horizontal transmittance at 550 nm of a
// clear atmosphere over 60 km: ~0.4 at sea level, the haze fade does the rest).
constexpr float kMaxDistance = 60000.f;
// The Sun's angular radius (rad; the Moon's is nearly the same): the transmittance's smoothed horizon (CLD_LIGHT_RADIUS).
constexpr double kLightRadius = 0.00465;

const std::vector<CloudPreset>& presets() {
    // Heights and coverages: fair-weather cumulus bases ~1-2 km, tops 2-3 km in mid-latitude
    // summer; stratocumulus a continuous sheet 0.5-2 km (WMO International Cloud Atlas, 2017,
    // "Cumulus humilis/mediocris", "Stratocumulus stratiformis"). Scattering: the extinction of
    // cloud ~ 0.02-0.1 /m (cumulus liquid water 0.2-0.5 g/m^3 with 10 um droplets: 3 LWC /
    // (2 rho r_e) = 0.045-0.075 /m; Stephens 1978).
    // Cloud type (clouds.cloud_type, the density's height gradient): cumulus (1) for the fair and
    // scattered skies, stratocumulus (0) for the overcast deck. Fair: 150 cells of semi-axes
    // 0.7-2.5 km in the 40 km weather map, a few oktas once their faded edges and the coverage
    // carve them (fair-weather cumulus: 1-4 oktas; 60 cells left the sky overhead empty).
    // Overcast: 0.15 /m, above a real stratocumulus' 0.05-0.1 /m: the deck's mean density
    // is ~0.3 (its carved cells and the weather map's faded cell edges), so its mean vertical
    // optical depth is ~45, and its thin cells pass more light than a uniform sheet. At 0.1 /m it
    // passes 0.42 of the clear sky's light, at 0.13 /m 0.34 (an overcast day: 0.2-0.4; the test);
    // 0.40 (41.8 klux) at 0.13 /m since the forward orders and the full-LOD light march
    // (2026-11-27), 0.37 (38.7 klux) at 0.15 /m.
    // Towering: cumulus congestus growing into cumulonimbus (WMO Cloud Atlas 2017, "Cumulus
    // congestus", "Cumulonimbus calvus"): one condensation level at 1.2 km (the cumulus gradient's
    // flat base), towers of 40-100 % of a 1.2-8 km layer (the weather map's tops: 3.9-8 km), 30
    // cells of 1.5-4 km semi-axes; 0.1 /m (liquid water ~0.7 g/m^3 in 10 um droplets: 3 LWC /
    // (2 rho r_e) = 0.1 /m; congestus 0.5-1.5 g/m^3), detail 1.3 (crisper cauliflower), rain 0.3
    // under the biggest cells, debris cirrus (coverage 0.3) at 10.5 km; coverage 0.9: at 0.8 the
    // coverage cut left the towers' upper halves as separate puffs.
    static const std::vector<CloudPreset> p{
        {"fair", 0.75, 1500, 3000, 0.5, 9000, 0.05, 1.0, 0.0, 150, 700, 2500},
        {"overcast", 0.9, 800, 2000, 0.0, 8000, 0.15, 0.6, 0.3, 800, 4000, 9000, 0.0},
        {"scattered-cirrus", 0.55, 1800, 2800, 0.85, 9500, 0.05, 1.2, 0.0, 25, 500, 1500},
        {"towering", 0.9, 1200, 8000, 0.3, 10500, 0.1, 1.3, 0.3, 30, 1500, 4000},
        {"clear", 0.0, 2000, 3000, 0.0, 9000, 0.05, 1.0, 0.0, 0, 500, 1000},
    };
    return p;
}

double lum(glm::dvec3 c) { return 0.2126 * c.x + 0.7152 * c.y + 0.0722 * c.z; }

// The effective value of a preset-driven key: what is set, else the preset's.
double eff(const SkyVars& v, const Key<double>& k, double presetValue) { return v.has(k) ? v.get(k) : presetValue; }
}  // namespace

const CloudPreset& cloudPreset(const std::string& name) {
    for (const CloudPreset& p : presets())
        if (p.name == name) return p;
    throw Error("clouds.preset: '" + name + "' not one of fair, overcast, scattered-cirrus, towering, clear");
}

std::vector<std::string> cloudPresetNames() {
    std::vector<std::string> n;
    for (const CloudPreset& p : presets()) n.push_back(p.name);
    return n;
}

}  // namespace welkin::elements

// The droplets' phase functions and the light transfer: the shader's text,
// clouds_transfer.shared.glsl, compiled in double (welkin/glsl_cpp.hpp) with the constants above.
namespace welkin::glsl::dp::clouds_transfer_shared {
#define CLD_PI std::numbers::pi
#define CLD_W_DRAINE welkin::elements::cloudcpu::kDropletWDraine
#define CLD_G_DRAINE welkin::elements::cloudcpu::kDropletGDraine
#define CLD_ALPHA_DRAINE welkin::elements::cloudcpu::kDropletAlphaDraine
#define CLD_MS_S welkin::elements::kMsS
#define CLD_MS_K welkin::elements::kMsK
#define CLD_MS_Z welkin::elements::kMsZ
#define CLD_MS_A welkin::elements::kMsA
#define CLD_MS_H welkin::elements::kMsH
#define CLD_MS_C (welkin::elements::kMsC / welkin::elements::cloudcpu::kDropletWDraine)
#define CLD_MS_Q welkin::elements::kMsQ
#define CLD_MS_MU_MIN welkin::elements::kMsMuMin
#define CLD_MS_AMBIENT welkin::elements::kMsAmbient
#define CLD_AMB_FORWARD welkin::elements::cloudcpu::kDraineForwardFraction
#define CLD_DIFFUSIVITY welkin::elements::cloudcpu::kDiffusivity
#define CLD_SUN_K welkin::elements::kSunK
#define CLD_SUN_Z welkin::elements::kSunZ
#define CLD_SUN_H welkin::elements::kSunH
#define CLD_SUN_C (welkin::elements::kSunC / welkin::elements::cloudcpu::kDropletWDraine)
#define CLD_FW_W0 welkin::elements::kFwW[0]
#define CLD_FW_W1 welkin::elements::kFwW[1]
#define CLD_FW_W2 welkin::elements::kFwW[2]
#define CLD_FW_W3 welkin::elements::kFwW[3]
#define CLD_FW_W4 welkin::elements::kFwW[4]
#define CLD_FW_G0 welkin::elements::kFwG[0]
#define CLD_FW_G1 welkin::elements::kFwG[1]
#define CLD_FW_G2 welkin::elements::kFwG[2]
#define CLD_FW_G3 welkin::elements::kFwG[3]
#define CLD_FW_G4 welkin::elements::kFwG[4]
#include "../shaders/clouds_transfer.shared.glsl"
#include "clouds_transfer_undef.inc"
}  // namespace welkin::glsl::dp::clouds_transfer_shared

namespace welkin::elements {

namespace cloudcpu {
namespace transfer = glsl::dp::clouds_transfer_shared;
double henyeyGreenstein(double nu, double g) { return transfer::cld_hg(nu, g); }
double draine(double nu, double g, double alpha) { return transfer::cld_draine(nu, g, alpha); }
double cloudPhase(double nu) {
    return (1.0 - kDropletWDraine) * henyeyGreenstein(nu, kDropletGPeak) + kDropletWDraine * scaledPhase(nu);
}
double scaledPhase(double nu) { return transfer::cld_scaledPhase(nu); }
double lightTransfer(double nu, double tauL, double tauB, double muL) { return transfer::cld_lightTransfer(nu, tauL, tauB, muL); }
double ambientTransfer(double nu, double tauN, double tauF) { return transfer::cld_ambientTransfer(nu, tauN, tauF); }
double forwardTransfer(double nu, double tauL) { return transfer::cld_forwardTransfer(nu, tauL); }
double lightDiffusion(double nu, double tauL, double tauB, double muL) { return transfer::cld_lightDiffusion(nu, tauL, tauB, muL); }
double diffusionShape(double muV, double tauAxis, double muL, double depthFrac) {
    return transfer::cld_diffusionShape(muV, tauAxis, muL, depthFrac);
}
double lightTransferTable(double nu, double muV, double tauL, double tauB, double muL, double deck) {
    return transfer::cld_lightTransferTable(nu, muV, tauL, tauB, muL, deck);
}
double deckness(double tauWidth, double tauAxis) { return transfer::cld_deckness(tauWidth, tauAxis); }
double tableDepth(double muV, double tauL, double tauB, double deck) { return transfer::cld_tableDepth(muV, tauL, tauB, deck); }
const double* diffusionShapeTable() { return &transfer::cld_msTable[0]; }
double finiteBackDepth(double tauB, double tauWidth) { return transfer::cld_finiteBackDepth(tauB, tauWidth); }
double litFaceCosine(double tauUp, double tauL, double muL) { return transfer::cld_litFaceCosine(tauUp, tauL, muL); }
double integrateStep(double source, double sigmaT, double dt) {
    if (sigmaT <= 0) return source * dt;
    return (source - source * std::exp(-sigmaT * dt)) / sigmaT;
}
int backSamples(int lightSamples) { return std::max(2, (lightSamples + 1) / 2); }
double twoStreamTransmission(double tau, double g) { return 1.0 / (1.0 + 0.75 * (1.0 - g) * tau); }
double lightDarkElevation(double planetRadiusM, double observerM, double layerTopM, double radius) {
    const double R = planetRadiusM;
    const double thetaTop = std::acos(R / (R + std::max(layerTopM, 0.0))), thetaObs = std::acos(R / (R + std::max(observerM, 0.0)));
    return -(std::asin(std::min(std::sin(thetaTop) + radius, 1.0)) + thetaObs + thetaTop) - 1e-3;
}
}  // namespace cloudcpu

Clouds::Clouds() : SkyElement("clouds") {
    option(cloudelemkeys::preset, std::string("fair"));
    option(cloudelemkeys::samples, 48);
    option(cloudelemkeys::lightSamples, 6);
    optionUnset(cloudelemkeys::reprojection);  // unset: follows render.interactive
    reads(keys::interactive);
    option(cloudelemkeys::cacheWidth, 512);
    option(cloudelemkeys::cacheFrames, 64);
    option(cloudelemkeys::skyShadow, true);
    optionUnset(ck::coverage);
    optionUnset(ck::bottom);
    optionUnset(ck::top);
    optionUnset(ck::cirrusCoverage);
    optionUnset(ck::cirrusHeight);
    optionUnset(ck::scattering);
    optionUnset(ck::detailScale);
    optionUnset(ck::cloudType);
    optionUnset(ck::rainDensity);
    optionUnset(ck::cloudCount);
    optionUnset(ck::cloudSizeMin);
    optionUnset(ck::cloudSizeMax);
    reads(keys::sunDirection);
    reads(keys::moonDirection);
    reads(keys::observerHeight);
    reads(lightkeys::sunIlluminance);
    reads(lightkeys::moonIlluminance);
    reads(lightkeys::sunTransmittance);
    reads(lightkeys::moonTransmittance);
    writes(keys::sunCloudTransmittance);
    writes(keys::moonCloudTransmittance);
    reads(skykeys::transmittanceLut);
    reads(skykeys::horizontalIlluminance);
    reads(skykeys::diffuseIrradiance);
    reads(ck::weatherMap);
    reads(ck::noiseBase);
    reads(ck::noiseDetail);
    reads(ck::curlNoise);
}

void Clouds::doValidateOptions(const SkyVars& v) const {
    const CloudPreset& p = cloudPreset(v.getOr(cloudelemkeys::preset, std::string("fair")));
    // The layer's heights as this element will use them (set values, else the preset's).
    SkyVars probe;
    probe.set(ck::bottom, eff(v, ck::bottom, p.bottom));
    probe.set(ck::top, eff(v, ck::top, p.top));
    probe.set(ck::cirrusHeight, eff(v, ck::cirrusHeight, p.cirrusHeight));
    validateCloudLayer(probe);
    const int frames = v.getOr(cloudelemkeys::cacheFrames, 64);
    if (frames != 1 && frames != 4 && frames != 16 && frames != 64)
        throw Error("clouds.cache_frames " + std::to_string(frames) + " not one of 1, 4, 16, 64 (the Bayer orders)");
}

void Clouds::applyPreset(SkyVars& v) {
    const std::string name = v.get(cloudelemkeys::preset);
    const CloudPreset& p = cloudPreset(name);
    if (name == appliedPreset_) return;
    auto put = [&](const auto& k, auto value) {
        auto it = std::find_if(written_.begin(), written_.end(), [&](auto& w) { return w.first == k.name(); });
        const bool ours = it != written_.end() && v.version(k) == it->second;
        if (v.has(k) && !ours) return;  // set by the host or --var: it wins over any preset
        v.set(k, value);
        if (it == written_.end()) written_.emplace_back(k.name(), v.version(k));
        else it->second = v.version(k);
    };
    put(ck::coverage, p.coverage);
    put(ck::bottom, p.bottom);
    put(ck::top, p.top);
    put(ck::cirrusCoverage, p.cirrusCoverage);
    put(ck::cirrusHeight, p.cirrusHeight);
    put(ck::scattering, p.scattering);
    put(ck::detailScale, p.detailScale);
    put(ck::cloudType, p.cloudType);
    put(ck::rainDensity, p.rain);
    put(ck::cloudCount, p.cloudCount);
    put(ck::cloudSizeMin, p.sizeMin);
    put(ck::cloudSizeMax, p.sizeMax);
    appliedPreset_ = name;
}

void Clouds::doInit(InitContext& ctx) {
    SkyVars& v = ctx.vars;
    declareOptions(v);
    appliedPreset_.clear();
    written_.clear();
    applyPreset(v);
    validateCloudLayer(v);
    luts_ = SkyLuts::obtain(v);
    addGenerator(AtmosphereLights::obtain(v));
    addGenerator(luts_.lightZenith);
    addGenerator(luts_.transmittance);
    addGenerator(luts_.multiScattering);
    addGenerator(luts_.sh);
    addGenerator(luts_.sunView);
    addGenerator(luts_.moonView);
    addGenerator(luts_.irradiance);
    // The generated noise, unless the host published its own textures before init (a test's
    // uniform slab, an artist's noise).
    if (!v.has(ck::noiseBase)) addGenerator(CloudNoise::obtain(v));
    // The generated weather map, unless the host published its own clouds.weather_map before
    // init (a tool, a test: then the host owns it and its offset).
    if (!v.has(ck::weatherMap)) addGenerator(WeatherMap::obtain(v));
    // The clouds' shadow: the map (shared with the host and the Rainbow) and its effect on the
    // atmosphere's in-scattering (sky.shadow_loss_lut, which the Sky element subtracts), unless
    // clouds.sky_shadow is off (read at init).
    if (v.get(cloudelemkeys::skyShadow)) {
        addGenerator(CloudShadowMap::obtain(v));
        addGenerator(CloudSkyShadow::obtain(v));
    }
    // The direction cache as its display pass samples it (the real-time path): units of its own.
    cacheRadianceUnit_ = textureUnit("CLOUD_CACHE_RADIANCE");
    cacheTransmittanceUnit_ = textureUnit("CLOUD_CACHE_TRANSMITTANCE");
    for (int lights = 0; lights < 4; ++lights) {
        programs_[size_t(lights)] = gl::ProjectionPrograms(recipe(false, false, lights));
        statsProgram_[size_t(lights)] = {};
    }
    atmUbo_ = gl::Buffer(sizeof(AtmosphereBlock));
    cloudUbo_ = gl::Buffer(sizeof(CloudLayerBlock));
    statsTex_ = gl::Texture2D(kStatsN, kStatsN + 1, GL_RGBA32F);
    statsFbo_ = gl::Framebuffer::create();
    statsFbo_.attach(GL_COLOR_ATTACHMENT0, statsTex_);
    photometry_ = {};
    photometryInputs_.clear();
}

gl::ProgramBuilder Clouds::recipe(bool stats, bool cacheFill, int lights) const {
    gl::ProgramBuilder b(stats ? "Clouds (photometry)" : cacheFill ? "Clouds (cache fill)" : "Clouds");
    b.define("ATM_USE_TRANSMITTANCE");
    b.define("CLD_LIGHTS", lights).define("CLD_LIGHT_RADIUS", kLightRadius);
    using namespace cloudcpu;  // the light transfer's constants, one source for GLSL and C++
    b.define("CLD_G_PEAK", kDropletGPeak).define("CLD_G_DRAINE", kDropletGDraine).define("CLD_ALPHA_DRAINE", kDropletAlphaDraine);
    b.define("CLD_W_DRAINE", kDropletWDraine).define("CLD_MS_S", kMsS).define("CLD_MS_K", kMsK).define("CLD_MS_Z", kMsZ);
    b.define("CLD_MS_A", kMsA).define("CLD_MS_H", kMsH).define("CLD_MS_C", kMsC / kDropletWDraine).define("CLD_MS_Q", kMsQ).define("CLD_MS_MU_MIN", kMsMuMin);
    b.define("CLD_MS_AMBIENT", kMsAmbient).define("CLD_AMB_FORWARD", kDraineForwardFraction).define("CLD_DIFFUSIVITY", kDiffusivity);
    b.define("CLD_SUN_K", kSunK).define("CLD_SUN_Z", kSunZ).define("CLD_SUN_H", kSunH).define("CLD_SUN_C", kSunC / kDropletWDraine);
    for (int m = 0; m < 5; ++m) b.define("CLD_FW_W" + std::to_string(m), kFwW[m]).define("CLD_FW_G" + std::to_string(m), kFwG[m]);
    b.define("CLD_T_CUT", kTransmittanceCut).define("CLD_MARCH_MAX_M", kMarchMaxM);
    if (stats) b.define("CLOUDS_STATS");
    if (cacheFill) {
        b.define("CLOUDS_CACHE_FILL");
        b.compute("generators/atmosphere.glsl", embedded::atmosphere_shaders("atmosphere.glsl"))
            .compute("generators/clouds/cloud_density.glsl", embedded::clouds_shaders("cloud_density.glsl"))
            .compute("clouds/clouds_cache.glsl", embedded::clouds_element_shaders("clouds_cache.glsl"))
            .compute("clouds/clouds.frag.glsl", embedded::clouds_element_shaders("clouds.frag.glsl"));
        return b;
    }
    b.fullscreenVertex();
    if (!stats)
        b.fragment("engine/camera.glsl", gl::engineShader("camera.glsl"))
            .fragment("engine/composite.glsl", gl::engineShader("composite.glsl"));
    b.fragment("generators/atmosphere.glsl", embedded::atmosphere_shaders("atmosphere.glsl"))
        .fragment("generators/clouds/cloud_density.glsl", embedded::clouds_shaders("cloud_density.glsl"))
        .fragment("clouds/clouds.frag.glsl", embedded::clouds_element_shaders("clouds.frag.glsl"));
    return b;
}

void Clouds::doUpdate(const FrameContext& ctx) { applyPreset(ctx.vars); }

void Clouds::bindResources(const FrameContext& ctx) {
    SkyVars& v = ctx.vars;
    AtmosphereBlock block = AtmosphereBlock::from(luts_.transmittance->model(), luts_.transmittance->quality().shBands);
    atmUbo_.update(&block, sizeof block);
    atmUbo_.bindBase(GL_UNIFORM_BUFFER, gl::binding::kAtmosphereUbo);
    CloudLayerBlock cb = CloudLayerBlock::from(v);
    cloudUbo_.update(&cb, sizeof cb);
    cloudUbo_.bindBase(GL_UNIFORM_BUFFER, gl::binding::kCloudUbo);
    glBindTextureUnit(gl::binding::kTransmittanceLut, v.get(skykeys::transmittanceLut).id);
    glBindTextureUnit(gl::binding::kCloudWeatherMap, v.get(ck::weatherMap).id);
    glBindTextureUnit(gl::binding::kCloudNoiseBase, v.get(ck::noiseBase).id);
    glBindTextureUnit(gl::binding::kCloudNoiseDetail, v.get(ck::noiseDetail).id);
    glBindTextureUnit(gl::binding::kCloudCurlNoise, v.get(ck::curlNoise).id);
}

namespace {
// The Moon's light below 1e-4 of the Sun's at the observer (setUniforms: dropped, and its march
// left out of the program by marchedLights).
bool moonNegligible(const SkyVars& v) {
    const double sunAtObs = lum(v.getOr(lightkeys::sunIlluminance, glm::dvec3(0.0)) * v.getOr(lightkeys::sunTransmittance, glm::dvec3(1.0)));
    const double moonAtObs = lum(v.getOr(lightkeys::moonIlluminance, glm::dvec3(0.0)) * v.getOr(lightkeys::moonTransmittance, glm::dvec3(1.0)));
    return moonAtObs < 1e-4 * sunAtObs;
}
}  // namespace

void Clouds::setUniforms(const gl::Program& p, const FrameContext& ctx) const {
    const SkyVars& v = ctx.vars;
    auto unit = [](glm::dvec3 d) { return glm::length(d) > 0 ? glm::normalize(d) : glm::dvec3(0, 0, -1); };
    p.use();
    p.set("u_h", float(std::max(v.getOr(keys::observerHeight, 0.0), 0.0)));
    p.set("u_sunDir", glm::vec3(unit(v.get(keys::sunDirection))));
    p.set("u_moonDir", glm::vec3(unit(v.get(keys::moonDirection))));
    const glm::dvec3 sunE = v.getOr(lightkeys::sunIlluminance, glm::dvec3(0.0));
    glm::dvec3 moonE = v.getOr(lightkeys::moonIlluminance, glm::dvec3(0.0));
    // The Moon's light march only when it matters: by day the full Moon (0.25 lux) is 1e-5 of
    // the Sun's light at the observer; below 1e-4 of the sunlight it is dropped (invisible under
    // any exposure), and marchedLights leaves its code out of the program (a uniform branch still
    // cost its march on llvmpipe: 38 % of a daytime frame).
    if (moonNegligible(v)) moonE = glm::dvec3(0.0);
    p.set("u_sunE", glm::vec3(sunE));
    p.set("u_moonE", glm::vec3(moonE));
    const glm::dvec3 diffuse = v.getOr(skykeys::diffuseIrradiance, glm::dvec3(0.0));
    p.set("u_ambientE", glm::vec3(diffuse));
    // The ground's global illuminance under the clouds (computePhotometry's solution).
    p.set("u_groundE", glm::vec3(groundE_));
    p.set("u_samples", v.get(cloudelemkeys::samples));
    p.set("u_lightSamples", v.get(cloudelemkeys::lightSamples));
    p.set("u_backSamples", backSamples(v.get(cloudelemkeys::lightSamples)));
    p.set("u_maxDistance", kMaxDistance);
    p.set("u_cirrusTau", kCirrusTau);
}

int Clouds::marchedLights(const SkyVars& v) const {
    const glm::dvec3 sunE = v.getOr(lightkeys::sunIlluminance, glm::dvec3(0.0)), moonE = v.getOr(lightkeys::moonIlluminance, glm::dvec3(0.0));
    const CloudLayerBlock cb = CloudLayerBlock::from(v);
    const double R = cb.radii[0];
    // the observer's height or the photometry pass' (0): the larger reaches further
    const double dark = lightDarkElevation(R, std::max(v.getOr(keys::observerHeight, 0.0), 0.0), double(cb.radii[2]) - R, double(kLightRadius));
    auto lights = [&](glm::dvec3 d) { return glm::length(d) > 0 && std::asin(std::clamp(glm::normalize(d).z, -1.0, 1.0)) > dark; };
    int m = 0;
    if (lum(sunE) > 0 && lights(v.get(keys::sunDirection))) m |= 1;
    if (lum(moonE) > 0 && !moonNegligible(v) && lights(v.get(keys::moonDirection))) m |= 2;
    return m;
}

namespace {
// The keys whose change changes every cloud the element marches (the layer, its density and the
// march's samples; texture contents through the keys' versions): the photometry pass and the
// real-time cache both track them.
constexpr const char* kLayerInputs[] = {"clouds.coverage",      "clouds.bottom_m",        "clouds.top_m",         "clouds.cirrus_coverage",
                                        "clouds.cirrus_height_m", "clouds.scattering_per_m", "clouds.detail_scale", "clouds.cloud_type",
                                        "clouds.noise_base",    "clouds.samples",         "clouds.light_samples", "sky.transmittance_lut"};
}  // namespace

void Clouds::computePhotometry(const FrameContext& ctx) {
    SkyVars& v = ctx.vars;
    // Inputs: everything the pass reads. The layer, the weather map's and noise's contents, the
    // samples: exactly (the keys' versions). What moves every frame while time runs: by a
    // tolerance, as the shadow map does — the lights' directions by 5e-4 rad (0.03 deg, 7 s of the
    // Sun), their illuminances and the clear sky's by 1 %, the wind's offset by 156 m (a weather
    // texel of the default 256-texel, 40 km map): photometry changes slowly, and a pass with a
    // read-back every frame cost the running frame ~10 %.
    std::vector<double> in;
    for (const char* k : kLayerInputs) in.push_back(double(v.version(k)));
    in.push_back(double(v.version(ck::weatherMap)));
    in.push_back(v.getOr(keys::observerHeight, 0.0));
    const glm::dvec3 sunDir = v.get(keys::sunDirection), moonDir = v.get(keys::moonDirection);
    const glm::dvec3 sunE = v.getOr(lightkeys::sunIlluminance, glm::dvec3(0.0)), moonE = v.getOr(lightkeys::moonIlluminance, glm::dvec3(0.0));
    const glm::dvec3 skyE = v.getOr(skykeys::horizontalIlluminance, glm::dvec3(0.0));
    const glm::dvec2 offset = v.getOr(ck::weatherOffset, glm::dvec2(0.0));
    auto moved = [](glm::dvec3 a, glm::dvec3 b) {
        const double la = glm::length(a), lb = glm::length(b);
        return la > 0 && lb > 0 ? glm::dot(a / la, b / lb) < std::cos(5e-4) : la != lb;
    };
    auto changed = [](glm::dvec3 a, glm::dvec3 b) {
        for (int c = 0; c < 3; ++c)
            if (std::abs(a[c] - b[c]) > 0.01 * std::max(std::abs(b[c]), 1e-12)) return true;
        return false;
    };
    const SkyVars& cv = ctx.vars;
    const bool realtime = cv.has(cloudelemkeys::reprojection) ? cv.get(cloudelemkeys::reprojection) : cv.getOr(keys::interactive, false);
    // Real time with a photometry of the same layer to show: a refresh is spread over frames, one
    // stats pass a frame (staged_); a change of the layer's inputs (which refills the direction
    // cache whole too) computes it whole, and meanwhile restarts one under way.
    const bool spread = realtime && photometry_.valid && in == photometryInputs_;
    PhotometryStaged& st = staged_;
    if (st.next > 0 && !spread) st.next = 0;
    if (st.next == 0) {
        const PhotometryLast& l = photometryLast_;
        const bool onlyMoving = photometry_.valid && in == photometryInputs_;
        ++photometryAge_;
        if (onlyMoving && !moved(sunDir, l.sunDir) && !moved(moonDir, l.moonDir) && !changed(sunE, l.sunE) && !changed(moonE, l.moonE) &&
            !changed(skyE, l.skyE) && glm::length(offset - l.offset) <= 156.0)
            return;
        // Real time (the direction cache's path: welkin view, a game loop): what only the lights'
        // motion, their illuminances and the wind ask for is redone at most every kPhotometryFrames
        // frames (time at 600x moved the Sun beyond 5e-4 rad every frame, and the pass with its
        // read-backs cost a running frame as much as the still frame at 512x256); a light that jumped
        // by more than 0.5 deg (a new time: the cache refills whole too) is redone at once. The lag:
        // at most kPhotometryFrames frames of the light's motion (1.6 deg of the Sun at 1440x), and
        // the refresh's passes are then spread over the next frames (one more frame on the ground,
        // two from a height).
        auto jumped = [](glm::dvec3 a, glm::dvec3 b) {
            const double la = glm::length(a), lb = glm::length(b);
            return la > 0 && lb > 0 ? glm::dot(a / la, b / lb) < std::cos(0.5 * kPi / 180) : la != lb;
        };
        if (onlyMoving && realtime && photometryAge_ < kPhotometryFrames && !jumped(sunDir, l.sunDir) && !jumped(moonDir, l.moonDir)) return;
        photometryAge_ = 0;
        ++photometryRuns_;
        photometryInputs_ = in;
        photometryLast_ = {sunDir, moonDir, sunE, moonE, skyE, offset};
        // The ground under the clouds, per channel: direct (the lights' beams through the clouds) +
        // the clear sky's diffuse light through them + the clouds' own light, which depends on the
        // ground's light reflected into their bases. The clouds' radiance is linear in groundE, so two
        // passes on the ground (groundE 0 and the clear sky's global light) give the fixed point
        // G = D + E_d T + pi (L0 + b G) exactly: G = (D + E_d T + pi L0) / (1 - pi b).
        // (Taken at the refresh's first frame: a refresh spread over frames uses them throughout.)
        st.diffuseE = v.getOr(skykeys::diffuseIrradiance, glm::dvec3(0.0));
        auto beam = [&](const Key<glm::dvec3>& e, const Key<glm::dvec3>& t, glm::dvec3 dir) {
            const double mu = glm::length(dir) > 0 ? glm::normalize(dir).z : 0.0;
            return v.getOr(e, glm::dvec3(0.0)) * v.getOr(t, glm::dvec3(0.0)) * std::max(mu, 0.0);
        };
        st.sunD = beam(lightkeys::sunIlluminance, lightkeys::sunTransmittance, sunDir);
        st.moonD = beam(lightkeys::moonIlluminance, lightkeys::moonTransmittance, moonDir);
        st.clearG = st.diffuseE + st.sunD + st.moonD;
        st.hObs = std::max(v.getOr(keys::observerHeight, 0.0), 0.0);
    }

    GLint prevFbo = 0, prevViewport[4];
    glGetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &prevFbo);
    glGetIntegerv(GL_VIEWPORT, prevViewport);
    const GLboolean blend = glIsEnabled(GL_BLEND);
    statsFbo_.bind();
    glViewport(0, 0, kStatsN, kStatsN + 1);
    glDisable(GL_BLEND);
    const int lights = marchedLights(v);
    gl::Program& statsProgram = statsProgram_[size_t(lights)];
    if (!statsProgram) statsProgram = recipe(true, false, lights).build();
    setUniforms(statsProgram, ctx);
    statsProgram.set("u_statsN", kStatsN);
    auto restore = [&] {
        glBindFramebuffer(GL_DRAW_FRAMEBUFFER, GLuint(prevFbo));
        glViewport(prevViewport[0], prevViewport[1], prevViewport[2], prevViewport[3]);
        if (blend) glEnable(GL_BLEND);
    };
    // One pass: the clouds' mean radiance (per channel) and transmittance over the cosine-weighted
    // directions from height h, the ground lit by groundE; and the transmittances to the lights.
    using Pass = PhotometryPass;
    auto pass = [&](double h, glm::dvec3 groundE) {
        ++photometryPassesLast_;
        statsProgram.set("u_h", float(h));
        statsProgram.set("u_groundE", glm::vec3(groundE));
        ctx.drawFullscreen();
        const std::vector<float> px = statsTex_.readRgbaFloat();
        // Cosine-weighted directions: E = pi x mean radiance.
        Pass r;
        for (int i = 0; i < kStatsN * kStatsN; ++i) {
            r.meanL += glm::dvec3(px[size_t(4 * i)], px[size_t(4 * i + 1)], px[size_t(4 * i + 2)]);
            r.meanT += px[size_t(4 * i + 3)];
        }
        r.meanL /= double(kStatsN * kStatsN);
        r.meanT /= double(kStatsN * kStatsN);
        r.sunT = px[size_t(4 * kStatsN * kStatsN + 3)];
        r.moonT = px[size_t(4 * kStatsN * kStatsN + 4 + 3)];
        return r;
    };
    auto fixedPoint = [&] {
        glm::dvec3 ground(0.0);
        for (int c = 0; c < 3; ++c) {
            const double b = st.clearG[c] > 0 ? (st.p1.meanL[c] - st.p0.meanL[c]) / st.clearG[c] : 0.0;
            const double num = st.sunD[c] * st.p0.sunT + st.moonD[c] * st.p0.moonT + st.diffuseE[c] * st.p0.meanT + kPi * st.p0.meanL[c];
            ground[c] = std::max(num / std::max(1.0 - kPi * b, 1e-3), 0.0);  // pi b < 1: the loop's gain (albedo x the bases' reflection)
        }
        st.ground = ground;
    };
    // The photometry at the observer: the same on the ground; from a height, one more pass there.
    auto onGround = [&] {
        Pass at = st.p0;
        const glm::dvec3 g = st.ground, cg = st.clearG;
        at.meanL = st.p0.meanL + (st.p1.meanL - st.p0.meanL) * glm::dvec3(cg.x > 0 ? g.x / cg.x : 0.0, cg.y > 0 ? g.y / cg.y : 0.0,
                                                                          cg.z > 0 ? g.z / cg.z : 0.0);
        return at;
    };
    Pass at;
    if (!spread) {
        st.p0 = pass(0.0, glm::dvec3(0.0));
        st.p1 = pass(0.0, st.clearG);
        fixedPoint();
        at = st.hObs > 1.0 ? pass(st.hObs, st.ground) : onGround();
        st.next = 0;
    } else if (st.next == 0) {
        st.p0 = pass(0.0, glm::dvec3(0.0));
        st.next = 1;
        restore();
        return;
    } else if (st.next == 1) {
        st.p1 = pass(0.0, st.clearG);
        fixedPoint();
        if (st.hObs > 1.0) {
            st.next = 2;
            restore();
            return;
        }
        at = onGround();
        st.next = 0;
    } else {
        at = pass(st.hObs, st.ground);
        st.next = 0;
    }
    groundE_ = st.ground;
    restore();

    // The clear sky behind the clouds is taken as uniform: its share is the clear diffuse
    // illuminance x the mean transmittance.
    const double meanL = lum(at.meanL), meanT = at.meanT, sunT = at.sunT, moonT = at.moonT;
    const glm::dvec3 hv = v.getOr(skykeys::horizontalIlluminance, glm::dvec3(0.0));
    Photometry& ph = photometry_;
    ph.clearGlobal = hv.x;
    ph.clearDirect = hv.y;
    ph.clearDiffuse = hv.z;
    ph.sunTransmittance = sunT;
    ph.moonTransmittance = moonT;
    ph.groundLux = lum(st.ground);
    v.set(keys::sunCloudTransmittance, std::clamp(sunT, 0.0, 1.0));
    v.set(keys::moonCloudTransmittance, std::clamp(moonT, 0.0, 1.0));
    ph.direct = hv.y * sunT;
    ph.diffuse = hv.z * meanT + kPi * meanL;
    ph.global = ph.direct + ph.diffuse;
    ph.valid = true;
}

void Clouds::doRender(const FrameContext& ctx) {
    SkyVars& v = ctx.vars;
    drew_ = false;
    cachePhasesLast_ = 0;
    photometryPassesLast_ = 0;
    const double cov = v.get(ck::coverage), cir = v.get(ck::cirrusCoverage);
    if (cov <= 0.0 && cir <= 0.0) {
        // Nothing to draw: the clear sky's photometry stands.
        const glm::dvec3 hv = v.getOr(skykeys::horizontalIlluminance, glm::dvec3(0.0));
        photometry_ = {hv.x, hv.y, hv.z, hv.x, hv.y, hv.z, 1.0, 1.0, true, hv.x};
        v.set(keys::sunCloudTransmittance, 1.0);
        v.set(keys::moonCloudTransmittance, 1.0);
        photometryInputs_.clear();
        return;
    }
    bindResources(ctx);
    computePhotometry(ctx);
    const int lights = marchedLights(v);
    const bool realtime = v.has(cloudelemkeys::reprojection) ? v.get(cloudelemkeys::reprojection) : v.getOr(keys::interactive, false);
    if (realtime) {
        renderCached(ctx);
    } else {
        const gl::Program& p = programs_[size_t(lights)].get(ctx.camera.projection);
        setUniforms(p, ctx);
        ctx.drawFullscreen();
    }
    drew_ = true;
}

// The real-time path. The clouds seen from the observer depend on the direction only (the camera
// turning changes nothing in them), so they are kept in a direction-space cache (azimuth x a view
// zenith mapping dense at the horizon, clouds.cache_width x half) holding the radiance and
// transmittance of cloudsShade() with the haze. Each frame refreshes one texel of every 4 x 4
// block (a Bayer order: 16 frames refresh all) and the frame samples the cache bilinearly. A
// change of anything but the lights' slow motion and the wind (the layer, the coverage, a preset,
// the observer's height, a jump of the Sun by more than 0.5 deg in a frame) refills all of it.
// Cost: 1/16 of W x W/2 ray marches per frame plus one texture fetch per pixel, whatever the
// frame's size. What it trades: the cache's angular resolution (360 deg / W: 0.7 deg at 512, so
// a cloud's edge is blurred over ~0.7 deg) and a lag of up to 16 frames for clouds moved by the
// wind (at 10 m/s and 60 fps, 2.7 m). welkin bench clouds measures both against the reference.
void Clouds::renderCached(const FrameContext& ctx) {
    SkyVars& v = ctx.vars;
    const int w = v.get(cloudelemkeys::cacheWidth), h = std::max(w / 2, 2);
    const int lights = marchedLights(v);
    gl::Program& cacheFill = cacheFill_[size_t(lights)];
    if (!cacheFill) cacheFill = recipe(false, true, lights).build();
    if (!cacheShow_) {
        cacheShow_ = gl::ProjectionPrograms(gl::ProgramBuilder("Clouds (cache display)")
                                                .bindings(bindings())
                                                .define("CLOUDS_CACHE_SHOW")
                                                .fullscreenVertex()
                                                .fragment("engine/camera.glsl", gl::engineShader("camera.glsl"))
                                                .fragment("engine/composite.glsl", gl::engineShader("composite.glsl"))
                                                .fragment("clouds/clouds_cache.glsl", embedded::clouds_element_shaders("clouds_cache.glsl")));
    }
    std::vector<double> in;
    for (const char* k : kLayerInputs) in.push_back(double(v.version(k)));
    for (const char* k : {"clouds.preset", "observer.height_m"}) in.push_back(double(v.version(k)));
    in.push_back(double(w));
    const glm::dvec3 sun = v.get(keys::sunDirection);
    // Whole, now: the first frame, the cache's size, the layer, the preset, the observer's height.
    // A jump of the Sun by more than 0.5 deg in a frame (a new time): the cache is refilled into a
    // second pair of textures, one Bayer phase a frame like the running refresh (so no frame
    // marches more than it), while the cache before the jump is drawn; the two swap once the
    // second is complete (kept for issue 22 item 5: the whole refill made one frame ~50x the
    // still one).
    bool whole = cacheL_.width() != w || cacheInputs_.size() != in.size() + 3;
    bool jump = false;
    if (!whole) {
        for (size_t i = 0; i < in.size(); ++i) whole = whole || in[i] != cacheInputs_[i];
        const glm::dvec3 last(cacheInputs_[in.size()], cacheInputs_[in.size() + 1], cacheInputs_[in.size() + 2]);
        jump = glm::dot(glm::normalize(sun), glm::normalize(last)) < std::cos(0.5 * kPi / 180);
    }
    const gl::Program& show = cacheShow_.get(ctx.camera.projection);
    auto draw = [&] {
        show.use();
        glBindTextureUnit(GLuint(cacheRadianceUnit_), cacheL_.id());
        glBindTextureUnit(GLuint(cacheTransmittanceUnit_), cacheT_.id());
        ctx.drawFullscreen();
    };
    if (jump && !whole && staged_.next > 0) {
        // The photometry of the new light is being computed over frames (its ground light lights
        // the bases in the march): the refill starts when it is complete (the next frame on the
        // ground), the cache before the jump drawn meanwhile, nothing marched in this frame. The
        // jump is seen again then (the cache's inputs keep the old light).
        draw();
        return;
    }
    in.insert(in.end(), {sun.x, sun.y, sun.z});
    cacheInputs_ = in;
    auto makeCache = [w, h](gl::Texture2D& L, gl::Texture2D& T) {
        L = gl::Texture2D(w, h, GL_RGBA16F);
        T = gl::Texture2D(w, h, GL_RGBA16F);
        for (const gl::Texture2D* t : {&L, &T}) {
            glTextureParameteri(t->id(), GL_TEXTURE_WRAP_S, GL_REPEAT);
            glTextureParameteri(t->id(), GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
            glTextureParameteri(t->id(), GL_TEXTURE_MIN_FILTER, GL_LINEAR);
            glTextureParameteri(t->id(), GL_TEXTURE_MAG_FILTER, GL_LINEAR);
        }
    };
    if (cacheL_.width() != w) {
        makeCache(cacheL_, cacheT_);
        backL_ = {}, backT_ = {};
    }
    const int frames = v.get(cloudelemkeys::cacheFrames);
    const int bits = frames >= 64 ? 3 : frames >= 16 ? 2 : frames >= 4 ? 1 : 0;
    const int n = 1 << bits;
    cachePhase_ %= n * n;
    const bool all = whole || bits == 0;
    if (all || backPhase_ >= n * n) backPhase_ = -1;  // a refill in progress is superseded
    if (!all && jump) {
        if (!backL_) makeCache(backL_, backT_);  // 2 more textures of the cache's size, once
        backPhase_ = 0;  // (re)started at this light
        ++cacheJumpRefills_;
    }
    const bool back = backPhase_ >= 0;
    const int phase = all ? -1 : back ? backPhase_ : cachePhase_;
    setUniforms(cacheFill, ctx);
    cacheFill.set("u_cacheSize", glm::ivec2(w, h));
    cacheFill.set("u_phase", phase);
    cacheFill.set("u_cacheBits", bits);
    glBindImageTexture(gl::binding::kLutImage, (back ? backL_ : cacheL_).id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA16F);
    glBindImageTexture(gl::binding::kSecondLutImage, (back ? backT_ : cacheT_).id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA16F);
    const int cw = all ? w : (w + n - 1) / n, ch = all ? h : (h + n - 1) / n;
    glDispatchCompute(GLuint((cw + 7) / 8), GLuint((ch + 7) / 8), 1);
    glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT);
    cachePhasesLast_ = all ? n * n : 1;
    if (back) {
        if (++backPhase_ == n * n) {  // complete: drawn from this frame on
            std::swap(cacheL_, backL_);
            std::swap(cacheT_, backT_);
            backPhase_ = -1;
        }
    } else {
        cachePhase_ = (cachePhase_ + 1) % (n * n);
    }
    draw();
}

void Clouds::doResize(int, int) {}

void Clouds::doApplyToScene(const FrameContext& ctx, ScenePass pass) {
    if (pass != ScenePass::Surfaces || !drew_ || !photometry_.valid) return;
    if (ctx.camera.projection != Projection::Perspective) return;  // a host's depth belongs to a pinhole view
    if (!ctx.vars.has(generators::cloudkeys::shadowMap)) return;   // no shadow map: nothing shadows
    if (!scenePass_) {
        scenePass_ = gl::ProgramBuilder("Clouds (host scene shadows)")
                         .fullscreenVertex()
                         .fragment("engine/camera.glsl", gl::engineShader("camera.glsl"))
                         .fragment("engine/composite.glsl", gl::engineShader("composite.glsl"))
                         .fragment("generators/clouds/cloud_shadow.glsl", std::string(generators::CloudShadowMap::hostGlsl()))
                         .fragment("clouds/clouds_scene.frag.glsl", embedded::clouds_element_shaders("clouds_scene.frag.glsl"))
                         .build();
    }
    generators::CloudShadowMap::bindForHost(ctx.vars, scenePass_.id());
    glBindTextureUnit(gl::binding::kSceneDepth, ctx.depth->depthTexture);
    scenePass_.use();
    // Luminance lux (the photometry's): the ratio is applied to every channel alike.
    scenePass_.set("u_direct", float(photometry_.clearDirect));
    scenePass_.set("u_diffuse", float(photometry_.diffuse));
    scenePass_.set("u_observerT", float(photometry_.sunTransmittance));
    ctx.drawFullscreen();
}

void Clouds::doRelease() {
    scenePass_ = {};
    for (auto& p : programs_) p.releasePrograms();
    cacheShow_.releasePrograms();
    for (auto& p : cacheFill_) p = {};
    cacheL_ = {};
    cacheT_ = {};
    backL_ = {};
    backT_ = {};
    backPhase_ = -1;
    cacheInputs_.clear();
    for (auto& p : statsProgram_) p = {};
    atmUbo_ = {};
    cloudUbo_ = {};
    statsTex_ = {};
    statsFbo_ = {};
    luts_.releaseGl();
}

void Clouds::doStats(nlohmann::json& root) const {
    // Composited after the Sky, the clouds' doStats runs after the Sky's (registration order):
    // the sky.* photometry becomes the one under the clouds; the clear sky's stays as sky.clear_*.
    if (!photometry_.valid) return;
    auto& s = root["sky"];
    s["clear_horizontal_illuminance_lux"] = photometry_.clearGlobal;
    s["clear_sun_illuminance_lux"] = photometry_.clearDirect;
    s["clear_diffuse_illuminance_lux"] = photometry_.clearDiffuse;
    s["horizontal_illuminance_lux"] = photometry_.global;
    s["sun_illuminance_lux"] = photometry_.direct;
    s["diffuse_illuminance_lux"] = photometry_.diffuse;
    root["clouds"]["sun_transmittance"] = photometry_.sunTransmittance;
    root["clouds"]["moon_transmittance"] = photometry_.moonTransmittance;
    root["clouds"]["drew"] = drew_;
}

}  // namespace welkin::elements

WELKIN_ELEMENT_DESCRIPTOR(clouds) {
    static const welkin::ElementDescriptor d{
        "clouds", "volumetric cumulus over a weather map and cirrus, lit by the Sun and Moon through the atmosphere",
        welkin::Layer::Clouds, false, [] { return std::make_unique<welkin::elements::Clouds>(); }};
    return d;
}
