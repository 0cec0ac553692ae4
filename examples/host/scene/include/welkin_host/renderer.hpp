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
//    (welkin_cloudShadow) on the light the cloud shadow map is made for. Roughness is clamped to
//    >= 0.045 for the direct light only (a = 0.002: a point light's highlight stays finite).
//  * Ambient diffuse: albedo (1 - metallic) / pi x E_sh(n), the irradiance of the environment from
//    its nine SH radiance coefficients: E(n) = sum_lm A_l L_lm Y_lm(n), A = (pi, 2pi/3, pi/4).
//  * Ambient specular (split sum, Karis 2013): the GGX-prefiltered radiance cube at
//    mip = roughness (mips - 1), times (F0 A + B) from a table of the directional albedo of the
//    same BRDF (computeBrdfTable(), made on the CPU at start-up).
// Depth: the renderer draws with the caller's depth state (the example sets reversed-Z,
// GL_GREATER); it leaves the program, vertex array and texture units 0..2 changed.
#pragma once
#include <welkin_host/gl.hpp>
#include <welkin_host/scene.hpp>

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

/// Everything the renderer is lit by, in the host's world axes where it says so.
struct SceneLighting {
    DirectionalLight sun, moon;
    /// Radiance of the environment in real SH (l <= 2), coefficients in cd/m^2 over ENU
    /// directions, order Y00, Y1-1(y), Y10(z), Y11(x), Y2-2, Y2-1, Y20, Y21, Y22.
    std::array<glm::vec3, 9> sh9RadianceEnu{};
    glm::mat3 worldToEnu{1.0f};   ///< rotation of host-world directions into ENU
    glm::dmat4 worldToEnuPoint{1.0};  ///< host-world positions to ENU metres (the cloud shadow)
    unsigned specularCube = 0;    ///< GGX-prefiltered radiance cube (cd/m^2); 0: the SH instead
    int specularMips = 1;         ///< mip k holds roughness k / (mips - 1)
    glm::mat3 worldToCube{1.0f};  ///< rotation of host-world directions into the cube's axes
    /// GLSL defining float welkin_cloudShadow(vec3 enuPositionM), and the call that binds its
    /// texture and sets its uniforms in a program; empty: no cloud shadow.
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

class SceneRenderer {
public:
    /// Compiles the programs and uploads the BRDF table (64 x 64, 512 samples: 11 ms on 2 cores).
    SceneRenderer();
    /// Draws every primitive of the scene with depth test and writes, no blending.
    void draw(const Scene& scene, const ViewParams& view, const SceneLighting& lighting);

private:
    unsigned program(bool cloudShadow, const std::string& cloudGlsl);
    GlName programPlain_, programClouds_;
    GlName brdfTable_;
};

}  // namespace host
