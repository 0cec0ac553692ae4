// Embedding welkin: a headless "game loop" that advances time and renders frames, then saves the
// last frame. Usage: example_embed_headless OUT.png
#include <welkin/elements/registry.hpp>
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
    try {
        welkin::Logger log;
        auto context = welkin::gl::HeadlessContext::create({}, log);
        welkin::SkyProcessor sky(welkin::SkyVars::earth(), log);
        // The default set (the registry's order: background first), then a grid overlay (where
        // the Grid's folder is in the tree: elements are found by name).
        for (const auto& name : welkin::elements::defaultElements()) sky.add(welkin::elements::makeElement(name));
        if (welkin::elements::findDescriptor("grid")) sky.add(welkin::elements::makeElement("grid"));

        constexpr double deg = std::numbers::pi / 180;
        sky.setObserver({.latitudeRad = 35.9 * deg, .longitudeRad = 14.5 * deg, .heightMeters = 50});
        welkin::Camera camera;
        camera.width = 320;
        camera.height = 180;
        camera.azimuthRad = 270 * deg;
        camera.altitudeRad = 15 * deg;
        sky.setCamera(camera);
        sky.setExposure({.automatic = true});

        auto t = welkin::UtcInstant::parse("2026-07-15T19:00:00+02:00");
        for (int frame = 0; frame < 4; ++frame) {  // the host's loop: one simulated minute per frame
            sky.setTime(t.plusSeconds(60.0 * frame));
            sky.renderFrame();  // or sky.renderInto({hostFbo, w, h}) to composite behind the host's scene
        }
        welkin::writeImage(sky.readToneMapped(), argv[1]);
        std::printf("%s\n", argv[1]);
    } catch (const welkin::Error& e) {
        std::fprintf(stderr, "example_embed_headless: %s\n", e.what());
        return 1;
    }
    return 0;
}
