// ToneMapper (engine-private): the SkyProcessor's tone map (docs/eye.md). Exposure: manual EV100,
// or automatic by the eye's adaptation (welkin/eye.hpp: Ferwerda's TVI, cone and rod states
// adapting over time) or a camera's log-average, metered on the GPU by one compute dispatch (several work groups) into
// the means of (w ln Y, w, w ln V') over 128x128 samples (meter.comp.glsl); the adaptation state is a 1x1 texture updated on the GPU
// (adapt.frag.glsl, ping-pong: nothing is read back per frame); then the per-pixel mesopic
// colour, the display curve and the sRGB transfer function (tonemap.frag.glsl).
//
//   ToneMapper tm;
//   tm.init();                                                      // needs a current context
//   tm.run(hdr, fbo, settings, cameraUbo, vao, dt);                 // draws into fbo at hdr's size
//   double ev = tm.lastEv100();
#pragma once
#include <welkin/eye.hpp>
#include <welkin/gl/objects.hpp>
#include <welkin/processor.hpp>

#include <array>
#include <optional>

namespace welkin {

/// The HDR frame to tone-map: the processor's own target or a host's texture (GL_TEXTURE_2D,
/// RGBA16F/32F, cd/m^2), not owned; its parameters are never changed (the meter's bilinear fetches
/// go through a sampler object).
struct HdrSource {
    unsigned texture = 0;
    int width = 0, height = 0;
    bool rgba32f = false;  ///< GL_RGBA32F: the tone map reads it with imageLoad (faster on llvmpipe)
};

/// Everything the tone map reads, gathered from the exposure.* and eye.* keys (eye.hpp).
struct ToneSettings {
    bool automatic = false;
    double ev100 = 15.0;
    double compensationEv = 0.0;
    int curve = 0;
    bool eye = true;
    double adaptationMin = eye::Defaults::adaptationMin, adaptationMax = eye::Defaults::adaptationMax;
    double coneTime = eye::Defaults::coneTime, rodTime = eye::Defaults::rodTime;
    double strength = eye::Defaults::strength;
    bool mesopic = true;
    double scotopicBelow = eye::Defaults::scotopicBelow, photopicAbove = eye::Defaults::photopicAbove;
    glm::dvec2 rodXy{eye::Defaults::rodX, eye::Defaults::rodY};
    /// Reads the keys; throws one line if the limits are out of order.
    static ToneSettings fromVars(const SkyVars& vars);
};

class ToneMapper {
public:
    /// Builds the programs and the log-luminance target (needs a current GL 4.5 context).
    void init();
    void release();
    bool ready() const { return bool(adaptProgram_); }

    /// Tone-maps `hdr` (RGBA32F, cd/m^2) into `framebuffer` (0 = default) over a viewport of
    /// hdr's size. The camera block (weights of the automatic meter by solid angle) must be in
    /// `cameraUbo`; draws with `vao` (no attributes). `dt`: seconds since the previous frame for
    /// the temporal adaptation (<= 0: the steady state, as a still render); nullopt: this is not
    /// a new frame (a second tone map of it), the adaptation state is kept. Changes GL state:
    /// the caller guards it.
    void run(const HdrSource& hdr, unsigned framebuffer, const ToneSettings& settings, const gl::Buffer& cameraUbo,
             const gl::VertexArray& vao, std::optional<double> dt);
    /// run()'s two halves. advance(): the automatic exposure's meter of `hdr` and the adaptation
    /// state's step by `dt` (as run(); nothing for a manual exposure). display(): the per-pixel
    /// pass into `framebuffer` with the state advance() left (the display of a frame can wait
    /// until someone asks for it: SkyProcessor's own LDR target is drawn on demand).
    void advance(const HdrSource& hdr, const ToneSettings& settings, const gl::Buffer& cameraUbo, const gl::VertexArray& vao,
                 std::optional<double> dt);
    void display(const HdrSource& hdr, unsigned framebuffer, const ToneSettings& settings, const gl::Buffer& cameraUbo,
                 const gl::VertexArray& vao);
    /// Whether the last display() wrote an sRGB-encoding target through GL_FRAMEBUFFER_SRGB (the
    /// window's sRGB-capable framebuffer, an SRGB8_ALPHA8 texture) instead of encoding in the shader.
    bool lastSrgbTarget() const { return lastSrgbTarget_; }
    /// The settings of the last advance() (or run()).
    const ToneSettings& lastSettings() const { return lastSettings_; }
    /// The meter of the last run no longer describes the frame (the target was resized).
    void invalidateMeter() { meterValid_ = false; }
    /// Forgets the adaptation state: the next automatic frame starts in the steady state.
    void resetAdaptation() {
        stateValid_ = false;
        readbackValue_.reset();
    }
    /// The automatic exposure the last advance() wrote, when its read-back (a copy into a buffer
    /// queued by that advance(), fenced) has arrived; nullopt while it has not, before the first
    /// automatic advance() and after resetAdaptation(). Never waits for the GPU.
    std::optional<double> previousExposure();
    /// EV100 of the last run (manual, or the adapted exposure: reads the state's texel back).
    double lastEv100() const;
    /// The adaptation state of the last automatic run (cd/m^2, scotopic cd/m^2; reads it back).
    eye::Adaptation adaptation() const;

private:
    void meter(const HdrSource& hdr, int next);  // the meter and the adaptation step into state_[next]
    glm::vec4 readState() const;

    gl::Texture2D meter_;  // 1x1 RGBA32F: (mean w ln Y, mean w, mean w ln V', 1) of the last meter
    gl::Texture2D state_[2];  // (cone, rod, exposure, 1); state_[current_] is the latest
    gl::Framebuffer stateFbo_[2];
    int current_ = 0;
    /// The tone map's program for these settings, built on first use (the settings are compiled
    /// in: engine/shaders/tonemap.frag.glsl).
    gl::Program& toneMapProgram(bool rgba32fImage, bool automatic, bool mesopic, int curve, bool srgbTarget = false);
    std::array<gl::Program, 64> toneMap_;  // by rgba32fImage | automatic << 1 | mesopic << 2 | curve << 3 | srgbTarget << 5
    gl::Program meterProgram_, adaptProgram_;
    unsigned linearSampler_ = 0;
    unsigned meterBlocks_ = 0;  // GL buffer: the meter's work groups' block sums and counter (meter.comp.glsl)  // GL sampler object: bilinear, clamped (the meter's fetches)
    bool meterValid_ = false;  // meter_ holds the last frame's meter
    bool stateValid_ = false;  // state_[current_] holds an adaptation
    bool lastAutomatic_ = false;
    bool lastSrgbTarget_ = false;
    ToneSettings lastSettings_;
    ToneSettings stepSettings_;  // the settings of the adaptation step that wrote state_[current_]
    static bool sameStep(const ToneSettings& a, const ToneSettings& b);
    double lastManualEv100_ = 15.0;
    // previousExposure(): the state's texel copied into a buffer after each automatic advance(),
    // with a fence; the value is kept only for the advance() that queued it (readbackFor_).
    unsigned readbackBuffer_ = 0;
    void* readbackFence_ = nullptr;  // GLsync
    long long advances_ = 0, readbackFor_ = -1;
    std::optional<double> readbackValue_;
    long long readbackValueFor_ = -1;
};

}  // namespace welkin
