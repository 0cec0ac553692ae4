// Renders one element with the SkyVars exactly as given (no astronomy step: the caller sets
// sun.direction, moon.direction, observer.height_m...), into an RGBA32F target, and reads the
// HDR radiance back. For tests, benchmarks and tools that scan configurations.
//
//   welkin::SkyVars vars = welkin::SkyVars::earth();
//   vars.set(welkin::keys::sunDirection, welkin::directionFromAzAlt(3.0, 0.1));
//   welkin::elements::Sky sky;
//   welkin::elements::OfflineRenderer r(vars, log);
//   welkin::Image hdr = r.render(sky, camera);     // cd/m^2, top row first
#pragma once
#include <welkin/camera.hpp>
#include <welkin/element.hpp>
#include <welkin/gl/objects.hpp>
#include <welkin/image.hpp>

namespace welkin::elements {

class OfflineRenderer {
public:
    OfflineRenderer(SkyVars& vars, const Logger& log) : vars_(vars), log_(log) {}
    /// Initialises `e` if needed, runs its due generators, updates and draws it over black.
    /// With `finish`, generator and draw times include the GPU work (glFinish).
    Image render(SkyElement& e, const Camera& camera, bool finish = false);
    /// Same without reading back (for timing).
    void draw(SkyElement& e, const Camera& camera, bool finish = false);
    double generatorsMs() const { return generatorsMs_; }
    double drawMs() const { return drawMs_; }
    void release();
    /// Passed to the element as FrameContext::nothingBehind (the target is cleared to black).
    /// false makes the element compute its transmittance output as if something were behind it
    /// (to time that case).
    bool nothingBehind = true;
    /// false: draw with the tables as they are, without running the element's due generators (to
    /// look at an animated state without advancing it).
    bool runGenerators = true;

private:
    SkyVars& vars_;
    const Logger& log_;
    gl::Texture2D hdr_;
    gl::Framebuffer fbo_;
    gl::Buffer cameraUbo_;
    gl::VertexArray vao_;
    double generatorsMs_ = 0, drawMs_ = 0;
};

}  // namespace welkin::elements
