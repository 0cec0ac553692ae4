// Directional multiple-scattering LUT generator (GPU pass sh_lut.glsl; CPU twin cpu::shTexel).
#include <welkin/embedded/generator_shaders.hpp>
#include <welkin/error.hpp>
#include <welkin/generators/sky_luts.hpp>
#include <welkin/gl/shader.hpp>

namespace welkin::generators {

ShLut::ShLut() : SkyGenerator("sky.ms_directional") {
    input(skykeys::transmittanceRev);
    input(skykeys::multiScatteringRev);
    output(skykeys::shLut);
    output(skykeys::shRev);
    output(skykeys::shLuts);
}

void ShLut::releaseGl() {
    tex_ = {};
    more_.clear();
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
    const skykeys::TextureList T = vars.get(skykeys::transmittanceLuts), MS = vars.get(skykeys::multiScatteringLuts);
    const int K = triples();
    if (int(T->size()) != K || int(MS->size()) != K)
        throw Error("ShLut: " + std::to_string(T->size()) + "/" + std::to_string(MS->size()) + " input LUTs for " + std::to_string(K) + " triples");
    if (int(more_.size()) != K - 1 || (K > 1 && (more_[0].width() != w || more_[0].height() != n || more_[0].internalFormat() != fmt))) {
        more_.clear();
        for (int k = 1; k < K; ++k) {
            more_.emplace_back(w, n, 6, fmt);
            more_.back().setFilter(GL_LINEAR);
            more_.back().setWrap(GL_CLAMP_TO_EDGE);
        }
    }
    const GLenum bufs[6] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1, GL_COLOR_ATTACHMENT2,
                            GL_COLOR_ATTACHMENT3, GL_COLOR_ATTACHMENT4, GL_COLOR_ATTACHMENT5};
    auto list = std::make_shared<std::vector<TextureRef>>();
    for (int k = 0; k < K; ++k) {
        const gl::Texture2DArray& target = texture(k);
        useTriple(k);
        for (int l = 0; l < 6; ++l) fbo_.attach(GL_COLOR_ATTACHMENT0 + l, target, 0, l);
        fbo_.bind();
        glNamedFramebufferDrawBuffers(fbo_.id(), 6, bufs);
        glViewport(0, 0, w, n);
        glBindTextureUnit(4, (*T)[size_t(k)].id);
        glBindTextureUnit(5, (*MS)[size_t(k)].id);
        prog_.use();
        prog_.set("u_directions", q_.shDirections);
        prog_.set("u_steps", q_.multiScatteringSteps);
        prog_.set("u_size", glm::ivec2(w, n));
        fullscreen();
        list->push_back(target.ref());
    }
    vars.set(skykeys::shLuts, skykeys::TextureList(list));
    vars.set(skykeys::shLut, tex_.ref());
    vars.set(skykeys::shRev, ++rev_);
}

}  // namespace welkin::generators
