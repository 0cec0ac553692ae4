#include "tone_mapper.hpp"

#include <welkin/gl/bindings.hpp>
#include <welkin/gl/shader.hpp>
#include <welkin/keys.hpp>

#include <epoxy/gl.h>

#include <algorithm>
#include <cmath>
#include <sstream>
#include <vector>

namespace welkin {

namespace {
constexpr int kLogLumSize = 128;  // log-luminance reduction resolution (power of two)
}

ToneSettings ToneSettings::fromVars(const SkyVars& v) {
    ToneSettings s;
    s.automatic = v.get(keys::exposureAuto);
    s.ev100 = v.get(keys::exposureEv100);
    s.compensationEv = v.get(eye::keys::compensation);
    s.curve = v.get(eye::keys::curve);
    s.eye = v.get(eye::keys::adaptation);
    s.adaptationMin = v.get(eye::keys::adaptationMin);
    s.adaptationMax = v.get(eye::keys::adaptationMax);
    s.coneTime = v.get(eye::keys::coneTime);
    s.rodTime = v.get(eye::keys::rodTime);
    s.mesopic = v.get(eye::keys::mesopic);
    s.scotopicBelow = v.get(eye::keys::scotopicBelow);
    s.photopicAbove = v.get(eye::keys::photopicAbove);
    s.rodXy = v.get(eye::keys::rodChromaticity);
    auto ordered = [](const char* a, double lo, const char* b, double hi) {
        if (lo < hi) return;
        std::ostringstream m;
        m << "SkyProcessor: " << a << " " << lo << " not below " << b << " " << hi;
        throw Error(m.str());
    };
    ordered("eye.adaptation_min_cd_m2", s.adaptationMin, "eye.adaptation_max_cd_m2", s.adaptationMax);
    ordered("eye.scotopic_cd_m2", s.scotopicBelow, "eye.photopic_cd_m2", s.photopicAbove);
    if (s.rodXy.x + s.rodXy.y >= 1.0) throw Error("SkyProcessor: eye.rod_chromaticity x + y not below 1");
    return s;
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
    logLum_ = gl::Texture2D(kLogLumSize, kLogLumSize, GL_RGBA32F, levels);
    logLumFbo_ = gl::Framebuffer::create();
    logLumFbo_.attach(GL_COLOR_ATTACHMENT0, logLum_);
    logLumFbo_.checkComplete("SkyProcessor log luminance");
    meterValid_ = false;
    stateValid_ = false;
}

void ToneMapper::release() {
    logLum_ = {};
    logLumFbo_ = {};
    toneMap_ = {};
    logLumProgram_ = {};
    meterValid_ = false;
    stateValid_ = false;
}

void ToneMapper::meter(gl::Texture2D& hdr) {
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

void ToneMapper::run(gl::Texture2D& hdr, unsigned framebuffer, const ToneSettings& s, const gl::Buffer& cameraUbo,
                     const gl::VertexArray& vao, std::optional<double> dt) {
    cameraUbo.bindBase(GL_UNIFORM_BUFFER, gl::binding::kCameraUbo);
    vao.bind();
    glDisable(GL_BLEND);
    glDisable(GL_DEPTH_TEST);
    double exposure = eye::exposureFromEv100(s.ev100);
    if (s.automatic) {
        if (dt || !stateValid_ || !meterValid_) {
            meter(hdr);
            // The weighted log-averages (sum w ln Y, sum w, sum w ln V') / N: one texel read back
            // (the CPU waits for the meter's pass; the adaptation model stays in one place, eye.cpp).
            std::vector<float> top = logLum_.readRgbaFloat(logLum_.levels() - 1);
            eye::Adaptation target{s.adaptationMin, s.adaptationMin};
            if (top[1] > 0) target = {std::exp(double(top[0]) / top[1]), std::exp(double(top[2]) / top[1])};
            // A frame with NaN or infinite pixels meters nothing: keep the eye where it was.
            if (!std::isfinite(target.cone) || !std::isfinite(target.rod))
                target = stateValid_ ? state_ : eye::Adaptation{s.adaptationMin, s.adaptationMin};
            target.cone = std::clamp(target.cone, s.adaptationMin, s.adaptationMax);
            target.rod = std::clamp(target.rod, s.adaptationMin, s.adaptationMax);
            if (!stateValid_ || !dt || *dt <= 0)
                state_ = target;  // a still render, or the first frame: the steady state
            else
                state_ = eye::adapt(state_, target, *dt, s.coneTime, s.rodTime);
            stateValid_ = true;
        }
        exposure = (s.eye ? eye::eyeExposure(state_) : eye::cameraExposure(state_.cone)) * std::exp2(s.compensationEv);
    }
    lastEv100_ = eye::ev100FromExposure(exposure);

    glBindFramebuffer(GL_FRAMEBUFFER, framebuffer);
    glViewport(0, 0, hdr.width(), hdr.height());
    hdr.bind(gl::binding::kHdrTexture);
    toneMap_.use();
    toneMap_.set("u_exposure", float(exposure));
    toneMap_.set("u_curve", s.curve);
    toneMap_.set("u_mesopic", s.mesopic ? 1 : 0);
    toneMap_.set("u_log10Scotopic", float(std::log10(s.scotopicBelow)));
    toneMap_.set("u_log10Photopic", float(std::log10(s.photopicAbove)));
    toneMap_.set("u_rodColor", glm::vec3(eye::rodColor(s.rodXy) / eye::scotopicPerPhotopicWhite()));
    glDrawArrays(GL_TRIANGLES, 0, 3);
}

}  // namespace welkin
