// Grid element: lines where the angles say, luminance as documented, options validated.
#include <catch2/catch.hpp>

#include "gl_test_context.hpp"

#include <epoxy/gl.h>

#include <welkin/elements/grid.hpp>
#include <welkin/processor.hpp>

#include <cmath>

using namespace welkin;

TEST_CASE("Grid options are validated with the member's name and range", "[cpu][grid]") {
    elements::GridOptions o;
    o.altitudeStepDeg = 0;
    CHECK_THROWS_WITH(elements::Grid(o), Catch::Contains("altitudeStepDeg 0 not in [1, 90]"));
    o = {};
    o.luminanceCdM2 = -1;
    CHECK_THROWS_WITH(elements::Grid(o), Catch::Contains("luminanceCdM2 -1 not in [0, 1e+10]"));
}

TEST_CASE("Grid draws altitude and azimuth lines at their angles (equirect)", "[gl][grid]") {
    test::glContext();
    SkyProcessor p;
    Camera cam;
    cam.projection = Projection::Equirect;
    cam.width = 360;  // 1 pixel = 1 degree
    cam.height = 180;
    p.setCamera(cam);
    elements::GridOptions o;
    o.altitudeStepDeg = 30;
    o.azimuthStepDeg = 45;
    o.luminanceCdM2 = 100;
    o.markers = false;
    p.add(std::make_unique<elements::Grid>(o));
    p.renderFrame();
    Image img = p.readHdr();
    auto L = [&](int x, int y) { return 0.2126 * img.at(x, y, 0) + 0.7152 * img.at(x, y, 1) + 0.0722 * img.at(x, y, 2); };
    // Altitude 30 deg is the boundary between rows 59 and 60 (v = (90 - 30)/180 * 180 = 60):
    // a 1.5-px line covers both neighbouring rows substantially.
    CHECK(L(100, 59) + L(100, 60) > 100.0);
    CHECK(L(100, 45) < 1.0);  // altitude 44.5: between lines
    // Azimuth 45 deg is the column boundary at x = 45 (on the horizon row band, cos(alt) ~ 1).
    CHECK(L(44, 100) + L(45, 100) > 80.0);
    CHECK(L(60, 100) < 1.0);
    // The horizon (row 90) is wider and has a warmer colour than the other lines.
    CHECK(L(20, 89) > 50.0);
    CHECK(L(20, 88) > 20.0);  // 3-px horizon reaches the second row, a 1.5-px line does not
    CHECK(L(100, 57) < 1.0);
    CHECK(img.at(20, 89, 0) > img.at(20, 89, 2));
    // Explicit luminance: a fully covered pixel emits luminanceCdM2 (colour has luminance <= 1).
    double peak = 0;
    for (int x = 0; x < 360; ++x) peak = std::max(peak, L(x, 89));
    CHECK(peak <= 100.0 * 1.0001);
    CHECK(peak > 50.0);
}
