// HostDepth: the host's depth buffer as welkin sees it (a game's scene drawn before the sky).
//
//   welkin::HostDepth depth{.depthTexture = hostDepthTex, .nearM = 0.1, .farM = 5e4};
//   sky.renderInto({.framebuffer = hostFbo, .width = w, .height = h, .depth = depth});
//   // elements may sample it in render() (FrameContext::depth) to know how far the host's
//   // geometry is, e.g. aerial perspective over the scene
//
// The texture holds OpenGL window depth in [0, 1] of a standard perspective projection with the
// given near and far planes (1 = far plane = nothing drawn), same size as the camera.
#pragma once

namespace welkin {

struct HostDepth {
    unsigned depthTexture = 0;   ///< GL texture name (GL_DEPTH_COMPONENT* format), not 0
    double nearM = 0.1;          ///< near plane of the host's projection, host units, > 0
    double farM = 1e5;           ///< far plane, host units, > nearM
    double metresPerUnit = 1.0;  ///< metres per host unit, > 0
    /// Throws welkin::Error("<where>: HostDepth ... not in ...") if a member is out of range or
    /// depthTexture is 0.
    void validate(const char* where) const;
};

}  // namespace welkin
