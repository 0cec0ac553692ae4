// The cloud density function: GLSL (shaders/cloud_density.glsl) against its double-precision
// CPU twin (cloud_density.hpp) on the same textures, and the physical facts it must obey.
#include <catch2/catch.hpp>

#include "clouds/cloud_test_util.hpp"
#include "gl_test_context.hpp"

#include <welkin/embedded/clouds_shaders.hpp>
#include <welkin/error.hpp>
#include <welkin/generators/cloud_density.hpp>
#include <welkin/generators/cloud_keys.hpp>
#include <welkin/gl/bindings.hpp>
#include <welkin/gl/shader.hpp>

#include <algorithm>
#include <cmath>
#include <random>

using namespace welkin;
using namespace welkin::generators;

namespace {

constexpr double kR = 6360e3;

CloudLayerBlock testBlock(double coverage, double detailScale = 1.0, double cloudType = 1.0) {
    // Layer 2000-3000 m, extent 20 km, an offset that exercises the modulo, the noise scrolling.
    return CloudLayerBlock::make(kR, 2000.0, 3000.0, coverage, detailScale, 0.05, 9000.0, 0.6, 20000.0, {123456.0, -98765.0},
                                 {123456.0, -98765.0, 0.0}, 8000.0, 1000.0, 40000.0, std::nullopt, cloudType);
}

// Small textures with hashed contents: the twin comparison needs texels the CPU knows, not
// realistic clouds. Weather: R in [0.4, 1], base G in [0, 0.3], top B in [0.6, 1] (B > G).
// Every density test below runs for both cloud types' height gradients (testBlock's cloudType).
struct TestTextures {
    gl::Texture2D weather, curl;
    gl::Texture3D base, detail;
    cpu::Image w, b, d, c;
    TestTextures() {
        const int nw = 32, n3 = 16, nd = 8, nc = 32;
        std::vector<float> wv(size_t(nw * nw * 4));
        for (size_t i = 0; i < wv.size(); i += 4) {
            wv[i] = 0.4f + 0.6f * test::hashUnit(uint32_t(i) + 1u);
            wv[i + 1] = 0.3f * test::hashUnit(uint32_t(i) + 2u);
            wv[i + 2] = 0.6f + 0.4f * test::hashUnit(uint32_t(i) + 3u);
            wv[i + 3] = test::hashUnit(uint32_t(i) + 4u);
        }
        weather = gl::Texture2D(nw, nw, GL_RGBA16F);
        weather.upload(GL_RGBA, GL_FLOAT, wv.data());
        auto bytes = [](size_t n, uint32_t salt) {
            std::vector<uint8_t> v(n);
            for (size_t i = 0; i < n; ++i) v[i] = uint8_t(std::lround(255.0f * test::hashUnit(uint32_t(i) * 7919u + salt)));
            return v;
        };
        base = gl::Texture3D(n3, n3, n3, GL_RGBA8);
        // The base's R (Perlin-Worley) in [0.7, 1], the generated noise's range (its 1st-99th
        // percentiles 0.6-0.89): uniform [0, 1] would put almost every point below the density's
        // shape stretch (kShapeLo) and compare zeros.
        std::vector<uint8_t> bv = bytes(size_t(n3 * n3 * n3 * 4), 11u);
        for (size_t i = 0; i < bv.size(); i += 4) bv[i] = uint8_t(178 + (bv[i] * 77 + 127) / 255);
        base.upload(GL_RGBA, GL_UNSIGNED_BYTE, bv.data());
        detail = gl::Texture3D(nd, nd, nd, GL_RGBA8);
        detail.upload(GL_RGBA, GL_UNSIGNED_BYTE, bytes(size_t(nd * nd * nd * 4), 23u).data());
        curl = gl::Texture2D(nc, nc, GL_RGBA8);
        curl.upload(GL_RGBA, GL_UNSIGNED_BYTE, bytes(size_t(nc * nc * 4), 37u).data());
        for (gl::Texture* t : {static_cast<gl::Texture*>(&weather), static_cast<gl::Texture*>(&curl), static_cast<gl::Texture*>(&base),
                               static_cast<gl::Texture*>(&detail)}) {
            t->setFilter(GL_LINEAR);
            t->setWrap(GL_REPEAT);
        }
        w = test::toImage(weather);
        b = test::toImage(base);
        d = test::toImage(detail);
        c = test::toImage(curl);
    }
    cpu::CloudTextures cpuTextures() const { return {w, b, d, c}; }
    void bind() const {
        weather.bind(gl::binding::kCloudWeatherMap);
        base.bind(gl::binding::kCloudNoiseBase);
        detail.bind(gl::binding::kCloudNoiseDetail);
        curl.bind(gl::binding::kCloudCurlNoise);
    }
};

// Evaluates on the GPU, per point (x, y, z, mu): (cheap, full, cirrus at (x, y), 0) and the shell
// crossing from radius R + z with cos zenith mu.
struct GpuEval {
    std::vector<glm::vec4> density, shell;
};
GpuEval evalGpu(const CloudLayerBlock& block, const TestTextures& tex, const std::vector<glm::vec4>& pts) {
    static const char* kMain = R"(
layout(local_size_x = 64) in;
layout(std430, binding = 4) readonly buffer Pts { vec4 pts[]; };
layout(std430, binding = 5) writeonly buffer Dens { vec4 dens[]; };
layout(std430, binding = 6) writeonly buffer Shell { vec4 shell[]; };
uniform int u_count;
void main() {
    int i = int(gl_GlobalInvocationID.x);
    if (i >= u_count) return;
    vec4 q = pts[i];
    dens[i] = vec4(cloudDensity(q.xyz, CLOUD_LOD_CHEAP), cloudDensity(q.xyz, CLOUD_LOD_FULL), cirrusDensity(q.xy), 0.0);
    shell[i] = vec4(cloudShellIntersect(cld_radii.x + q.z, q.w), 0.0, 0.0);
}
)";
    gl::Program prog = gl::ProgramBuilder("CloudDensityTest")
                           .compute("generators/cloud_density.glsl", embedded::clouds_shaders("cloud_density.glsl"))
                           .compute("test_main.glsl", kMain)
                           .build();
    gl::Buffer ubo(sizeof block, &block);
    ubo.bindBase(GL_UNIFORM_BUFFER, gl::binding::kCloudUbo);
    const size_t bytes = pts.size() * sizeof(glm::vec4);
    gl::Buffer in(bytes, pts.data()), outD(bytes), outS(bytes);
    in.bindBase(GL_SHADER_STORAGE_BUFFER, 4);
    outD.bindBase(GL_SHADER_STORAGE_BUFFER, 5);
    outS.bindBase(GL_SHADER_STORAGE_BUFFER, 6);
    tex.bind();
    prog.use();
    prog.set("u_count", int(pts.size()));
    glDispatchCompute(GLuint((pts.size() + 63) / 64), 1, 1);
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    GpuEval r;
    r.density.resize(pts.size());
    r.shell.resize(pts.size());
    glGetNamedBufferSubData(outD.id(), 0, GLsizeiptr(bytes), r.density.data());
    glGetNamedBufferSubData(outS.id(), 0, GLsizeiptr(bytes), r.shell.data());
    glUseProgram(0);
    gl::checkError("CloudDensityTest");
    return r;
}

std::vector<glm::vec4> randomPoints(int n, double zLo, double zHi, uint32_t seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> xy(-30000.0, 30000.0), z(zLo, zHi), mu(-1.0, 1.0);
    std::vector<glm::vec4> p;
    for (int i = 0; i < n; ++i) p.emplace_back(float(xy(rng)), float(xy(rng)), float(z(rng)), float(mu(rng)));
    return p;
}

}  // namespace

TEST_CASE("Cloud density: GLSL matches the CPU twin on the same textures", "[gl][clouds]") {
    test::glContext();
    TestTextures tex;
    const auto pts = randomPoints(2048, 1950.0, 3050.0, 7u);
    for (double type : {0.0, 0.5, 1.0}) {  // stratocumulus, a blend, cumulus
    const CloudLayerBlock block = testBlock(0.8, 1.0, type);
    const GpuEval gpu = evalGpu(block, tex, pts);
    double maxCheap = 0, maxFull = 0, maxCirrus = 0;
    int nonzero = 0;
    for (size_t i = 0; i < pts.size(); ++i) {
        const glm::dvec3 p(pts[i]);
        const double cheap = cpu::cloudDensity(block, tex.cpuTextures(), p, CloudLod::Cheap);
        const double full = cpu::cloudDensity(block, tex.cpuTextures(), p, CloudLod::Full);
        const double cirrus = cpu::cirrusDensity(block, tex.c, {p.x, p.y});
        nonzero += full > 0.05;
        maxCheap = std::max(maxCheap, std::abs(cheap - gpu.density[i].x));
        maxFull = std::max(maxFull, std::abs(full - gpu.density[i].y));
        maxCirrus = std::max(maxCirrus, std::abs(cirrus - gpu.density[i].z));
    }
    INFO("cloud type " << type << ": max |GPU - CPU|: cheap " << maxCheap << ", full " << maxFull << ", cirrus " << maxCirrus
                       << "; nonzero " << nonzero);
    // The comparison means something only if many points are inside clouds.
    CHECK(nonzero > 200);
    // llvmpipe filters with 8-bit interpolation weights (error <= 1/512 of a texel step, ~0.002 on
    // [0, 1] data) and in float. The remaps amplify it: the base shape's by 1 / (2 - fbm) <= 1 / 1.3
    // and its stretch by 1 / (kShapeHi - kShapeLo) = 3.7 (2.8 in all), the erosion by
    // 1 / (1 - 0.35 x detail scale) = 1.54: 0.002 x 2.8 x 1.54 = 0.009 from the base fetch, plus
    // the weather's and the detail's 0.002 x 1.54 each, ~0.015 at worst; measured 0.014 for the
    // three cloud types (0.004 before the stretch). A density error of 0.03 is 0.0015 /m of
    // extinction at 0.05 /m: below one 8-bit step of the image over a 1 km path.
    CHECK(maxCheap < 0.03);
    CHECK(maxFull < 0.03);
    // The cirrus' second fetch moves with the first (the warp): a filtering error of ~0.002 in RG
    // moves it by 2 x 0.002 x 0.05 = 2e-4 in uv, 0.0064 texel of this 32-texel hashed map whose
    // neighbours differ by up to 1: ~0.007, plus its own filtering 0.002 (measured 0.011).
    CHECK(maxCirrus < 0.02);
    }
}

TEST_CASE("Cloud shell crossing: GLSL matches the analytic double-precision twin", "[gl][clouds]") {
    test::glContext();
    TestTextures tex;
    const CloudLayerBlock block = testBlock(0.5);
    // Observers below, inside and above the layer (2000-3000 m).
    auto pts = randomPoints(1024, 0.0, 8000.0, 9u);
    const GpuEval gpu = evalGpu(block, tex, pts);
    int crossing = 0, skipped = 0;
    auto ulp = [](double x) {
        const float f = float(x);
        return double(std::nextafter(f, 2.0f * std::abs(f) + 1.0f) - f);
    };
    for (size_t i = 0; i < pts.size(); ++i) {
        const double r = double(block.radii[0]) + double(pts[i].z), mu = double(pts[i].w);
        const glm::dvec2 ref = cpu::cloudShellIntersect(block, r, mu);
        // The float evaluation only knows r and mu to their float spacing: the tolerance is the
        // spread of the exact crossing over inputs perturbed by 1 ulp of r and 4 of mu (the
        // conditioning: near tangency the crossing moves kilometres per 1e-7 of mu), + 2 m. A
        // point whose hit/miss verdict flips within that perturbation is ambiguous in float:
        // skipped (counted; a few at most).
        double spread = 0.0;
        bool ambiguous = false;
        for (int dr = -1; dr <= 1; ++dr)
            for (int dm = -4; dm <= 4; dm += 4) {
                const glm::dvec2 q = cpu::cloudShellIntersect(block, r + dr * ulp(r), mu + dm * ulp(mu));
                if ((q.y < 0) != (ref.y < 0)) ambiguous = true;
                else spread = std::max({spread, std::abs(q.x - ref.x), std::abs(q.y - ref.y)});
            }
        if (ambiguous) {
            ++skipped;
            continue;
        }
        if (ref.y < 0) {
            CHECK(gpu.shell[i].y < 0);
            continue;
        }
        ++crossing;
        CHECK(std::abs(gpu.shell[i].x - ref.x) <= 2.0 + 2.0 * spread);
        CHECK(std::abs(gpu.shell[i].y - ref.y) <= 2.0 + 2.0 * spread);
    }
    CHECK(skipped < 10);
    CHECK(crossing > 300);
}

TEST_CASE("Cloud shell crossing: below, inside and above the layer", "[cpu][clouds]") {
    const double rb = kR + 2000.0, rt = kR + 3000.0;
    // Zenith from the ground: straight through 1000 m of layer starting at 2000 m.
    glm::dvec2 s = cpu::shellIntersect(kR, rb, rt, kR, 1.0);
    CHECK(s.x == Approx(2000.0).margin(1e-6));
    CHECK(s.y == Approx(3000.0).margin(1e-6));
    // Downwards from the ground: the ground hides the layer.
    CHECK(cpu::shellIntersect(kR, rb, rt, kR + 10.0, -0.5).y < 0);
    // Horizontal from the ground: entry sqrt(rb^2 - R^2) (Pythagoras), exit sqrt(rt^2 - R^2).
    s = cpu::shellIntersect(kR, rb, rt, kR, 0.0);
    CHECK(s.x == Approx(std::sqrt(rb * rb - kR * kR)).epsilon(1e-9));
    CHECK(s.y == Approx(std::sqrt(rt * rt - kR * kR)).epsilon(1e-9));
    // Inside at 2500 m: entry 0, up exits at 500 m, down at 500 m (the base).
    s = cpu::shellIntersect(kR, rb, rt, kR + 2500.0, 1.0);
    CHECK(s.x == 0.0);
    CHECK(s.y == Approx(500.0).margin(1e-6));
    s = cpu::shellIntersect(kR, rb, rt, kR + 2500.0, -1.0);
    CHECK(s.y == Approx(500.0).margin(1e-6));
    // Above at 5000 m: straight down enters at 2000 m, leaves at 3000 m; up misses.
    s = cpu::shellIntersect(kR, rb, rt, kR + 5000.0, -1.0);
    CHECK(s.x == Approx(2000.0).margin(1e-6));
    CHECK(s.y == Approx(3000.0).margin(1e-6));
    CHECK(cpu::shellIntersect(kR, rb, rt, kR + 5000.0, 0.2).y < 0);
}

TEST_CASE("Cloud density: zero outside the layer and at coverage 0, monotone in coverage", "[gl][clouds]") {
    test::glContext();
    TestTextures tex;
    const auto t = tex.cpuTextures();
    const auto pts = randomPoints(3000, 0.0, 6000.0, 3u);
    int inside = 0, positive = 0;
    for (const glm::vec4& q : pts) {
        const glm::dvec3 p(q);
        const CloudLayerBlock b0 = testBlock(0.0);
        const double h = cpu::cloudAltitude(b0, p);
        const bool in = h >= 2000.0 && h <= 3000.0;
        inside += in;
        double prev = 0.0;
        for (double type : {0.0, 1.0})
        for (double c : {0.0, 0.2, 0.4, 0.6, 0.8, 1.0}) {
            if (c == 0.0) prev = 0.0;
            const CloudLayerBlock b = testBlock(c, 2.0, type);
            const double full = cpu::cloudDensity(b, t, p, CloudLod::Full);
            const double cheap = cpu::cloudDensity(b, t, p, CloudLod::Cheap);
            REQUIRE(full >= 0.0);
            REQUIRE(full <= 1.0);
            REQUIRE(full <= cheap + 1e-12);  // erosion only removes
            if (!in || c == 0.0) REQUIRE(cheap == 0.0);
            REQUIRE(full >= prev - 1e-12);  // nondecreasing in coverage
            prev = full;
        }
        positive += prev > 0.0;
    }
    CHECK(inside > 300);
    CHECK(positive > 100);  // the monotonicity was checked on real clouds, not only zeros
    // The altitude is the height above the sphere, not the tangent plane's z: 30 km east at z = 0
    // the ground has fallen away by 30000^2 / 2R ~ 70.75 m (to 1e-3 relative: next term ~ x^4/R^3).
    CHECK(cpu::cloudAltitude(testBlock(0.5), {30000.0, 0.0, 0.0}) == Approx(30000.0 * 30000.0 / (2 * kR)).epsilon(1e-3));
}

TEST_CASE("CloudLayerBlock::from reads the keys and checks the layer", "[cpu][clouds]") {
    SkyVars vars;
    vars.declare(cloudkeys::bottom, 1500.0);
    vars.declare(cloudkeys::top, 1550.0);
    CHECK_THROWS_WITH(CloudLayerBlock::from(vars), Catch::Contains("clouds.top_m"));
    vars.set(cloudkeys::top, 4000.0);
    vars.declare(cloudkeys::weatherExtent, 10000.0);
    vars.declare(cloudkeys::weatherOffset, glm::dvec2(1e9 + 2500.0, -2500.0));
    const CloudLayerBlock b = CloudLayerBlock::from(vars);
    CHECK(b.radii[1] - b.radii[0] == Approx(1500.0).margin(0.5));  // float radii: 0.5 m ulp at 6.4e6 m
    CHECK(b.radii[2] - b.radii[0] == Approx(4000.0).margin(0.5));
    CHECK(b.weather[0] == Approx(2500.0).margin(1e-3));  // 1e9 is a whole number of 10 km tiles
    CHECK(b.weather[1] == Approx(7500.0).margin(1e-3));  // -2500 wraps into [0, extent)
    CHECK(b.cirrus[0] == Approx(std::fmod(1e9 + 2500.0, kDefaultCurlPeriodM)).margin(1e-3));  // no cirrus key: the weather's
    vars.declare(cloudkeys::cirrusOffset, glm::dvec2(-1000.0, 500.0));
    CHECK(CloudLayerBlock::from(vars).cirrus[0] == Approx(kDefaultCurlPeriodM - 1000.0).margin(1e-3));
    CHECK(CloudLayerBlock::from(vars).cirrus[1] == Approx(500.0).margin(1e-3));
    // Bad explicit values: one line naming the argument and its range; NaN is never in range.
    CHECK_THROWS_WITH(CloudLayerBlock::make(6360e3, 2000, 3000, 1.3, 1, 0.05, 9000, 0.3, 4e4, {}, {}),
                      "CloudLayerBlock::make(): coverage 1.3 not in [0, 1]");
    CHECK_THROWS_WITH(CloudLayerBlock::make(6360e3, 2000, 3000, 0.5, 1, 0.05, 9000, 0.3, std::nan(""), {}, {}),
                      Catch::Contains("weatherExtent (m) nan not in"));
}

TEST_CASE("Cloud depth along a direction: GLSL matches the CPU twin, exact in a deck, clear air behind a cloud, the full LOD", "[gl][clouds]") {
    test::glContext();
    TestTextures tex;
    const CloudLayerBlock block = testBlock(0.8, 1.0, 1.0);
    // Points inside the layer (2000-3000 m), directions uniform on the sphere, 6 and 3 steps over at
    // most 3 km (the Clouds element's light march and its march to the far side).
    std::mt19937 rng(5u);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    const auto pts = randomPoints(512, 2000.0, 3000.0, 11u);
    std::vector<glm::vec4> dirs;
    for (size_t i = 0; i < pts.size(); ++i) {
        const double z = 2.0 * u(rng) - 1.0, phi = 2.0 * M_PI * u(rng), s = std::sqrt(1.0 - z * z);
        dirs.emplace_back(float(s * std::cos(phi)), float(s * std::sin(phi)), float(z), 0.0f);
    }
    static const char* kMain = R"(
layout(local_size_x = 64) in;
layout(std430, binding = 4) readonly buffer Pts { vec4 pts[]; };
layout(std430, binding = 5) readonly buffer Dirs { vec4 dirs[]; };
layout(std430, binding = 6) writeonly buffer Depth { vec4 depth[]; };
uniform int u_count;
void main() {
    int i = int(gl_GlobalInvocationID.x);
    if (i >= u_count) return;
    depth[i] = vec4(cloudDepthAlong(pts[i].xyz, dirs[i].xyz, 6, 3000.0), cloudDepthAlong(pts[i].xyz, dirs[i].xyz, 3, 3000.0), 0.0, 0.0);
}
)";
    gl::Program prog = gl::ProgramBuilder("CloudDepthTest")
                           .compute("generators/cloud_density.glsl", embedded::clouds_shaders("cloud_density.glsl"))
                           .compute("test_main.glsl", kMain)
                           .build();
    gl::Buffer ubo(sizeof block, &block);
    ubo.bindBase(GL_UNIFORM_BUFFER, gl::binding::kCloudUbo);
    const size_t bytes = pts.size() * sizeof(glm::vec4);
    gl::Buffer in(bytes, pts.data()), inD(bytes, dirs.data()), out(bytes);
    in.bindBase(GL_SHADER_STORAGE_BUFFER, 4);
    inD.bindBase(GL_SHADER_STORAGE_BUFFER, 5);
    out.bindBase(GL_SHADER_STORAGE_BUFFER, 6);
    tex.bind();
    prog.use();
    prog.set("u_count", int(pts.size()));
    glDispatchCompute(GLuint((pts.size() + 63) / 64), 1, 1);
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    std::vector<glm::vec4> gpu(pts.size());
    glGetNamedBufferSubData(out.id(), 0, GLsizeiptr(bytes), gpu.data());
    glUseProgram(0);
    gl::checkError("CloudDepthTest");
    double worst = 0.0;
    int deep = 0;
    for (size_t i = 0; i < pts.size(); ++i) {
        const glm::dvec3 p(pts[i]), d(dirs[i]);
        const double c6 = cpu::cloudDepthAlong(block, tex.cpuTextures(), p, d, 6, 3000.0);
        const double c3 = cpu::cloudDepthAlong(block, tex.cpuTextures(), p, d, 3, 3000.0);
        deep += c6 > 100.0;
        worst = std::max({worst, std::abs(c6 - gpu[i].x), std::abs(c3 - gpu[i].y)});
    }
    INFO("max |GPU - CPU| " << worst << " m (density x m); paths with more than 100 m: " << deep);
    CHECK(deep > 100);  // the comparison crosses real clouds, not only clear air
    // Each sample's density within 0.03 of the twin (the density test's bound and its reason: 8-bit
    // filtering weights amplified by the remaps), over at most 3000 m of path: 90; plus the float
    // shell crossing (2 m of path at density <= 1).
    CHECK(worst < 92.0);

    // Facts on the CPU twin. A horizontally uniform deck (weather 1, noise 1, no erosion,
    // stratocumulus sheet): straight down from 400 m above the base the march sums the profile over
    // those 400 m; along a slant the same to the base at 1/mu the path.
    const cpu::Image w{1, 1, 1, {1, 0, 1, 0}}, one{1, 1, 1, {1, 1, 1, 1}};
    const cpu::CloudTextures t1{w, one, one, one};
    const CloudLayerBlock deck = CloudLayerBlock::make(kR, 1000.0, 2000.0, 1.0, 0.0, 0.05, 9000.0, 0.0, 20000.0, {0.0, 0.0}, {0.0, 0.0, 0.0},
                                                       kDefaultNoiseBasePeriodM, kDefaultNoiseDetailPeriodM, kDefaultCurlPeriodM, std::nullopt, 0.0);
    // Where the sheet's profile is linear in height (its middle, 1300-1600 m: the upward gradient
    // 0.75 + 0.25 t, no ramp), the midpoint rule is exact whatever the steps: 300 m up from 1300 m
    // against the integral of the profile, and 600 m along a ray 30 deg below the horizontal from
    // 1600 m (the same 300 m of height at 2x the path; the Earth's curvature over 520 m moves it by
    // 2 cm).
    double ref = 0.0;
    for (int i = 0; i < 30000; ++i) ref += cpu::cloudDensity(deck, t1, {0.0, 0.0, 1300.0 + 300.0 * (i + 0.5) / 30000}, CloudLod::Full) * 0.01;
    const double up = cpu::cloudDepthAlong(deck, t1, {0.0, 0.0, 1300.0}, {0.0, 0.0, 1.0}, 3, 300.0);
    const double slant = cpu::cloudDepthAlong(deck, t1, {0.0, 0.0, 1600.0}, {std::sqrt(0.75), 0.0, -0.5}, 6, 600.0);
    INFO("deck: up " << up << ", slant " << slant << ", integral " << ref);
    CHECK(ref > 250.0);  // the sheet is dense there (0.83-0.9)
    CHECK(up == Approx(ref).epsilon(1e-4));  // the reference quadrature's own error is ~1e-9
    CHECK(slant == Approx(2.0 * ref).epsilon(1e-4));
    // An isolated cloud: a weather map with a single disc of radius 1 km at the origin; from a point
    // inside it, 800 m from its edge, a horizontal march outwards sees density only over those 800 m
    // (so it is at most 800 m x 1) and none in the clear air beyond.
    cpu::Image disc;
    disc.w = disc.h = 200;
    disc.d = 1;
    disc.rgba.resize(size_t(200 * 200 * 4));
    for (int y = 0; y < 200; ++y)
        for (int x = 0; x < 200; ++x) {
            const double px = (x + 0.5) * 100.0 - 10000.0, py = (y + 0.5) * 100.0 - 10000.0;  // 100 m texels, 20 km square
            const float r = std::hypot(px, py) < 1000.0 ? 1.0f : 0.0f;
            float* q = &disc.rgba[(size_t(y) * 200 + x) * 4];
            q[0] = r, q[1] = 0.0f, q[2] = 1.0f, q[3] = 0.0f;
        }
    const cpu::CloudTextures t2{disc, one, one, one};
    const CloudLayerBlock cloud = CloudLayerBlock::make(kR, 1000.0, 2000.0, 1.0, 0.0, 0.05, 9000.0, 0.0, 20000.0, {10000.0, 10000.0},
                                                        {0.0, 0.0, 0.0}, kDefaultNoiseBasePeriodM, kDefaultNoiseDetailPeriodM,
                                                        kDefaultCurlPeriodM, std::nullopt, 0.0);
    const double out3 = cpu::cloudDepthAlong(cloud, t2, {200.0, 0.0, 1500.0}, {1.0, 0.0, 0.0}, 3, 3000.0);
    const double in3 = cpu::cloudDepthAlong(cloud, t2, {200.0, 0.0, 1500.0}, {-1.0, 0.0, 0.0}, 3, 3000.0);
    INFO("isolated cloud: outwards " << out3 << ", inwards " << in3);
    CHECK(out3 <= 800.0 + 200.0);  // + one 100 m texel of bilinear edge each side of the midpoint sample
    CHECK(in3 > out3);             // inwards it crosses 1200 m of cloud
    // The march reads the full LOD (the density the view march and the path tracer see): through
    // the eroded test cloud (detail scale 1) its depth is the sum of the full density at its
    // midpoints, below the cheap density's (the erosion only removes), on the 512 paths above.
    int eroded = 0;
    for (size_t i = 0; i < pts.size(); ++i) {
        const glm::dvec3 p(pts[i]), d(dirs[i]);
        double full = 0.0, cheap = 0.0, t = 0.0;
        const glm::dvec3 q = p + glm::dvec3(0.0, 0.0, kR);
        const glm::dvec2 seg = cpu::shellIntersect(kR, kR + 2000.0, kR + 3000.0, glm::length(q), glm::dot(q, d) / glm::length(q));
        const double total = seg.y > 0.0 ? std::min(3000.0, seg.y) : 3000.0;
        double ds = total * 0.5 / (std::pow(1.5, 3.0) - 1.0);  // the march's first step (x1.5 growth)
        for (int k = 0; k < 3; ++k, t += ds, ds *= 1.5) {
            full += cpu::cloudDensity(block, tex.cpuTextures(), p + d * (t + 0.5 * ds), CloudLod::Full) * ds;
            cheap += cpu::cloudDensity(block, tex.cpuTextures(), p + d * (t + 0.5 * ds), CloudLod::Cheap) * ds;
        }
        CHECK(cpu::cloudDepthAlong(block, tex.cpuTextures(), p, d, 3, 3000.0) == Approx(full).margin(1e-6));
        eroded += cheap > full + 1.0;
    }
    CHECK(eroded > 50);  // the erosion matters on these paths (it is what the full LOD adds)
}
