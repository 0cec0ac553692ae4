#include "tone_mapper.hpp"

#include <welkin/gl/bindings.hpp>

#include <welkin/gl/shader.hpp>

#include <epoxy/gl.h>

#include <algorithm>
#include <cmath>
#include <vector>

namespace welkin {

namespace {
constexpr int kLogLumSize = 128;  // log-luminance reduction resolution (power of two)
}

void ToneMapper::init() {
    toneMap_ = gl::ProgramBuilder("SkyProcessor tone map")
                   .fullscreenVertex()
                   .fragment("engine/tonemap.frag.glsl", gl::engineShader("tonemap.frag.glsl"))
                   .build();
    logLumProgram_ = gl::ProgramBuilder("SkyProcessor log luminance")
                         .fullscreenVertex()
                         .fragment("engine/camera.glsl", gl::engineShader("camera.glsl"))
                         .fragment("engine/loglum.frag.glsl", gl::engineShader("loglum.frag.glsl"))
                         .build();
    const int levels = int(std::log2(kLogLumSize)) + 1;
    logLum_ = gl::Texture2D(kLogLumSize, kLogLumSize, GL_RG32F, levels);
    logLumFbo_ = gl::Framebuffer::create();
    logLumFbo_.attach(GL_COLOR_ATTACHMENT0, logLum_);
    logLumFbo_.checkComplete("SkyProcessor log luminance");
    meterValid_ = false;
}

void ToneMapper::release() {
    logLum_ = {};
    logLumFbo_ = {};
    toneMap_ = {};
    logLumProgram_ = {};
    meterValid_ = false;
}

void ToneMapper::run(gl::Texture2D& hdr, unsigned framebuffer, const Exposure& exposure, const gl::Buffer& cameraUbo,
                     const gl::VertexArray& vao) {
    cameraUbo.bindBase(GL_UNIFORM_BUFFER, gl::binding::kCameraUbo);
    vao.bind();
    glDisable(GL_BLEND);
    glDisable(GL_DEPTH_TEST);
    if (exposure.automatic) {
        logLumFbo_.bind();
        glViewport(0, 0, kLogLumSize, kLogLumSize);
        hdr.bind(gl::binding::kHdrTexture);
        hdr.setFilter(GL_LINEAR);  // each meter fetch averages 2x2 texels
        logLumProgram_.use();
        glDrawArrays(GL_TRIANGLES, 0, 3);
        hdr.setFilter(GL_NEAREST);
        logLum_.generateMipmaps();
        meterValid_ = true;
    }
    glBindFramebuffer(GL_FRAMEBUFFER, framebuffer);
    glViewport(0, 0, hdr.width(), hdr.height());
    hdr.bind(gl::binding::kHdrTexture);
    logLum_.bind(gl::binding::kLogLumTexture);
    toneMap_.use();
    toneMap_.set("u_ev100", float(exposure.ev100));
    toneMap_.set("u_auto", exposure.automatic ? 1 : 0);
    toneMap_.set("u_compensation", float(exposure.compensationEv));
    toneMap_.set("u_logLumLevel", logLum_.levels() - 1);
    glDrawArrays(GL_TRIANGLES, 0, 3);
}

double ToneMapper::lastEv100(const Exposure& exposure) const {
    if (!exposure.automatic || !meterValid_) return exposure.ev100;
    std::vector<float> top = logLum_.readRgbaFloat(logLum_.levels() - 1);
    // Same arithmetic as welkin_autoEv100() in tonemap.frag.glsl.
    double logAvg = top[1] > 0 ? top[0] / top[1] : std::log(1e-7);
    double ev = std::clamp(std::log2(std::exp(logAvg) * 100.0 / 12.5), -20.0, 30.0);
    return ev - exposure.compensationEv;
}

}  // namespace welkin
