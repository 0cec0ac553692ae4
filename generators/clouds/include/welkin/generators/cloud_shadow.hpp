// CloudShadowMap: the transmittance of the direct light (the Sun, or the Moon at night) through
// the cumulus layer and the cirrus, over a square of ground centred below the observer, for the
// host's scene (clouds.shadow_map, R32F, clamp to edge) and a CPU twin of the same march.
//
//   // C++, once (the processor runs it only when the light, the weather map, its offset or the
//   // layer changed):
//   auto shadow = welkin::generators::CloudShadowMap::obtain(processor.vars());
//   processor.addGenerator(shadow);
//   // each frame, with the host's program current or not:
//   welkin::generators::CloudShadowMap::bindForHost(processor.vars(), hostProgram);
//
//   // GLSL of the host (any stage): prepend the text of cloud_shadow.glsl
//   // (welkin::generators::CloudShadowMap::hostGlsl(); it defines the sampler at
//   // WELKIN_BINDING_CLOUD_SHADOW_MAP, 9 unless the host defines it, and two vec4 uniforms)
//   float s = welkin_cloudShadow(worldPosEnuM);   // 1 in full light, 0 under a thick cloud
//   vec3 direct = s * sunIlluminanceLux * max(dot(n, sunDir), 0.0) * albedo / pi;
//
// Model (docs/clouds.md, "Cloud shadows"): for each texel's ground point the light ray is marched
// in the spherical geometry of the planet (radius planet.radius_m) through the shell between
// clouds.bottom_m and clouds.top_m in clouds.shadow_steps equal steps (midpoint rule), summing
// the optical depth sigma * D(p) ds with sigma = clouds.scattering_per_m (single-scattering
// albedo ~1: extinction = scattering) and D the cumulus density at its cheap level of detail:
// SevenSky's density (Papp 2018, eq. 5.2-5.5) from the weather map alone, without the detail
// noise's erosion,
//     D(p) = clamp(Dcov(W_R) * Hs(h), 0, 1),  Dcov(d) = max(d + c - 1, 0) / c  (eq. 5.4),
//     Hs(h) = 4 (h - hb)(ht - h) / (ht - hb)^2  (the parabola of eq. 5.2 between the cloud's
//     base hb = bottom + W_G (top - bottom) and top ht = bottom + W_B (top - bottom)),
// the weather map read with the contract's mapping (cloud_keys.hpp) at the sample's ENU x, y.
// The cirrus (clouds.cirrus_coverage, a thin sheet at clouds.cirrus_height_m) adds a uniform
// optical depth kCirrusOpticalDepth * coverage / mu_c along the slant (mu_c the ray's cosine of
// zenith at the cirrus' height). Transmittance = exp(-(tau_cumulus + tau_cirrus)).
//
// The light: the Sun while it is above -6 deg (civil twilight; below it a full Moon's 0.1-0.3 lux
// competes with the sky's few lux), else the Moon; its elevation is clamped to >= 0 (a ray along
// the horizon crosses the curved shell over a finite ~40 km: the map stays finite). The light the
// map was built for is published as clouds.shadow_light_direction.
//
// Wind: the weather offset enters the host's lookup as a shift (the map built at offset o0 read at
// offset o is the map at xy + (o - o0), exactly, since the march is translation-invariant), so
// the map is rebuilt only when the offset moved by more than kOffsetTolerance or any other input
// changed; near the map's edges, the shifted lookup clamps to the edge texel.
#pragma once
#include <welkin/element.hpp>
#include <welkin/generators/cloud_keys.hpp>

#include <memory>
#include <string_view>
#include <vector>

namespace welkin::generators {

/// Vertical optical depth of a cirrus sheet at clouds.cirrus_coverage = 1: 0.3, the upper end of
/// "thin" cirrus (0.03-0.3) in Sassen & Cho, J. Appl. Meteor. 31 (1992) 1275.
inline constexpr double kCirrusOpticalDepth = 0.3;
/// The Moon takes over as the shadow's light when the Sun is below this elevation, rad (-6 deg).
inline constexpr double kShadowMoonBelowSunElevationRad = -0.10471975511965977;
/// A weather-offset change below this does not rebuild the map (the lookup shifts instead), m.
inline constexpr double kOffsetTolerance = 1000.0;

/// Everything the shadow march reads, in double (the CPU twin's input; the GPU pass gets the same
/// values as uniforms and the weather map as a texture).
struct CloudShadowParams {
    double bottomM = 2000.0, topM = 3000.0;  ///< the cumulus layer above the ground, m
    double coverage = 0.5;                   ///< [0, 1]
    double scatteringPerM = 0.05;            ///< 1/m at density 1
    double cirrusCoverage = 0.0;             ///< [0, 1]
    double cirrusHeightM = 9000.0;           ///< m above the ground
    double planetRadiusM = 6360e3;           ///< m
    double weatherExtentM = 50e3;            ///< m
    glm::dvec2 weatherOffsetM{0.0};          ///< m
    glm::dvec3 light{0.0, 0.0, 1.0};         ///< unit, ENU, z >= 0
    int steps = 16;                          ///< [1, 256]
};

/// The weather map on the CPU: RGBA per texel, row 0 at v = 0 (south), as GL stores it; sampled
/// bilinearly with repeat like GL_LINEAR + GL_REPEAT.
struct WeatherImage {
    int width = 0, height = 0;
    std::vector<glm::dvec4> texels;  ///< width * height, row-major from v = 0
    glm::dvec4 sample(glm::dvec2 uv) const;
};

namespace cpu {
/// The cheap-LOD cumulus density D in [0, 1] at ENU (x, y) and height hM above the ground.
double cloudShadowDensity(const WeatherImage& weather, const CloudShadowParams& p, glm::dvec2 xyM, double hM);
/// Transmittance in [0, 1] of the light from the ground point at ENU (x, y) (height 0 above the
/// ground) through the cumulus layer and the cirrus: the value of clouds.shadow_map there. An empty
/// weather image means no cumulus.
double cloudShadowTransmittance(const WeatherImage& weather, const CloudShadowParams& p, glm::dvec2 groundXyM);
/// The ground point whose map texel lights ENU point `worldPosEnuM` (height above the ground
/// hM = z + observer height, clamped to [0, bottom]): xy - hM * light.xy / light.z, then shifted
/// by the weather offset's change since the map was built. The twin of welkin_cloudShadow()'s
/// mapping.
glm::dvec2 cloudShadowGroundPoint(glm::dvec3 worldPosEnuM, double observerHeightM, const CloudShadowParams& p, glm::dvec2 shiftM);
}  // namespace cpu

class CloudShadowMap final : public Generator {
public:
    CloudShadowMap();
    /// The shared instance of `vars` (created on first request).
    static std::shared_ptr<CloudShadowMap> obtain(SkyVars& vars);
    /// The parameters the next run would use, from `vars` (undeclared cloud keys take the
    /// CloudShadowParams defaults).
    static CloudShadowParams params(const SkyVars& vars);
    /// Binds clouds.shadow_map to WELKIN_BINDING_CLOUD_SHADOW_MAP and sets the two mapping
    /// uniforms of cloud_shadow.glsl in `program` (a GL program name; 0: only the texture). Does
    /// nothing if the map was never built. Call after the processor's update().
    static void bindForHost(const SkyVars& vars, unsigned program);
    /// The two mapping uniforms: m0 = (shift x, shift y, 1 / extent, ground z in ENU), m1 =
    /// (light x, y, z, cloud base height above the ground), as cloud_shadow.glsl reads them.
    static void hostUniforms(const SkyVars& vars, float m0[4], float m1[4]);
    /// The text of cloud_shadow.glsl (welkin_cloudShadow()), for a host's shader.
    static std::string_view hostGlsl();

private:
    void doRun(SkyVars& vars, const Logger& log) override;
    void doRelease() override;
    void doDeclare(SkyVars& vars) override;
    void doStats(nlohmann::json& root) const override;
    struct Gl;
    std::shared_ptr<Gl> gl_;
    CloudShadowParams last_;
};

}  // namespace welkin::generators
