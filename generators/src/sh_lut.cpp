// Directional multiple-scattering LUT generator (GPU pass sh_lut.glsl; CPU twin cpu::shTexel).
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
    releaseCommon();
}

void ShLut::doRun(SkyVars& vars, const Logger&) {
    prepare(vars);
    const GLenum fmt = q_.halfFloat ? GL_RGBA16F : GL_RGBA32F;
    const int w = q_.multiScatteringMuS, n = q_.multiScatteringSize;
    if (!tex_ || tex_.width() != w || tex_.height() != n || tex_.internalFormat() != fmt) {
        tex_ = gl::Texture2DArray(w, n, 6, fmt);
        tex_.setFilter(GL_LINEAR);
        tex_.setWrap(GL_CLAMP_TO_EDGE);
        fbo_ = gl::Framebuffer::create();
        for (int k = 0; k < 6; ++k) fbo_.attach(GL_COLOR_ATTACHMENT0 + k, tex_, 0, k);
        fbo_.checkComplete("ShLut");
    }
    if (!prog_)
        prog_ = gl::ProgramBuilder("ShLut")
                    .define("ATM_USE_TRANSMITTANCE")
                    .define("ATM_USE_MULTISCATTERING")
                    .fullscreenVertex()
                    .fragment("generators/atmosphere.glsl", embedded::generator_shaders("atmosphere.glsl"))
                    .fragment("generators/sh_lut.glsl", embedded::generator_shaders("sh_lut.glsl"))
                    .build();
    fbo_.bind();
    const GLenum bufs[6] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1, GL_COLOR_ATTACHMENT2,
                            GL_COLOR_ATTACHMENT3, GL_COLOR_ATTACHMENT4, GL_COLOR_ATTACHMENT5};
    glNamedFramebufferDrawBuffers(fbo_.id(), 6, bufs);
    glViewport(0, 0, w, n);
    glBindTextureUnit(4, vars.get(skykeys::transmittanceLut).id);
    glBindTextureUnit(5, vars.get(skykeys::multiScatteringLut).id);
    prog_.use();
    prog_.set("u_directions", q_.shDirections);
    prog_.set("u_steps", q_.multiScatteringSteps);
    prog_.set("u_size", glm::ivec2(w, n));
    fullscreen();
    vars.set(skykeys::shLut, tex_.ref());
    vars.set(skykeys::shRev, ++rev_);
}

}  // namespace welkin::generators
