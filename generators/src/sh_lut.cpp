// Directional multiple-scattering LUT generator (GPU passes sh_lut.glsl; CPU twins
// cpu::groundIrradianceTexel and cpu::shTexel).
#include <welkin/embedded/generator_shaders.hpp>
#include <welkin/generators/sky_luts.hpp>
#include <welkin/gl/shader.hpp>

namespace welkin::generators {

ShLut::ShLut() : SkyGenerator("sky.ms_directional") {
    input(skykeys::transmittanceRev);
    input(skykeys::multiScatteringRev);
    output(skykeys::shLut);
    output(skykeys::shRev);
}

void ShLut::releaseGl() {
    tex_ = {};
    fbo_ = {};
    prog_ = {};
    ground_ = {};
    groundFbo_ = {};
    groundProg_ = {};
    releaseCommon();
}

void ShLut::doRun(SkyVars& vars, const Logger&) {
    prepare(vars);
    const GLenum fmt = q_.halfFloat ? GL_RGBA16F : GL_RGBA32F;
    const int w = q_.multiScatteringMuS, n = q_.multiScatteringSize;
    if (!tex_ || tex_.width() != w || tex_.height() != n || tex_.internalFormat() != fmt) {
        // Layers 0-5: SH coefficients; layer 6, row 0: the ground's sky irradiance (copied from
        // ground_ below; the other rows stay 0 and are never sampled with weight).
        tex_ = gl::Texture2DArray(w, n, 7, fmt);
        tex_.setFilter(GL_LINEAR);
        tex_.setWrap(GL_CLAMP_TO_EDGE);
        const float zero[4] = {0, 0, 0, 0};
        glClearTexImage(tex_.id(), 0, GL_RGBA, GL_FLOAT, zero);
        fbo_ = gl::Framebuffer::create();
        for (int k = 0; k < 6; ++k) fbo_.attach(GL_COLOR_ATTACHMENT0 + k, tex_, 0, k);
        fbo_.checkComplete("ShLut");
        ground_ = gl::Texture2D(w, 1, fmt);
        ground_.setFilter(GL_LINEAR);
        ground_.setWrap(GL_CLAMP_TO_EDGE);
        groundFbo_ = gl::Framebuffer::create();
        groundFbo_.attach(GL_COLOR_ATTACHMENT0, ground_);
        groundFbo_.checkComplete("ShLut ground");
    }
    auto build = [](const char* label, bool groundPass) {
        auto b = gl::ProgramBuilder(label).define("ATM_USE_TRANSMITTANCE").define("ATM_USE_MULTISCATTERING");
        if (groundPass) b.define("SH_GROUND_PASS");
        return b.fullscreenVertex()
            .fragment("generators/atmosphere.glsl", embedded::generator_shaders("atmosphere.glsl"))
            .fragment("generators/sh_lut.glsl", embedded::generator_shaders("sh_lut.glsl"))
            .build();
    };
    if (!prog_) prog_ = build("ShLut", false);
    if (!groundProg_) groundProg_ = build("ShLut ground", true);
    glBindTextureUnit(4, vars.get(skykeys::transmittanceLut).id);
    glBindTextureUnit(5, vars.get(skykeys::multiScatteringLut).id);
    // 1. The sky's irradiance on the ground over mu_s (what lights the ground besides the light).
    groundFbo_.bind();
    glViewport(0, 0, w, 1);
    groundProg_.use();
    groundProg_.set("u_directions", q_.shDirections);
    groundProg_.set("u_steps", q_.multiScatteringSteps);
    groundProg_.set("u_size", glm::ivec2(w, n));
    fullscreen();
    // 2. The SH layers, with the ground lit by the light and the sky.
    glBindTextureUnit(9, ground_.id());
    fbo_.bind();
    const GLenum bufs[6] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1, GL_COLOR_ATTACHMENT2,
                            GL_COLOR_ATTACHMENT3, GL_COLOR_ATTACHMENT4, GL_COLOR_ATTACHMENT5};
    glNamedFramebufferDrawBuffers(fbo_.id(), 6, bufs);
    glViewport(0, 0, w, n);
    prog_.use();
    prog_.set("u_directions", q_.shDirections);
    prog_.set("u_steps", q_.multiScatteringSteps);
    prog_.set("u_size", glm::ivec2(w, n));
    fullscreen();
    glCopyImageSubData(ground_.id(), GL_TEXTURE_2D, 0, 0, 0, 0, tex_.id(), GL_TEXTURE_2D_ARRAY, 0, 0, 0, 6, w, 1, 1);
    vars.set(skykeys::shLut, tex_.ref());
    vars.set(skykeys::shRev, ++rev_);
}

}  // namespace welkin::generators
