// The clouds' shadow map (generators/clouds/cloud_shadow.hpp): the GPU pass against its double
// CPU twin (both through the shared density, cloud_density.hpp), the geometry of a shadow, and
// the limits (no cloud, overcast, the light at the horizon, the Moon at night), and the host's
// GLSL lookup welkin_cloudShadow().
#include <algorithm>
#include <catch2/catch.hpp>

#include "cloud_test_textures.hpp"
#include "gl_test_context.hpp"

#include <welkin/generators/cloud_shadow.hpp>
#include <welkin/generators/lights.hpp>
#include <welkin/gl/objects.hpp>
#include <welkin/gl/shader.hpp>
#include <welkin/keys.hpp>

#include <cmath>
#include <cstdint>

using namespace welkin;
using namespace welkin::generators;

namespace {
constexpr double kPi = 3.14159265358979323846;

// A test weather map: a round cumulus of radius `radiusM` centred at ENU (0, 0) whose base and
// top are the layer's bottom and top (G = 0, B = 1), over `extentM` with offset extent / 2 so ENU
// (0, 0) reads uv (0.5, 0.5); a cosine edge over 400 m keeps the bilinear lookup smooth.
// `everywhere`: density 1 over the whole map (overcast); radius 0: an empty map.
cpu::Image testWeather(int n, double extentM, double radiusM, bool everywhere = false) {
    cpu::Image w{n, n, 1, std::vector<float>(size_t(n) * size_t(n) * 4, 0.0f)};
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            const glm::dvec2 xy = (glm::dvec2(i + 0.5, j + 0.5) / double(n) - 0.5) * extentM;
            const double d = everywhere ? 1.0 : std::clamp((radiusM - glm::length(xy)) / 400.0 + 0.5, 0.0, 1.0);
            const double s = everywhere ? 1.0 : 0.5 - 0.5 * std::cos(kPi * d);
            float* t = &w.rgba[(size_t(j) * size_t(n) + size_t(i)) * 4];
            if (s > 0.0) t[0] = float(s), t[1] = 0.0f, t[2] = 1.0f;
        }
    return w;
}

// Deterministic pseudo-random texels (a 32-bit integer hash), so the base shape and the cirrus
// vary in space like the generated noise does, without depending on the noise generator.
float hashUnit(uint32_t x) {
    x ^= x >> 16, x *= 0x7feb352dU, x ^= x >> 15, x *= 0x846ca68bU, x ^= x >> 16;
    return float(x >> 8) / float(1 << 24);
}
cpu::Image randomImage(int w, int h, int d, uint32_t seed, float lo) {
    cpu::Image im{w, h, d, std::vector<float>(size_t(w) * size_t(h) * size_t(d) * 4)};
    for (size_t i = 0; i < im.rgba.size(); ++i) im.rgba[i] = lo + (1.0f - lo) * hashUnit(uint32_t(i) * 2654435761U + seed);
    return im;
}
// Base noise that leaves the weather map's shape as it is: R = 1 makes the remap 1 whatever G, B, A.
cpu::Image flatBase() { return cpu::Image{1, 1, 1, {1.0f, 0.5f, 0.5f, 0.5f}}; }

gl::Texture upload(const cpu::Image& im, bool is3D) { return test::uploadCloudTexture(im, is3D); }

std::vector<float> readR(TextureRef ref) {
    std::vector<float> px(size_t(ref.width) * size_t(ref.height));
    glGetTextureImage(ref.id, 0, GL_RED, GL_FLOAT, GLsizei(px.size() * sizeof(float)), px.data());
    return px;
}

glm::dvec3 lightAt(double elevationRad, double azimuthRad) {  // azimuth from north through east
    return {std::cos(elevationRad) * std::sin(azimuthRad), std::cos(elevationRad) * std::cos(azimuthRad), std::sin(elevationRad)};
}

struct Scene {
    SkyVars vars;
    std::shared_ptr<CloudShadowMap> gen = std::make_shared<CloudShadowMap>();
    cpu::Image weather, base, detail{1, 1, 1, {0.0f, 0.0f, 0.0f, 0.0f}}, curl;
    std::vector<gl::Texture> textures;
    Scene(cpu::Image w, double extentM, glm::dvec3 sun, double coverage, double sigma, cpu::Image b = flatBase(), cpu::Image c = {})
        : weather(std::move(w)), base(std::move(b)), curl(std::move(c)) {
        gen->declareKeys(vars);
        textures.push_back(upload(weather, false));
        vars.set(cloudkeys::weatherMap, textures.back().ref());
        textures.push_back(upload(base, true));
        vars.set(cloudkeys::noiseBase, textures.back().ref());
        if (!curl.rgba.empty()) {
            textures.push_back(upload(curl, false));
            vars.set(cloudkeys::curlNoise, textures.back().ref());
        }
        vars.set(cloudkeys::weatherExtent, extentM);
        vars.set(cloudkeys::weatherOffset, glm::dvec2(extentM / 2));
        vars.set(cloudkeys::bottom, 2000.0);
        vars.set(cloudkeys::top, 3000.0);
        vars.set(cloudkeys::coverage, coverage);
        vars.set(cloudkeys::scattering, sigma);
        vars.set(cloudkeys::cirrusCoverage, curl.rgba.empty() ? 0.0 : 0.7);
        vars.set(cloudkeys::cirrusHeight, 9000.0);
        vars.set(lightkeys::planetRadius, 6360e3);
        vars.set(keys::sunDirection, glm::normalize(sun));
        vars.set(keys::moonDirection, glm::dvec3(0, 0, -1));
    }
    std::vector<float> run() {
        gen->run(vars, test::testLogger());
        return readR(vars.get(cloudkeys::shadowMap));
    }
    cpu::CloudTextures cpuTextures() const { return {weather, base, detail, curl}; }
    double cpuShadow(glm::dvec2 xy) const {
        return cpu::cloudShadowTransmittance(CloudLayerBlock::from(vars), cpuTextures(), CloudShadowMap::lightDirection(vars),
                                             vars.get(cloudkeys::shadowSteps), xy);
    }
    glm::dvec2 texelXy(int i, int j) const {  // ENU xy of texel (i, j)'s centre
        const int n = vars.get(cloudkeys::shadowResolution);
        return (glm::dvec2(i + 0.5, j + 0.5) / double(n) - 0.5) * vars.get(cloudkeys::shadowExtent);
    }
};
}  // namespace

TEST_CASE("Cloud shadow map: GPU pass against the double CPU twin", "[gl][clouds][shadow]") {
    test::glContext();
    // A cumulus shaped by a random base noise (8^3 over an 8 km period), a cirrus from a random
    // curl texture, a low Sun: every branch of the march and the density.
    Scene s(testWeather(128, 20e3, 2500.0), 20e3, lightAt(0.5, 2.0), 0.8, 0.004, randomImage(8, 8, 8, 7u, 0.3f), randomImage(16, 16, 1, 11u, 0.0f));
    s.vars.set(cloudkeys::shadowResolution, 64);
    s.vars.set(cloudkeys::shadowExtent, 20e3);
    const std::vector<float> map = s.run();
    double worst = 0.0, minT = 1.0;
    for (int j = 0; j < 64; j += 3)
        for (int i = 0; i < 64; i += 3) {
            const double cpu = s.cpuShadow(s.texelXy(i, j));
            worst = std::max(worst, std::abs(cpu - map[size_t(j) * 64 + size_t(i)]));
            minT = std::min(minT, cpu);
        }
    INFO("largest |GPU - CPU| " << worst << ", darkest " << minT);
    CHECK(minT < 0.3);  // the test cloud does cast a dark shadow (the match is not trivial)
    // float march and float block vs double; a GPU whose linear filter weights have 8 fractional
    // bits (the GL minimum) shifts a density by < 0.3 % on the 400 m ramp: 2e-3 in transmittance
    // on llvmpipe; an NVIDIA H100 (driver 580, hardware trilinear filtering of the 3-D noise)
    // measured 3.0e-3: 4e-3, still 1/50 of the shadow's depth (darkest 0.23).
    CHECK(worst < 4e-3);
}

TEST_CASE("Cloud shadow lies displaced along the light by height / tan(elevation)", "[gl][clouds][shadow]") {
    test::glContext();
    // The Sun 35 deg up in the east (azimuth 90 deg): each bit of cloud at height h shadows the
    // ground h / tan 35 deg west of the point below it, so the optical depth's centroid on the
    // ground lies mean(h) / tan 35 deg west of the cloud's centre (flat ground), mean(h) the
    // density-weighted mean height of the cloud, integrated independently with the CPU density.
    const double e = 35.0 * kPi / 180.0;
    Scene s(testWeather(128, 20e3, 1500.0), 20e3, lightAt(e, kPi / 2), 1.0, 0.002);
    s.vars.set(cloudkeys::shadowResolution, 128);
    s.vars.set(cloudkeys::shadowExtent, 20e3);
    s.vars.set(cloudkeys::shadowSteps, 32);
    const std::vector<float> map = s.run();
    const CloudLayerBlock b = CloudLayerBlock::from(s.vars);
    double dSum = 0.0, hSum = 0.0;
    for (double x = -2000; x <= 2000; x += 50)
        for (double y = -2000; y <= 2000; y += 50)
            for (double h = 2002.5; h < 3000; h += 5) {
                const double d = cpu::cloudDensity(b, s.cpuTextures(), {x, y, h}, CloudLod::Cheap);
                dSum += d, hSum += d * h;
            }
    REQUIRE(dSum > 0.0);
    const double meanH = hSum / dSum;
    double w = 0.0, cx = 0.0, cy = 0.0;
    for (int j = 0; j < 128; ++j)
        for (int i = 0; i < 128; ++i) {
            const double k = -std::log(double(map[size_t(j) * 128 + size_t(i)]));  // optical depth: linear in the cloud
            const glm::dvec2 xy = s.texelXy(i, j);
            w += k, cx += k * xy.x, cy += k * xy.y;
        }
    REQUIRE(w > 1.0);
    cx /= w, cy /= w;
    const double expected = -meanH / std::tan(e);
    INFO("mean height " << meanH << " m; shadow centroid (" << cx << ", " << cy << ") m, expected (" << expected << ", 0)");
    // 15 m (a tenth of a 156 m texel): the planet's curvature lowers the layer by 1-2 m over the
    // 3.6 km of slant (the flat formula's only approximation), the 32-step march against the
    // 5 m integration grid of the mean height, and the texel grid's sampling of a smooth blob.
    CHECK(std::abs(cx - expected) < 15.0);
    CHECK(std::abs(cy) < 15.0);
    CHECK(map[size_t(64) * 128 + 64] > 0.9);  // the point below the cloud is lit
}

TEST_CASE("Cloud shadow: no clouds, overcast, light at the horizon, the Moon at night", "[gl][clouds][shadow]") {
    test::glContext();
    SECTION("no clouds: 1 everywhere") {
        Scene s(testWeather(64, 20e3, 3000.0), 20e3, lightAt(0.7, 1.0), 0.0, 0.05);  // coverage 0
        s.vars.set(cloudkeys::shadowResolution, 32);
        for (float t : s.run()) REQUIRE(t == 1.0f);  // exp(-0): exactly 1
        // The light moves with nothing to shadow (time running without clouds: the Rainbow's
        // scene): the map of 1 is not drawn again, only the light is published; the end is what a
        // whole build gives (1 everywhere), and a change of the layer still draws.
        const unsigned id = s.vars.get(cloudkeys::shadowMap).id;
        const uint64_t version = s.vars.version(cloudkeys::shadowMap);
        const int builds = s.gen->wholeBuilds(), parts = s.gen->slicesBuilt();
        REQUIRE(builds >= 1);
        s.vars.set(keys::sunDirection, lightAt(0.6, 1.2));
        for (float t : s.run()) REQUIRE(t == 1.0f);
        CHECK(s.gen->wholeBuilds() == builds);  // not drawn again: neither whole ...
        CHECK(s.gen->slicesBuilt() == parts);   // ... nor in parts
        CHECK(s.vars.get(cloudkeys::shadowMap).id == id);
        CHECK(s.vars.version(cloudkeys::shadowMap) != version);  // republished: readers see the new light
        CHECK(glm::length(s.vars.get(cloudkeys::shadowLight) - lightAt(0.6, 1.2)) < 1e-12);
        s.vars.set(cloudkeys::coverage, 1.0);  // clouds: drawn, some texel shadowed
        const std::vector<float> cloudy = s.run();
        CHECK(s.gen->wholeBuilds() == builds + 1);  // the layer changed: a whole build
        CHECK(*std::min_element(cloudy.begin(), cloudy.end()) < 0.999f);
        s.vars.set(cloudkeys::coverage, 0.0);  // and clear again: 1 everywhere, drawn
        for (float t : s.run()) REQUIRE(t == 1.0f);
        Scene e(testWeather(64, 20e3, 0.0), 20e3, lightAt(0.7, 1.0), 1.0, 0.05);  // an empty map
        e.vars.set(cloudkeys::shadowResolution, 32);
        for (float t : e.run()) REQUIRE(t == 1.0f);
    }
    SECTION("full overcast: near 0 everywhere") {
        Scene s(testWeather(64, 20e3, 0.0, true), 20e3, lightAt(1.2, 1.0), 1.0, 0.05);
        s.vars.set(cloudkeys::shadowResolution, 32);
        // Vertical optical depth 0.05/m x 1000 m x the height profile's mean (~0.6) = 30:
        // T ~ 1e-13, less along the slant; 1e-6 leaves room for float.
        for (float t : s.run()) REQUIRE(t < 1e-6f);
    }
    SECTION("the Sun at and below the horizon: finite, in [0, 1]") {
        for (double el : {0.0, -0.05}) {
            Scene s(testWeather(64, 20e3, 3000.0), 20e3, lightAt(el, 1.0), 0.6, 0.01, randomImage(8, 8, 8, 3u, 0.3f),
                    randomImage(16, 16, 1, 5u, 0.0f));
            s.vars.set(cloudkeys::shadowResolution, 32);
            for (float t : s.run()) REQUIRE((std::isfinite(t) && t >= 0.0f && t <= 1.0f));
            const glm::dvec3 L = s.vars.get(cloudkeys::shadowLight);
            CHECK(L.z == 0.0);  // laid along the horizon, unit
            CHECK(glm::length(L) == Approx(1.0));
        }
        // The cirrus alone at grazing incidence, the curl texture uniform so its density is
        // n + c - 1 = 0.5 + 0.7 - 1 = 0.2: tau = 0.3 x 0.2 / mu_c with mu_c = sqrt(1 - (R / (R +
        // 9 km))^2) = 0.0532 at the ground point below the observer.
        Scene c(testWeather(64, 20e3, 0.0), 20e3, lightAt(0.0, 1.0), 0.6, 0.01, flatBase(), cpu::Image{1, 1, 1, {0.5f, 0.5f, 0.5f, 1.0f}});
        const double mu = std::sqrt(1.0 - std::pow(6360e3 / (6360e3 + 9000.0), 2));
        CHECK(c.cpuShadow({0, 0}) == Approx(std::exp(-0.3 * 0.2 / mu)).epsilon(1e-6));  // float block: 1e-6
    }
    SECTION("at night the Moon casts the shadow") {
        Scene s(testWeather(64, 20e3, 0.0), 20e3, lightAt(-0.3, 1.0), 0.5, 0.01);  // Sun -17 deg
        s.vars.set(cloudkeys::shadowResolution, 16);
        const glm::dvec3 moon = lightAt(0.6, 4.0);
        s.vars.set(keys::moonDirection, moon);
        s.run();
        CHECK(glm::length(s.vars.get(cloudkeys::shadowLight) - moon) < 1e-12);
    }
}

TEST_CASE("welkin_cloudShadow(): the host's lookup matches the CPU twin", "[gl][clouds][shadow]") {
    test::glContext();
    const double e = 50.0 * kPi / 180.0;
    Scene s(testWeather(128, 20e3, 2000.0), 20e3, lightAt(e, 3.5), 0.9, 0.003);
    s.vars.set(cloudkeys::shadowResolution, 128);
    s.vars.set(cloudkeys::shadowExtent, 20e3);
    s.vars.set(keys::observerHeight, 120.0);
    s.run();
    // The wind moves the clouds by 500 m (< kOffsetTolerance): the map is not rebuilt, the lookup
    // shifts.
    s.vars.set(cloudkeys::weatherOffset, glm::dvec2(10e3 + 400.0, 10e3 - 300.0));
    CHECK_FALSE(s.gen->isDue(s.vars));
    const std::vector<glm::dvec3> points = {{0, 0, 0}, {1500, -800, -120}, {-2500, 1200, 600}, {300, 2500, 1500}, {-900, -1700, 30}, {2000, 2000, 3000}};
    const int N = int(points.size());
    gl::Program prog = gl::ProgramBuilder("CloudShadowHostTest")
                           .fullscreenVertex()
                           .fragment("generators/cloud_shadow.glsl", std::string(CloudShadowMap::hostGlsl()))
                           .fragment("test.glsl", R"(
uniform vec3 u_points[8];
out vec4 o_value;
void main() { o_value = vec4(welkin_cloudShadow(u_points[int(gl_FragCoord.x)]), 0.0, 0.0, 1.0); })")
                           .build();
    gl::Texture2D out(N, 1, GL_R32F);
    gl::Framebuffer fbo = gl::Framebuffer::create();
    fbo.attach(GL_COLOR_ATTACHMENT0, out);
    fbo.bind();
    glViewport(0, 0, N, 1);
    prog.use();
    for (int k = 0; k < N; ++k)
        glUniform3f(glGetUniformLocation(prog.id(), ("u_points[" + std::to_string(k) + "]").c_str()), float(points[size_t(k)].x),
                    float(points[size_t(k)].y), float(points[size_t(k)].z));
    CloudShadowMap::bindForHost(s.vars, prog.id());
    gl::VertexArray vao = gl::VertexArray::create();
    vao.bind();
    glDrawArrays(GL_TRIANGLES, 0, 3);
    const std::vector<float> got = readR(out.ref());
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    double minT = 1.0;
    const glm::dvec3 L = CloudShadowMap::lightDirection(s.vars);
    for (int k = 0; k < N; ++k) {
        // The CPU twin straight from the weather map at the current offset (no map involved): the
        // ground point the light passes through, then the march there.
        const glm::dvec2 g = cpu::cloudShadowGroundPoint(points[size_t(k)], 120.0, 2000.0, L);
        const double cpuT = s.cpuShadow(g);
        minT = std::min(minT, cpuT);
        INFO("point " << k << " ground (" << g.x << ", " << g.y << "): GLSL " << got[size_t(k)] << ", CPU " << cpuT);
        // The map's bilinear interpolation over 156 m texels of a shadow whose edge ramps from 1
        // to ~0.1 over ~1 km (the 400 m weather ramp widened by the slant through the layer):
        // the curvature term h^2 |T''| / 8 reaches ~0.02 there (0.018 measured); 0.03.
        CHECK(std::abs(got[size_t(k)] - cpuT) < 0.03);
    }
    CHECK(minT < 0.5);  // some of the points lie in the shadow
}
