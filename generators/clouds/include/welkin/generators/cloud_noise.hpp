// The clouds' noise textures (Generator CloudNoise): tileable 3-D base and detail noise and the
// 2-D curl noise of the cirrus, computed on the GPU (shaders/cloud_noise*.glsl, curl_noise.glsl)
// from clouds.seed, mipmapped, GL_REPEAT. cpu:: holds the twin of each texel's formula: the
// shaders' cloud_noise.shared.glsl compiled as C++ in double.
//
//   auto noise = welkin::generators::CloudNoise::obtain(vars);   // one per SkyVars
//   element.addGenerator(noise);                                  // in doInit
//   // publishes clouds.noise_base (128^3 RGBA8), clouds.noise_detail (32^3 RGBA8),
//   // clouds.curl_noise (256^2 RGBA8); re-runs when clouds.seed changes
//
// Layouts (all channels in [0, 1], linear, 8 bits):
//   noise_base   R Perlin-Worley: Perlin fBm (4 cells per tile, 4 octaves) dilated by Worley fBm
//                (4 cells): remap(perlin, 0, 1, worley, 1); G, B, A Worley fBm at 8, 16, 32 cells
//                (Schneider & Vos 2015, "Nubis" layout)
//   noise_detail R, G, B Worley fBm at 2, 4, 8 cells; A = 1
//   curl_noise   R, G the curl of a 2-D Perlin fBm potential (4 cells, 5 octaves), /8, encoded
//                0.5 + 0.5 v; B the potential; A = 1 (Bridson, Hourihan & Nordenstam 2007)
// Worley fBm(f) = 0.625 W(f) + 0.25 W(2f) + 0.125 W(4f), W = 1 - distance to the nearest feature
// point in cell units (one point per cell, Worley 1996). Every texture is periodic: texel N
// continues texel 0 seamlessly (the feature points and gradients are hashed from the cell index
// modulo the cells per tile).
#pragma once
#include <welkin/element.hpp>
#include <welkin/gl/objects.hpp>

#include <cstdint>
#include <memory>

namespace welkin::generators {

class CloudNoise : public Generator {
public:
    /// Texels per edge (each >= 4, a power of two keeps the texel centres off cell borders).
    struct Sizes {
        int base = 128;
        int detail = 32;
        int curl = 256;
    };
    CloudNoise();  ///< default Sizes
    explicit CloudNoise(Sizes sizes);
    /// The instance shared by every element of `vars` (default sizes).
    static std::shared_ptr<CloudNoise> obtain(SkyVars& vars);
    const gl::Texture3D& base() const { return base_; }
    const gl::Texture3D& detail() const { return detail_; }
    const gl::Texture2D& curl() const { return curl_; }
    const Sizes& sizes() const { return sizes_; }
    /// GPU time of the last run's passes (s, measured with glFinish), for the docs and stats.
    double lastRunSeconds() const { return lastSeconds_; }

private:
    void doRun(SkyVars& vars, const Logger& log) override;
    void doRelease() override;
    void doStats(nlohmann::json& root) const override;
    Sizes sizes_;
    gl::Texture3D base_, detail_;
    gl::Texture2D curl_;
    gl::Program prog3d_, progCurl_;
    double lastSeconds_ = 0.0;
};

namespace cpu {
/// Texel (x, y, z) of the base noise of `size`^3 texels (centre (i + 0.5) / size), RGBA in [0, 1]
/// before the 8-bit quantisation.
glm::dvec4 baseNoise(int x, int y, int z, int size, uint32_t seed);
/// Texel of the detail noise.
glm::dvec4 detailNoise(int x, int y, int z, int size, uint32_t seed);
/// Texel (x, y) of the curl noise of `size`^2 texels.
glm::dvec4 curlNoise(int x, int y, int size, uint32_t seed);
/// The primitives at a normalised point p (period 1), f cells per tile (cloud_noise.shared.glsl).
uint32_t noiseHash(uint32_t x);
double worley(glm::dvec3 p, int f, uint32_t seed);
double worleyFbm(glm::dvec3 p, int f, uint32_t seed);
double perlin(glm::dvec3 p, int f, uint32_t seed);
double perlinFbm(glm::dvec3 p, int f, int octaves, uint32_t seed);
double perlin2(glm::dvec2 p, int f, uint32_t seed);
double perlinFbm2(glm::dvec2 p, int f, int octaves, uint32_t seed);
}  // namespace cpu

}  // namespace welkin::generators
