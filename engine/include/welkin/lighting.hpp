// SkyLighting: the light a host's scene receives from the sky it stands under (docs/lighting.md).
//
//   welkin::SkyProcessor sky;                               // elements added, time and place set
//   sky.setLighting(welkin::LightingOptions{});             // lighting.enabled = true (off by default)
//   sky.renderInto(target);                                 // the capture runs at the end of update()
//   const welkin::SkyLighting& L = sky.lighting();
//   glm::dvec3 sunLux = L.sun.illuminanceRgb;               // lux on a surface facing the Sun
//   glm::dvec3 ambient = L.irradiance({0, 0, 1});           // lux on an upward-facing surface
//   // In the host's shaders (GLSL 4.5): add the chunks of lightingGlslChunks() to the fragment
//   // stage, call welkin::bindLighting(program, L, unit) before drawing, then
//   //   vec3 E = welkin_shIrradiance(welkin_toEnu(n));              // lux
//   //   vec3 Ls = welkin_specularRadiance(welkin_toEnu(r), rough);  // cd/m^2, GGX-prefiltered
//
// Outputs: the Sun's and the Moon's directional lights (through the atmosphere, the clouds and
// eclipses; from the lights.* keys), the environment's radiance (every element that
// contributesToLighting(): sky, clouds, aureole, ground bounce, night sky; not the Sun's and
// Moon's disks, which are the directional lights, nor overlays) as 9 spherical-harmonic
// coefficients, a GGX-prefiltered specular cube map, SevenSky's 16x16 sky light map and six
// axis lights, and the exposure the tone map used. Units: radiance cd/m^2, illuminance lux,
// directions unit vectors in the observer's East-North-Up frame.
//
// Cost: recomputed only when a key of the SkyVars changed since the last capture; in the
// interactive path (render.interactive) spread over frames, lighting.slices_per_frame slices per
// frame (a slice: one face of the capture, the reductions, or one mip of the specular cube); in
// an offline frame all of it at once. Each stage's time is in --stats ("lighting").
#pragma once
#include <welkin/vars.hpp>

#include <array>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace welkin {

/// A light at infinity (the Sun, the Moon) as the observer receives it.
struct DirectionalLight {
    glm::dvec3 directionEnu{0, 0, 1};  ///< unit vector towards the body (ENU)
    /// Illuminance per linear-sRGB channel on a surface facing the body, lux, after the
    /// atmosphere, the clouds and eclipses; its luminance (Y) is illuminanceLux.
    glm::dvec3 illuminanceRgb{0.0};
    double illuminanceLux = 0.0;  ///< photopic illuminance, lux, >= 0
    glm::dvec3 colorRgb{1.0};     ///< illuminanceRgb / illuminanceLux (luminance 1), or 1 when dark
};

/// Real spherical harmonics up to l = 2 in the ENU frame (n = (x east, y north, z up), unit).
namespace sh {
/// Order of the coefficients: Y00, Y1-1 (y), Y10 (z), Y11 (x), Y2-2 (xy), Y2-1 (yz), Y20, Y21 (xz), Y22.
std::array<double, 9> basis(const glm::dvec3& n);
/// The clamped-cosine kernel's convolution constants A_l: pi, 2 pi / 3, pi / 4 (Ramamoorthi &
/// Hanrahan 2001): E_lm = A_l L_lm.
inline constexpr double kA0 = 3.14159265358979323846, kA1 = 2.0 * kA0 / 3.0, kA2 = kA0 / 4.0;
/// A_l of coefficient i (0..8).
double convolution(int i);
}  // namespace sh

struct SkyLighting {
    DirectionalLight sun, moon;
    /// Radiance of the environment in real SH (sh::basis order, ENU axes): coefficients L_lm in
    /// cd/m^2 (lux per steradian): L(d) ~ sum L_lm Y_lm(d).
    std::array<glm::dvec3, 9> sh9Radiance{};
    /// Irradiance (lux) on a surface with unit normal n (ENU): sum A_l L_lm Y_lm(n).
    glm::dvec3 irradiance(const glm::dvec3& normalEnu) const;
    /// The irradiance-convolved coefficients E_lm = A_l L_lm (lux): E(n) = sum E_lm Y_lm(n).
    std::array<glm::dvec3, 9> sh9Irradiance() const;
    /// GGX-prefiltered radiance cube map (RGBA32F, cd/m^2): mip k holds perceptual roughness
    /// r = k / (specularMips - 1) (GGX alpha = r^2), mip 0 the radiance itself. Faces in the
    /// camera's CubeFace convention: cube axes x east, y up, z south (a direction d in ENU is
    /// looked up at (d.x, d.z, -d.y)). id 0 until the first capture.
    TextureRef specularCube;
    int specularMips = 0;
    /// SevenSky's 16x16 sky light map: an equirect of the environment (RGBA32F, cd/m^2, each
    /// texel the mean radiance over its solid angle); u = azimuth / 2 pi (from north through
    /// east), v = (altitude + pi/2) / pi (texel row 0, the first in GL's memory, is the nadir's).
    TextureRef skyLightMap;
    /// SevenSky's six directional lights along +E, -E, +N, -N, +U, -U (lux): the sum over the
    /// light map's texels on that side of sum L |d . axis| Omega (the irradiance of a surface
    /// facing the axis, from the light map). Shade with sum D_i max(n . axis_i, 0).
    std::array<glm::dvec3, 6> axisLights{};
    double ev100 = 0.0;     ///< the exposure (EV100) of the last tone map: the eye's, or the manual setting
    uint64_t revision = 0;  ///< bumped each time any output changed
};

/// Options (also the keys lighting.*; setLighting() writes them).
struct LightingOptions {
    int cubeSize = 32;        ///< face size of the captured radiance cube, texels, power of two in [8, 1024]
    int specularMips = 5;     ///< mips of the specular cube (roughness steps), [1, log2(cubeSize) + 1]
    int slicesPerFrame = 1;   ///< interactive path: slices per frame, [1, 64] (a face, the reductions, a mip)
    /// Throws welkin::Error with one line naming `where`, the member and its accepted range.
    void validate(const char* where) const;
};

namespace keys {
inline const Key<bool> lightingEnabled{"lighting.enabled", "compute SkyLighting (host lighting: Sun, Moon, SH irradiance, specular cube, light map) at the end of update()"};
inline const Key<int> lightingCubeSize{"lighting.cube_size", Range{8, 1024}, "face size of SkyLighting's environment cube, texels (power of two)"};
inline const Key<int> lightingSpecularMips{"lighting.specular_mips", Range{1, 11}, "mips (roughness steps) of SkyLighting's specular cube"};
inline const Key<int> lightingSlicesPerFrame{"lighting.slices_per_frame", Range{1, 64}, "interactive path: SkyLighting slices per frame (a cube face, the reductions, a specular mip)"};
// Published outputs (read-only for hosts and elements).
inline const Key<glm::dvec3> lightingSunIlluminance{"lighting.sun_illuminance", Range{0, 1e7}, "SkyLighting: the Sun's illuminance at the observer after the air, clouds and eclipses, per channel", "lx"};
inline const Key<glm::dvec3> lightingMoonIlluminance{"lighting.moon_illuminance", Range{0, 1e6}, "SkyLighting: the Moon's illuminance at the observer after the air, clouds and eclipses, per channel", "lx"};
inline const Key<glm::dvec3> lightingIrradianceUp{"lighting.irradiance_up", Range{0, 1e7}, "SkyLighting: the environment's irradiance on an upward-facing surface from its SH (no Sun or Moon), per channel", "lx"};
inline const Key<TextureRef> lightingSpecularCube{"lighting.specular_cube", "SkyLighting: GGX-prefiltered radiance cube (RGBA32F, cd/m^2)"};
inline const Key<TextureRef> lightingSkyLightMap{"lighting.sky_light_map", "SkyLighting: SevenSky's 16x16 equirect sky light map (RGBA32F, cd/m^2)"};
}  // namespace keys

/// GLSL for a host's fragment (or any) stage, as (name, text) chunks to add in order after the
/// host's `#version 450`: uniforms welkin_sh9[9] (E_lm, lux), welkin_specularCube,
/// welkin_specularMips, welkin_enuFromWorld (mat3), and the functions
///   vec3 welkin_toEnu(vec3 worldVector);                  // host world -> ENU (welkin_enuFromWorld)
///   vec3 welkin_shIrradiance(vec3 nEnu);                  // lux on a surface of unit normal n
///   vec3 welkin_specularRadiance(vec3 rEnu, float roughness);  // cd/m^2, roughness in [0, 1]
///   vec3 welkin_specular(vec3 rEnu, float roughness);          // the same
std::vector<std::pair<std::string, std::string>> lightingGlslChunks();

/// Sets the uniforms of lightingGlslChunks() in `program` (a linked GL program name) and binds
/// the specular cube to texture unit `textureUnit` (the host's choice, [0, 79]).
/// `enuFromWorld`: the rotation from the host's world axes to ENU (for a Y-up world with -z
/// north: columns (1,0,0), (0,0,1), (0,-1,0)); identity if the host shades in ENU.
void bindLighting(unsigned program, const SkyLighting& lighting, int textureUnit, const glm::dmat3& enuFromWorld = glm::dmat3(1.0));

}  // namespace welkin
