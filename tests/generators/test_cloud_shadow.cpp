// The clouds' shadow map (generators/clouds/cloud_shadow.hpp): the GPU pass against its double
// CPU twin, the geometry of a shadow, and the limits (no cloud, overcast, the light at the horizon).
#include <catch2/catch.hpp>

#include "gl_test_context.hpp"

#include <welkin/generators/cloud_shadow.hpp>
#include <welkin/generators/lights.hpp>
#include <welkin/gl/objects.hpp>
#include <welkin/gl/shader.hpp>
#include <welkin/keys.hpp>

#include <cmath>

using namespace welkin;
using namespace welkin::generators;

namespace {
constexpr double kPi = 3.14159265358979323846;

// A test weather map: a round cumulus of radius `radiusM` centred at ENU (0, 0), its base and top
// at the layer's bottom and top (G = 0, B = 1), over `extentM` with offset extent / 2 so ENU (0, 0)
// reads uv (0.5, 0.5). `everywhere`: density 1 over the whole map (overcast).
WeatherImage testWeather(int n, double extentM, double radiusM, bool everywhere = false) {
    WeatherImage w{n, n, std::vector<glm::dvec4>(size_t(n) * size_t(n), glm::dvec4(0.0))};
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            const glm::dvec2 xy = (glm::dvec2(i + 0.5, j + 0.5) / double(n) - 0.5) * extentM;
            const double r = glm::length(xy);
            // A smooth edge over 400 m (a cosine ramp) so the bilinear weather lookup is smooth.
            const double d = everywhere ? 1.0 : std::clamp((radiusM - r) / 400.0 + 0.5, 0.0, 1.0);
            const double s = everywhere ? 1.0 : 0.5 - 0.5 * std::cos(kPi * d);
            if (s > 0.0) w.texels[size_t(j) * size_t(n) + size_t(i)] = {s, 0.0, 1.0, 0.0};
        }
    return w;
}

gl::Texture2D upload(const WeatherImage& w) {
    std::vector<float> px;
    for (const glm::dvec4& t : w.texels)
        for (int c = 0; c < 4; ++c) px.push_back(float(t[c]));
    gl::Texture2D tex(w.width, w.height, GL_RGBA32F);
    tex.upload(GL_RGBA, GL_FLOAT, px.data());
    tex.setFilter(GL_LINEAR);
    tex.setWrap(GL_REPEAT);
    return tex;
}

std::vector<float> readR(TextureRef ref) {
    std::vector<float> px(size_t(ref.width) * size_t(ref.height));
    glGetTextureImage(ref.id, 0, GL_RED, GL_FLOAT, GLsizei(px.size() * sizeof(float)), px.data());
    return px;
}

struct Scene {
    SkyVars vars;
    std::shared_ptr<CloudShadowMap> gen = std::make_shared<CloudShadowMap>();
    gl::Texture2D weatherTex;
    WeatherImage weather;
    Scene(const WeatherImage& w, double weatherExtentM, glm::dvec3 sun, double coverage, double sigma) : weather(w) {
        gen->declareKeys(vars);
        weatherTex = upload(w);
        vars.set(cloudkeys::weatherMap, weatherTex.ref());
        vars.set(cloudkeys::weatherExtent, weatherExtentM);
        vars.set(cloudkeys::weatherOffset, glm::dvec2(weatherExtentM / 2));
        vars.set(cloudkeys::bottom, 2000.0);
        vars.set(cloudkeys::top, 3000.0);
        vars.set(cloudkeys::coverage, coverage);
        vars.set(cloudkeys::scattering, sigma);
        vars.set(cloudkeys::cirrusCoverage, 0.0);
        vars.set(cloudkeys::cirrusHeight, 9000.0);
        vars.set(lightkeys::planetRadius, 6360e3);
        vars.set(keys::sunDirection, glm::normalize(sun));
        vars.set(keys::moonDirection, glm::dvec3(0, 0, -1));
    }
    std::vector<float> run() {
        gen->run(vars, test::testLogger());
        return readR(vars.get(cloudkeys::shadowMap));
    }
    // ENU xy of texel (i, j)'s centre.
    glm::dvec2 texelXy(int i, int j) const {
        const int n = vars.get(cloudkeys::shadowResolution);
        return (glm::dvec2(i + 0.5, j + 0.5) / double(n) - 0.5) * vars.get(cloudkeys::shadowExtent);
    }
};

glm::dvec3 lightAt(double elevationRad, double azimuthRad) {  // azimuth from north through east
    return {std::cos(elevationRad) * std::sin(azimuthRad), std::cos(elevationRad) * std::cos(azimuthRad), std::sin(elevationRad)};
}
}  // namespace

TEST_CASE("Cloud shadow map: GPU pass against the double CPU twin", "[gl][clouds][shadow]") {
    test::glContext();
    Scene s(testWeather(128, 20e3, 2500.0), 20e3, lightAt(0.5, 2.0), 0.8, 0.004);
    s.vars.set(cloudkeys::shadowResolution, 64);
    s.vars.set(cloudkeys::shadowExtent, 20e3);
    s.vars.set(cloudkeys::cirrusCoverage, 0.5);
    const std::vector<float> map = s.run();
    const CloudShadowParams p = CloudShadowMap::params(s.vars);
    double worst = 0.0, minT = 1.0;
    for (int j = 0; j < 64; j += 3)
        for (int i = 0; i < 64; i += 3) {
            const double cpu = cpu::cloudShadowTransmittance(s.weather, p, s.texelXy(i, j));
            worst = std::max(worst, std::abs(cpu - map[size_t(j) * 64 + size_t(i)]));
            minT = std::min(minT, cpu);
        }
    INFO("largest |GPU - CPU| " << worst << ", darkest " << minT);
    CHECK(minT < 0.2);  // the test cloud does cast a dark shadow in the map (not a trivial match)
    // float march vs double (1.3e-6 measured on llvmpipe, whose float textures filter with float
    // weights); 1e-3 leaves room for a GPU with 8-bit filtering weights (a weight off by 1/512 on
    // the cloud's 400 m ramp changes the density by < 0.3 %, the transmittance by < 1e-3 here).
    CHECK(worst < 1e-3);
}

TEST_CASE("Cloud shadow lies displaced along the light by height / tan(elevation)", "[gl][clouds][shadow]") {
    test::glContext();
    // Sun 35 deg up in the east (azimuth 90 deg): the shadow of a cloud centred 2500 m up (the
    // parabolic density of a base at 2000 m and top at 3000 m is symmetric about its middle) lies
    // 2500 / tan 35 deg = 3570 m west of the point below it.
    const double e = 35.0 * kPi / 180.0;
    Scene s(testWeather(128, 20e3, 1500.0), 20e3, lightAt(e, kPi / 2), 1.0, 0.002);
    s.vars.set(cloudkeys::shadowResolution, 128);
    s.vars.set(cloudkeys::shadowExtent, 20e3);
    s.vars.set(cloudkeys::shadowSteps, 32);
    const std::vector<float> map = s.run();
    double w = 0.0, cx = 0.0, cy = 0.0;
    for (int j = 0; j < 128; ++j)
        for (int i = 0; i < 128; ++i) {
            const double k = 1.0 - map[size_t(j) * 128 + size_t(i)];
            const glm::dvec2 xy = s.texelXy(i, j);
            w += k, cx += k * xy.x, cy += k * xy.y;
        }
    REQUIRE(w > 10.0);  // a shadow of at least 10 texels' worth of darkness exists
    cx /= w, cy /= w;
    const double expected = -2500.0 / std::tan(e);
    INFO("shadow centroid (" << cx << ", " << cy << ") m, expected (" << expected << ", 0)");
    // 10 m (a sixteenth of a 156 m texel): the planet's curvature lowers the layer by ~1-2 m
    // over the 3.6 km of slant (the flat-ground formula's only error: 2.2 m measured); the
    // centroid of a smooth blob sampled on the texel grid and the 32-step midpoint march
    // (symmetric about the layer's middle) add far less.
    CHECK(std::abs(cx - expected) < 10.0);
    CHECK(std::abs(cy) < 10.0);
    // And it is not below the cloud: the point under the cloud's centre is lit.
    CHECK(map[size_t(64) * 128 + 64] > 0.95);
}

TEST_CASE("Cloud shadow: no clouds, overcast, light at the horizon, the Moon at night", "[gl][clouds][shadow]") {
    test::glContext();
    SECTION("no clouds: 1 everywhere") {
        Scene s(testWeather(64, 20e3, 3000.0), 20e3, lightAt(0.7, 1.0), 0.0, 0.05);  // coverage 0
        s.vars.set(cloudkeys::shadowResolution, 32);
        for (float t : s.run()) REQUIRE(t == 1.0f);  // exp(-0): exactly 1
        Scene e(testWeather(64, 20e3, 0.0), 20e3, lightAt(0.7, 1.0), 1.0, 0.05);  // empty map
        e.vars.set(cloudkeys::shadowResolution, 32);
        for (float t : e.run()) REQUIRE(t == 1.0f);
    }
    SECTION("full overcast: near 0 everywhere") {
        Scene s(testWeather(64, 20e3, 0.0, true), 20e3, lightAt(1.2, 1.0), 1.0, 0.05);
        s.vars.set(cloudkeys::shadowResolution, 32);
        // Vertical optical depth 0.05/m x 1000 m x 2/3 (the parabola's mean) = 33: T ~ 4e-15,
        // more along the slant; 1e-6 leaves room for float.
        for (float t : s.run()) REQUIRE(t < 1e-6f);
    }
    SECTION("the Sun at and below the horizon: finite, in [0, 1]") {
        for (double el : {0.0, -0.05}) {
            Scene s(testWeather(64, 20e3, 3000.0), 20e3, lightAt(el, 1.0), 0.6, 0.01);
            s.vars.set(cloudkeys::shadowResolution, 32);
            s.vars.set(cloudkeys::cirrusCoverage, 1.0);
            for (float t : s.run()) REQUIRE((std::isfinite(t) && t >= 0.0f && t <= 1.0f));
            // The light is laid along the horizon: z = 0, unit.
            const glm::dvec3 L = s.vars.get(cloudkeys::shadowLight);
            CHECK(L.z == 0.0);
            CHECK(glm::length(L) == Approx(1.0));
            // The cirrus alone at grazing incidence: tau = 0.3 / mu_c with mu_c = sqrt(1 - (R /
            // (R + 9 km))^2) = 0.0532 at the ground point below the observer: T = exp(-5.64).
            Scene c(testWeather(64, 20e3, 0.0), 20e3, lightAt(el, 1.0), 0.6, 0.01);
            c.vars.set(cloudkeys::shadowResolution, 32);
            c.vars.set(cloudkeys::cirrusCoverage, 1.0);
            const CloudShadowParams p = CloudShadowMap::params(c.vars);
            const double mu = std::sqrt(1.0 - std::pow(6360e3 / (6360e3 + 9000.0), 2));
            CHECK(cpu::cloudShadowTransmittance(c.weather, p, {0, 0}) == Approx(std::exp(-0.3 / mu)).epsilon(1e-9));
        }
    }
    SECTION("at night the Moon casts the shadow") {
        Scene s(testWeather(64, 20e3, 0.0), 20e3, lightAt(-0.3, 1.0), 0.5, 0.01);
        s.vars.set(cloudkeys::shadowResolution, 16);
        const glm::dvec3 moon = lightAt(0.6, 4.0);
        s.vars.set(keys::moonDirection, moon);
        s.run();
        const glm::dvec3 L = s.vars.get(cloudkeys::shadowLight);
        CHECK(glm::length(L - moon) < 1e-12);
    }
}

TEST_CASE("welkin_cloudShadow(): the host's lookup matches the map and the CPU mapping", "[gl][clouds][shadow]") {
    test::glContext();
    const double e = 50.0 * kPi / 180.0;
    Scene s(testWeather(128, 20e3, 2000.0), 20e3, lightAt(e, 3.5), 0.9, 0.003);
    s.vars.set(cloudkeys::shadowResolution, 128);
    s.vars.set(cloudkeys::shadowExtent, 20e3);
    s.vars.set(keys::observerHeight, 120.0);
    const std::vector<float> map = s.run();
    // The wind moves the clouds by 400 m (< kOffsetTolerance): the map is not rebuilt, the lookup
    // shifts.
    s.vars.set(cloudkeys::weatherOffset, glm::dvec2(10e3 + 400.0, 10e3 - 300.0));
    CHECK_FALSE(s.gen->isDue(s.vars));
    const CloudShadowParams p = CloudShadowMap::params(s.vars);  // the current offset
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
        glUniform3f(glGetUniformLocation(prog.id(), ("u_points[" + std::to_string(k) + "]").c_str()), float(points[k].x), float(points[k].y), float(points[k].z));
    CloudShadowMap::bindForHost(s.vars, prog.id());
    gl::VertexArray vao = gl::VertexArray::create();
    vao.bind();
    glDrawArrays(GL_TRIANGLES, 0, 3);
    const std::vector<float> got = readR(out.ref());
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    const glm::dvec2 shift = s.vars.get(cloudkeys::weatherOffset) - s.vars.get(cloudkeys::shadowOffset);
    double minT = 1.0;
    for (int k = 0; k < N; ++k) {
        // The CPU twin straight from the weather map at the current offset (no map involved):
        // the ground point the light passes through, then the march there. The map was built
        // with the old offset; the shift makes them the same function.
        CloudShadowParams q = p;
        const glm::dvec2 g = cpu::cloudShadowGroundPoint(points[size_t(k)], 120.0, q, {0, 0});
        const double cpuT = cpu::cloudShadowTransmittance(s.weather, q, g);
        minT = std::min(minT, cpuT);
        INFO("point " << k << " ground (" << g.x << ", " << g.y << "): GLSL " << got[size_t(k)] << ", CPU " << cpuT);
        // The map's bilinear interpolation over 156 m texels of a shadow whose edge ramps over
        // ~1 km (the 400 m weather ramp widened by the slant through 1 km of layer) plus the
        // float march: 0.02.
        CHECK(std::abs(got[size_t(k)] - cpuT) < 0.02);
    }
    (void)shift;
    CHECK(minT < 0.5);  // some of the points lie in the shadow
}
