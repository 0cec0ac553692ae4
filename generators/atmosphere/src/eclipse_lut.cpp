// The Moon's shadow on the air: EclipseSkyLut (GPU pass eclipse_lut.glsl; CPU twin
// cpu::eclipseRadiance in sky_model.cpp).
#include <welkin/astro/astro_keys.hpp>
#include <welkin/embedded/atmosphere_shaders.hpp>
#include <welkin/error.hpp>
#include <welkin/generators/sky_luts.hpp>
#include <welkin/gl/shader.hpp>
#include <welkin/keys.hpp>

#include <epoxy/gl.h>

#include <algorithm>
#include <cmath>

namespace welkin::generators {

EclipseSkyLut::EclipseSkyLut() : SkyGenerator("sky.eclipse_view") {
    input(skykeys::transmittanceLuts);
    input(skykeys::multiScatteringLuts);
    input(skykeys::shLuts);
    input(keys::observerHeight);
    input(keys::sunDirection);
    input(astro::keys::moonPosition, {.optional = true});
    input(astro::keys::sunDistance, {.optional = true});
    input(astro::keys::eclipses, {.optional = true});
    output(skykeys::eclipseViewLut);
    output(skykeys::eclipseViewMieLut);
}

void EclipseSkyLut::releaseGl() {
    smooth_ = {};
    mie_ = {};
    fbo_ = {};
    prog_ = {};
    active_ = published_ = false;
    releaseCommon();
}

bool EclipseSkyLut::shadowNear(const glm::dvec3& sunDir, double sunAngularRadius, const glm::dvec3& moonPos, double reachMeters) {
    const double dm = glm::length(moonPos);
    if (!(dm > astro::keys::kMoonRadiusMeters)) return false;
    const glm::dvec3 m = moonPos / dm, s = glm::normalize(sunDir);
    const double sep = 2.0 * std::asin(std::min(0.5 * glm::length(m - s), 1.0));
    const double ro = std::asin(astro::keys::kMoonRadiusMeters / dm);
    // From a point `reach` metres away the Moon moves by at most reach / dm (the Sun by ~1e-6 of
    // that): 1e-4 rad of margin.
    return sep < sunAngularRadius + ro + reachMeters / dm + 1e-4;
}

void EclipseSkyLut::doRun(SkyVars& vars, const Logger&) {
    prepare(vars);
    const double Ht = model_.topRadius - model_.bottomRadius;
    const double h = std::clamp(vars.getOr(keys::observerHeight, 0.0), 0.0, Ht);
    const glm::dvec3 sunDir = glm::normalize(vars.get(keys::sunDirection));
    const bool haveMoon = vars.has(astro::keys::moonPosition) && vars.getOr(astro::keys::eclipses, true);
    const glm::dvec3 moonPos = haveMoon ? vars.get(astro::keys::moonPosition) : glm::dvec3(0.0);
    // The farthest air a sky-view ray reaches: the horizontal ray to the top of the atmosphere
    // (rays below the horizon end on the ground, nearer), plus the multiple-scattering disk.
    const double R = model_.bottomRadius, r = R + h, reach = std::sqrt(std::max(model_.topRadius * model_.topRadius - r * r, 0.0)) +
                                                           kEclipseMsRadiusMeters;
    const bool want = haveMoon && !spectral_ && sunDir.z > kDarkBelowCosZenith &&
                      shadowNear(sunDir, model_.sunAngularRadius, moonPos, reach);
    if (!want) {
        if (active_ || !published_) {
            vars.publish(skykeys::eclipseViewLut, TextureRef{});
            vars.publish(skykeys::eclipseViewMieLut, TextureRef{});
        }
        active_ = false;
        published_ = true;
        return;
    }
    const int W = 2 * q_.skyViewW, H = q_.skyViewH;
    const GLenum fmt = q_.halfFloat ? GL_RGBA16F : GL_RGBA32F;
    if (!smooth_ || smooth_.width() != W || smooth_.height() != H || smooth_.internalFormat() != fmt) {
        for (gl::Texture2D* t : {&smooth_, &mie_}) {
            *t = gl::Texture2D(W, H, fmt);
            t->setFilter(GL_LINEAR);
            t->setWrap(GL_CLAMP_TO_EDGE);
            glTextureParameteri(t->id(), GL_TEXTURE_WRAP_S, GL_REPEAT);  // the circle of azimuth
        }
        fbo_ = gl::Framebuffer::create();
        fbo_.attach(GL_COLOR_ATTACHMENT0, smooth_);
        fbo_.attach(GL_COLOR_ATTACHMENT1, mie_);
        fbo_.checkComplete("EclipseSkyLut");
    }
    if (!prog_ || progBands_ != q_.shBands) {
        progBands_ = q_.shBands;
        prog_ = gl::ProgramBuilder(name())
                    .define("ATM_USE_TRANSMITTANCE")
                    .define("ATM_USE_MULTISCATTERING")
                    .define("ATM_MS_DIRECTIONAL")
                    .define("ATM_ECLIPSE")
                    .define("ATM_SH_BANDS", q_.shBands)
                    .fullscreenVertex()
                    .fragment("generators/atmosphere.glsl", embedded::atmosphere_shaders("atmosphere.glsl"))
                    .fragment("generators/eclipse_lut.glsl", embedded::atmosphere_shaders("eclipse_lut.glsl"))
                    .build();
    }
    const skykeys::TextureList T = vars.get(skykeys::transmittanceLuts), MS = vars.get(skykeys::multiScatteringLuts),
                               SH = vars.get(skykeys::shLuts);
    if (T->empty() || MS->empty() || SH->empty()) throw Error("EclipseSkyLut: no input LUTs");
    fbo_.bind();
    glViewport(0, 0, W, H);
    const GLenum bufs[2] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1};
    glNamedFramebufferDrawBuffers(fbo_.id(), 2, bufs);
    glBindTextureUnit(gl::binding::kTransmittanceLut, (*T)[0].id);
    glBindTextureUnit(gl::binding::kMultiScatteringLut, (*MS)[0].id);
    glBindTextureUnit(gl::binding::kShLut, (*SH)[0].id);
    const double sunDist = vars.getOr(astro::keys::sunDistance, 1.496e11);
    prog_.use();
    prog_.set("u_h", float(h));
    prog_.set("u_sunDir", glm::vec3(sunDir));
    prog_.set("u_steps", q_.skyViewSteps);
    prog_.set("u_size", glm::ivec2(W, H));
    prog_.set("u_scale", float(kLutScale));
    prog_.set("u_angular", float(model_.sunAngularRadius));
    prog_.set("u_eclMoonPos", glm::vec3(moonPos));
    prog_.set("u_eclMoonRadius", float(astro::keys::kMoonRadiusMeters));
    prog_.set("u_eclSunPos", glm::vec3(sunDir * sunDist));
    prog_.set("u_eclSunRadius", float(kSunRadiusMeters));
    prog_.set("u_eclMsRadius", float(kEclipseMsRadiusMeters));
    fullscreen();
    glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_FRAMEBUFFER_BARRIER_BIT);
    active_ = true;
    published_ = true;
    vars.publish(skykeys::eclipseViewLut, smooth_.ref());
    vars.publish(skykeys::eclipseViewMieLut, mie_.ref());
}

}  // namespace welkin::generators
