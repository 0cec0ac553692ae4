// The cloud density function, shared by everything that reads the clouds: its parameters as a
// std140 uniform block (CloudLayerBlock, binding WELKIN_BINDING_CLOUD_UBO = 2) and the CPU twin
// (double precision) of generators/clouds/shaders/cloud_density.glsl: the shader's own maths,
// cloud_density.shared.glsl, compiled as C++ (docs/architecture.md, "One source").
//
//   using namespace welkin::generators;
//   CloudLayerBlock b = CloudLayerBlock::from(vars);          // keys of cloud_keys.hpp
//   gl::Buffer ubo(sizeof b, &b);  ubo.bindBase(GL_UNIFORM_BUFFER, gl::binding::kCloudUbo);
//   bindCloudTextures(vars);                                  // weather, noises, curl, path LUT
//   // GLSL: include embedded::clouds_shaders("cloud_density.glsl") after your header, then
//   //       float d = cloudDensity(p, CLOUD_LOD_FULL);        // p: ENU metres, see below
//   // CPU (tests, tools): the same function on read-back textures
//   cpu::CloudTextures tex{weather, base, detail, curl};       // cpu::Image, RGBA float texels
//   double d = cpu::cloudDensity(b, tex, {x, y, z}, CloudLod::Full);
//
// Contract (GLSL and C++ alike):
// - Positions are world ENU metres relative to the observer's ground point: the observer stands
//   at (0, 0, observer height), the planet's centre at (0, 0, -R), R = planet.radius_m. The
//   altitude of p is |p + (0,0,R)| - R (evaluated in the cancellation-free form
//   (x^2 + y^2 + z^2 + 2 R z) / (|p + (0,0,R)| + R)); the weather map is read at the point's
//   tangent-plane (x, y): uv = ((x, y) + offset) / extent, repeat (cloud_keys.hpp).
// - cloudDensity() returns the cloud's relative density in [0, 1] (0 outside the layer
//   [clouds.bottom_m, clouds.top_m], 0 when clouds.coverage = 0, nondecreasing in the coverage);
//   the extinction coefficient is density x CloudLayerBlock::shape.z (clouds.scattering_per_m,
//   1/m; single-scattering albedo ~1).
// - CloudLod::Cheap: weather map, height profile and base shape only (light marches, shadows);
//   CloudLod::Full: eroded by the detail noise (clouds.detail_scale). Cheap >= Full everywhere.
// - cloudShellIntersect(r, mu) gives the entry and exit distances (m) along a ray from radius r
//   (distance to the planet's centre, m) with cos(zenith) mu through the shell [bottom, top]:
//   below, inside or above the layer; the first crossing only (a grazing ray that leaves the
//   layer downwards and comes back up is cut at the first exit). Negative exit: no crossing
//   (the ray misses the shell or the ground hides it).
// - cirrusDensity(xy) is the cirrus layer's relative density in [0, 1] at a point of its layer
//   (ENU x, y metres), from clouds.curl_noise at ((x, y) + clouds.cirrus_offset_m) / curl
//   period; 0 when clouds.cirrus_coverage = 0.
// Textures are sampled at level 0 with linear filtering and GL_REPEAT (the ray march's steps are
// far longer than a texel: derivative-based mip selection means nothing there).
//
// Sources: Papp, "Atmospheric and cloud rendering in real time" (SevenSky, 2018) eqs. 5.1-5.5
// (altitude on the sphere, the weather map's height scale and gradient, coverage, erosion);
// Schneider & Vos, "The real-time volumetric cloudscapes of Horizon Zero Dawn" (SIGGRAPH 2015)
// and Schneider, "Nubis: authoring real-time volumetric cloudscapes" (SIGGRAPH 2017): the remap-
// based erosion of the Perlin-Worley shape by Worley fBm and the detail noise, the height profile.
#pragma once
#include <welkin/vars.hpp>

#include <array>
#include <optional>
#include <vector>

namespace welkin::generators {

/// Default periods of the noise tiles when the keys are undeclared, m. The base tile spans a few
/// cumulus (its Perlin-Worley cells, 4 per tile edge, are 1 km: the turrets of a 1-6 km wide
/// cloud); the detail tile's Worley cells (2-8 per 500 m) are the 60-250 m cauliflower edges
/// (Schneider 2015 uses the same ~1:8 ratio between the two).
inline constexpr double kDefaultNoiseBasePeriodM = 4000.0;
inline constexpr double kDefaultNoiseDetailPeriodM = 500.0;
inline constexpr double kDefaultCurlPeriodM = 40000.0;

/// The cloud layer's parameters, std140 (all vec4: no padding surprises). Mirror of the GLSL
/// block WelkinClouds in cloud_density.glsl.
struct CloudLayerBlock {
    /// x planet radius R, y R + clouds.bottom_m, z R + clouds.top_m, w R + clouds.cirrus_height_m (m)
    float radii[4];
    /// x clouds.coverage [0,1], y clouds.detail_scale [0,4], z clouds.scattering_per_m (1/m),
    /// w clouds.cirrus_coverage [0,1]
    float shape[4];
    /// xy clouds.weather_offset_m reduced modulo the extent (m), z extent (m), w 1 / extent (1/m)
    float weather[4];
    /// x base-noise period, y detail-noise period, z curl-noise period (m), w clouds.cloud_type
    /// [0, 1] (0 stratocumulus, 1 cumulus: the height gradient)
    float noise[4];
    /// xyz the base noise's scroll (m, reduced modulo its period), w unused
    float scrollBase[4];
    /// xyz the detail noise's scroll (m, reduced modulo its period), w unused
    float scrollDetail[4];
    /// xy the cirrus' offset (clouds.cirrus_offset_m, m, reduced modulo the curl period), zw unused
    float cirrus[4];

    /// From the keys of cloud_keys.hpp (undeclared keys take the defaults the Clouds element
    /// declares: bottom 2000 m, top 3000 m, coverage 0.5, detail scale 1, scattering 0.05/m,
    /// cirrus 9000 m / 0.3, extent 40 km, offset 0, cloud type 1) and planet.radius_m (6 360 000 m). The noise
    /// scrolls with the weather map (noise scroll = (clouds.weather_offset_m, 0)): detail moves
    /// with its cloud; the cirrus moves by clouds.cirrus_offset_m (clouds.weather_offset_m if
    /// unset). Checks the layer (validateCloudLayer()).
    static CloudLayerBlock from(const SkyVars& vars);
    /// The same from explicit values (m, [0,1], 1/m); `noiseScroll` in m; `cirrusOffset` in m
    /// (nullopt: the weather offset); `cloudType` in [0, 1] (0 stratocumulus, 1 cumulus).
    static CloudLayerBlock make(double planetRadius, double bottom, double top, double coverage, double detailScale,
                                double scatteringPerM, double cirrusHeight, double cirrusCoverage, double weatherExtent,
                                glm::dvec2 weatherOffset, glm::dvec3 noiseScroll, double basePeriod = kDefaultNoiseBasePeriodM,
                                double detailPeriod = kDefaultNoiseDetailPeriodM, double curlPeriod = kDefaultCurlPeriodM,
                                std::optional<glm::dvec2> cirrusOffset = std::nullopt, double cloudType = 1.0);
};
static_assert(sizeof(CloudLayerBlock) == 7 * 16, "CloudLayerBlock: std140 layout of 7 vec4");

enum class CloudLod { Cheap = 0, Full = 1 };

/// The density's shape constants (cloud_density.shared.glsl's CLD_* defines, checked equal at
/// compile time).
/// The eroded Perlin-Worley base shape remap(R, fbm - 1, 1, 0, 1) of the generated noise
/// (CloudNoise, 128^3, seed 1) is narrow and bright: its 1st, 5th, 50th and 99th percentiles are
/// 0.69, 0.735, 0.83, 0.93. Stretched from [kShapeLo, kShapeHi] to [0, 1] (the median to 0.63,
/// the 5th percentile to 0.28), the coverage cut max(shape + cov - 1, 0) carves cells and gaps
/// out of the clouds; unstretched, the cut at the fair preset's 0.75 (shape < 0.25) removes no
/// texel and a cloud is the weather map's smooth blob. kShapeLo a little below the 1st
/// percentile: a harder stretch (from the 5th) left only scattered turrets of a cloud at coverage
/// 0.75 (skyelements/clouds/README.md); the stretch also multiplies the 8-bit noise's filtering error (3.7x).
/// Tested: "Cloud density: the base shape fills [0, 1], so the coverage cut carves".
inline constexpr double kShapeLo = 0.66, kShapeHi = 0.93;
/// Height gradients (heightGradient()): cumulus full at 7 % of its height, tapering from 50 %;
/// stratocumulus full at 10 % of its thickness, rounded from 65 %.
inline constexpr double kCuBaseRamp = 0.07, kCuTopStart = 0.5, kScBaseRamp = 0.1, kScTopStart = 0.65;
/// Detail erosion: at most kErosion x clouds.detail_scale of the base density is cut (Schneider
/// 2015 uses 0.2 for a detail noise at 4x the frequency of ours: our cells are larger, the cut
/// deeper); the wispy-to-billowy switch over the lowest 1/kDetailFlip of the cloud.
inline constexpr double kErosion = 0.35, kDetailFlip = 4.0;

/// Binds the clouds' published textures to their units (WELKIN_BINDING_CLOUD_WEATHER_MAP,
/// _NOISE_BASE, _NOISE_DETAIL, _CURL_NOISE, _PATH_LUT; glBindTextureUnit): those set in `vars`
/// (a reader's render() or a generator's pass, before its draw). Needs a current context.
void bindCloudTextures(const SkyVars& vars);

namespace cpu {

/// A texture's level 0 on the CPU: RGBA float texels, x fastest then y then z (GL's order, as
/// gl::Texture::readRgbaFloat() returns them). d = 1 for 2-D.
struct Image {
    int w = 0, h = 0, d = 1;
    std::vector<float> rgba;
    /// Linear filtering with GL_REPEAT at normalised coordinates (GL's texel-centre convention),
    /// double precision.
    glm::dvec4 sample2D(glm::dvec2 uv) const;
    glm::dvec4 sample3D(glm::dvec3 uvw) const;
    glm::dvec4 texel(int x, int y, int z = 0) const;
};

/// The four textures the density reads (level 0 each).
struct CloudTextures {
    const Image& weather;  ///< clouds.weather_map
    const Image& base;     ///< clouds.noise_base
    const Image& detail;   ///< clouds.noise_detail
    const Image& curl;     ///< clouds.curl_noise
};

/// GLSL's remap: (v - lo) / (hi - lo) * (newHi - newLo) + newLo (no clamp).
double remap(double v, double lo, double hi, double newLo, double newHi);
/// Altitude above the ground of ENU point p (m), cancellation-free.
double cloudAltitude(const CloudLayerBlock& b, glm::dvec3 p);
/// Weather-map uv of ENU point p (repeat not applied).
glm::dvec2 weatherUv(const CloudLayerBlock& b, glm::dvec3 p);
/// The height gradient at layer fraction a (0 bottom, 1 top) of a cloud whose base and top sit
/// at fractions wb, wt of the layer (weather G, B), for cloud type `type` in [0, 1] (0
/// stratocumulus: a sheet from wb to wt; 1 cumulus: a flat base at the layer's bottom, full within
/// 7 % of its height, tapering over its upper half to wt; between: a blend): x the profile in
/// [0, 1] (times the upward density gradient 0.75-1), y the position within the cloud's own
/// vertical extent, [0, 1] (what the detail erosion's wispy-to-billowy switch reads).
glm::dvec2 heightGradient(double a, double wb, double wt, double type);
/// Relative density in [0, 1] (contract at the top of this file).
double cloudDensity(const CloudLayerBlock& b, const CloudTextures& t, glm::dvec3 p, CloudLod lod);
/// Entry and exit distances (m) of the shell [b.radii.y, b.radii.z] from radius r with cos
/// zenith mu; exit < 0: no crossing (contract above).
glm::dvec2 cloudShellIntersect(const CloudLayerBlock& b, double r, double mu);
/// The same for explicit radii (planet R, shell [rb, rt], m).
glm::dvec2 shellIntersect(double R, double rb, double rt, double r, double mu);
/// The path integral of the full-LOD density (density x m) from ENU point p along the unit
/// direction dir through the cumulus: n steps growing x1.5, midpoint rule, over min(maxDist (m),
/// the distance to the shell's exit along dir). Times the extinction per unit density it is the
/// optical depth; the Clouds element's light march and its depth to a cloud's far side.
double cloudDepthAlong(const CloudLayerBlock& b, const CloudTextures& t, glm::dvec3 p, glm::dvec3 dir, int n, double maxDist);
/// Cirrus relative density in [0, 1] at ENU (x, y) on its layer.
double cirrusDensity(const CloudLayerBlock& b, const Image& curl, glm::dvec2 xy);

}  // namespace cpu
}  // namespace welkin::generators
