// By day the night sky, the stars and the planets draw nothing (SkyElement::reportNothingDrawn()),
// so the Sky is the first pass over the processor's black target: it skips its transmittance
// (FrameContext::nothingBehind) and writes without blending (issue 22, README "Cost"). The frame
// must be the blended composite's over a black host target, where every element is drawn with
// something possibly behind it.
#include <catch2/catch.hpp>

#include "elements_present.hpp"
#include "gl_test_context.hpp"

#include <welkin/elements/registry.hpp>
#include <welkin/gl/objects.hpp>
#include <welkin/processor.hpp>
#include <welkin/time.hpp>

#include <epoxy/gl.h>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <string>
#include <vector>

using namespace welkin;

#if defined(WELKIN_HAS_ELEMENT_nightsky) && defined(WELKIN_HAS_ELEMENT_stars) && defined(WELKIN_HAS_ELEMENT_planet)
TEST_CASE("Sky: by day the elements before it draw nothing, and its unblended pass equals the blended composite", "[gl][sky][display]") {
    test::glContext();
    constexpr double kDeg = std::numbers::pi / 180.0;
    Camera cam;
    cam.azimuthRad = std::numbers::pi;  // the bench display's day view: south, 30 deg up, 60 deg
    cam.altitudeRad = 30 * kDeg;
    cam.verticalFovRad = 60 * kDeg;
    cam.width = 160;
    cam.height = 90;
    struct Frame {
        Image hdr;
        std::vector<bool> drewNothing;
    };
    auto frame = [&](const char* when, bool hostTarget) {
        SkyProcessor p;
        p.setObserver({.latitudeRad = 35.9 * kDeg, .longitudeRad = 14.5 * kDeg, .heightMeters = 50});
        p.setTime(UtcInstant::parse(when));
        p.setCamera(cam);
        for (const char* e : {"nightsky", "stars", "planet", "sky"}) p.add(elements::makeElement(e));
        Frame f;
        if (!hostTarget) {
            p.renderFrame();
            f.hdr = p.readHdr();
        } else {
            gl::Texture2D colour(cam.width, cam.height, GL_RGBA32F);
            auto fbo = gl::Framebuffer::create();
            fbo.attach(GL_COLOR_ATTACHMENT0, colour);
            fbo.bind();
            const float black[4] = {0, 0, 0, 1};
            glClearBufferfv(GL_COLOR, 0, black);
            p.renderInto({.framebuffer = fbo.id(), .width = cam.width, .height = cam.height});
            glBindFramebuffer(GL_FRAMEBUFFER, 0);
            const std::vector<float> rgba = colour.readRgbaFloat();  // bottom row first
            f.hdr.width = cam.width;
            f.hdr.height = cam.height;
            f.hdr.pixels.resize(size_t(cam.width) * cam.height * 3);
            for (int y = 0; y < cam.height; ++y)
                for (int x = 0; x < cam.width; ++x)
                    for (int c = 0; c < 3; ++c) f.hdr.at(x, y, c) = rgba[(size_t(cam.height - 1 - y) * cam.width + x) * 4 + c];
        }
        for (const auto& e : p.elements()) f.drewNothing.push_back(e->drewNothing());
        return f;
    };
    for (const char* when : {"2026-06-21T10:00:00Z", "2026-08-12T22:00:00Z"}) {
        CAPTURE(when);
        const bool day = std::string(when).find("T10") != std::string::npos;
        const Frame own = frame(when, false), host = frame(when, true);
        // By day: the night sky skipped (its zenith under 1e-5 of the Sky's), no star above the
        // limit, neither the Sun (71 deg up, above the 60 deg field) nor a planet in view. At
        // night the night sky draws (so the Sky is blended over it).
        REQUIRE(own.drewNothing.size() == 4);
        CHECK(own.drewNothing[0] == day);
        CHECK(own.drewNothing[1] == day);
        CHECK(own.drewNothing[2] == true);
        CHECK_FALSE(own.drewNothing[3]);
        double maxRel = 0, mean = 0;
        for (size_t i = 0; i < own.hdr.pixels.size(); ++i) {
            const double a = own.hdr.pixels[i], b = host.hdr.pixels[i];
            maxRel = std::max(maxRel, std::abs(a - b) / std::max(std::abs(b), 1e-30));
            mean += b;
        }
        mean /= double(own.hdr.pixels.size());
        std::printf("%s: unblended over black against the blended composite: max relative difference %.3g (image mean %.3g cd/m^2)\n",
                    when, maxRel, mean);
        CHECK(mean > (day ? 1e3 : 1e-4));
        // By day the two are different programs of the Sky (with and without the transmittance
        // output) computing the same radiance; the blend over black adds 0. Measured 0; 1e-6
        // allows the compiler one different rounding of the same sum.
        CHECK(maxRel <= 1e-6);
    }
}

// At night without the Moon's term the Sky adds no radiance, and its pass only multiplies what is
// behind it by the transmittance (sky.night_multiply: blend dst x T, without the dual-source
// output; README "The Sky's pass at twilight and at night"). The fast pass against the general
// one, each named by --stats' sky.night_multiply, over the night sky and stars actually drawn.
TEST_CASE("Sky: at night without the Moon the multiply-only pass equals the general blended pass", "[gl][sky][display]") {
    test::glContext();
    constexpr double kDeg = std::numbers::pi / 180.0;
    Camera cam;
    cam.azimuthRad = std::numbers::pi;  // the bench display's moonless view: south, 30 deg up, 60 deg
    cam.altitudeRad = 30 * kDeg;
    cam.verticalFovRad = 60 * kDeg;
    cam.width = 160;
    cam.height = 90;
    auto frame = [&](const char* when, bool multiply, bool& ran) {
        SkyProcessor p;
        p.setObserver({.latitudeRad = 35.9 * kDeg, .longitudeRad = 14.5 * kDeg, .heightMeters = 50});
        p.setTime(UtcInstant::parse(when));
        p.setCamera(cam);
        for (const char* e : {"nightsky", "stars", "planet", "sky"}) p.add(elements::makeElement(e));
        p.vars().setFromString("sky.night_multiply", multiply ? "true" : "false");
        p.renderFrame();
        ran = p.stats()["sky"]["night_multiply"].get<bool>();
        return p.readHdr();
    };
    // Moonless (new Moon 37 deg below the horizon, Sun -37 deg): the fast pass runs when allowed.
    // Moonlit (a 98 % Moon 35 deg up): it never runs (the Moon's radiance needs the general pass).
    for (const char* when : {"2026-08-12T22:00:00Z", "2026-08-26T21:00:00Z"}) {
        CAPTURE(when);
        const bool moonless = std::string(when).find("08-12") != std::string::npos;
        bool ranFast = false, ranGeneral = true;
        const Image fast = frame(when, true, ranFast), general = frame(when, false, ranGeneral);
        CHECK(ranFast == moonless);  // the flags name the paths: never a path against itself
        CHECK_FALSE(ranGeneral);
        double maxRel = 0, mean = 0;
        for (size_t i = 0; i < fast.pixels.size(); ++i) {
            const double a = fast.pixels[i], b = general.pixels[i];
            maxRel = std::max(maxRel, std::abs(a - b) / std::max(std::abs(b), 1e-30));
            mean += b;
        }
        mean /= double(fast.pixels.size());
        std::printf("%s: the Sky's multiply-only pass against the general one: max relative difference %.3g (image mean %.3g cd/m^2)\n",
                    when, maxRel, mean);
        CHECK(mean > 1e-5);  // the night sky is there (2e-4 cd/m^2 at the zenith): not a black frame
        // dst T against 0 + dst T: the same product. Measured 0; 1e-6 allows the compiler one
        // different rounding.
        CHECK(maxRel <= 1e-6);
    }
}
#endif
