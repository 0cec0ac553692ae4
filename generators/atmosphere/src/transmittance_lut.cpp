// Transmittance LUT generator (GPU pass transmittance_lut.glsl; CPU twin cpu::transmittanceLut).
#include <welkin/embedded/atmosphere_shaders.hpp>
#include <welkin/generators/atmosphere.hpp>
#include <welkin/generators/sky_luts.hpp>
#include <welkin/gl/shader.hpp>

#include <epoxy/gl.h>

namespace welkin::generators {

TransmittanceLut::TransmittanceLut() : SkyGenerator("sky.transmittance") {
    output(skykeys::transmittanceLut);
    output(skykeys::transmittanceLuts);
}

void TransmittanceLut::releaseGl() {
    tex_ = {};
    triples_.clear();
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
                    .fragment("generators/atmosphere.glsl", embedded::atmosphere_shaders("atmosphere.glsl"))
                    .fragment("generators/transmittance_lut.glsl", embedded::atmosphere_shaders("transmittance_lut.glsl"))
                    .build();
    // Spectral mode: one LUT per wavelength triple (read by the passes after this one), and
    // their solar-weighted combination in tex_ (read by the Sky, the irradiance and the lights).
    const int K = triples();
    if (spectral_ && (int(triples_.size()) != K || triples_[0].width() != tex_.width() || triples_[0].height() != tex_.height() ||
                      triples_[0].internalFormat() != fmt)) {
        triples_.clear();
        for (int k = 0; k < K; ++k) {
            triples_.emplace_back(tex_.width(), tex_.height(), fmt);
            triples_.back().setFilter(GL_LINEAR);
            triples_.back().setWrap(GL_CLAMP_TO_EDGE);
        }
    }
    if (!spectral_) triples_.clear();
    auto list = std::make_shared<std::vector<TextureRef>>();
    for (int k = 0; k < K; ++k) {
        const gl::Texture2D& target = spectral_ ? triples_[size_t(k)] : tex_;
        useTriple(k);
        fbo_.attach(GL_COLOR_ATTACHMENT0, target);
        fbo_.bind();
        glViewport(0, 0, tex_.width(), tex_.height());
        prog_.use();
        prog_.set("u_steps", q_.transmittanceSteps);
        prog_.set("u_size", glm::ivec2(tex_.width(), tex_.height()));
        fullscreen();
        if (spectral_) combine(target, tex_, k);
        list->push_back(target.ref());
    }
    vars.publish(skykeys::transmittanceLuts, skykeys::TextureList(list));
    vars.publish(skykeys::transmittanceLut, tex_.ref());
}

}  // namespace welkin::generators
