// The clouds' noise textures: GPU texels against the CPU twin, seamless tiling, determinism.
#include <catch2/catch.hpp>

#include "clouds/cloud_test_util.hpp"
#include "gl_test_context.hpp"

#include <welkin/generators/cloud_density.hpp>
#include <welkin/generators/cloud_keys.hpp>
#include <welkin/gl/bindings.hpp>
#include <welkin/generators/cloud_noise.hpp>
#include <welkin/generators/cloud_path_lut.hpp>
#include <welkin/generators/weather_map.hpp>

#include <chrono>

#include <cmath>

using namespace welkin;
using namespace welkin::generators;

namespace {
// Small sizes: the formulas are the same at any size; llvmpipe builds these in well under 1 s.
const CloudNoise::Sizes kSmall{16, 8, 32};

struct Built {
    cpu::Image base, detail, curl;
};
Built build(int seed) {
    SkyVars vars;
    vars.declare(cloudkeys::seed, seed);
    CloudNoise noise(kSmall);
    noise.run(vars, test::testLogger(), true);
    REQUIRE(vars.get(cloudkeys::noiseBase).id == noise.base().id());
    return {test::toImage(noise.base()), test::toImage(noise.detail()), test::toImage(noise.curl())};
}

// Mean absolute difference between neighbours along x inside the image, and across the x border
// (texel N-1 to texel 0), channel c: a seam shows as a border step far larger than the inside's.
std::pair<double, double> stepsX(const cpu::Image& im, int c) {
    double inside = 0, border = 0;
    int ni = 0, nb = 0;
    for (int z = 0; z < im.d; ++z)
        for (int y = 0; y < im.h; ++y)
            for (int x = 0; x < im.w; ++x) {
                const double d = std::abs(im.texel(x + 1, y, z)[c] - im.texel(x, y, z)[c]);
                if (x == im.w - 1) border += d, ++nb;
                else inside += d, ++ni;
            }
    return {inside / ni, border / nb};
}
}  // namespace

TEST_CASE("Cloud noise: GPU texels match the CPU twin", "[gl][clouds]") {
    test::glContext();
    const Built b = build(42);
    // 8-bit storage rounds to the nearest of 255 steps (0.5 / 255); the float evaluation on the
    // GPU may move a value across a rounding boundary: one step (1 / 255) plus float slack.
    const double tol = 1.0 / 255.0 + 1e-4;
    double worst = 0;
    for (int z = 0; z < kSmall.base; z += 3)
        for (int y = 0; y < kSmall.base; y += 2)
            for (int x = 0; x < kSmall.base; ++x) {
                const glm::dvec4 ref = cpu::baseNoise(x, y, z, kSmall.base, 42);
                for (int c = 0; c < 4; ++c) worst = std::max(worst, std::abs(b.base.texel(x, y, z)[c] - ref[c]));
            }
    for (int z = 0; z < kSmall.detail; ++z)
        for (int y = 0; y < kSmall.detail; ++y)
            for (int x = 0; x < kSmall.detail; ++x) {
                const glm::dvec4 ref = cpu::detailNoise(x, y, z, kSmall.detail, 42);
                for (int c = 0; c < 4; ++c) worst = std::max(worst, std::abs(b.detail.texel(x, y, z)[c] - ref[c]));
            }
    for (int y = 0; y < kSmall.curl; ++y)
        for (int x = 0; x < kSmall.curl; ++x) {
            const glm::dvec4 ref = cpu::curlNoise(x, y, kSmall.curl, 42);
            for (int c = 0; c < 4; ++c) worst = std::max(worst, std::abs(b.curl.texel(x, y)[c] - ref[c]));
        }
    INFO("worst |GPU - CPU| " << worst);
    CHECK(worst <= tol);
}

TEST_CASE("Cloud noise: the functions are periodic and the textures tile seamlessly", "[gl][clouds]") {
    // Periodicity of the formulas: f(p + 1) == f(p) exactly up to double rounding (1e-9: the
    // hashed lattice is the same integer set, only the fractional part's rounding differs).
    for (double x : {0.013, 0.37, 0.99}) {
        const glm::dvec3 p(x, 0.21, 0.74);
        CHECK(cpu::worleyFbm(p, 4, 5) == Approx(cpu::worleyFbm(p + glm::dvec3(1, 0, 0), 4, 5)).margin(1e-9));
        CHECK(cpu::worleyFbm(p, 4, 5) == Approx(cpu::worleyFbm(p + glm::dvec3(0, -1, 1), 4, 5)).margin(1e-9));
        CHECK(cpu::perlinFbm(p, 4, 4, 5) == Approx(cpu::perlinFbm(p + glm::dvec3(0, 0, 1), 4, 4, 5)).margin(1e-9));
        CHECK(cpu::perlinFbm2({x, 0.3}, 4, 5, 5) == Approx(cpu::perlinFbm2({x - 1.0, 1.3}, 4, 5, 5)).margin(1e-9));
    }
    test::glContext();
    const Built b = build(7);
    // Across the border the texture changes like inside it (a seam would be a step of ~0.2-0.5,
    // i.e. several times the mean neighbour difference): the border's mean step is within
    // 1.6x of the inside's (a random row of N texels: the border is one sample of N; 1.6x leaves
    // room for that sampling noise over N^2 rows).
    for (int c = 0; c < 4; ++c) {
        auto [in, border] = stepsX(b.base, c);
        INFO("base channel " << c << ": inside " << in << ", border " << border);
        CHECK(border < 1.6 * in + 2.0 / 255.0);
    }
    for (int c = 0; c < 3; ++c) {
        auto [in, border] = stepsX(b.detail, c);
        INFO("detail channel " << c << ": inside " << in << ", border " << border);
        CHECK(border < 1.6 * in + 2.0 / 255.0);
        auto [ci, cb] = stepsX(b.curl, c);
        INFO("curl channel " << c << ": inside " << ci << ", border " << cb);
        CHECK(cb < 1.6 * ci + 2.0 / 255.0);
    }
    // The continuation is exact: texel N (one period on) of the twin equals the stored texel 0.
    for (int y = 0; y < kSmall.base; y += 5)
        for (int c = 0; c < 4; ++c)
            CHECK(std::abs(cpu::baseNoise(kSmall.base, y, 3, kSmall.base, 7)[c] - b.base.texel(0, y, 3)[c]) <= 1.0 / 255.0 + 1e-4);
}

TEST_CASE("bindCloudTextures() puts the published textures on their units", "[gl][clouds]") {
    test::glContext();
    SkyVars vars;
    vars.declare(cloudkeys::seed, 1);
    CloudNoise noise(kSmall);
    noise.run(vars, test::testLogger(), true);
    glBindTextureUnit(gl::binding::kCloudWeatherMap, 0);
    bindCloudTextures(vars);
    GLint b3 = 0, d3 = 0, c2 = 0, w2 = -1;
    glActiveTexture(GL_TEXTURE0 + gl::binding::kCloudNoiseBase);
    glGetIntegerv(GL_TEXTURE_BINDING_3D, &b3);
    glActiveTexture(GL_TEXTURE0 + gl::binding::kCloudNoiseDetail);
    glGetIntegerv(GL_TEXTURE_BINDING_3D, &d3);
    glActiveTexture(GL_TEXTURE0 + gl::binding::kCloudCurlNoise);
    glGetIntegerv(GL_TEXTURE_BINDING_2D, &c2);
    glActiveTexture(GL_TEXTURE0 + gl::binding::kCloudWeatherMap);
    glGetIntegerv(GL_TEXTURE_BINDING_2D, &w2);
    glActiveTexture(GL_TEXTURE0);
    CHECK(GLuint(b3) == noise.base().id());
    CHECK(GLuint(d3) == noise.detail().id());
    CHECK(GLuint(c2) == noise.curl().id());
    CHECK(w2 == 0);  // no weather map published: its unit is left alone
    glBindTextureUnit(gl::binding::kCloudNoiseBase, 0);
    glBindTextureUnit(gl::binding::kCloudNoiseDetail, 0);
    glBindTextureUnit(gl::binding::kCloudCurlNoise, 0);
}

TEST_CASE("Cloud noise: same seed same textures, another seed differs", "[gl][clouds]") {
    test::glContext();
    const Built a = build(3), a2 = build(3), c = build(4);
    CHECK(a.base.rgba == a2.base.rgba);
    CHECK(a.detail.rgba == a2.detail.rgba);
    CHECK(a.curl.rgba == a2.curl.rgba);
    auto differs = [](const cpu::Image& x, const cpu::Image& y) {
        size_t n = 0;
        for (size_t i = 0; i < x.rgba.size(); ++i) n += x.rgba[i] != y.rgba[i];
        return double(n) / double(x.rgba.size());
    };
    // Another seed: most texels change (A of the detail and curl is the constant 1: < 100 %).
    CHECK(differs(a.base, c.base) > 0.5);
    CHECK(differs(a.detail, c.detail) > 0.5);
    CHECK(differs(a.curl, c.curl) > 0.5);
}

TEST_CASE("Cloud generators at their default sizes: cost, and sane contents", "[gl][clouds][slow]") {
    test::glContext();
    SkyVars vars;
    vars.declare(cloudkeys::seed, 1);
    CloudNoise noise;
    noise.run(vars, test::testLogger(), true);
    WARN("CloudNoise 128^3 + 32^3 + 256^2 on this machine: " << noise.lastRunSeconds() << " s");
    const cpu::Image base = test::toImage(noise.base());
    // Worley of one feature point per cell (a jittered grid, close to a unit-density Poisson
    // process whose mean nearest-neighbour distance is Gamma(4/3) (3 / 4 pi)^(1/3) = 0.554):
    // the inverted channels average ~0.45-0.5 (measured 0.48); a broken pass (all zeros, all
    // ones, NaN) falls far outside [0.35, 0.7].
    for (int c = 1; c < 4; ++c) {
        double mean = 0;
        for (size_t i = size_t(c); i < base.rgba.size(); i += 4) mean += base.rgba[i];
        mean /= double(base.rgba.size() / 4);
        INFO("base channel " << c << " mean " << mean);
        CHECK(mean > 0.35);
        CHECK(mean < 0.7);
    }
    CHECK(noise.base().levels() == 8);  // 128 -> 1: mipmapped
    // The curl's scale (1/8) keeps |v| < 1: under 1 % of the texels clamped (R or G at 0 or 1).
    const cpu::Image curl = test::toImage(noise.curl());
    size_t clamped = 0;
    for (size_t i = 0; i < curl.rgba.size(); i += 4)
        clamped += curl.rgba[i] <= 0.f || curl.rgba[i] >= 1.f || curl.rgba[i + 1] <= 0.f || curl.rgba[i + 1] >= 1.f;
    float lo = 1.f, hi = 0.f;
    for (size_t i = 0; i < curl.rgba.size(); i += 4) lo = std::min(lo, curl.rgba[i]), hi = std::max(hi, curl.rgba[i]);
    INFO("clamped curl texels " << clamped << ", R in [" << lo << ", " << hi << "]");
    CHECK(double(clamped) < 0.01 * double(curl.rgba.size() / 4));
    CHECK(hi - lo > 0.3);  // and uses the 8 bits: |v| reaches ~0.6 (measured R in [0.22, 0.79])

    using Clock = std::chrono::steady_clock;
    vars.declare(cloudkeys::bottom, 2000.0);
    vars.declare(cloudkeys::top, 3000.0);
    CloudPathLut lut;
    auto t0 = Clock::now();
    lut.run(vars, test::testLogger(), true);
    WARN("CloudPathLut 256 x 96: " << std::chrono::duration<double>(Clock::now() - t0).count() << " s");
    WeatherMap wm;
    wm.declareKeys(vars);
    t0 = Clock::now();
    wm.run(vars, test::testLogger(), true);
    WARN("WeatherMap 512^2, 48 clouds: " << std::chrono::duration<double>(Clock::now() - t0).count() << " s");
    // The default generation covers a fair part of the map (broken cumulus, not overcast, not
    // clear): 5-60 % of the texels at density > 0.2.
    const cpu::Image w = test::toImage(wm.texture());
    size_t cloudy = 0;
    for (size_t i = 0; i < w.rgba.size(); i += 4) cloudy += w.rgba[i] > 0.2f;
    const double frac = double(cloudy) / double(w.rgba.size() / 4);
    INFO("cloudy fraction " << frac);
    CHECK(frac > 0.05);
    CHECK(frac < 0.6);
}
