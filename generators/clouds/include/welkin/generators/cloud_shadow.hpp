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
// Model (skyelements/clouds/README.md, "Cloud shadows"): for each texel's ground point the light ray is marched
// in the spherical geometry of the planet (radius planet.radius_m) through the shell between
// clouds.bottom_m and clouds.top_m in clouds.shadow_steps equal steps (midpoint rule), summing
// the optical depth sigma * D(p) ds with sigma = clouds.scattering_per_m (single-scattering
// albedo ~1: extinction = scattering) and D the shared cloud density (cloud_density.hpp) at its
// cheap level of detail (CloudLod::Cheap: weather map, height profile and base shape, without the
// detail noise's erosion; Cheap >= Full, so the shadow is at most slightly too dark at the
// clouds' frayed edges). The cirrus adds kCirrusOpticalDepth x cirrusDensity(x, y) / mu_c where
// the ray crosses its layer (mu_c the ray's cosine of zenith there). Transmittance =
// exp(-(tau_cumulus + tau_cirrus)).
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
#include <welkin/generators/cloud_density.hpp>
#include <welkin/generators/cloud_keys.hpp>

#include <memory>
#include <string_view>
#include <vector>

namespace welkin::generators {

/// Vertical optical depth of the cirrus at relative density 1 (cirrusDensity() = 1): 0.3, the
/// upper end of "thin" cirrus (0.03-0.3) in Sassen & Cho, J. Appl. Meteor. 31 (1992) 1275.
inline constexpr double kCirrusOpticalDepth = 0.3;
/// The Moon takes over as the shadow's light when the Sun is below this elevation, rad (-6 deg).
inline constexpr double kShadowMoonBelowSunElevationRad = -0.10471975511965977;
/// A weather-offset change below this does not rebuild the map (the lookup shifts instead), m.
inline constexpr double kOffsetTolerance = 1000.0;

namespace cpu {
/// Transmittance in [0, 1] of the light `light` (unit, ENU, z >= 0) from the ground point at ENU
/// (x, y) (height 0) through the cumulus layer (`steps` steps, the cheap density) and the cirrus:
/// the value of clouds.shadow_map there. `t.weather`, `t.base`, `t.curl` are read; an empty
/// weather image means no cumulus, an empty curl image no cirrus.
double cloudShadowTransmittance(const CloudLayerBlock& b, const CloudTextures& t, glm::dvec3 light, int steps, glm::dvec2 groundXyM);
/// The ground point whose map texel lights ENU point `worldPosEnuM` (origin at the observer;
/// height above the ground hM = z + observer height, clamped to [0, bottomM]):
/// xy - hM * light.xy / max(light.z, 1e-3). The twin of welkin_cloudShadow()'s mapping (without
/// the wind's shift).
glm::dvec2 cloudShadowGroundPoint(glm::dvec3 worldPosEnuM, double observerHeightM, double bottomM, glm::dvec3 light);
}  // namespace cpu

class CloudShadowMap final : public Generator {
public:
    CloudShadowMap();
    /// The shared instance of `vars` (created on first request).
    static std::shared_ptr<CloudShadowMap> obtain(SkyVars& vars);
    /// The light the next run would use (the Sun, or the Moon at night; elevation clamped to
    /// >= 0), from sun.direction and moon.direction.
    static glm::dvec3 lightDirection(const SkyVars& vars);
    /// Binds clouds.shadow_map to WELKIN_BINDING_CLOUD_SHADOW_MAP and sets the two mapping
    /// uniforms of cloud_shadow.glsl in `program` (a GL program name; 0: only the texture). Does
    /// nothing if the map was never built. Call after the processor's update().
    static void bindForHost(const SkyVars& vars, unsigned program);
    /// The two mapping uniforms: m0 = (shift x, shift y, 1 / extent, ground z in ENU), m1 =
    /// (light x, y, z, cloud base height above the ground), as cloud_shadow.glsl reads them.
    static void hostUniforms(const SkyVars& vars, float m0[4], float m1[4]);
    /// True when there is nothing to shadow (no cumulus and no cirrus coverage: the clear preset, or
    /// no clouds at all): the map is then 1 everywhere, exactly, and a reader may skip its lookup.
    static bool nothingToShadow(const SkyVars& vars);
    /// The text of cloud_shadow.glsl (welkin_cloudShadow()), for a host's shader.
    static std::string_view hostGlsl();
    /// Parts of time-sliced rebuilds drawn so far (clouds.shadow_slices), for tests.
    int slicesBuilt() const { return slicesBuilt_; }
    /// Whole maps drawn so far (the first build, a change of the layer, a render), for tests.
    int wholeBuilds() const { return wholeBuilds_; }

private:
    void doRun(SkyVars& vars, const Logger& log) override;
    void doRelease() override;
    void doDeclare(SkyVars& vars) override;
    void doStats(nlohmann::json& root) const override;
    struct Gl;
    std::shared_ptr<Gl> gl_;
    glm::dvec3 lastLight_{0.0, 0.0, 1.0};
    int lastSteps_ = 0;
    int slicesBuilt_ = 0;
    int wholeBuilds_ = 0;
};

}  // namespace welkin::generators
