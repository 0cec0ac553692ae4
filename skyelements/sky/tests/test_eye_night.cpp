// The eye's automatic exposure on real skies (welkin/eye.hpp, docs/eye.md): a moonless night
// displays darker than a full-Moon night, both darker than civil twilight.
#include <catch2/catch.hpp>

#include "gl_test_context.hpp"

#include <welkin/astro/astro_keys.hpp>
#include <welkin/color.hpp>
#include <welkin/elements/sky.hpp>
#include <welkin/eye.hpp>
#include <welkin/generators/atmosphere.hpp>
#include <welkin/keys.hpp>
#include <welkin/processor.hpp>

#include <cmath>
#include <cstdio>

using namespace welkin;

namespace {
constexpr double kDeg = M_PI / 180;

double srgbDecode(double v) { return v <= 0.04045 ? v / 12.92 : std::pow((v + 0.055) / 1.055, 2.4); }

struct Night {
    double displayed;  // mean displayed luminance (linear, of the decoded sRGB) over the sky
    double scene;      // mean scene luminance, cd/m^2
    double ev100;
};

// The whole sky (fisheye, 48x48) with the Sun at `sunAltDeg` and, if `moon`, a full Moon at 45 deg.
Night renderSky(double sunAltDeg, bool moon, bool eyeModel = true) {
    test::glContext();
    SkyProcessor p(SkyVars::earth(), Logger(), ProcessorOptions{.astronomy = false});
    p.vars().set(atmosphere::kAtmosphere, std::make_shared<const atmosphere::Atmosphere>(atmosphere::Atmosphere::earthClear()));
    p.vars().set(keys::sunDirection, directionFromAzAlt(270 * kDeg, sunAltDeg * kDeg));
    p.vars().set(keys::moonDirection, moon ? directionFromAzAlt(120 * kDeg, 45 * kDeg) : glm::dvec3(0, 0, -1));
    Camera cam;
    cam.projection = Projection::Fisheye;
    cam.width = cam.height = 48;
    p.setCamera(cam);
    p.add(std::make_unique<elements::Sky>(elements::SkyOptions{.quality = 0}));
    p.vars().set(astro::keys::moonPhaseAngle, 0.0);  // full
    p.vars().set(eye::keys::adaptation, eyeModel);
    p.setExposure({.automatic = true});
    p.setAnimationTime(0.0);  // a still render: the steady state
    p.renderFrame();
    const Image hdr = p.readHdr(), ldr = p.readToneMapped();
    Night n{0, 0, p.lastEv100()};
    int count = 0;
    for (int y = 0; y < cam.height; ++y)
        for (int x = 0; x < cam.width; ++x) {
            if (!cam.directionAt({x + 0.5, y + 0.5})) continue;  // outside the fisheye circle
            glm::dvec3 shown, scene;
            for (int c = 0; c < 3; ++c) {
                shown[c] = srgbDecode(ldr.at(x, y, c));
                scene[c] = hdr.at(x, y, c);
            }
            n.displayed += color::luminance(shown);
            n.scene += color::luminance(scene);
            ++count;
        }
    n.displayed /= count;
    n.scene /= count;
    p.release();
    return n;
}
}  // namespace

TEST_CASE("Eye: a moonless night displays darker than a full-Moon night, both darker than civil twilight", "[gl][eye][sky]") {
    const Night moonless = renderSky(-18, false), moonlit = renderSky(-18, true), civil = renderSky(-6, false),
                day = renderSky(30, false);
    for (auto [name, n] : {std::pair{"moonless", moonless}, {"full Moon", moonlit}, {"civil twilight", civil}, {"day", day}})
        std::printf("eye: %-15s scene %.3g cd/m^2, EV100 %.2f, displayed %.4f\n", name, n.scene, n.ev100, n.displayed);
    // The scenes themselves are ordered (the sky's physics, not the eye).
    REQUIRE(moonless.scene < moonlit.scene);
    REQUIRE(moonlit.scene < civil.scene);
    // The eye keeps the order on the display, each step by more than 8-bit noise (a factor 1.5:
    // the model's ladder is at least a stop per rung, [cpu] test; the curve compresses some).
    CHECK(moonless.displayed * 1.5 < moonlit.displayed);
    CHECK(moonlit.displayed * 1.5 < civil.displayed);
    CHECK(civil.displayed * 1.5 < day.displayed);
    // A moonless night is dark: below 2 % of the display's white (linear).
    CHECK(moonless.displayed < 0.02);
    // The camera's log-average lifts every scene to about the same grey; the eye does not.
    const Night camera = renderSky(-18, false, false);
    CHECK(camera.displayed > 3 * moonless.displayed);
}
