// ToneMapper (engine-private): the SkyProcessor's tone map. Exposure (manual EV100, or automatic
// from the log-average luminance of the frame, metered on the GPU into a 128x128 RG32F mip
// chain), Narkowicz's filmic curve and the sRGB transfer function (engine/shaders/tonemap.frag.glsl,
// loglum.frag.glsl).
//
//   ToneMapper tm;
//   tm.init();                                                 // needs a current context
//   tm.run(hdr, fbo, exposure, cameraUbo, vao);                // draws into fbo at hdr's size
//   double ev = tm.lastEv100(exposure);
#pragma once
#include <welkin/gl/objects.hpp>
#include <welkin/processor.hpp>

namespace welkin {

class ToneMapper {
public:
    /// Builds the programs and the log-luminance target (needs a current GL 4.5 context).
    void init();
    void release();
    bool ready() const { return bool(toneMap_); }

    /// Tone-maps `hdr` (RGBA32F, cd/m^2) into `framebuffer` (0 = default) over a viewport of
    /// hdr's size. The camera block (weights of the automatic meter by solid angle) must be in
    /// `cameraUbo`; draws with `vao` (no attributes). Changes GL state: the caller guards it.
    void run(gl::Texture2D& hdr, unsigned framebuffer, const Exposure& exposure, const gl::Buffer& cameraUbo,
             const gl::VertexArray& vao);
    /// The meter of the last run no longer describes the frame (the target was resized).
    void invalidateMeter() { meterValid_ = false; }
    /// EV100 of the last run: `exposure.ev100` if manual, else the metered value (reads 1 texel).
    double lastEv100(const Exposure& exposure) const;

private:
    gl::Texture2D logLum_;
    gl::Framebuffer logLumFbo_;
    gl::Program toneMap_, logLumProgram_;
    bool meterValid_ = false;  // logLum_ holds the last frame's meter
};

}  // namespace welkin
