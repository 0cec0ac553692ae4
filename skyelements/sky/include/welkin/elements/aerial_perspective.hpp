// Aerial perspective over a host's scene, from the Sky element's aerial-perspective volume.
//
//   // The Sky builds the volume only when asked (a scene pays only for what it uses):
//   processor.vars().set(welkin::generators::skykeys::aerialVolume, true);  // or --var sky.aerial_volume=true
//   // C++: composite over the host's HDR framebuffer (cd/m^2) using its depth texture.
//   welkin::elements::AerialPerspective ap;                    // needs a current context
//   ap.apply(processor.vars(), camera, {.depthTexture = hostDepth, .nearM = 0.1, .farM = 5e4},
//            hostFbo);                                         // dst = inscatter + dst * T
//
//   // GLSL: in the host's own shaders.
//   auto b = welkin::gl::ProgramBuilder("host");
//   for (auto& [name, text] : welkin::elements::aerialPerspectiveGlslChunks()) b.fragment(name, text);
//   b.fragment("host.frag", hostText);   // calls welkin_aerialPerspective(dir, distance, T)
//   ...; ap.bindResources(processor.vars(), program);          // before drawing
//
// The volume is camera-independent (directions x distance, see AerialPerspectiveLut), so one
// volume serves every view and projection; Sun light only (the Moon's share is negligible for
// aerial perspective). Distances beyond SkyQuality::aerialMaxDistance (100 km) use the last slice.
// Directions are world ENU; distances in metres from the observer.
#pragma once
#include <welkin/camera.hpp>
#include <welkin/gl/objects.hpp>
#include <welkin/host_depth.hpp>
#include <welkin/vars.hpp>

#include <string>
#include <utility>
#include <vector>

namespace welkin::elements {

/// The host's depth buffer (moved into the engine: welkin/host_depth.hpp).
using HostDepth = welkin::HostDepth;

/// (name, text) of the GLSL chunks to add before a host shader calling welkin_aerialPerspective.
std::vector<std::pair<std::string, std::string>> aerialPerspectiveGlslChunks();

class AerialPerspective {
public:
    AerialPerspective() = default;
    /// Binds the atmosphere block (binding 1), the volumes (units 6, 7) and sets the uniforms of
    /// `program` (which includes aerialPerspectiveGlslChunks()). Throws welkin::Error if the Sky's
    /// generators have not run yet.
    void bindResources(const SkyVars& vars, const gl::Program& program);
    /// Composites the aerial perspective over `framebuffer` (perspective camera only; the camera
    /// must match the depth texture's size).
    void apply(const SkyVars& vars, const Camera& camera, const HostDepth& depth, unsigned framebuffer);
    void release();

private:
    gl::Program program_;
    gl::Buffer ubo_, cameraUbo_;
    gl::VertexArray vao_;
};

}  // namespace welkin::elements
