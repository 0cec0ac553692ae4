// Multiple-scattering LUT generator (GPU pass multiscattering_lut.glsl; CPU twin
// cpu::multiScatteringLut).
#include <welkin/embedded/generator_shaders.hpp>
#include <welkin/generators/sky_luts.hpp>
#include <welkin/gl/shader.hpp>

namespace welkin::generators {

MultiScatteringLut::MultiScatteringLut() : SkyGenerator("sky.multiscattering") {
    input(skykeys::transmittanceRev);
    output(skykeys::multiScatteringLut);
    output(skykeys::multiScatteringRev);
}

void MultiScatteringLut::releaseGl() {
    tex_ = {};
    fbo_ = {};
    prog_ = {};
    releaseCommon();
}

void MultiScatteringLut::doRun(SkyVars& vars, const Logger&) {
    prepare(vars);
    const TextureRef T = vars.get(skykeys::transmittanceLut);
    const GLenum fmt = q_.halfFloat ? GL_RGBA16F : GL_RGBA32F;
    const int w = q_.multiScatteringMuS, n = q_.multiScatteringSize;
    if (!tex_ || tex_.width() != w || tex_.height() != n || tex_.internalFormat() != fmt) {
        tex_ = gl::Texture2D(w, n, fmt);
        tex_.setFilter(GL_LINEAR);
        tex_.setWrap(GL_CLAMP_TO_EDGE);
        fbo_ = gl::Framebuffer::create();
        fbo_.attach(GL_COLOR_ATTACHMENT0, tex_);
        fbo_.checkComplete("MultiScatteringLut");
    }
    if (!prog_)
        prog_ = gl::ProgramBuilder("MultiScatteringLut")
                    .define("ATM_USE_TRANSMITTANCE")
                    .fullscreenVertex()
                    .fragment("generators/atmosphere.glsl", embedded::generator_shaders("atmosphere.glsl"))
                    .fragment("generators/multiscattering_lut.glsl", embedded::generator_shaders("multiscattering_lut.glsl"))
                    .build();
    fbo_.bind();
    glViewport(0, 0, w, n);
    glBindTextureUnit(4, T.id);
    prog_.use();
    prog_.set("u_directions", q_.multiScatteringDirections);
    prog_.set("u_steps", q_.multiScatteringSteps);
    prog_.set("u_size", glm::ivec2(w, n));
    fullscreen();
    vars.set(skykeys::multiScatteringLut, tex_.ref());
    vars.set(skykeys::multiScatteringRev, ++rev_);
}

}  // namespace welkin::generators
