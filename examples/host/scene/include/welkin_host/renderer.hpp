// The host's PBR renderer: glTF metallic-roughness materials lit only by the sky's outputs.
//
//   host::SceneRenderer renderer;                        // compiles its programs, builds the BRDF table
//   renderer.draw(scene, view, lighting);                // into the bound HDR framebuffer (cd/m^2)
//
// Shading (per fragment, linear RGB whose Y is luminance; output radiance in cd/m^2):
//  * BRDF: Lambert diffuse (albedo (1 - metallic) / pi) + GGX specular: D = a^2 / (pi ((n.h)^2
//    (a^2 - 1) + 1)^2) with a = roughness^2, Smith-GGX height-correlated visibility
//    V = 0.5 / (n.l sqrt((n.v)^2 (1 - a^2) + a^2) + n.v sqrt((n.l)^2 (1 - a^2) + a^2)) (Heitz 2014),
//    Schlick's Fresnel F = F0 + (1 - F0)(1 - v.h)^5, F0 = mix(0.04, baseColor, metallic).
//  * Direct light: the Sun and the Moon as directional lights, illuminance E (lux, per channel,
//    on a surface facing the body): L = f(l, v) E (n.l) s, where s is the clouds' shadow
//    (welkin_cloudShadow) on the light the cloud shadow map is made for, and the scene's own
//    shadow (ShadowSettings) on the brighter light. Roughness is clamped to
//    >= 0.045 for the direct light only (a = 0.002: a point light's highlight stays finite).
//  * Ambient diffuse: albedo (1 - metallic) / pi x E(n), the environment's irradiance from welkin's
//    nine SH coefficients (GLSL welkin_shIrradiance, welkin::lightingGlslChunks()).
//  * Ambient specular (split sum, Karis 2013): welkin's GGX-prefiltered radiance cube around the
//    reflected direction at the material's roughness (welkin_specularRadiance), times
//    (F0 A + B) from a table of the directional albedo of the same BRDF (computeBrdfTable(),
//    made on the CPU at start-up).
// Depth: the renderer draws with the caller's depth state (the example sets reversed-Z,
// GL_GREATER); it leaves the program, vertex array and texture units 0, 1, 2 and 9 changed.
#pragma once
#include <welkin_host/gl.hpp>
#include <welkin_host/scene.hpp>

#include <welkin/lighting.hpp>

#include <glm/glm.hpp>

#include <array>
#include <functional>
#include <string>
#include <vector>

namespace host {

struct DirectionalLight {
    glm::vec3 directionWorld{0.0f, 1.0f, 0.0f};  ///< unit vector towards the body, host world axes
    glm::vec3 illuminanceRgb{0.0f};              ///< lux per channel on a surface facing the body
    bool cloudShadow = false;                    ///< the cloud shadow map is made for this light
};

/// Everything the renderer is lit by.
struct SceneLighting {
    DirectionalLight sun, moon;
    /// welkin's lighting: the environment's SH irradiance and the GGX-prefiltered specular cube,
    /// set in the program by welkin::bindLighting() and read by welkin's GLSL chunks
    /// (welkin_shIrradiance, welkin_specularRadiance). Required.
    const welkin::SkyLighting* sky = nullptr;
    glm::dmat3 enuFromWorld{1.0};         ///< rotation of host-world directions into ENU
    glm::dmat4 worldToEnuPoint{1.0};      ///< host-world positions to ENU metres (the cloud shadow)
    /// GLSL defining float welkin_cloudShadow(vec3 enuPositionM), and the call that binds its
    /// texture and sets its uniforms in a program; empty: no cloud shadow in the shader.
    std::string cloudShadowGlsl;
    std::function<void(unsigned program)> bindCloudShadow;
};

struct ViewParams {
    glm::mat4 view{1.0f};
    glm::mat4 projection{1.0f};
    glm::vec3 eyeWorld{0.0f};
};

/// The split-sum table: for (n.v, roughness) on a size x size grid (texel centres), the
/// directional albedo of the GGX specular lobe split into F0 scale (x) and bias (y):
/// integral f(l, v) (n.l) dl = F0 x + y, by importance sampling the GGX distribution with
/// `samples` Hammersley points (deterministic). Row-major, n.v along x.
std::vector<glm::vec2> computeBrdfTable(int size, int samples);

/// The scene's own shadows: one shadow map for the brighter of the Sun and the Moon (the host's
/// business: welkin knows the light, the host knows its geometry). An orthographic depth map of
/// `size`^2 texels over a square 2 halfExtentM wide about a point (the camera), looked up with
/// 2 x 2 hardware-filtered taps (PCF) and a normal offset against acne.
struct ShadowSettings {
    bool enabled = true;
    int size = 2048;             ///< texels per side, [256, 8192]
    float halfExtentM = 400.0f;  ///< half the side of the shadowed square, metres
};

class SceneRenderer {
public:
    /// Compiles the programs and uploads the BRDF table (64 x 64, 512 samples: about 0.15 s on
    /// one core of this machine, once).
    explicit SceneRenderer(const ShadowSettings& shadows = {});
    /// Renders the shadow map of the brighter light about `centreWorld` (call before draw(), with
    /// no framebuffer requirement: it binds its own and restores the caller's framebuffer,
    /// viewport, clip control and depth state). Nothing when shadows are disabled or both
    /// lights are dark or below the horizon.
    void renderShadows(const Scene& scene, const SceneLighting& lighting, const glm::vec3& centreWorld);
    /// Draws every primitive of the scene with depth test and writes, no blending.
    void draw(const Scene& scene, const ViewParams& view, const SceneLighting& lighting);

private:
    unsigned program(bool cloudShadow, const std::string& cloudGlsl);
    ShadowSettings shadowSettings_;
    GlName programPlain_, programClouds_, depthProgram_;
    GlName brdfTable_;
    GlName shadowMap_, shadowFbo_;
    glm::mat4 shadowViewProjection_{1.0f};
    int shadowLight_ = 0;  // 0: none this frame, 1: the Sun, 2: the Moon
};

}  // namespace host
