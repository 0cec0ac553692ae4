// Directional multiple-scattering LUT generator (GPU passes sh_lut.glsl; CPU twins
// cpu::groundIrradianceTexel and cpu::shTexel). In spectral mode, one layered texture per
// wavelength triple.
#include <welkin/embedded/atmosphere_shaders.hpp>
#include <welkin/error.hpp>
#include <welkin/generators/sky_luts.hpp>
#include <welkin/gl/shader.hpp>

#include <epoxy/gl.h>

#include <algorithm>

namespace welkin::generators {

ShLut::ShLut() : SkyGenerator("sky.ms_directional") {
    input(skykeys::transmittanceLuts);
    input(skykeys::multiScatteringLuts);
    output(skykeys::shLut);
    output(skykeys::shLuts);
}

void ShLut::releaseGl() {
    first_.clear();
    iter_.clear();
    prog_ = {};
    iterProg_ = {};
    iterGroundProg_ = {};
    ground_ = {};
    groundFbo_ = {};
    groundProg_ = {};
    releaseCommon();
}

const gl::Texture2DArray& ShLut::texture(int k) const {
    const auto& v = iter_.empty() ? first_ : iter_;
    return v.at(size_t(k));
}

void ShLut::doRun(SkyVars& vars, const Logger&) {
    prepare(vars);
    const GLenum fmt = q_.halfFloat ? GL_RGBA16F : GL_RGBA32F;
    const int w = q_.multiScatteringMuS, n = q_.multiScatteringSize;
    const int K = triples();
    if (q_.shBands < cpu::kShMinBands || q_.shBands > cpu::kShMaxBands)
        throw Error("ShLut: SkyQuality::shBands " + std::to_string(q_.shBands) + " not in [" + std::to_string(cpu::kShMinBands) +
                    ", " + std::to_string(cpu::kShMaxBands) + "]");
    const int nc = cpu::shCoefficients(q_.shBands);
    // Layers 0 .. nc - 1: SH coefficients; layer nc, row 0: the ground's sky irradiance (copied
    // from ground_ below; the other rows stay 0, never sampled with weight).
    auto makeLayered = [&] {
        gl::Texture2DArray t(w, n, nc + 1, fmt);
        t.setFilter(GL_LINEAR);
        t.setWrap(GL_CLAMP_TO_EDGE);
        const float zero[4] = {0, 0, 0, 0};
        glClearTexImage(t.id(), 0, GL_RGBA, GL_FLOAT, zero);
        return t;
    };
    const bool resized = first_.empty() || first_[0].width() != w || first_[0].height() != n || first_[0].internalFormat() != fmt ||
                         first_[0].depth() != nc + 1;
    if (resized) {
        first_.clear();
        iter_.clear();
        ground_ = gl::Texture2D(w, 1, fmt);
        ground_.setFilter(GL_LINEAR);
        ground_.setWrap(GL_CLAMP_TO_EDGE);
        groundFbo_ = gl::Framebuffer::create();
        groundFbo_.attach(GL_COLOR_ATTACHMENT0, ground_);
        groundFbo_.checkComplete("ShLut ground");
        prog_ = {};  // the image format and the SH bands are compiled in
        iterProg_ = {};
        groundProg_ = {};
        iterGroundProg_ = {};
    }
    while (int(first_.size()) < K) first_.push_back(makeLayered());
    first_.resize(size_t(K));
    const int iterations = q_.shIterations > 0 ? 1 : 0;
    if (iterations == 0) iter_.clear();
    while (iterations > 0 && int(iter_.size()) < K) iter_.push_back(makeLayered());
    if (iterations > 0) iter_.resize(size_t(K));
    if (iterations > 0 && !iterGroundProg_)
        iterGroundProg_ = gl::ProgramBuilder("ShLut iteration ground")
                              .define("ATM_USE_TRANSMITTANCE")
                              .define("ATM_USE_MULTISCATTERING")
                              .define("ATM_MS_DIRECTIONAL")
                              .define("SH_ITERATION")
                              .define("ATM_SH_BANDS", q_.shBands)
                              .define("SH_GROUND_PASS")
                              .fullscreenVertex()
                              .fragment("generators/atmosphere.glsl", embedded::atmosphere_shaders("atmosphere.glsl"))
                              .fragment("generators/sh_lut.glsl", embedded::atmosphere_shaders("sh_lut.glsl"))
                              .build();
    if (iterations > 0 && !iterProg_)
        iterProg_ = gl::ProgramBuilder("ShLut iteration")
                        .define("ATM_USE_TRANSMITTANCE")
                        .define("ATM_USE_MULTISCATTERING")
                        .define("ATM_MS_DIRECTIONAL")
                        .define("SH_ITERATION")
                        .define("ATM_SH_BANDS", q_.shBands)
                        .define("SH_IMAGE_FORMAT", q_.halfFloat ? "rgba16f" : "rgba32f")
                        .compute("generators/atmosphere.glsl", embedded::atmosphere_shaders("atmosphere.glsl"))
                        .compute("generators/sh_lut.glsl", embedded::atmosphere_shaders("sh_lut.glsl"))
                        .build();
    if (!prog_)
        prog_ = gl::ProgramBuilder("ShLut")
                    .define("ATM_USE_TRANSMITTANCE")
                    .define("ATM_USE_MULTISCATTERING")
                    .define("ATM_SH_BANDS", q_.shBands)
                    .define("SH_IMAGE_FORMAT", q_.halfFloat ? "rgba16f" : "rgba32f")
                    .compute("generators/atmosphere.glsl", embedded::atmosphere_shaders("atmosphere.glsl"))
                    .compute("generators/sh_lut.glsl", embedded::atmosphere_shaders("sh_lut.glsl"))
                    .build();
    if (!groundProg_)
        groundProg_ = gl::ProgramBuilder("ShLut ground")
                          .define("ATM_USE_TRANSMITTANCE")
                          .define("ATM_USE_MULTISCATTERING")
                          .define("SH_GROUND_PASS")
                          .define("ATM_SH_BANDS", q_.shBands)
                          .fullscreenVertex()
                          .fragment("generators/atmosphere.glsl", embedded::atmosphere_shaders("atmosphere.glsl"))
                          .fragment("generators/sh_lut.glsl", embedded::atmosphere_shaders("sh_lut.glsl"))
                          .build();
    const skykeys::TextureList T = vars.get(skykeys::transmittanceLuts), MS = vars.get(skykeys::multiScatteringLuts);
    if (int(T->size()) != K || int(MS->size()) != K)
        throw Error("ShLut: " + std::to_string(T->size()) + "/" + std::to_string(MS->size()) + " input LUTs for " + std::to_string(K) + " triples");
    auto list = std::make_shared<std::vector<TextureRef>>();
    for (int k = 0; k < K; ++k) {
        useTriple(k);
        glBindTextureUnit(gl::binding::kTransmittanceLut, (*T)[size_t(k)].id);
        glBindTextureUnit(gl::binding::kMultiScatteringLut, (*MS)[size_t(k)].id);
        // 1. The sky's irradiance on the ground over mu_s (what lights the ground besides the light).
        groundFbo_.bind();
        glViewport(0, 0, w, 1);
        groundProg_.use();
        groundProg_.set("u_directions", q_.shDirections);
        groundProg_.set("u_steps", q_.multiScatteringSteps);
        groundProg_.set("u_size", glm::ivec2(w, n));
        fullscreen();
        // 2. The SH layers, with the ground lit by the light and the sky.
        const gl::Texture2DArray& first = first_[size_t(k)];
        glBindTextureUnit(gl::binding::kShGroundLut, ground_.id());
        glBindImageTexture(gl::binding::kLutImage, first.id(), 0, GL_TRUE, 0, GL_WRITE_ONLY, fmt);
        prog_.use();
        prog_.set("u_directions", q_.shDirections);
        prog_.set("u_steps", q_.multiScatteringSteps);
        prog_.set("u_size", glm::ivec2(w, n));
        glDispatchCompute((w + 7) / 8, (n + 7) / 8, 1);
        glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_SHADER_IMAGE_ACCESS_BARRIER_BIT | GL_TEXTURE_UPDATE_BARRIER_BIT);
        glCopyImageSubData(ground_.id(), GL_TEXTURE_2D, 0, 0, 0, 0, first.id(), GL_TEXTURE_2D_ARRAY, 0, 0, 0,
                           nc, w, 1, 1);
        if (iterations > 0) {
            // 3. Second pass: every gathered ray marched through the first pass's field. The
            // directions are split over several dispatches (draws) of at most kMaxSamples samples
            // per texel, each adding to the previous: one invocation marching 128 x 16 samples
            // through the l <= 6 field came out wrong on Mesa llvmpipe 22.3 (texels 10-170 % off
            // the CPU twin where the Sun is up; 128 x 12 too, 96 x 12 and 64 x 16 right), as if
            // a loop-iteration limit per invocation were reached.
            constexpr int kMaxSamples = 1024;
            const int D = q_.shIterationDirections, chunk = std::max(1, kMaxSamples / std::max(q_.shIterationSteps, 1));
            const gl::Texture2DArray& it = iter_[size_t(k)];
            glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_TEXTURE_UPDATE_BARRIER_BIT);
            glBindTextureUnit(gl::binding::kShLut, first.id());
            glBindImageTexture(gl::binding::kLutImage, it.id(), 0, GL_TRUE, 0, GL_READ_WRITE, fmt);
            iterProg_.use();
            iterProg_.set("u_directions", D);
            iterProg_.set("u_steps", q_.shIterationSteps);
            iterProg_.set("u_size", glm::ivec2(w, n));
            for (int begin = 0; begin < D; begin += chunk) {
                iterProg_.set("u_directionRange", glm::ivec2(begin, std::min(begin + chunk, D)));
                glDispatchCompute((w + 7) / 8, (n + 7) / 8, 1);
                glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_SHADER_IMAGE_ACCESS_BARRIER_BIT | GL_TEXTURE_UPDATE_BARRIER_BIT);
            }
            // The ground's sky irradiance again, from the first pass's field (ground_ is free
            // again: its first-pass values are in the first pass's last layer); the chunks are
            // added by blending.
            glBindTextureUnit(gl::binding::kShGroundLut, 0);
            groundFbo_.bind();
            glViewport(0, 0, w, 1);
            iterGroundProg_.use();
            iterGroundProg_.set("u_directions", D);
            iterGroundProg_.set("u_steps", q_.shIterationSteps);
            iterGroundProg_.set("u_size", glm::ivec2(w, n));
            for (int begin = 0; begin < D; begin += chunk) {
                iterGroundProg_.set("u_directionRange", glm::ivec2(begin, std::min(begin + chunk, D)));
                if (begin == 0) {
                    fullscreen();  // the first chunk overwrites (blending off, VAO bound)
                } else {
                    glEnable(GL_BLEND);
                    glBlendFunc(GL_ONE, GL_ONE);
                    glDrawArrays(GL_TRIANGLES, 0, 3);
                }
            }
            glDisable(GL_BLEND);
            glCopyImageSubData(ground_.id(), GL_TEXTURE_2D, 0, 0, 0, 0, it.id(), GL_TEXTURE_2D_ARRAY, 0, 0, 0,
                               nc, w, 1, 1);
        }
        list->push_back(texture(k).ref());
    }
    vars.publish(skykeys::shLuts, skykeys::TextureList(list));
    vars.publish(skykeys::shLut, texture(0).ref());
}

}  // namespace welkin::generators
