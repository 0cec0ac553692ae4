// CloudShadowMap (GPU pass cloud_shadow_map.glsl) and its CPU twin (double precision): the model
// and its sources are in cloud_shadow.hpp.
#include <welkin/error.hpp>
#include <welkin/embedded/clouds_shaders.hpp>
#include <welkin/generators/cloud_shadow.hpp>
#include <welkin/generators/lights.hpp>
#include <welkin/gl/bindings.hpp>
#include <welkin/gl/objects.hpp>
#include <welkin/gl/shader.hpp>
#include <welkin/keys.hpp>

#include <epoxy/gl.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>

namespace welkin::generators {

namespace {
constexpr double kDefaultExtentM = 40e3;  // a few tens of km around the observer
constexpr int kDefaultResolution = 256;   // 156 m texels over 40 km
constexpr int kDefaultSteps = 16;         // through a 1 km layer: 63 m steps at the zenith

// Exit distance of the unit ray L from the ground point (xy, R) through the sphere R + H (the
// GLSL's exitDistance(), same stable form).
double exitDistance(glm::dvec2 xy, glm::dvec3 L, double R, double H) {
    const double b = glm::dot(xy, glm::dvec2(L)) + R * L.z;
    const double q = glm::dot(xy, xy) - H * (2.0 * R + H);
    const double s = std::sqrt(std::max(b * b - q, 0.0));
    return b > 0.0 ? -q / (b + s) : s - b;
}

glm::dvec3 shadowLight(const SkyVars& vars) {
    glm::dvec3 sun = vars.getOr(keys::sunDirection, glm::dvec3(0, 0, 1));
    glm::dvec3 moon = vars.getOr(keys::moonDirection, glm::dvec3(0, 0, -1));
    glm::dvec3 L = sun.z >= std::sin(kShadowMoonBelowSunElevationRad) ? sun : moon;
    if (glm::length(L) < 1e-9) L = {0, 0, 1};
    L = glm::normalize(L);
    if (L.z < 0.0) {  // below the horizon: the light along the horizon, same azimuth
        L.z = 0.0;
        L = glm::length(glm::dvec2(L)) > 1e-9 ? glm::normalize(L) : glm::dvec3(1, 0, 0);
    }
    return L;
}
}  // namespace

glm::dvec4 WeatherImage::sample(glm::dvec2 uv) const {
    if (width <= 0 || height <= 0) return glm::dvec4(0.0);
    // GL_LINEAR: texel centres at (i + 0.5) / width; GL_REPEAT wraps the integer indices.
    const double x = uv.x * width - 0.5, y = uv.y * height - 0.5;
    const double fx = std::floor(x), fy = std::floor(y);
    const double ax = x - fx, ay = y - fy;
    auto wrap = [](long long i, int n) { return int(((i % n) + n) % n); };
    const int x0 = wrap((long long)fx, width), x1 = wrap((long long)fx + 1, width);
    const int y0 = wrap((long long)fy, height), y1 = wrap((long long)fy + 1, height);
    auto at = [&](int i, int j) { return texels[size_t(j) * size_t(width) + size_t(i)]; };
    return (1 - ay) * ((1 - ax) * at(x0, y0) + ax * at(x1, y0)) + ay * ((1 - ax) * at(x0, y1) + ax * at(x1, y1));
}

namespace cpu {

double cloudShadowDensity(const WeatherImage& weather, const CloudShadowParams& p, glm::dvec2 xyM, double hM) {
    if (p.coverage <= 0.0) return 0.0;
    const glm::dvec4 w = weather.sample((xyM + p.weatherOffsetM) / p.weatherExtentM);
    const double hb = p.bottomM + w.g * (p.topM - p.bottomM), ht = p.bottomM + w.b * (p.topM - p.bottomM);
    if (ht <= hb) return 0.0;
    const double hs = 4.0 * (hM - hb) * (ht - hM) / ((ht - hb) * (ht - hb));      // Papp 2018 eq. 5.2
    const double dcov = std::max(w.r + p.coverage - 1.0, 0.0) / p.coverage;        // eq. 5.4
    return std::clamp(dcov * std::max(hs, 0.0), 0.0, 1.0);                         // eq. 5.5 without N(p)
}

double cloudShadowTransmittance(const WeatherImage& weather, const CloudShadowParams& p, glm::dvec2 xy) {
    const double R = p.planetRadiusM;
    const glm::dvec3 L = p.light;
    double tau = 0.0;
    if (weather.width > 0 && p.coverage > 0.0 && p.scatteringPerM > 0.0) {
        const double t0 = exitDistance(xy, L, R, p.bottomM), t1 = exitDistance(xy, L, R, p.topM);
        const double dt = (t1 - t0) / p.steps;
        for (int i = 0; i < p.steps; ++i) {
            const double t = t0 + (i + 0.5) * dt;
            const glm::dvec2 q = xy + t * glm::dvec2(L);
            const glm::dvec3 pos(q, R + t * L.z);
            const double h = glm::length(pos) - R;  // double: exact enough directly
            tau += p.scatteringPerM * cloudShadowDensity(weather, p, q, h) * dt;
        }
    }
    const double cirrusTau = kCirrusOpticalDepth * p.cirrusCoverage;
    if (cirrusTau > 0.0) {
        const double rc = R + p.cirrusHeightM;
        const glm::dvec3 k = glm::cross(glm::dvec3(xy, R), L);
        const double mu = std::sqrt(std::max(1.0 - glm::dot(k, k) / (rc * rc), 0.0));
        tau += cirrusTau / std::max(mu, 1e-3);
    }
    return std::exp(-tau);
}

glm::dvec2 cloudShadowGroundPoint(glm::dvec3 pos, double observerHeightM, const CloudShadowParams& p, glm::dvec2 shiftM) {
    const double h = std::clamp(pos.z + observerHeightM, 0.0, p.bottomM);
    return glm::dvec2(pos) - h * glm::dvec2(p.light) / std::max(p.light.z, 1e-3) + shiftM;
}

}  // namespace cpu

struct CloudShadowMap::Gl {
    gl::Texture2D tex;
    gl::Framebuffer fbo;
    gl::Program prog;
    gl::VertexArray vao;  // empty: the fullscreen triangle's vertices come from gl_VertexID
};

CloudShadowMap::CloudShadowMap() : Generator("clouds.shadow_map") {
    // 5e-4 rad: at 30 deg elevation the shadow of a cloud 2.5 km up moves by h / sin^2(e) x 5e-4
    // = 5 m, a thirtieth of a default texel (156 m).
    input(keys::sunDirection, {.tolerance = 5e-4, .optional = true});
    input(keys::moonDirection, {.tolerance = 5e-4, .optional = true});
    input(cloudkeys::weatherMap, {.optional = true});
    input(cloudkeys::weatherOffset, {.tolerance = kOffsetTolerance, .optional = true});
    input(cloudkeys::weatherExtent, {.optional = true});
    input(cloudkeys::bottom, {.optional = true});
    input(cloudkeys::top, {.optional = true});
    input(cloudkeys::coverage, {.optional = true});
    input(cloudkeys::scattering, {.optional = true});
    input(cloudkeys::cirrusCoverage, {.optional = true});
    input(cloudkeys::cirrusHeight, {.optional = true});
    input(lightkeys::planetRadius, {.optional = true});
    input(cloudkeys::shadowExtent);
    input(cloudkeys::shadowResolution);
    input(cloudkeys::shadowSteps);
    output(cloudkeys::shadowMap);
    output(cloudkeys::shadowLight);
    output(cloudkeys::shadowOffset);
}

std::shared_ptr<CloudShadowMap> CloudShadowMap::obtain(SkyVars& vars) {
    static const Key<std::shared_ptr<CloudShadowMap>> kShared{"generators.cloud_shadow_map"};
    return vars.obtain<CloudShadowMap>(kShared, [] { return std::make_shared<CloudShadowMap>(); });
}

void CloudShadowMap::doDeclare(SkyVars& vars) {
    vars.declare(cloudkeys::shadowExtent, kDefaultExtentM);
    vars.declare(cloudkeys::shadowResolution, kDefaultResolution);
    vars.declare(cloudkeys::shadowSteps, kDefaultSteps);
}

CloudShadowParams CloudShadowMap::params(const SkyVars& vars) {
    CloudShadowParams p;
    p.bottomM = vars.getOr(cloudkeys::bottom, p.bottomM);
    p.topM = vars.getOr(cloudkeys::top, p.topM);
    p.coverage = vars.getOr(cloudkeys::coverage, p.coverage);
    p.scatteringPerM = vars.getOr(cloudkeys::scattering, p.scatteringPerM);
    p.cirrusCoverage = vars.getOr(cloudkeys::cirrusCoverage, p.cirrusCoverage);
    p.cirrusHeightM = vars.getOr(cloudkeys::cirrusHeight, p.cirrusHeightM);
    p.planetRadiusM = vars.getOr(lightkeys::planetRadius, p.planetRadiusM);
    p.weatherExtentM = vars.getOr(cloudkeys::weatherExtent, p.weatherExtentM);
    p.weatherOffsetM = vars.getOr(cloudkeys::weatherOffset, p.weatherOffsetM);
    p.light = shadowLight(vars);
    p.steps = vars.getOr(cloudkeys::shadowSteps, kDefaultSteps);
    return p;
}

void CloudShadowMap::doRun(SkyVars& vars, const Logger&) {
    const CloudShadowParams p = params(vars);
    if (p.topM < p.bottomM + 100.0)
        throw Error("CloudShadowMap: clouds.top_m " + std::to_string(p.topM) + " not above clouds.bottom_m " + std::to_string(p.bottomM) + " + 100 m");
    const int n = vars.get(cloudkeys::shadowResolution);
    const double extent = vars.get(cloudkeys::shadowExtent);
    if (!gl_) gl_ = std::make_shared<Gl>();
    Gl& g = *gl_;
    if (!g.tex || g.tex.width() != n) {
        g.tex = gl::Texture2D(n, n, GL_R32F);
        g.tex.setFilter(GL_LINEAR);
        g.tex.setWrap(GL_CLAMP_TO_EDGE);
        g.fbo = gl::Framebuffer::create();
        g.fbo.attach(GL_COLOR_ATTACHMENT0, g.tex);
        g.fbo.checkComplete("CloudShadowMap");
    }
    if (!g.vao) g.vao = gl::VertexArray::create();
    if (!g.prog)
        g.prog = gl::ProgramBuilder("CloudShadowMap")
                     .fullscreenVertex()
                     .fragment("generators/cloud_shadow_map.glsl", embedded::clouds_shaders("cloud_shadow_map.glsl"))
                     .build();
    const TextureRef weather = vars.getOr(cloudkeys::weatherMap, TextureRef{});
    g.fbo.bind();
    glViewport(0, 0, n, n);
    glDisable(GL_BLEND);
    g.prog.use();
    if (weather.id) {
        glBindTextureUnit(gl::binding::kCloudWeatherMap, weather.id);
    }
    g.prog.set("u_size", glm::ivec2(n, n));
    g.prog.set("u_extent", float(extent));
    g.prog.set("u_weatherOffset", glm::vec2(p.weatherOffsetM));
    g.prog.set("u_weatherExtent", float(p.weatherExtentM));
    g.prog.set("u_bottom", float(p.bottomM));
    g.prog.set("u_top", float(p.topM));
    g.prog.set("u_coverage", float(p.coverage));
    g.prog.set("u_sigma", float(p.scatteringPerM));
    g.prog.set("u_cirrusTau", float(kCirrusOpticalDepth * p.cirrusCoverage));
    g.prog.set("u_cirrusHeight", float(p.cirrusHeightM));
    g.prog.set("u_radius", float(p.planetRadiusM));
    g.prog.set("u_light", glm::vec3(p.light));
    g.prog.set("u_steps", p.steps);
    g.prog.set("u_hasWeather", weather.id ? 1 : 0);
    g.vao.bind();
    glDrawArrays(GL_TRIANGLES, 0, 3);
    last_ = p;
    vars.publish(cloudkeys::shadowLight, p.light);
    vars.publish(cloudkeys::shadowOffset, p.weatherOffsetM);
    vars.publish(cloudkeys::shadowMap, g.tex.ref());
}

void CloudShadowMap::doRelease() { gl_.reset(); }

void CloudShadowMap::doStats(nlohmann::json& root) const {
    root["clouds"]["shadow_light_direction"] = {last_.light.x, last_.light.y, last_.light.z};
    root["clouds"]["shadow_steps"] = last_.steps;
}

void CloudShadowMap::hostUniforms(const SkyVars& vars, float m0[4], float m1[4]) {
    const glm::dvec2 shift = vars.getOr(cloudkeys::weatherOffset, glm::dvec2(0.0)) - vars.getOr(cloudkeys::shadowOffset, glm::dvec2(0.0));
    const double extent = vars.getOr(cloudkeys::shadowExtent, kDefaultExtentM);
    const glm::dvec3 L = vars.getOr(cloudkeys::shadowLight, glm::dvec3(0, 0, 1));
    m0[0] = float(shift.x);
    m0[1] = float(shift.y);
    m0[2] = float(1.0 / extent);
    m0[3] = float(-vars.getOr(keys::observerHeight, 0.0));
    m1[0] = float(L.x);
    m1[1] = float(L.y);
    m1[2] = float(L.z);
    m1[3] = float(vars.getOr(cloudkeys::bottom, CloudShadowParams{}.bottomM));
}

void CloudShadowMap::bindForHost(const SkyVars& vars, unsigned program) {
    if (!vars.has(cloudkeys::shadowMap)) return;
    glBindTextureUnit(gl::binding::kCloudShadowMap, vars.get(cloudkeys::shadowMap).id);
    if (!program) return;
    float m0[4], m1[4];
    hostUniforms(vars, m0, m1);
    glProgramUniform4fv(program, glGetUniformLocation(program, "welkin_cloudShadowMapping0"), 1, m0);
    glProgramUniform4fv(program, glGetUniformLocation(program, "welkin_cloudShadowMapping1"), 1, m1);
}

std::string_view CloudShadowMap::hostGlsl() { return embedded::clouds_shaders("cloud_shadow.glsl"); }

}  // namespace welkin::generators
