// HostDepth: the host's depth buffer as welkin sees it (a game's scene drawn before the sky).
//
//   welkin::HostDepth depth{.depthTexture = hostDepthTex, .nearM = 0.1, .farM = 5e4};
//   sky.renderInto({.framebuffer = hostFbo, .width = w, .height = h, .depth = depth});
//   // elements may sample it in render() (FrameContext::depth) to know how far the host's
//   // geometry is, e.g. aerial perspective over the scene
//
// The texture holds OpenGL window depth in [0, 1], same size as the camera, in the camera's
// DepthMode (standard: 1 = far plane = nothing drawn; reversed-Z: 0). A camera made from the
// host's matrices (Camera::fromViewProjection) reads it with the host's own projection matrix
// (any near plane, a finite or infinite far plane); other cameras with a perspective projection
// of the near and far planes given here.
#pragma once

namespace welkin {

struct HostDepth {
    unsigned depthTexture = 0;   ///< GL texture name (GL_DEPTH_COMPONENT* format), not 0
    double nearM = 0.1;          ///< near plane of the host's projection, host units, > 0 (not used by host cameras)
    double farM = 1e5;           ///< far plane, host units, > nearM, may be +inf (not used by host cameras)
    double metresPerUnit = 1.0;  ///< metres per host unit, > 0
    /// Throws welkin::Error("<where>: HostDepth ... not in ...") if a member is out of range or
    /// depthTexture is 0.
    void validate(const char* where) const;
};

}  // namespace welkin
