// Projections on the CPU: the documented conventions, written out independently of camera.cpp.
#include <catch2/catch.hpp>

#include <welkin/camera.hpp>
#include <welkin/error.hpp>

#include <cmath>

using namespace welkin;

namespace {
constexpr double kDeg = M_PI / 180;
}

TEST_CASE("Fisheye: the issue's formula, both ways", "[cpu][camera]") {
    Camera c;
    c.projection = Projection::Fisheye;
    c.width = c.height = 512;
    const double W = 512;
    for (double az : {0.0, 37.0, 90.0, 180.0, 270.0, 333.0}) {
        for (double alt : {0.0, 10.0, 45.0, 80.0}) {
            // r = (90 - alt)/90 * W/2, x = W/2 - r sin(az), y = H/2 - r cos(az)
            double r = (90 - alt) / 90 * W / 2;
            glm::dvec2 expected(W / 2 - r * std::sin(az * kDeg), W / 2 - r * std::cos(az * kDeg));
            auto p = c.pixelOf(directionFromAzAlt(az * kDeg, alt * kDeg));
            REQUIRE(p);
            CHECK(p->x == Approx(expected.x).margin(1e-9));
            CHECK(p->y == Approx(expected.y).margin(1e-9));
            auto d = c.directionAt(expected);
            REQUIRE(d);
            // Round trip to 1e-9 rad: pure double arithmetic.
            CHECK(glm::length(*d - directionFromAzAlt(az * kDeg, alt * kDeg)) < 1e-9);
        }
    }
    // Zenith at the centre; north up, east on the left.
    CHECK(glm::length(*c.pixelOf({0, 0, 1}) - glm::dvec2(256, 256)) < 1e-9);
    CHECK(c.pixelOf({1, 0, 0})->x == Approx(0.0).margin(1e-9));  // east horizon: left edge
    CHECK(c.pixelOf({0, 1, 0})->y == Approx(0.0).margin(1e-9));  // north horizon: top edge
    CHECK_FALSE(c.pixelOf({0, 0, -1}));                           // below the horizon
    CHECK_FALSE(c.directionAt({2, 2}));                           // corner: outside the circle
}

TEST_CASE("Equirect: u = az/360 from north through east, zenith on the top row", "[cpu][camera]") {
    Camera c;
    c.projection = Projection::Equirect;
    c.width = 720;
    c.height = 360;
    auto p = c.pixelOf(directionFromAzAlt(90 * kDeg, 30 * kDeg));
    CHECK(p->x == Approx(180.0));
    CHECK(p->y == Approx(120.0));  // (90 - 30)/180 * 360
    CHECK(c.directionAt({0.0, 0.0})->z == Approx(1.0));
    CHECK(c.directionAt({360.0, 360.0})->z == Approx(-1.0));
}

TEST_CASE("Perspective: the view direction is at the centre, the zenith is up", "[cpu][camera]") {
    Camera c;
    c.azimuthRad = 120 * kDeg;
    c.altitudeRad = 15 * kDeg;
    c.verticalFovRad = 50 * kDeg;
    c.width = 400;
    c.height = 200;
    auto centre = c.pixelOf(directionFromAzAlt(120 * kDeg, 15 * kDeg));
    CHECK(centre->x == Approx(200.0));
    CHECK(centre->y == Approx(100.0));
    // A direction 25 deg (half the vertical FOV) above the view direction is on the top edge.
    CHECK(c.pixelOf(directionFromAzAlt(120 * kDeg, 40 * kDeg))->y == Approx(0.0).margin(1e-9));
    CHECK_FALSE(c.pixelOf(directionFromAzAlt(300 * kDeg, -15 * kDeg)));  // behind
    // Looking straight up stays well defined.
    c.altitudeRad = 90 * kDeg;
    auto up = c.directionAt({200, 100});
    CHECK(up->z == Approx(1.0));
}

TEST_CASE("Cube faces follow the OpenGL order with x east, y up, z south", "[cpu][camera]") {
    Camera c;
    c.projection = Projection::CubeFace;
    c.width = c.height = 64;
    const glm::dvec3 axes[6] = {{1, 0, 0}, {-1, 0, 0}, {0, 0, 1}, {0, 0, -1}, {0, -1, 0}, {0, 1, 0}};  // ENU
    for (int f = 0; f < 6; ++f) {
        c.cubeFace = f;
        CHECK(glm::length(*c.directionAt({32, 32}) - axes[f]) < 1e-12);
        for (auto px : {glm::dvec2(5.5, 17.25), glm::dvec2(60, 3)}) {
            auto d = c.directionAt(px);
            auto back = c.pixelOf(*d);
            REQUIRE(back);
            CHECK(glm::length(*back - px) < 1e-9);
        }
    }
}

TEST_CASE("Camera validation names the member", "[cpu][camera]") {
    Camera c;
    c.width = 0;
    CHECK_THROWS_WITH(c.validate(), Catch::Contains("width 0 not in [1, 16384]"));
    c.width = 10;
    c.verticalFovRad = 4;
    CHECK_THROWS_WITH(c.validate(), Catch::Contains("verticalFovRad"));
    CHECK_THROWS_WITH(parseProjection("mercator"), Catch::Contains("perspective, fisheye, equirect, cube"));
}
