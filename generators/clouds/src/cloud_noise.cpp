// Cloud noise generator (GPU passes cloud_noise_3d.glsl, curl_noise.glsl on cloud_noise.glsl) and
// the CPU twin of each texel (the same integer hash; the float formulas in double).
#include <welkin/embedded/clouds_shaders.hpp>
#include <welkin/generators/cloud_keys.hpp>
#include <welkin/generators/cloud_noise.hpp>
#include <welkin/gl/bindings.hpp>
#include <welkin/gl/shader.hpp>
#include <welkin/check.hpp>

#include <epoxy/gl.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>

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

namespace {
uint32_t hash3(glm::ivec3 c, uint32_t seed) {
    return noiseHash(uint32_t(c.x) + noiseHash(uint32_t(c.y) + noiseHash(uint32_t(c.z) + noiseHash(seed))));
}
double unit(uint32_t h) { return double(h & 0xffffffu) / 16777216.0; }
int wrap(int c, int f) { return ((c % f) + f) % f; }
double fade(double t) { return t * t * t * (t * (t * 6.0 - 15.0) + 10.0); }
double grad(uint32_t h, glm::dvec3 d) {
    const int k = int(h % 12u);
    const double s0 = k % 2 == 0 ? 1.0 : -1.0;
    if (k < 4) return glm::dot(glm::dvec3(s0, k / 2 == 0 ? 1.0 : -1.0, 0.0), d);
    if (k < 8) return glm::dot(glm::dvec3(s0, 0.0, (k - 4) / 2 == 0 ? 1.0 : -1.0), d);
    return glm::dot(glm::dvec3(0.0, s0, (k - 8) / 2 == 0 ? 1.0 : -1.0), d);
}
}  // namespace

uint32_t noiseHash(uint32_t x) {
    // Wellons' "lowbias32" integer mixer (2018): full avalanche, bit-identical in GLSL.
    x ^= x >> 16;
    x *= 0x7feb352dU;
    x ^= x >> 15;
    x *= 0x846ca68bU;
    x ^= x >> 16;
    return x;
}

double worley(glm::dvec3 p, int f, uint32_t seed) {
    const glm::dvec3 q = p * double(f);
    const glm::ivec3 c0(glm::floor(q));
    double best = 1e9;
    for (int dz = -1; dz <= 1; ++dz)
        for (int dy = -1; dy <= 1; ++dy)
            for (int dx = -1; dx <= 1; ++dx) {
                const glm::ivec3 c = c0 + glm::ivec3(dx, dy, dz);
                const uint32_t h = hash3({wrap(c.x, f), wrap(c.y, f), wrap(c.z, f)}, seed);
                const glm::dvec3 fp = glm::dvec3(c) + glm::dvec3(unit(noiseHash(h)), unit(noiseHash(h + 1u)), unit(noiseHash(h + 2u)));
                const glm::dvec3 d = fp - q;
                best = std::min(best, glm::dot(d, d));
            }
    return 1.0 - std::clamp(std::sqrt(best), 0.0, 1.0);
}

double worleyFbm(glm::dvec3 p, int f, uint32_t seed) {
    return 0.625 * worley(p, f, seed) + 0.25 * worley(p, 2 * f, seed + 1u) + 0.125 * worley(p, 4 * f, seed + 2u);
}

double perlin(glm::dvec3 p, int f, uint32_t seed) {
    const glm::dvec3 q = p * double(f);
    const glm::ivec3 c(glm::floor(q));
    const glm::dvec3 t = q - glm::dvec3(c);
    double v[8];
    for (int i = 0; i < 8; ++i) {
        const glm::ivec3 o(i & 1, (i >> 1) & 1, (i >> 2) & 1);
        const glm::ivec3 w(wrap(c.x + o.x, f), wrap(c.y + o.y, f), wrap(c.z + o.z, f));
        v[i] = grad(hash3(w, seed), t - glm::dvec3(o));
    }
    const glm::dvec3 u(fade(t.x), fade(t.y), fade(t.z));
    const double x00 = glm::mix(v[0], v[1], u.x), x10 = glm::mix(v[2], v[3], u.x), x01 = glm::mix(v[4], v[5], u.x),
                 x11 = glm::mix(v[6], v[7], u.x);
    return glm::mix(glm::mix(x00, x10, u.y), glm::mix(x01, x11, u.y), u.z);
}

double perlinFbm(glm::dvec3 p, int f, int octaves, uint32_t seed) {
    double sum = 0.0, amp = 0.5, norm = 0.0;
    for (int o = 0; o < octaves; ++o) {
        sum += amp * perlin(p, f << o, seed + uint32_t(o));
        norm += amp;
        amp *= 0.5;
    }
    return std::clamp(0.5 + 0.5 * sum / norm, 0.0, 1.0);
}

double perlin2(glm::dvec2 p, int f, uint32_t seed) {
    const glm::dvec2 q = p * double(f);
    const glm::ivec2 c(glm::floor(q));
    const glm::dvec2 t = q - glm::dvec2(c);
    double v[4];
    for (int i = 0; i < 4; ++i) {
        const glm::ivec2 o(i & 1, (i >> 1) & 1);
        const uint32_t h = hash3({wrap(c.x + o.x, f), wrap(c.y + o.y, f), 0}, seed);
        const double a = double(h % 8u) * 0.7853981633974483;  // k pi / 4
        v[i] = glm::dot(glm::dvec2(std::cos(a), std::sin(a)), t - glm::dvec2(o));
    }
    const glm::dvec2 u(fade(t.x), fade(t.y));
    return glm::mix(glm::mix(v[0], v[1], u.x), glm::mix(v[2], v[3], u.x), u.y);
}

double perlinFbm2(glm::dvec2 p, int f, int octaves, uint32_t seed) {
    double sum = 0.0, amp = 0.5, norm = 0.0;
    for (int o = 0; o < octaves; ++o) {
        sum += amp * perlin2(p, f << o, seed + uint32_t(o));
        norm += amp;
        amp *= 0.5;
    }
    return 0.5 + 0.5 * sum / norm;
}

glm::dvec4 baseNoise(int x, int y, int z, int size, uint32_t seed) {
    const glm::dvec3 p = (glm::dvec3(x, y, z) + 0.5) / double(size);
    const double pl = perlinFbm(p, 4, 4, seed);
    const double w = worleyFbm(p, 4, seed + 10u);
    const double pw = std::clamp(w + pl * (1.0 - w), 0.0, 1.0);  // remap(perlin, 0, 1, worley, 1)
    return {pw, worleyFbm(p, 8, seed + 20u), worleyFbm(p, 16, seed + 30u), worleyFbm(p, 32, seed + 40u)};
}

glm::dvec4 detailNoise(int x, int y, int z, int size, uint32_t seed) {
    const glm::dvec3 p = (glm::dvec3(x, y, z) + 0.5) / double(size);
    return {worleyFbm(p, 2, seed + 60u), worleyFbm(p, 4, seed + 70u), worleyFbm(p, 8, seed + 80u), 1.0};
}

glm::dvec4 curlNoise(int x, int y, int size, uint32_t seed) {
    const glm::dvec2 p = (glm::dvec2(x, y) + 0.5) / double(size);
    const double e = 1.0 / double(size);
    auto psi = [&](glm::dvec2 q) { return perlinFbm2(q, 4, 5, seed + 50u); };
    const double dx = (psi(p + glm::dvec2(e, 0)) - psi(p - glm::dvec2(e, 0))) / (2.0 * e);
    const double dy = (psi(p + glm::dvec2(0, e)) - psi(p - glm::dvec2(0, e))) / (2.0 * e);
    const glm::dvec2 v = glm::clamp(glm::dvec2(dy, -dx) / 8.0, -1.0, 1.0);
    return {0.5 + 0.5 * v.x, 0.5 + 0.5 * v.y, std::clamp(psi(p), 0.0, 1.0), 1.0};
}

}  // namespace cpu
}  // namespace welkin::generators
