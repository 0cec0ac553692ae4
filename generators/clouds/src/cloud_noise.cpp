// Cloud noise generator (GPU passes cloud_noise_3d.glsl, curl_noise.glsl on cloud_noise.glsl) and
// the CPU twin of each texel: cloud_noise.shared.glsl compiled in double (welkin/glsl_cpp.hpp).
#include <welkin/embedded/clouds_shaders.hpp>
#include <welkin/generators/cloud_keys.hpp>
#include <welkin/generators/cloud_noise.hpp>
#include <welkin/gl/bindings.hpp>
#include <welkin/gl/shader.hpp>
#include <welkin/check.hpp>
#include <welkin/glsl_cpp.hpp>

#include <epoxy/gl.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>

namespace welkin::glsl::dp::cloud_noise_shared {
#include "cloud_noise.shared.glsl"
}  // namespace welkin::glsl::dp::cloud_noise_shared

namespace welkin::generators {

namespace {
int mipLevels(int n) {
    int l = 1;
    while (n > 1) n >>= 1, ++l;
    return l;
}
}  // namespace

CloudNoise::CloudNoise() : CloudNoise(Sizes{}) {}

CloudNoise::CloudNoise(Sizes sizes) : Generator("clouds.noise"), sizes_(sizes) {
    checkRange("CloudNoise", "base size", sizes.base, 4, 512);
    checkRange("CloudNoise", "detail size", sizes.detail, 4, 256);
    checkRange("CloudNoise", "curl size", sizes.curl, 4, 4096);
    input(cloudkeys::seed, {.optional = true});
    output(cloudkeys::noiseBase);
    output(cloudkeys::noiseDetail);
    output(cloudkeys::curlNoise);
}

std::shared_ptr<CloudNoise> CloudNoise::obtain(SkyVars& vars) {
    static const Key<std::shared_ptr<CloudNoise>> kShared{"generators.cloud_noise"};
    return vars.obtain<CloudNoise>(kShared, [] { return std::make_shared<CloudNoise>(); });
}

void CloudNoise::doRelease() {
    base_ = {};
    detail_ = {};
    curl_ = {};
    prog3d_ = {};
    progCurl_ = {};
}

void CloudNoise::doStats(nlohmann::json& root) const {
    root["clouds"]["noise"] = {{"base_size", sizes_.base},
                               {"detail_size", sizes_.detail},
                               {"curl_size", sizes_.curl},
                               {"last_run_s", lastSeconds_}};
}

void CloudNoise::doRun(SkyVars& vars, const Logger&) {
    const auto seed = uint32_t(vars.getOr(cloudkeys::seed, 1));
    const auto t0 = std::chrono::steady_clock::now();
    if (!prog3d_) {
        prog3d_ = gl::ProgramBuilder("CloudNoise")
                      .compute("generators/cloud_noise.glsl", embedded::clouds_shaders("cloud_noise.glsl"))
                      .compute("generators/cloud_noise_3d.glsl", embedded::clouds_shaders("cloud_noise_3d.glsl"))
                      .build();
        progCurl_ = gl::ProgramBuilder("CurlNoise")
                        .compute("generators/cloud_noise.glsl", embedded::clouds_shaders("cloud_noise.glsl"))
                        .compute("generators/curl_noise.glsl", embedded::clouds_shaders("curl_noise.glsl"))
                        .build();
    }
    auto make3d = [](gl::Texture3D& t, int n) {
        if (t && t.width() == n) return;
        t = gl::Texture3D(n, n, n, GL_RGBA8, mipLevels(n));
        t.setFilter(GL_LINEAR_MIPMAP_LINEAR, GL_LINEAR);
        t.setWrap(GL_REPEAT);
    };
    make3d(base_, sizes_.base);
    make3d(detail_, sizes_.detail);
    if (!curl_) {
        curl_ = gl::Texture2D(sizes_.curl, sizes_.curl, GL_RGBA8, mipLevels(sizes_.curl));
        curl_.setFilter(GL_LINEAR_MIPMAP_LINEAR, GL_LINEAR);
        curl_.setWrap(GL_REPEAT);
    }
    prog3d_.use();
    glUniform1ui(prog3d_.location("u_seed"), seed);
    for (int kind = 0; kind < 2; ++kind) {
        gl::Texture3D& t = kind == 0 ? base_ : detail_;
        const int n = t.width();
        glBindImageTexture(gl::binding::kLutImage, t.id(), 0, GL_TRUE, 0, GL_WRITE_ONLY, GL_RGBA8);
        prog3d_.set("u_size", n);
        prog3d_.set("u_kind", kind);
        // Slabs of 8 slices: each dispatch stays short (llvmpipe runs one to completion).
        for (int z0 = 0; z0 < n; z0 += 8) {
            prog3d_.set("u_z0", z0);
            glDispatchCompute(GLuint((n + 3) / 4), GLuint((n + 3) / 4), GLuint((std::min(8, n - z0) + 3) / 4));
        }
    }
    progCurl_.use();
    glUniform1ui(progCurl_.location("u_seed"), seed);
    progCurl_.set("u_size", sizes_.curl);
    glBindImageTexture(gl::binding::kLutImage, curl_.id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA8);
    glDispatchCompute(GLuint((sizes_.curl + 7) / 8), GLuint((sizes_.curl + 7) / 8), 1);
    glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_SHADER_IMAGE_ACCESS_BARRIER_BIT | GL_TEXTURE_UPDATE_BARRIER_BIT);
    glBindImageTexture(gl::binding::kLutImage, 0, 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA8);
    glUseProgram(0);
    base_.generateMipmaps();
    detail_.generateMipmaps();
    curl_.generateMipmaps();
    glFinish();
    lastSeconds_ = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    vars.publish(cloudkeys::noiseBase, base_.ref());
    vars.publish(cloudkeys::noiseDetail, detail_.ref());
    vars.publish(cloudkeys::curlNoise, curl_.ref());
}

namespace cpu {

uint32_t noiseHash(uint32_t x) { return glsl::dp::cloud_noise_shared::cn_hash(x); }
double worley(glm::dvec3 p, int f, uint32_t seed) { return glsl::dp::cloud_noise_shared::cn_worley(p, f, seed); }
double worleyFbm(glm::dvec3 p, int f, uint32_t seed) { return glsl::dp::cloud_noise_shared::cn_worleyFbm(p, f, seed); }
double perlin(glm::dvec3 p, int f, uint32_t seed) { return glsl::dp::cloud_noise_shared::cn_perlin(p, f, seed); }
double perlinFbm(glm::dvec3 p, int f, int octaves, uint32_t seed) {
    return glsl::dp::cloud_noise_shared::cn_perlinFbm(p, f, octaves, seed);
}
double perlin2(glm::dvec2 p, int f, uint32_t seed) { return glsl::dp::cloud_noise_shared::cn_perlin2(p, f, seed); }
double perlinFbm2(glm::dvec2 p, int f, int octaves, uint32_t seed) {
    return glsl::dp::cloud_noise_shared::cn_perlinFbm2(p, f, octaves, seed);
}

// The texel centres as cloud_noise_3d.glsl and curl_noise.glsl compute them.
glm::dvec4 baseNoise(int x, int y, int z, int size, uint32_t seed) {
    return glsl::dp::cloud_noise_shared::cloudBaseNoise((glm::dvec3(x, y, z) + 0.5) / double(size), seed);
}
glm::dvec4 detailNoise(int x, int y, int z, int size, uint32_t seed) {
    return glsl::dp::cloud_noise_shared::cloudDetailNoise((glm::dvec3(x, y, z) + 0.5) / double(size), seed);
}
glm::dvec4 curlNoise(int x, int y, int size, uint32_t seed) {
    return glsl::dp::cloud_noise_shared::cloudCurlNoise((glm::dvec2(x, y) + 0.5) / double(size), 1.0 / double(size), seed);
}

}  // namespace cpu
}  // namespace welkin::generators
