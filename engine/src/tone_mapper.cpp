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
// The image unit the meter's dispatch writes the eye's new state through (meter.comp.glsl's
// WELKIN_TONEMAP_STATE_IMAGE): beside gl::binding::kMeterImage (1) and kHdrImage (0), below the
// private ranges; bound only around that dispatch (the processor's state guard covers units 0-7).
constexpr int kStateImageUnit = 2;
// The meter's work groups (meter.comp.glsl): llvmpipe runs each on one of its threads; 256 must be
// a multiple (16 rows of 16 invocations split between them). The means do not depend on it.
constexpr int kMeterGroups = 4;
static_assert(16 % kMeterGroups == 0);
}  // namespace

ToneSettings ToneSettings::fromVars(const SkyVars& v) {
    ToneSettings s;
    s.automatic = v.get(keys::exposureAuto);
    s.ev100 = v.get(keys::exposureEv100);
    s.compensationEv = v.get(eye::keys::compensation);
    s.curve = eye::keys::curve.value(v);
    s.eye = v.get(eye::keys::adaptation);
    s.adaptationMin = v.get(eye::keys::adaptationMin);
    s.adaptationMax = v.get(eye::keys::adaptationMax);
    s.coneTime = v.get(eye::keys::coneTime);
    s.rodTime = v.get(eye::keys::rodTime);
    s.strength = v.get(eye::keys::strength);
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
    for (auto& p : toneMap_) p = {};
    toneMapProgram(true, false, true, 0);  // the default settings' program: a first frame's compile is not in its tone map
    meterProgram_ = gl::ProgramBuilder("SkyProcessor eye meter")
                        .define("WELKIN_TONEMAP_STATE_IMAGE", kStateImageUnit)
                        .define("WELKIN_METER_GROUPS", kMeterGroups)
                        .compute("engine/camera.glsl", gl::engineShader("camera.glsl"))
                        .compute("engine/adapt.glsl", gl::engineShader("adapt.glsl"))
                        .compute("engine/meter.comp.glsl", gl::engineShader("meter.comp.glsl"))
                        .build();
    adaptProgram_ = gl::ProgramBuilder("SkyProcessor eye adaptation")
                        .fullscreenVertex()
                        .fragment("engine/adapt.glsl", gl::engineShader("adapt.glsl"))
                        .fragment("engine/adapt.frag.glsl", gl::engineShader("adapt.frag.glsl"))
                        .build();
    for (int i = 0; i < 2; ++i) {
        state_[i] = gl::Texture2D(1, 1, GL_RGBA32F);
        state_[i].setFilter(GL_NEAREST);
        stateFbo_[i] = gl::Framebuffer::create();
        stateFbo_[i].attach(GL_COLOR_ATTACHMENT0, state_[i]);
        stateFbo_[i].checkComplete("SkyProcessor eye state");
    }
    meter_ = gl::Texture2D(1, 1, GL_RGBA32F);
    meter_.setFilter(GL_NEAREST);
    // The meter's block sums and its count of groups done, zeroed (the last group resets it).
    if (meterBlocks_) glDeleteBuffers(1, &meterBlocks_);
    glCreateBuffers(1, &meterBlocks_);
    const std::vector<unsigned char> zeros((4 + 256 * 4) * sizeof(float), 0);
    glNamedBufferStorage(meterBlocks_, GLsizeiptr(zeros.size()), zeros.data(), 0);
    glCreateSamplers(1, &linearSampler_);
    glSamplerParameteri(linearSampler_, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
    glSamplerParameteri(linearSampler_, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    glSamplerParameteri(linearSampler_, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glSamplerParameteri(linearSampler_, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    meterValid_ = false;
    stateValid_ = false;
}

gl::Program& ToneMapper::toneMapProgram(bool rgba32fImage, bool automatic, bool mesopic, int curve, bool srgbTarget) {
    curve = std::clamp(curve, 0, 3);
    gl::Program& p = toneMap_[size_t(rgba32fImage) | size_t(automatic) << 1 | size_t(mesopic) << 2 | size_t(curve) << 3 | size_t(srgbTarget) << 5];
    if (!p) {
        gl::ProgramBuilder b("SkyProcessor tone map");
        if (srgbTarget) b.define("WELKIN_TONEMAP_SRGB_TARGET");
        if (rgba32fImage) b.define("WELKIN_TONEMAP_IMAGE");
        if (automatic) b.define("WELKIN_TONEMAP_AUTO");
        if (mesopic) b.define("WELKIN_TONEMAP_MESOPIC");
        b.define("WELKIN_TONEMAP_CURVE", curve);
        p = b.vertex("engine/tonemap.vert.glsl", gl::engineShader("tonemap.vert.glsl"))
                .fragment("engine/tonemap.frag.glsl", gl::engineShader("tonemap.frag.glsl"))
                .build();
    }
    return p;
}

void ToneMapper::release() {
    if (readbackFence_) glDeleteSync(GLsync(readbackFence_));
    readbackFence_ = nullptr;
    if (readbackBuffer_) glDeleteBuffers(1, &readbackBuffer_);
    readbackBuffer_ = 0;
    readbackValue_.reset();
    readbackValueFor_ = readbackFor_ = -1;
    if (linearSampler_) glDeleteSamplers(1, &linearSampler_);
    linearSampler_ = 0;
    if (meterBlocks_) glDeleteBuffers(1, &meterBlocks_);
    meterBlocks_ = 0;
    meter_ = {};
    for (auto& p : toneMap_) p = {};
    meterProgram_ = {};
    adaptProgram_ = {};
    for (int i = 0; i < 2; ++i) {
        state_[i] = {};
        stateFbo_[i] = {};
    }
    meterValid_ = false;
    stateValid_ = false;
}

void ToneMapper::meter(const HdrSource& hdr, int next) {
    // kMeterGroups work groups, the means over 128x128 samples (meter.comp.glsl) and the
    // adaptation step into state_[next]; the camera block gives the frame's size and projection
    // (the weights outside a fisheye's circle).
    glBindTextureUnit(gl::binding::kHdrTexture, hdr.texture);
    glBindSampler(gl::binding::kHdrTexture, linearSampler_);  // each meter fetch averages 2x2 texels
    glBindImageTexture(gl::binding::kMeterImage, meter_.id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA32F);
    glBindImageTexture(kStateImageUnit, state_[next].id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA32F);
    state_[current_].bind(gl::binding::kEyeStateTexture);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, gl::binding::kMeterSsbo, meterBlocks_);
    meterProgram_.use();
    glDispatchCompute(1, GLuint(kMeterGroups), 1);
    glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_TEXTURE_UPDATE_BARRIER_BIT | GL_FRAMEBUFFER_BARRIER_BIT | GL_SHADER_STORAGE_BARRIER_BIT);
    glBindSampler(gl::binding::kHdrTexture, 0);
    meterValid_ = true;
}

bool ToneMapper::sameStep(const ToneSettings& a, const ToneSettings& b) {
    // The settings welkin_eyeStep() reads (adapt.glsl's uniforms).
    return a.automatic == b.automatic && a.eye == b.eye && a.adaptationMin == b.adaptationMin && a.adaptationMax == b.adaptationMax &&
           a.coneTime == b.coneTime && a.rodTime == b.rodTime && a.strength == b.strength && a.compensationEv == b.compensationEv;
}

void ToneMapper::run(const HdrSource& hdr, unsigned framebuffer, const ToneSettings& s, const gl::Buffer& cameraUbo,
                     const gl::VertexArray& vao, std::optional<double> dt) {
    advance(hdr, s, cameraUbo, vao, dt);
    display(hdr, framebuffer, s, cameraUbo, vao);
}

void ToneMapper::advance(const HdrSource& hdr, const ToneSettings& s, const gl::Buffer& cameraUbo, const gl::VertexArray& vao,
                         std::optional<double> dt) {
    cameraUbo.bindBase(GL_UNIFORM_BUFFER, gl::binding::kCameraUbo);
    vao.bind();
    glDisable(GL_BLEND);
    glDisable(GL_DEPTH_TEST);
    lastAutomatic_ = s.automatic;
    lastManualEv100_ = s.ev100;
    lastSettings_ = s;
    if (s.automatic) {
        // A new frame is metered; a second tone map of it only re-derives the exposure from the
        // state (dt = 0), so changed settings apply, and with unchanged settings does nothing.
        const bool steady = !stateValid_ || (dt && *dt <= 0);
        const int next = 1 - current_;
        auto setAdaptation = [&](gl::Program& p) {
            p.use();
            p.set("u_steady", steady ? 1 : 0);
            p.set("u_dt", float(dt && *dt > 0 ? *dt : 0.0));
            p.set("u_coneTime", float(s.coneTime));
            p.set("u_rodTime", float(s.rodTime));
            p.set("u_min", float(s.adaptationMin));
            p.set("u_max", float(s.adaptationMax));
            p.set("u_eye", s.eye ? 1 : 0);
            p.set("u_strength", float(s.strength));
            p.set("u_compensation", float(s.compensationEv));
            p.set("u_kTvi", float(eye::eyeExposureScale()));
            p.set("u_kappa", float(eye::scotopicPerPhotopicWhite()));
        };
        if (!dt && stateValid_ && meterValid_ && sameStep(s, stepSettings_)) {
            // A second tone map of the frame with the settings its step used: that step again
            // (dt = 0 keeps the cone and rod states, the exposure follows from them by the same
            // settings) would write the same texel. Nothing to draw: the one-texel pass cost
            // llvmpipe a draw the display pass then waited for (docs/eye.md, session 21).
            return;
        }
        stepSettings_ = s;
        if (dt || !stateValid_ || !meterValid_) {
            // The meter and the adaptation step in one dispatch (meter.comp.glsl).
            setAdaptation(meterProgram_);
            meter(hdr, next);
        } else {
            // The same frame again: the step from the stored meter, by the one-texel pass.
            stateFbo_[next].bind();
            glViewport(0, 0, 1, 1);
            meter_.bind(gl::binding::kLogLumTexture);
            state_[current_].bind(gl::binding::kEyeStateTexture);
            setAdaptation(adaptProgram_);
            glDrawArrays(GL_TRIANGLES, 0, 3);
        }
        current_ = next;
        stateValid_ = true;
        ++advances_;
        // The state's texel into a buffer, fenced: previousExposure() reads it in a later frame
        // once the fence has signalled (no wait). An older copy not read yet is dropped.
        if (!readbackBuffer_) {
            glCreateBuffers(1, &readbackBuffer_);
            glNamedBufferStorage(readbackBuffer_, 4 * sizeof(float), nullptr, 0);
        }
        if (readbackFence_) glDeleteSync(GLsync(readbackFence_));
        glBindBuffer(GL_PIXEL_PACK_BUFFER, readbackBuffer_);
        glGetTextureImage(state_[current_].id(), 0, GL_RGBA, GL_FLOAT, GLsizei(4 * sizeof(float)), nullptr);
        glBindBuffer(GL_PIXEL_PACK_BUFFER, 0);
        readbackFence_ = glFenceSync(GL_SYNC_GPU_COMMANDS_COMPLETE, 0);
        readbackFor_ = advances_;
    }
}

std::optional<double> ToneMapper::previousExposure() {
    if (readbackFence_) {
        const GLenum r = glClientWaitSync(GLsync(readbackFence_), 0, 0);
        if (r == GL_ALREADY_SIGNALED || r == GL_CONDITION_SATISFIED) {
            float t[4] = {0, 0, 0, 0};
            glGetNamedBufferSubData(readbackBuffer_, 0, sizeof t, t);
            glDeleteSync(GLsync(readbackFence_));
            readbackFence_ = nullptr;
            readbackValue_ = double(t[2]);
            readbackValueFor_ = readbackFor_;
        }
    }
    if (!stateValid_ || !lastAutomatic_ || readbackValueFor_ != advances_) return std::nullopt;
    return readbackValue_;
}

namespace {
// Whether the bound draw framebuffer's first draw buffer encodes sRGB on write (an SRGB8_ALPHA8
// attachment, or a window's sRGB-capable default framebuffer). A default framebuffer without a
// surface (headless) or no draw buffer: false.
bool drawTargetIsSrgb(unsigned framebuffer) {
    if (glCheckNamedFramebufferStatus(framebuffer, GL_DRAW_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE) return false;
    GLint buffer = GL_NONE;
    glGetIntegerv(GL_DRAW_BUFFER0, &buffer);
    if (buffer == GL_NONE) return false;
    GLenum attachment = GLenum(buffer);
    if (framebuffer == 0) {
        if (attachment == GL_BACK || attachment == GL_FRONT_AND_BACK) attachment = GL_BACK_LEFT;
        else if (attachment == GL_FRONT || attachment == GL_LEFT) attachment = GL_FRONT_LEFT;
        else if (attachment == GL_RIGHT) attachment = GL_FRONT_RIGHT;
    }
    GLint type = GL_NONE, encoding = GL_LINEAR;
    glGetNamedFramebufferAttachmentParameteriv(framebuffer, attachment, GL_FRAMEBUFFER_ATTACHMENT_OBJECT_TYPE, &type);
    if (type == GL_NONE) return false;
    glGetNamedFramebufferAttachmentParameteriv(framebuffer, attachment, GL_FRAMEBUFFER_ATTACHMENT_COLOR_ENCODING, &encoding);
    return encoding == GL_SRGB;
}
}  // namespace

void ToneMapper::display(const HdrSource& hdr, unsigned framebuffer, const ToneSettings& s, const gl::Buffer& cameraUbo,
                         const gl::VertexArray& vao) {
    cameraUbo.bindBase(GL_UNIFORM_BUFFER, gl::binding::kCameraUbo);
    vao.bind();
    glDisable(GL_BLEND);
    glDisable(GL_DEPTH_TEST);
    glBindFramebuffer(GL_FRAMEBUFFER, framebuffer);
    glViewport(0, 0, hdr.width, hdr.height);
    if (hdr.rgba32f)
        glBindImageTexture(gl::binding::kHdrImage, hdr.texture, 0, GL_FALSE, 0, GL_READ_ONLY, GL_RGBA32F);
    else
        glBindTextureUnit(gl::binding::kHdrTexture, hdr.texture);
    state_[current_].bind(gl::binding::kEyeStateTexture);
    // An sRGB target encodes on write (GL_FRAMEBUFFER_SRGB, restored after the draw): the program
    // leaves its own encoding out (docs/eye.md "The sRGB encoding on write").
    const bool srgbTarget = drawTargetIsSrgb(framebuffer);
    lastSrgbTarget_ = srgbTarget;
    const GLboolean wasSrgb = glIsEnabled(GL_FRAMEBUFFER_SRGB);
    if (srgbTarget != bool(wasSrgb)) (srgbTarget ? glEnable : glDisable)(GL_FRAMEBUFFER_SRGB);
    gl::Program& program = toneMapProgram(hdr.rgba32f, s.automatic, s.mesopic, s.curve, srgbTarget);
    program.use();
    if (!s.automatic) program.set("u_exposure", float(eye::exposureFromEv100(s.ev100)));
    if (s.mesopic) {
        const double lo = std::log2(s.scotopicBelow), span = std::log2(s.photopicAbove) - lo;  // span > 0 (fromVars)
        program.set("u_rodRamp", glm::vec2(float(1.0 / span), float(lo / span)));
        program.set("u_rodColor", glm::vec3(eye::rodColor(s.rodXy) / eye::scotopicPerPhotopicWhite()));
    }
    glDrawArrays(GL_TRIANGLES, 0, 3);
    if (srgbTarget != bool(wasSrgb)) (wasSrgb ? glEnable : glDisable)(GL_FRAMEBUFFER_SRGB);
}

glm::vec4 ToneMapper::readState() const {
    if (!stateValid_) return glm::vec4(1.0f, 1.0f, float(eye::exposureFromEv100(lastManualEv100_)), 1.0f);
    std::vector<float> t = state_[current_].readRgbaFloat();
    return {t[0], t[1], t[2], t[3]};
}

double ToneMapper::lastEv100() const {
    if (!lastAutomatic_) return lastManualEv100_;
    return eye::ev100FromExposure(readState().z);
}

eye::Adaptation ToneMapper::adaptation() const {
    const glm::vec4 s = readState();
    return {s.x, s.y};
}

}  // namespace welkin
