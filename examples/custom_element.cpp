// Using your own element: the Halo of the element template (examples/elements/halo/, the
// walkthrough is docs/writing-an-element.md) composited with the library's Sky and Grid, one of
// its options set through SkyVars as `welkin render --var` would.
// Usage: example_custom_element OUT.png
#include <welkin/elements/halo.hpp>
#include <welkin/elements/registry.hpp>
#include <welkin/error.hpp>
#include <welkin/gl/context.hpp>
#include <welkin/image.hpp>
#include <welkin/processor.hpp>

#include <cstdio>
#include <numbers>

int main(int argc, char** argv) {
    if (argc != 2) {
        std::fprintf(stderr, "usage: %s OUT.png\n", argv[0]);
        return 2;
    }
    constexpr double kDeg = std::numbers::pi / 180;
    try {
        welkin::Logger log;
        auto context = welkin::gl::HeadlessContext::create({}, log);
        welkin::SkyProcessor sky(welkin::SkyVars::earth(), log);
        sky.add(welkin::elements::makeElement("sky"));     // farthest first
        sky.add(std::make_unique<welkin::elements::Halo>());
        if (welkin::elements::findDescriptor("grid"))      // overlay last, where its folder is in the tree
            sky.add(welkin::elements::makeElement("grid"));
        sky.vars().set(welkin::elements::halokeys::gain, 0.15);          // per sr; bright, for the picture
        sky.vars().setFromString("halo.width_rad", "1deg");              // what --var does
        welkin::Camera camera;
        camera.projection = welkin::Projection::Fisheye;
        camera.width = camera.height = 256;
        sky.setCamera(camera);
        // Equinox, local noon at 50 deg N: the Sun stands ~40 deg up in the south.
        sky.setObserver({.latitudeRad = 50 * kDeg, .longitudeRad = 0.0, .heightMeters = 0.0});
        sky.setTime(welkin::UtcInstant::parse("2026-03-20T12:07:00Z"));
        sky.setExposure({.automatic = true});
        sky.renderFrame();
        welkin::writeImage(sky.readToneMapped(), argv[1]);
        std::printf("%s\n", argv[1]);
    } catch (const welkin::Error& e) {
        std::fprintf(stderr, "example_custom_element: %s\n", e.what());
        return 1;
    }
    return 0;
}
