// Renders one element with the SkyVars exactly as given (no astronomy step: the caller sets
// sun.direction, moon.direction, observer.height_m...), into an RGBA32F target, and reads the
// HDR radiance back. For tests, benchmarks and tools that scan configurations. It goes through a
// SkyProcessor (the one compositor) that borrows the caller's SkyVars and the caller's element
// (which stays the caller's: OfflineRenderer never releases it).
//
//   welkin::SkyVars vars = welkin::SkyVars::earth();
//   vars.set(welkin::keys::sunDirection, welkin::directionFromAzAlt(3.0, 0.1));
//   welkin::elements::Sky sky;
//   welkin::elements::OfflineRenderer r(vars, log);
//   welkin::Image hdr = r.render(sky, camera);     // cd/m^2, top row first
#pragma once
#include <welkin/camera.hpp>
#include <welkin/element.hpp>
#include <welkin/image.hpp>
#include <welkin/processor.hpp>

#include <memory>

namespace welkin::elements {

class OfflineRenderer {
public:
    OfflineRenderer(SkyVars& vars, const Logger& log);
    ~OfflineRenderer();
    OfflineRenderer(const OfflineRenderer&) = delete;
    OfflineRenderer& operator=(const OfflineRenderer&) = delete;
    /// Initialises `e` if needed, runs its due generators, updates and draws it over black.
    /// With `finish`, generator and draw times include the GPU work (glFinish).
    Image render(SkyElement& e, const Camera& camera, bool finish = false);
    /// Same without reading back (for timing).
    void draw(SkyElement& e, const Camera& camera, bool finish = false);
    double generatorsMs() const { return generatorsMs_; }
    double drawMs() const { return drawMs_; }
    /// Frees the processor's GL resources and invalidates the element's generators (context
    /// current); the element itself is the caller's to release.
    void release();
    /// Passed to the element as FrameContext::nothingBehind (the target is cleared to black).
    /// false makes the element compute its transmittance output as if something were behind it
    /// (to time that case).
    bool nothingBehind = true;
    /// false: draw with the tables as they are, without running the element's due generators (to
    /// look at an animated state without advancing it).
    bool runGenerators = true;

private:
    class Borrowed;
    SkyVars& vars_;
    const Logger& log_;
    std::unique_ptr<SkyProcessor> processor_;
    SkyElement* current_ = nullptr;
    Borrowed* proxy_ = nullptr;
    double generatorsMs_ = 0, drawMs_ = 0;
};

}  // namespace welkin::elements
