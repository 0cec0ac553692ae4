// Transmittance LUT generator (GPU pass transmittance_lut.glsl; CPU twin cpu::transmittanceLut).
#include <welkin/embedded/generator_shaders.hpp>
#include <welkin/generators/atmosphere.hpp>
#include <welkin/generators/sky_luts.hpp>
#include <welkin/gl/shader.hpp>

namespace welkin::generators {

TransmittanceLut::TransmittanceLut() : SkyGenerator("sky.transmittance") {
    output(skykeys::transmittanceLut);
    output(skykeys::transmittanceRev);
}

void TransmittanceLut::releaseGl() {
    tex_ = {};
    fbo_ = {};
    prog_ = {};
    releaseCommon();
}

void TransmittanceLut::doRun(SkyVars& vars, const Logger&) {
    prepare(vars);
    const GLenum fmt = q_.halfFloat ? GL_RGBA16F : GL_RGBA32F;
    if (!tex_ || tex_.width() != q_.transmittanceW || tex_.height() != q_.transmittanceH || tex_.internalFormat() != fmt) {
        tex_ = gl::Texture2D(q_.transmittanceW, q_.transmittanceH, fmt);
        tex_.setFilter(GL_LINEAR);
        tex_.setWrap(GL_CLAMP_TO_EDGE);
        fbo_ = gl::Framebuffer::create();
        fbo_.attach(GL_COLOR_ATTACHMENT0, tex_);
        fbo_.checkComplete("TransmittanceLut");
    }
    if (!prog_)
        prog_ = gl::ProgramBuilder("TransmittanceLut")
                    .fullscreenVertex()
                    .fragment("generators/atmosphere.glsl", embedded::generator_shaders("atmosphere.glsl"))
                    .fragment("generators/transmittance_lut.glsl", embedded::generator_shaders("transmittance_lut.glsl"))
                    .build();
    fbo_.bind();
    glViewport(0, 0, tex_.width(), tex_.height());
    prog_.use();
    prog_.set("u_steps", q_.transmittanceSteps);
    prog_.set("u_size", glm::ivec2(tex_.width(), tex_.height()));
    fullscreen();
    vars.set(skykeys::transmittanceLut, tex_.ref());
    vars.set(skykeys::transmittanceRev, ++rev_);
}

}  // namespace welkin::generators
