// GlStateGuard (engine-private): saves the host's OpenGL state on construction, puts the pieces
// welkin's passes rely on into their default state, and restores everything saved on destruction.
//
//   void SkyProcessor::renderInto(const RenderTarget& t) {
//       gl::GlStateGuard guard(t.framebuffer);   // also saves t.framebuffer's draw buffers
//       ...                                      // generators, compositing
//   }                                            // host state restored, also on exceptions
//
// Saved and restored (documented in docs/architecture.md, "A guest in the host's GL"):
//   draw and read framebuffer bindings; the draw buffers of the framebuffers passed in;
//   current program; vertex array; every viewport and its depth range; the clip control (origin,
//   depth mode); per draw buffer (< GL_MAX_DRAW_BUFFERS, at
//   most 8): blend enable, blend functions and equations, colour mask; blend colour; depth test,
//   function and mask; cull face enable and mode; front face; scissor test and box; colour logic
//   op; rasterizer discard; polygon mode; active texture unit; on texture units 0..kUnits-1 the
//   binding of every texture target and the sampler object; indexed and generic uniform-buffer
//   and shader-storage bindings 0..kBufferBindings-1 (with their ranges); image units
//   0..kImageUnits-1; pixel pack/unpack buffers and pixel-store parameters.
// Welkin's defaults applied after saving: clip control (lower left, [-1, 1]), depth range [0, 1], scissor test, colour logic op, rasterizer discard and
// face culling off, colour mask on, polygon mode fill, no sampler objects on units 0..kUnits-1,
// no pixel pack/unpack buffer, default pixel-store parameters. Stencil state is left to the host
// (a host may stencil the sky out on purpose).
//
// Objects the host deleted since saving are not rebound (0 instead): a name can be reported by a
// binding query after deletion and rebinding it would fail or create a new object.
#pragma once
#include <array>
#include <vector>

namespace welkin::gl {

class GlStateGuard {
public:
    // Every unit and index of gl/bindings.hpp: the shared table and the private ranges that
    // elements' own bindings are assigned from (gl/private_bindings.hpp; a static_assert in
    // state_guard.cpp keeps the counts above the ranges' ends).
    static constexpr int kUnits = 32;           ///< texture units guarded (through binding::kPrivateTextureUnitLast)
    static constexpr int kBufferBindings = 16;  ///< UBO indices guarded (through kPrivateUboLast); SSBO: the first kSsboBindings
    static constexpr int kSsboBindings = 8;     ///< SSBO indices guarded (through kPrivateSsboLast; GL 4.5 guarantees 8)
    static constexpr int kImageUnits = 8;       ///< image units guarded (through kPrivateImageUnitLast)
    static constexpr int kDrawBuffers = 8;      ///< per-draw-buffer state guarded (at most)

    /// Saves the state; `framebuffers`: host framebuffer objects whose draw buffers welkin may
    /// change (0, the default framebuffer, is ignored: welkin never changes its draw buffer).
    explicit GlStateGuard(std::vector<unsigned> framebuffers = {});
    ~GlStateGuard();
    GlStateGuard(const GlStateGuard&) = delete;
    GlStateGuard& operator=(const GlStateGuard&) = delete;

private:
    struct Blend {
        int srcRgb = 0, dstRgb = 0, srcA = 0, dstA = 0, eqRgb = 0, eqA = 0;
        bool enabled = false;
        std::array<unsigned char, 4> colorMask{};
    };
    struct Indexed {  // a buffer binding point
        int name = 0;
        long long start = 0, size = 0;
    };
    struct Image {
        int name = 0, level = 0, layer = 0, access = 0, format = 0;
        unsigned char layered = 0;
    };
    struct FramebufferDraw {
        unsigned framebuffer = 0;
        std::vector<unsigned> drawBuffers;
    };

    void save(const std::vector<unsigned>& framebuffers);
    void applyDefaults() const;
    void restore() const;

    int drawFbo_ = 0, readFbo_ = 0, program_ = 0, vao_ = 0, activeTexture_ = 0;
    int drawBufferCount_ = 0, viewportCount_ = 0;
    std::vector<std::array<float, 4>> viewports_;
    std::array<Blend, kDrawBuffers> blend_{};
    std::array<float, 4> blendColor_{};
    std::vector<std::array<double, 2>> depthRanges_;  // per viewport
    int clipOrigin_ = 0, clipDepthMode_ = 0;
    int depthFunc_ = 0, cullMode_ = 0, frontFace_ = 0, logicOp_ = 0;
    unsigned char depthTest_ = 0, depthMask_ = 0, cull_ = 0, scissor_ = 0, logicOpEnabled_ = 0, discard_ = 0;
    std::array<unsigned char, 8> clipDistances_{};  // GL_CLIP_DISTANCE0..7 (GL 4.5 guarantees 8)
    std::array<int, 4> scissorBox_{};
    std::array<int, 2> polygonMode_{};
    std::vector<FramebufferDraw> framebufferDraws_;
    // textures_[unit][target index] (targets in state_guard.cpp's kTargets), samplers_[unit]
    std::array<std::array<int, 11>, kUnits> textures_{};
    std::array<int, kUnits> samplers_{};
    std::array<Indexed, kBufferBindings> ubos_{}, ssbos_{};
    int genericUbo_ = 0, genericSsbo_ = 0, packBuffer_ = 0, unpackBuffer_ = 0;
    std::array<Image, kImageUnits> images_{};
    std::array<int, 12> pixelStore_{};
};

}  // namespace welkin::gl
