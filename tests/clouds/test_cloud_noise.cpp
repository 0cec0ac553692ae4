// The clouds' noise textures: GPU texels against the CPU twin, seamless tiling, determinism.
#include <catch2/catch.hpp>

#include "clouds/cloud_test_util.hpp"
#include "gl_test_context.hpp"

#include <welkin/generators/cloud_keys.hpp>
#include <welkin/generators/cloud_noise.hpp>

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
