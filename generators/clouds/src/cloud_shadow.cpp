// CloudShadowMap (GPU pass cloud_shadow_map.glsl) and its CPU twin (double precision): the model
// and its sources are in cloud_shadow.hpp.
#include <welkin/error.hpp>
#include <welkin/embedded/clouds_shaders.hpp>
#include <welkin/generators/cloud_shadow.hpp>
#include <welkin/generators/lights.hpp>
#include <welkin/gl/bindings.hpp>
#include <welkin/gl/objects.hpp>
#include <welkin/gl/shader.hpp>
#include <welkin/glsl_cpp.hpp>
#include <welkin/keys.hpp>

#include <epoxy/gl.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>

// The column's optical depth: cloud_shadow.shared.glsl (the pass's text) in double, as members of
// ShadowColumn, whose other members read the shared density (cloud_density.cpp) on the CPU textures.
namespace welkin::glsl::dp::cloud_shadow_shared {
struct ShadowColumn {
    const generators::CloudLayerBlock& b;
    const generators::cpu::CloudTextures& t;
    static constexpr int CLOUD_LOD_CHEAP = int(generators::CloudLod::Cheap);
    real cloudDensity(vec3 p, int lod) const { return generators::cpu::cloudDensity(b, t, p, generators::CloudLod(lod)); }
    real cirrusDensity(vec2 xy) const { return generators::cpu::cirrusDensity(b, t.curl, xy); }
#include "cloud_shadow.shared.glsl"
};
}  // namespace welkin::glsl::dp::cloud_shadow_shared

namespace welkin::generators {

namespace {
constexpr double kDefaultExtentM = 40e3;  // a few tens of km around the observer
constexpr int kDefaultResolution = 256;   // 156 m texels over 40 km
constexpr int kDefaultSteps = 16;         // through a 1 km layer: 63 m steps at the zenith
// 8 frames: at 1440x and 30 frames/s the Sun moves ~0.03 rad meanwhile; a cloud 2.5 km up at
// 30 deg elevation then casts its shadow ~300 m (two texels) from where the map shows it.
constexpr int kDefaultSlices = 8;
constexpr double kLightTolerance = 5e-4;  // rad, the lights' change tolerance (see the constructor)

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

namespace cpu {

double cloudShadowTransmittance(const CloudLayerBlock& b, const CloudTextures& t, glm::dvec3 L, int steps, glm::dvec2 xy) {
    glsl::dp::cloud_shadow_shared::ShadowColumn c{b, t};
    const bool clouds = !t.weather.rgba.empty() && !t.base.rgba.empty(), cirrus = !t.curl.rgba.empty();
    const glm::dvec4 radii(b.radii[0], b.radii[1], b.radii[2], b.radii[3]), shape(b.shape[0], b.shape[1], b.shape[2], b.shape[3]);
    return std::exp(-c.cld_shadowOpticalDepth(xy, L, radii, shape, steps, clouds, cirrus, kCirrusOpticalDepth));
}

glm::dvec2 cloudShadowGroundPoint(glm::dvec3 pos, double observerHeightM, double bottomM, glm::dvec3 light) {
    const double h = std::clamp(pos.z + observerHeightM, 0.0, bottomM);
    return glm::dvec2(pos) - h * glm::dvec2(light) / std::max(light.z, 1e-3);
}

}  // namespace cpu

struct CloudShadowMap::Gl {
    // Time-sliced rebuilds (clouds.shadow_slices): tex is shown; back is being built; prev is the
    // map shown before tex, kept intact for one more rebuild (a reader that snapshot it, the
    // sky's cloud shadow built over as many frames, still finds it whole).
    gl::Texture2D tex, back, prev;
    gl::Framebuffer fbo, backFbo, prevFbo;
    std::vector<float> setup;  // what the shown map was built with, but the light and the offsets
    bool slicing = false;
    int sliceRow = 0;
    glm::dvec3 sliceLight{0.0, 0.0, 1.0};
    glm::dvec2 sliceOffset{0.0};
    gl::Buffer sliceUbo;
    gl::Program prog;
    gl::VertexArray vao;  // empty: the fullscreen triangle's vertices come from gl_VertexID
    gl::Buffer ubo;       // CloudLayerBlock
};

CloudShadowMap::CloudShadowMap() : Generator("clouds.shadow_map") {
    // 5e-4 rad: at 30 deg elevation the shadow of a cloud 2.5 km up moves by h / sin^2(e) x 5e-4
    // = 5 m, a thirtieth of a default texel (156 m).
    input(keys::sunDirection, {.tolerance = kLightTolerance, .optional = true});
    input(keys::moonDirection, {.tolerance = kLightTolerance, .optional = true});
    input(cloudkeys::weatherMap, {.optional = true});
    input(cloudkeys::weatherOffset, {.tolerance = kOffsetTolerance, .optional = true});
    // The cirrus drifts on its own offset, which the host's shift does not follow: the map's
    // cirrus lags by at most this tolerance (its optical depth is <= 0.3: a faint pattern).
    input(cloudkeys::cirrusOffset, {.tolerance = kOffsetTolerance, .optional = true});
    input(cloudkeys::weatherExtent, {.optional = true});
    input(cloudkeys::noiseBase, {.optional = true});
    input(cloudkeys::curlNoise, {.optional = true});
    input(cloudkeys::noiseBasePeriod, {.optional = true});
    input(cloudkeys::curlPeriod, {.optional = true});
    input(cloudkeys::bottom, {.optional = true});
    input(cloudkeys::top, {.optional = true});
    input(cloudkeys::coverage, {.optional = true});
    input(cloudkeys::cloudType, {.optional = true});
    input(cloudkeys::scattering, {.optional = true});
    input(cloudkeys::cirrusCoverage, {.optional = true});
    input(cloudkeys::cirrusHeight, {.optional = true});
    input(lightkeys::planetRadius, {.optional = true});
    input(cloudkeys::shadowExtent);
    input(cloudkeys::shadowResolution);
    input(cloudkeys::shadowSteps);
    input(cloudkeys::shadowSlices, {.optional = true});
    input(keys::interactive, {.optional = true});
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
    vars.declare(cloudkeys::shadowSlices, kDefaultSlices);
}

glm::dvec3 CloudShadowMap::lightDirection(const SkyVars& vars) { return shadowLight(vars); }

bool CloudShadowMap::nothingToShadow(const SkyVars& vars) {
    return vars.getOr(cloudkeys::coverage, 0.0) <= 0.0 && vars.getOr(cloudkeys::cirrusCoverage, 0.0) <= 0.0;
}

void CloudShadowMap::doRun(SkyVars& vars, const Logger&) {
    const CloudLayerBlock block = CloudLayerBlock::from(vars);  // checks the layer (validateCloudLayer)
    const glm::dvec3 light = shadowLight(vars);
    const glm::dvec2 offset = vars.getOr(cloudkeys::weatherOffset, glm::dvec2(0.0));
    const int steps = vars.get(cloudkeys::shadowSteps);
    const int n = vars.get(cloudkeys::shadowResolution);
    const double extent = vars.get(cloudkeys::shadowExtent);
    const int slices = vars.getOr(keys::interactive, false) ? vars.getOr(cloudkeys::shadowSlices, kDefaultSlices) : 1;
    if (!gl_) gl_ = std::make_shared<Gl>();
    Gl& g = *gl_;
    auto makeTex = [n](gl::Texture2D& t, gl::Framebuffer& fb) {
        t = gl::Texture2D(n, n, GL_R32F);
        t.setFilter(GL_LINEAR);
        t.setWrap(GL_CLAMP_TO_EDGE);
        fb = gl::Framebuffer::create();
        fb.attach(GL_COLOR_ATTACHMENT0, t);
        fb.checkComplete("CloudShadowMap");
    };
    if (!g.tex || g.tex.width() != n) {
        makeTex(g.tex, g.fbo);
        g.back = {}, g.prev = {}, g.backFbo = {}, g.prevFbo = {};
        g.setup.clear();
        g.slicing = false;
    }
    if (!g.vao) g.vao = gl::VertexArray::create();
    if (!g.prog)
        g.prog = gl::ProgramBuilder("CloudShadowMap")
                     .fullscreenVertex()
                     .fragment("generators/cloud_density.glsl", embedded::clouds_shaders("cloud_density.glsl"))
                     .fragment("generators/cloud_shadow_map.glsl", embedded::clouds_shaders("cloud_shadow_map.glsl"))
                     .build();
    const TextureRef weather = vars.getOr(cloudkeys::weatherMap, TextureRef{});
    const TextureRef base = vars.getOr(cloudkeys::noiseBase, TextureRef{});
    const TextureRef curl = vars.getOr(cloudkeys::curlNoise, TextureRef{});
    const bool hasClouds = weather.id && base.id;
    // Nothing to shadow (no cumulus, no cirrus: the clear preset, or no clouds at all): a map of
    // 1 without the march (what the march gives there, at no cost).
    const bool clear = nothingToShadow(vars);
    // Everything the map depends on but the light and the offsets (the wind): when only those
    // moved, the map may be rebuilt over several frames.
    std::vector<float> setup(block.radii, block.radii + 4);
    setup.insert(setup.end(), block.shape, block.shape + 4);
    setup.insert(setup.end(), block.noise, block.noise + 4);
    setup.insert(setup.end(), {block.weather[2], float(steps), float(extent), float(weather.id), float(base.id), float(curl.id), float(clear)});
    // Rows [r0, r1) of the map into `fb` for `light` with the layer block in `ubo`.
    auto draw = [&](gl::Framebuffer& fb, gl::Buffer& ubo, glm::dvec3 L, int r0, int r1) {
        fb.bind();
        glViewport(0, 0, n, n);
        glDisable(GL_BLEND);
        if (clear) {
            const float one = 1.0f;
            glClearTexImage(&fb == &g.fbo ? g.tex.id() : g.back.id(), 0, GL_RED, GL_FLOAT, &one);
            return;
        }
        g.prog.use();
        ubo.bindBase(GL_UNIFORM_BUFFER, gl::binding::kCloudUbo);
        if (weather.id) glBindTextureUnit(gl::binding::kCloudWeatherMap, weather.id);
        if (base.id) glBindTextureUnit(gl::binding::kCloudNoiseBase, base.id);
        if (curl.id) glBindTextureUnit(gl::binding::kCloudCurlNoise, curl.id);
        g.prog.set("u_size", glm::ivec2(n, n));
        g.prog.set("u_extent", float(extent));
        g.prog.set("u_cirrusTau", float(kCirrusOpticalDepth));
        g.prog.set("u_light", glm::vec3(L));
        g.prog.set("u_steps", steps);
        g.prog.set("u_hasClouds", hasClouds ? 1 : 0);
        g.prog.set("u_hasCurl", curl.id ? 1 : 0);
        g.vao.bind();
        const bool part = r0 > 0 || r1 < n;
        if (part) {
            glEnable(GL_SCISSOR_TEST);
            glScissor(0, r0, n, r1 - r0);
        }
        glDrawArrays(GL_TRIANGLES, 0, 3);
        if (part) glDisable(GL_SCISSOR_TEST);
    };
    auto publish = [&](glm::dvec3 L, glm::dvec2 o) {
        lastLight_ = L;
        lastSteps_ = steps;
        vars.publish(cloudkeys::shadowLight, L);
        vars.publish(cloudkeys::shadowOffset, o);
        vars.publish(cloudkeys::shadowMap, g.tex.ref());
    };
    if (clear && setup == g.setup) {
        // Still nothing to shadow, and the shown map is already the map of 1 of this setup (a clear
        // map is always drawn whole into it): only the light moved. Nothing to draw; the light
        // published (the Rainbow, with no clouds, paid a clear of the whole map every frame in
        // which the light moved 0.03 deg: 0.04-0.05 ms in a per-part trace at load 6, against a
        // still frame of 0.7 ms quiet at 512x256).
        publish(light, offset);
        return;
    }
    if (slices <= 1 || clear || setup != g.setup) {
        // Whole, now, into the shown map (the first build, a change of the layer, a render).
        g.slicing = false;
        g.setup = setup;
        g.ubo = gl::Buffer(sizeof block, &block);
        draw(g.fbo, g.ubo, light, 0, n);
        ++wholeBuilds_;
        publish(light, offset);
        return;
    }
    // Only the light or the wind moved: a 1/slices of the rows per run into the back map, with
    // the light, offset and layer block of the run that began it; shown when complete.
    if (!g.slicing) {
        if (!g.back) makeTex(g.back, g.backFbo);
        g.slicing = true;
        g.sliceRow = 0;
        g.sliceLight = light;
        g.sliceOffset = offset;
        g.sliceUbo = gl::Buffer(sizeof block, &block);
    }
    const int rows = (n + slices - 1) / slices;
    const int r1 = std::min(n, g.sliceRow + rows);
    draw(g.backFbo, g.sliceUbo, g.sliceLight, g.sliceRow, r1);
    g.sliceRow = r1;
    ++slicesBuilt_;
    if (r1 < n) {
        runAgain();
        return;
    }
    // Complete: back -> shown -> kept -> back.
    g.slicing = false;
    std::swap(g.prev, g.tex);
    std::swap(g.prevFbo, g.fbo);
    std::swap(g.tex, g.back);
    std::swap(g.fbo, g.backFbo);
    publish(g.sliceLight, g.sliceOffset);
    // Built for a light or an offset that has moved on meanwhile: once more, even if nothing
    // changes from now on (the inputs' tolerances).
    if (glm::length(light - g.sliceLight) > kLightTolerance || glm::length(offset - g.sliceOffset) > kOffsetTolerance) runAgain();
}

void CloudShadowMap::doRelease() { gl_.reset(); }

void CloudShadowMap::doStats(nlohmann::json& root) const {
    root["clouds"]["shadow_light_direction"] = {lastLight_.x, lastLight_.y, lastLight_.z};
    root["clouds"]["shadow_steps"] = lastSteps_;
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
    m1[3] = float(vars.getOr(cloudkeys::bottom, 2000.0));  // the Clouds element's default base
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
