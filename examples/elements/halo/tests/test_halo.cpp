// Halo (the element template): the ring lies at its radius from the Sun, its crest has the
// luminance its gain gives, and it vanishes with the Sun below the horizon.
#include <catch2/catch.hpp>

#include "gl_test_context.hpp"

#include <welkin/elements/halo.hpp>
#include <welkin/generators/lights.hpp>
#include <welkin/keys.hpp>
#include <welkin/processor.hpp>

#include <epoxy/gl.h>

#include <cmath>

using namespace welkin;

TEST_CASE("Halo: a ring at its radius from the Sun, as bright as its gain says", "[gl][halo]") {
    test::glContext();
    SkyProcessor p(SkyVars::earth(), Logger(), ProcessorOptions{.astronomy = false});  // the Sun set by hand
    Camera cam;
    cam.projection = Projection::Equirect;
    cam.width = 720;  // 0.5 deg per pixel
    cam.height = 360;
    p.setCamera(cam);
    p.setExposure({.ev100 = 10});
    p.add(std::make_unique<elements::Halo>());
    p.vars().set(keys::sunDirection, directionFromAzAlt(M_PI, 60 * M_PI / 180));  // south, 60 deg up
    p.renderFrame();
    Image img = p.readHdr();
    auto Y = [&](int x, int y) { return 0.2126 * img.at(x, y, 0) + 0.7152 * img.at(x, y, 1) + 0.0722 * img.at(x, y, 2); };
    // Down the Sun's meridian (azimuth 180 deg = column 360): the crest 22 deg below the Sun, at
    // altitude 38 deg = row (90 - 38) * 2 = 104 (pixel centre 104.5 -> 37.75 deg; one pixel).
    // (The ring also crosses the meridian above the Sun, at 82 deg: search below the Sun only.)
    int best = 60;
    for (int y = 60; y < 180; ++y)
        if (Y(360, y) > Y(360, best)) best = y;
    CHECK(std::abs((90.0 - (best + 0.5) * 0.5) - 38.0) <= 0.5);
    // Crest luminance = gain x the Sun's illuminance at the observer (lux), within the Gaussian's
    // value half a pixel off the crest (exp(-0.5 (0.25/1.5)^2) = 0.986).
    const glm::dvec3 E = p.vars().get(generators::lightkeys::sunIlluminance) * p.vars().get(generators::lightkeys::sunTransmittance);
    const double expected = 0.02 * (0.2126 * E.r + 0.7152 * E.g + 0.0722 * E.b);
    CHECK(Y(360, best) <= expected * 1.0001);
    CHECK(Y(360, best) >= expected * 0.98);
    // Far from the ring: nothing.
    CHECK(Y(0, 300) < 1e-6 * expected);
    // The Sun below the horizon: no halo at all.
    p.vars().set(keys::sunDirection, directionFromAzAlt(M_PI, -10 * M_PI / 180));
    p.renderFrame();
    Image night = p.readHdr();
    double peak = 0;
    for (float v : night.pixels) peak = std::max(peak, double(v));
    CHECK(peak == 0.0);
}
