// CloudSkyShadow (GPU pass cloud_sky_shadow.glsl) and its CPU twin (double precision): the
// model and its keys are in cloud_sky_shadow.hpp and skyelements/clouds/README.md.
#include <welkin/embedded/atmosphere_shaders.hpp>
#include <welkin/embedded/clouds_shaders.hpp>
#include <welkin/error.hpp>
#include <welkin/generators/cloud_keys.hpp>
#include <welkin/generators/cloud_shadow.hpp>
#include <welkin/generators/cloud_sky_shadow.hpp>
#include <welkin/gl/bindings.hpp>
#include <welkin/gl/shader.hpp>
#include <welkin/glsl_cpp.hpp>
#include <welkin/keys.hpp>

#include <epoxy/gl.h>

#include <algorithm>
#include <cmath>

#include "../../atmosphere/src/sky_model_access.hpp"

// The march: cloud_sky_shadow.shared.glsl (the pass's text) in double, as members of SkyShadowMarch
// whose other members are what it calls of the atmosphere (SkyModelAccess, the atmosphere family's:
// atmosphere.glsl's block wrappers' twins on a SkyModel and its transmittance LUT, as the sky's
// SkyMarch has them) and the shadow map's read.
namespace welkin::glsl::dp::sky_shadow_shared {
#define ATM_SEGMENT_LINEAR 1e-7  // atm_segmentFactor()'s linear limit in double (as sky_model.cpp)
#include "atmosphere.shared.glsl"
struct SkyShadowMarch : SkyModelAccess {
    const std::function<double(glm::dvec2)>& map;
    real cld_skyShadowMapAt(vec2 uv) const { return map(uv); }
#include "cloud_sky_shadow.shared.glsl"
};
}  // namespace welkin::glsl::dp::sky_shadow_shared

namespace welkin::generators {

namespace {
constexpr double kMoonAngularRadius = 0.0045;  // rad, mean (as the sky view's Moon)
constexpr double kLightTolerance = 5e-4;       // rad: the lights' change tolerance (as the shadow map's)
}

namespace cpu {

std::pair<glm::dvec3, glm::dvec3> skyShadowLoss(const SkyModel& m, const Lut2D& T, double deltaM, const SkyShadowInputs& in,
                                                double angularRadius, glm::dvec3 dir, bool ground,
                                                const std::function<double(glm::dvec2)>& map) {
    glm::dvec3 lossR, lossM;
    glsl::dp::sky_shadow_shared::SkyShadowMarch{{m, &T}, map}.cld_skyShadowLoss(
        in.observerHeightM, dir, ground, in.light, angularRadius, in.mapLight, glm::dvec4(in.shift, 1.0 / in.extentM, in.extentM),
        glm::dvec2(in.bottomM, in.topM), in.steps, deltaM, lossR, lossM);  // the pass's text
    return {lossR, lossM};
}

}  // namespace cpu

CloudSkyShadow::CloudSkyShadow() : SkyGenerator("sky.shadow_loss") {
    input(cloudkeys::shadowMap);
    input(cloudkeys::shadowLight);
    input(cloudkeys::shadowOffset);
    input(cloudkeys::shadowExtent);
    input(cloudkeys::weatherOffset, {.tolerance = kSkyShadowOffsetTolerance, .optional = true});
    input(cloudkeys::bottom, {.optional = true});
    input(cloudkeys::top, {.optional = true});
    // The shadowed light's direction enters the light's transmittance and the phase (same
    // tolerance as the shadow map's: 5e-4 rad).
    input(keys::sunDirection, {.tolerance = kLightTolerance, .optional = true});
    input(keys::moonDirection, {.tolerance = kLightTolerance, .optional = true});
    input(keys::observerHeight, {.optional = true});
    input(skykeys::transmittanceLut);
    input(cloudkeys::shadowSlices, {.optional = true});
    input(keys::interactive, {.optional = true});
    output(skykeys::shadowLossLut);
    output(skykeys::shadowLossMieLut);
    output(skykeys::shadowLossMoon);
}

std::shared_ptr<CloudSkyShadow> CloudSkyShadow::obtain(SkyVars& vars) {
    static const Key<std::shared_ptr<CloudSkyShadow>> kShared{"generators.cloud_sky_shadow"};
    return vars.obtain<CloudSkyShadow>(kShared, [] { return std::make_shared<CloudSkyShadow>(); });
}

void CloudSkyShadow::releaseGl() {
    loss_ = {};
    lossMie_ = {};
    fbo_ = {};
    backLoss_ = {};
    backLossMie_ = {};
    backFbo_ = {};
    slicing_ = false;
    setup_.clear();
    prog_ = {};
    releaseCommon();
}

void CloudSkyShadow::doRun(SkyVars& vars, const Logger&) {
    // Nothing to shadow (no cumulus, no cirrus): no table, so the Sky draws its unshadowed
    // variant (no fetch, no cost) rather than subtracting zeros.
    if (vars.getOr(cloudkeys::coverage, 0.0) <= 0.0 && vars.getOr(cloudkeys::cirrusCoverage, 0.0) <= 0.0) {
        vars.publish(skykeys::shadowLossLut, TextureRef{});
        vars.publish(skykeys::shadowLossMieLut, TextureRef{});
        vars.publish(skykeys::shadowLossMoon, false);
        setup_.clear();  // the next table is built whole
        slicing_ = false;
        return;
    }
    prepare(vars);
    // The RGB model's block (in spectral mode prepare() uploads triple 0's): the loss is RGB.
    {
        AtmosphereBlock block = AtmosphereBlock::from(model_, q_.shBands);
        ubo_.update(&block, sizeof block);
        ubo_.bindBase(GL_UNIFORM_BUFFER, gl::binding::kAtmosphereUbo);
    }
    const int W = 2 * q_.skyViewW, H = q_.skyViewH;
    const GLenum fmt = q_.halfFloat ? GL_RGBA16F : GL_RGBA32F;
    auto makeTables = [&](gl::Texture2D& a, gl::Texture2D& b, gl::Framebuffer& fb) {
        for (gl::Texture2D* t : {&a, &b}) {
            *t = gl::Texture2D(W, H, fmt);
            t->setFilter(GL_LINEAR);
            t->setWrap(GL_CLAMP_TO_EDGE);
            // Azimuth wraps around (the seam at north interpolates across it).
            glTextureParameteri(t->id(), GL_TEXTURE_WRAP_S, GL_REPEAT);
        }
        fb = gl::Framebuffer::create();
        fb.attach(GL_COLOR_ATTACHMENT0, a);
        fb.attach(GL_COLOR_ATTACHMENT1, b);
        fb.checkComplete("CloudSkyShadow");
    };
    if (!loss_ || loss_.width() != W || loss_.height() != H || loss_.internalFormat() != fmt) {
        makeTables(loss_, lossMie_, fbo_);
        backLoss_ = {}, backLossMie_ = {}, backFbo_ = {};
        slicing_ = false;
        setup_.clear();
    }
    if (!prog_)
        prog_ = gl::ProgramBuilder("CloudSkyShadow")
                    .define("ATM_USE_TRANSMITTANCE")
                    .fullscreenVertex()
                    .fragment("generators/atmosphere.glsl", embedded::atmosphere_shaders("atmosphere.glsl"))
                    .fragment("generators/cloud_sky_shadow.glsl", embedded::clouds_shaders("cloud_sky_shadow.glsl"))
                    .build();
    auto unit = [](glm::dvec3 d, glm::dvec3 fallback) { return glm::length(d) > 1e-12 ? glm::normalize(d) : fallback; };
    const glm::dvec3 sun = unit(vars.getOr(keys::sunDirection, glm::dvec3(0, 0, 1)), {0, 0, 1});
    const glm::dvec3 moon = unit(vars.getOr(keys::moonDirection, glm::dvec3(0, 0, -1)), {0, 0, -1});
    // The shadowed light is the one the map was built for (CloudShadowMap: the Sun above -6 deg,
    // else the Moon).
    SkyShadowInputs in;
    in.moon = sun.z < std::sin(kShadowMoonBelowSunElevationRad);
    in.light = in.moon ? moon : sun;
    in.mapLight = unit(vars.get(cloudkeys::shadowLight), {0, 0, 1});
    in.shift = vars.getOr(cloudkeys::weatherOffset, glm::dvec2(0.0)) - vars.get(cloudkeys::shadowOffset);
    in.extentM = vars.get(cloudkeys::shadowExtent);
    in.bottomM = vars.getOr(cloudkeys::bottom, 2000.0);  // the Clouds element's defaults
    in.topM = std::max(vars.getOr(cloudkeys::top, 3000.0), in.bottomM + 1.0);
    in.observerHeightM = std::clamp(vars.getOr(keys::observerHeight, 0.0), 0.0, model_.topRadius - model_.bottomRadius);
    const unsigned map = vars.get(cloudkeys::shadowMap).id;
    const unsigned transmittance = vars.get(skykeys::transmittanceLut).id;
    // Rows [r0, r1) of the tables into `fb` with `inp` and the shadow map `mapId`.
    auto draw = [&](gl::Framebuffer& fb, const SkyShadowInputs& inp, unsigned mapId, int r0, int r1) {
        fb.bind();
        glViewport(0, 0, W, H);
        glDisable(GL_BLEND);
        const GLenum bufs[2] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1};
        glNamedFramebufferDrawBuffers(fb.id(), 2, bufs);
        glBindTextureUnit(gl::binding::kTransmittanceLut, transmittance);
        glBindTextureUnit(gl::binding::kCloudShadowMap, mapId);
        prog_.use();
        prog_.set("u_h", float(inp.observerHeightM));
        prog_.set("u_light", glm::vec3(inp.light));
        prog_.set("u_mapLight", glm::vec3(inp.mapLight));
        prog_.set("u_map", glm::vec4(float(inp.shift.x), float(inp.shift.y), float(1.0 / inp.extentM), float(inp.extentM)));
        prog_.set("u_layer", glm::vec2(float(inp.bottomM), float(inp.topM)));
        prog_.set("u_angular", float(inp.moon ? kMoonAngularRadius : model_.sunAngularRadius));
        prog_.set("u_steps", inp.steps);
        prog_.set("u_size", glm::ivec2(W, H));
        prog_.set("u_scale", float(kLutScale));
        const bool part = r0 > 0 || r1 < H;
        if (part) {
            glEnable(GL_SCISSOR_TEST);
            glScissor(0, r0, W, r1 - r0);
        }
        fullscreen();
        if (part) glDisable(GL_SCISSOR_TEST);
    };
    auto publish = [&](const SkyShadowInputs& inp) {
        in_ = inp;
        vars.publish(skykeys::shadowLossLut, loss_.ref());
        vars.publish(skykeys::shadowLossMieLut, lossMie_.ref());
        vars.publish(skykeys::shadowLossMoon, inp.moon);
    };
    // Everything the tables depend on but the lights, the map and its shift: when only those
    // moved (time running, the wind), the tables may be rebuilt over several frames. The map
    // itself: CloudShadowMap keeps the one it replaced whole for one more rebuild over as many
    // frames, so the map snapshot here stays intact until this rebuild completes.
    const std::vector<double> setup = {in.extentM, in.bottomM, in.topM, in.observerHeightM, double(in.steps), double(in.moon),
                                       double(transmittance), model_.sunAngularRadius, double(vars.version(skykeys::transmittanceLut.name()))};
    const int slices = vars.getOr(keys::interactive, false) ? vars.getOr(cloudkeys::shadowSlices, 8) : 1;
    if (slices <= 1 || setup != setup_) {
        slicing_ = false;
        setup_ = setup;
        draw(fbo_, in, map, 0, H);
        publish(in);
        return;
    }
    if (!slicing_) {
        if (!backLoss_) makeTables(backLoss_, backLossMie_, backFbo_);
        slicing_ = true;
        sliceRow_ = 0;
        sliceIn_ = in;
        sliceMap_ = map;
    }
    const int rows = (H + slices - 1) / slices;
    const int r1 = std::min(H, sliceRow_ + rows);
    draw(backFbo_, sliceIn_, sliceMap_, sliceRow_, r1);
    sliceRow_ = r1;
    ++slicesBuilt_;
    if (r1 < H) {
        runAgain();
        return;
    }
    slicing_ = false;
    std::swap(loss_, backLoss_);
    std::swap(lossMie_, backLossMie_);
    std::swap(fbo_, backFbo_);
    publish(sliceIn_);
    // Built for inputs that have moved on meanwhile (a new map, the light beyond the inputs'
    // tolerance): once more, even if nothing changes from now on.
    if (map != sliceMap_ || in.mapLight != sliceIn_.mapLight || glm::length(in.light - sliceIn_.light) > kLightTolerance ||
        glm::length(in.shift - sliceIn_.shift) > kSkyShadowOffsetTolerance)
        runAgain();
}

}  // namespace welkin::generators
