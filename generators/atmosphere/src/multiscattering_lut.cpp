// Multiple-scattering LUT generator (GPU pass multiscattering_lut.glsl; CPU twin
// cpu::multiScatteringLut).
#include <welkin/embedded/atmosphere_shaders.hpp>
#include <welkin/error.hpp>
#include <welkin/generators/sky_luts.hpp>
#include <welkin/gl/shader.hpp>

#include <epoxy/gl.h>

namespace welkin::generators {

MultiScatteringLut::MultiScatteringLut() : SkyGenerator("sky.multiscattering") {
    input(skykeys::transmittanceLuts);
    output(skykeys::multiScatteringLut);
    output(skykeys::multiScatteringLuts);
}

void MultiScatteringLut::releaseGl() {
    tex_ = {};
    more_.clear();
    prog_ = {};
    releaseCommon();
}

void MultiScatteringLut::doRun(SkyVars& vars, const Logger&) {
    prepare(vars);
    const skykeys::TextureList T = vars.get(skykeys::transmittanceLuts);
    const GLenum fmt = q_.halfFloat ? GL_RGBA16F : GL_RGBA32F;
    const int w = q_.multiScatteringMuS, n = q_.multiScatteringSize;
    if (!tex_ || tex_.width() != w || tex_.height() != n || tex_.internalFormat() != fmt) {
        tex_ = gl::Texture2D(w, n, fmt);
        tex_.setFilter(GL_LINEAR);
        tex_.setWrap(GL_CLAMP_TO_EDGE);
        more_.clear();
        prog_ = {};  // the image format is compiled in
    }
    if (!prog_)
        prog_ = gl::ProgramBuilder("MultiScatteringLut")
                    .define("ATM_USE_TRANSMITTANCE")
                    .define("MS_IMAGE_FORMAT", q_.halfFloat ? "rgba16f" : "rgba32f")
                    .compute("generators/atmosphere.glsl", embedded::atmosphere_shaders("atmosphere.glsl"))
                    .compute("generators/multiscattering_lut.glsl", embedded::atmosphere_shaders("multiscattering_lut.glsl"))
                    .build();
    const int K = triples();
    if (int(T->size()) != K) throw Error("MultiScatteringLut: " + std::to_string(T->size()) + " transmittance LUTs for " + std::to_string(K) + " triples");
    if (int(more_.size()) != K - 1 || (K > 1 && (more_[0].width() != w || more_[0].height() != n || more_[0].internalFormat() != fmt))) {
        more_.clear();
        for (int k = 1; k < K; ++k) {
            more_.emplace_back(w, n, fmt);
            more_.back().setFilter(GL_LINEAR);
            more_.back().setWrap(GL_CLAMP_TO_EDGE);
        }
    }
    auto list = std::make_shared<std::vector<TextureRef>>();
    for (int k = 0; k < K; ++k) {
        const gl::Texture2D& target = texture(k);
        useTriple(k);
        glBindTextureUnit(gl::binding::kTransmittanceLut, (*T)[size_t(k)].id);
        glBindImageTexture(gl::binding::kLutImage, target.id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, fmt);
        prog_.use();
        prog_.set("u_directions", q_.multiScatteringDirections);
        prog_.set("u_steps", q_.multiScatteringSteps);
        prog_.set("u_size", glm::ivec2(w, n));
        glDispatchCompute(GLuint((w + 7) / 8), GLuint((n + 7) / 8), 1);
        glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_SHADER_IMAGE_ACCESS_BARRIER_BIT | GL_TEXTURE_UPDATE_BARRIER_BIT);
        list->push_back(target.ref());
    }
    vars.publish(skykeys::multiScatteringLuts, skykeys::TextureList(list));
    vars.publish(skykeys::multiScatteringLut, tex_.ref());
}

}  // namespace welkin::generators
