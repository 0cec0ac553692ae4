// Sky-view LUT generator, one instance per light (GPU pass skyview_lut.glsl; CPU twin
// cpu::skyViewTexel).
#include <welkin/embedded/generator_shaders.hpp>
#include <welkin/error.hpp>
#include <welkin/generators/sky_luts.hpp>
#include <welkin/gl/shader.hpp>
#include <welkin/keys.hpp>

#include <epoxy/gl.h>

#include <algorithm>

namespace welkin::generators {

SkyViewLut::SkyViewLut(Light light) : SkyGenerator(light == Light::Sun ? "sky.sun_view" : "sky.moon_view"), light_(light) {
    input(skykeys::transmittanceLuts);
    input(skykeys::multiScatteringLuts);
    input(skykeys::shLuts);
    input(keys::observerHeight);
    if (light == Light::Sun) {
        input(keys::sunDirection);
        output(skykeys::sunViewLut);
        output(skykeys::sunViewMieLut);
        output(skykeys::sunViewTotalLut);
        output(skykeys::viewTransmittanceLut);
    } else {
        input(keys::moonDirection);
        input(lightkeys::moonIlluminance);
        output(skykeys::moonViewLut);
        output(skykeys::moonViewMieLut);
        output(skykeys::moonViewTotalLut);
    }
}

void SkyViewLut::releaseGl() {
    smooth_ = {};
    mie_ = {};
    total_ = {};
    viewT_ = {};
    viewTProg_ = {};
    smoothK_ = {};
    mieK_ = {};
    totalK_ = {};
    fbo_ = {};
    fboK_ = {};
    prog_ = {};
    releaseCommon();
}

void SkyViewLut::doRun(SkyVars& vars, const Logger&) {
    prepare(vars);
    // Even heights: the two halves (sky, ground) then have the same rows and the pixel shaders'
    // mapping stays inside its half without a clamp.
    if (q_.skyViewH % 2 != 0 || q_.skyViewH < 4)
        throw Error("SkyViewLut: height " + std::to_string(q_.skyViewH) + " texels must be even and >= 4");
    const GLenum fmt = q_.halfFloat ? GL_RGBA16F : GL_RGBA32F;
    if (!smooth_ || smooth_.width() != q_.skyViewW || smooth_.height() != q_.skyViewH || smooth_.internalFormat() != fmt) {
        smooth_ = gl::Texture2D(q_.skyViewW, q_.skyViewH, fmt);
        mie_ = gl::Texture2D(q_.skyViewW, q_.skyViewH, fmt);
        total_ = gl::Texture2D(q_.skyViewW, q_.skyViewH, fmt);
        for (gl::Texture2D* t : {&smooth_, &mie_, &total_}) {
            t->setFilter(GL_LINEAR);
            t->setWrap(GL_CLAMP_TO_EDGE);
        }
        fbo_ = gl::Framebuffer::create();
        fbo_.attach(GL_COLOR_ATTACHMENT0, smooth_);
        fbo_.attach(GL_COLOR_ATTACHMENT1, mie_);
        fbo_.attach(GL_COLOR_ATTACHMENT2, total_);
        fbo_.checkComplete("SkyViewLut");
    }
    if (!prog_ || progBands_ != q_.shBands) {
        progBands_ = q_.shBands;
        prog_ = gl::ProgramBuilder(name())
                    .define("ATM_USE_TRANSMITTANCE")
                    .define("ATM_USE_MULTISCATTERING")
                    .define("ATM_MS_DIRECTIONAL")
                    .define("ATM_SH_BANDS", q_.shBands)
                    .fullscreenVertex()
                    .fragment("generators/atmosphere.glsl", embedded::generator_shaders("atmosphere.glsl"))
                    .fragment("generators/skyview_lut.glsl", embedded::generator_shaders("skyview_lut.glsl"))
                    .build();
    }
    const double Ht = model_.topRadius - model_.bottomRadius;
    h_ = std::clamp(vars.getOr(keys::observerHeight, 0.0), 0.0, Ht);
    const Key<glm::dvec3>& dirKey = light_ == Light::Sun ? keys::sunDirection : keys::moonDirection;
    glm::dvec3 dir = vars.getOr(dirKey, glm::dvec3(0, 0, 1));
    muS_ = std::clamp(dir.z / std::max(glm::length(dir), 1e-12), -1.0, 1.0);
    // Spectral mode: each triple's pass goes to the scratch textures, then is added to the RGB
    // ones through the triple's matrix (combine()).
    if (spectral_ && (!smoothK_ || smoothK_.width() != smooth_.width() || smoothK_.height() != smooth_.height() ||
                      smoothK_.internalFormat() != fmt)) {
        smoothK_ = gl::Texture2D(q_.skyViewW, q_.skyViewH, fmt);
        mieK_ = gl::Texture2D(q_.skyViewW, q_.skyViewH, fmt);
        totalK_ = gl::Texture2D(q_.skyViewW, q_.skyViewH, fmt);
        fboK_ = gl::Framebuffer::create();
        fboK_.attach(GL_COLOR_ATTACHMENT0, smoothK_);
        fboK_.attach(GL_COLOR_ATTACHMENT1, mieK_);
        fboK_.attach(GL_COLOR_ATTACHMENT2, totalK_);
        fboK_.checkComplete("SkyViewLut (triple)");
    }
    const GLenum bufs[3] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1, GL_COLOR_ATTACHMENT2};
    // The Moon's LUT is skipped (left black) while the Moon gives no light or is far below the
    // horizon (< -20 deg: its scattered light is then below the night sky's airglow by orders of
    // magnitude).
    bool dark = light_ == Light::Moon &&
                (glm::length(vars.getOr(lightkeys::moonIlluminance, glm::dvec3(0.0))) <= 0.0 || muS_ < -0.342);
    if (dark) {
        const float zero[4] = {0, 0, 0, 1};
        glClearNamedFramebufferfv(fbo_.id(), GL_COLOR, 0, zero);
        glClearNamedFramebufferfv(fbo_.id(), GL_COLOR, 1, zero);
        glClearNamedFramebufferfv(fbo_.id(), GL_COLOR, 2, zero);
    } else {
        const skykeys::TextureList T = vars.get(skykeys::transmittanceLuts), MS = vars.get(skykeys::multiScatteringLuts),
                                   SH = vars.get(skykeys::shLuts);
        const int K = triples();
        if (int(T->size()) != K || int(MS->size()) != K || int(SH->size()) != K)
            throw Error("SkyViewLut: input LUTs for " + std::to_string(T->size()) + " triples, expected " + std::to_string(K));
        for (int k = 0; k < K; ++k) {
            const gl::Framebuffer& fb = spectral_ ? fboK_ : fbo_;
            useTriple(k);
            fb.bind();
            glViewport(0, 0, q_.skyViewW, q_.skyViewH);
            glNamedFramebufferDrawBuffers(fb.id(), 3, bufs);
            glBindTextureUnit(gl::binding::kTransmittanceLut, (*T)[size_t(k)].id);
            glBindTextureUnit(gl::binding::kMultiScatteringLut, (*MS)[size_t(k)].id);
            glBindTextureUnit(gl::binding::kShLut, (*SH)[size_t(k)].id);
            prog_.use();
            prog_.set("u_h", float(h_));
            prog_.set("u_muS", float(muS_));
            prog_.set("u_steps", q_.skyViewSteps);
            prog_.set("u_size", glm::ivec2(q_.skyViewW, q_.skyViewH));
            prog_.set("u_scale", float(kLutScale));
            prog_.set("u_angular", float(light_ == Light::Sun ? model_.sunAngularRadius : 0.0045));
            fullscreen();
            if (spectral_) {
                combine(smoothK_, smooth_, k);
                combine(mieK_, mie_, k);
                combine(totalK_, total_, k);
            }
        }
    }
    if (light_ == Light::Sun) {
        // The view-transmittance row (view_transmittance.glsl), from the RGB (or, in spectral
        // mode, solar-weighted combined) transmittance LUT; the geometry is every triple's.
        const int nT = 4 * q_.skyViewH;
        if (!viewT_ || viewT_.width() != nT) {
            viewT_ = gl::Texture1D(nT, GL_RGBA32F);
            viewT_.setFilter(GL_LINEAR);
            viewT_.setWrap(GL_CLAMP_TO_EDGE);
        }
        if (!viewTProg_)
            viewTProg_ = gl::ProgramBuilder("SkyViewLut transmittance row")
                             .define("ATM_USE_TRANSMITTANCE")
                             .compute("generators/atmosphere.glsl", embedded::generator_shaders("atmosphere.glsl"))
                             .compute("generators/view_transmittance.glsl", embedded::generator_shaders("view_transmittance.glsl"))
                             .build();
        if (spectral_) useTriple(0);
        glBindTextureUnit(gl::binding::kTransmittanceLut, vars.get(skykeys::transmittanceLut).id);
        glBindImageTexture(gl::binding::kLutImage, viewT_.id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA32F);
        viewTProg_.use();
        viewTProg_.set("u_h", float(h_));
        viewTProg_.set("u_size", nT);
        viewTProg_.set("u_skyViewH", q_.skyViewH);
        glDispatchCompute(GLuint((nT + 63) / 64), 1, 1);
        glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
        vars.publish(skykeys::viewTransmittanceLut, viewT_.ref());
        vars.publish(skykeys::sunViewLut, smooth_.ref());
        vars.publish(skykeys::sunViewMieLut, mie_.ref());
        vars.publish(skykeys::sunViewTotalLut, total_.ref());
    } else {
        vars.publish(skykeys::moonViewLut, smooth_.ref());
        vars.publish(skykeys::moonViewMieLut, mie_.ref());
        vars.publish(skykeys::moonViewTotalLut, total_.ref());
    }
}

}  // namespace welkin::generators
