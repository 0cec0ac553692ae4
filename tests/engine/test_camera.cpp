// Projections on the CPU: the documented conventions, written out independently of camera.cpp.
#include <catch2/catch.hpp>

#include "camera_cases.hpp"

#include <welkin/camera.hpp>
#include <welkin/error.hpp>

#include <cmath>
#include <optional>
#include <string>
#include <vector>

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

// ---- Both ways: direction -> clip -> pixel -> direction ----------------------------------------

namespace {
// The cameras every two-way test runs through: perspective at 0.5, 60 and 179 deg (looking up,
// down, straight up and straight down), fisheye square and not, equirect, each cube face.
std::vector<Camera> allCameras() {
    std::vector<Camera> out;
    auto persp = [&](double fovDeg, double azDeg, double altDeg, int w, int h) {
        Camera c;
        c.verticalFovRad = fovDeg * kDeg;
        c.azimuthRad = azDeg * kDeg;
        c.altitudeRad = altDeg * kDeg;
        c.width = w;
        c.height = h;
        out.push_back(c);
    };
    persp(0.5, 200, 35, 64, 48);
    persp(60, 10, -20, 64, 48);
    persp(60, -100, 90, 48, 64);
    persp(179, 300, 5, 64, 48);
    persp(179, 45, -90, 40, 40);
    test::appendNonPerspectiveCameras(out);
    return out;
}

std::string describe(const Camera& c) {
    return std::string(toString(c.projection)) + " " + std::to_string(c.width) + "x" + std::to_string(c.height) +
           " fov " + std::to_string(c.verticalFovRad / kDeg) + " az " + std::to_string(c.azimuthRad / kDeg) + " alt " +
           std::to_string(c.altitudeRad / kDeg) + " face " + std::to_string(c.cubeFace);
}

// Deterministic uniform directions on the sphere (z uniform in [-1, 1], azimuth uniform).
std::vector<glm::dvec3> sphereDirections(int n, unsigned seed) {
    std::vector<glm::dvec3> out;
    unsigned s = seed;
    auto next = [&] {
        s = s * 1664525u + 1013904223u;
        return (s >> 8) / double(1u << 24);
    };
    for (int i = 0; i < n; ++i) {
        double z = 2 * next() - 1, phi = 2 * M_PI * next(), r = std::sqrt(1 - z * z);
        out.push_back({r * std::cos(phi), r * std::sin(phi), z});
    }
    return out;
}

double angleBetween(const glm::dvec3& a, const glm::dvec3& b) {
    return std::atan2(glm::length(glm::cross(a, b)), glm::dot(a, b));
}
}  // namespace

TEST_CASE("clipFromDirection agrees with pixelOf and directionAt, every projection", "[cpu][camera]") {
    for (const Camera& c : allCameras()) {
        INFO(describe(c));
        int inFrame = 0;
        for (const glm::dvec3& d : sphereDirections(2000, 7)) {
            auto p = c.pixelOf(d);
            auto clip = c.clipFromDirection(d);
            REQUIRE(bool(p) == bool(clip));  // nullopt exactly when pixelOf() is
            if (!clip) continue;
            INFO("direction " << d.x << " " << d.y << " " << d.z);
            CHECK(clip->z == clip->w);  // the far plane
            REQUIRE(clip->w > 0);
            glm::dvec2 q = c.pixelFromClip(*clip);
            // Two double-precision formulas of the same position: 1e-9 relative.
            CHECK(glm::length(q - *p) <= 1e-9 * std::max(1.0, glm::length(*p)));
            // Inside the clip volume exactly when the pixel position is inside the image.
            const bool inside = std::abs(clip->x) <= clip->w && std::abs(clip->y) <= clip->w;
            const bool onImage = q.x >= 0 && q.x <= c.width && q.y >= 0 && q.y <= c.height;
            CHECK(inside == onImage);
            if (!onImage) continue;
            ++inFrame;
            auto back = c.directionAt(q);
            REQUIRE(back);
            // Back to the direction: double arithmetic, 1e-9 rad (1e-5 of the smallest pixel here).
            CHECK(angleBetween(*back, d) < 1e-9);
        }
        // The other way: pixel -> direction -> clip -> the same pixel, for pixel positions that
        // do not come from pixelOf (a jittered grid, centres and corners alike).
        for (double y = 0.25; y < c.height; y += c.height / 7.0 + 0.13) {
            for (double x = 0.1; x < c.width; x += c.width / 9.0 + 0.07) {
                auto d = c.directionAt({x, y});
                if (!d) continue;  // a fisheye corner
                auto clip = c.clipFromDirection(*d);
                REQUIRE(clip);
                INFO("pixel " << x << ", " << y);
                CHECK(glm::length(c.pixelFromClip(*clip) - glm::dvec2(x, y)) < 1e-9 * c.width);
            }
        }
        // Sphere sampling reaches every frame but the 0.5-degree one (covering 2e-5 of the sphere).
        if (c.verticalFovRad > 1 * kDeg || c.projection != Projection::Perspective) CHECK(inFrame > 0);
    }
}

TEST_CASE("Invisible directions have no clip position", "[cpu][camera]") {
    Camera c;  // perspective looking at az 0, alt 0.35 rad
    CHECK_FALSE(c.clipFromDirection(-directionFromAzAlt(c.azimuthRad, c.altitudeRad)));  // behind
    auto side = c.clipFromDirection(directionFromAzAlt(c.azimuthRad + 80 * kDeg, 0.0));  // in front, off the frame
    REQUIRE(side);
    CHECK(side->x > side->w);
    c.projection = Projection::Fisheye;
    CHECK_FALSE(c.clipFromDirection(directionFromAzAlt(1.0, -0.01)));  // below the horizon
    CHECK(c.clipFromDirection(directionFromAzAlt(1.0, 0.0)));           // on it
    c.projection = Projection::CubeFace;
    c.cubeFace = 2;                                                     // +Y: the zenith face
    CHECK_FALSE(c.clipFromDirection(directionFromAzAlt(0.3, 40 * kDeg)));  // 50 deg from the axis: a side face
    CHECK(c.clipFromDirection(directionFromAzAlt(0.3, 50 * kDeg)));
    CHECK_THROWS_WITH(c.clipFromDirection({0, 0, 0}), Catch::Contains("Camera::clipFromDirection(): direction has zero length"));
    CHECK_THROWS_WITH(c.clipFromDirection({0, 0, 1}, 2), Catch::Contains("copy 2 not in [0, 1]"));
    CHECK_THROWS_WITH(c.pixelFromClip({0, 0, 0, -1}), Catch::Contains("not > 0"));
}

TEST_CASE("Equirect seam: a direction within half a pixel of it has a twin on the other side", "[cpu][camera]") {
    Camera c;
    c.projection = Projection::Equirect;
    c.width = 720;
    c.height = 360;
    const double W = c.width;
    for (double x : {0.25, 0.499, W - 0.25, W - 0.499}) {
        INFO("x " << x);
        // Azimuth of pixel position x, written from the documented convention u = az / 2pi.
        glm::dvec3 d = directionFromAzAlt(2 * M_PI * x / W, 12 * kDeg);
        glm::dvec2 p0 = c.pixelFromClip(*c.clipFromDirection(d, 0));
        glm::dvec2 p1 = c.pixelFromClip(*c.clipFromDirection(d, 1));
        CHECK(p0.x == Approx(x).margin(1e-9));
        // The twin is one image width away, beyond the edge that the sprite straddles.
        CHECK(p1.x == Approx(x < W / 2 ? x + W : x - W).margin(1e-9));
        CHECK(p1.y == Approx(p0.y).margin(1e-12));
        // ... and it is the same direction (directionAt does not wrap; its sine and cosine do).
        CHECK(angleBetween(*c.directionAt(p1), d) < 1e-9);
    }
    // Other projections have no twin.
    c.projection = Projection::Fisheye;
    CHECK_FALSE(c.clipFromDirection({0, 0, 1}, 1));
}

TEST_CASE("pixelJacobian and pixelScale match finite differences of pixelOf", "[cpu][camera]") {
    for (const Camera& c : allCameras()) {
        INFO(describe(c));
        int checked = 0;
        auto dirs = sphereDirections(400, 11);
        // Directions in every frame, including the 0.5-degree one: through a grid of pixels.
        for (double y = 1.3; y < c.height; y += c.height / 5.0)
            for (double x = 0.7; x < c.width; x += c.width / 5.0)
                if (auto d = c.directionAt({x, y})) dirs.push_back(*d);
        for (const glm::dvec3& d : dirs) {
            auto J = c.pixelJacobian(d);
            auto S = c.pixelScale(d);
            REQUIRE(bool(J) == bool(c.pixelOf(d)));
            REQUIRE(bool(S) == bool(J));
            if (!J) continue;
            auto aa = azAltFromDirection(d);
            if (c.projection == Projection::Equirect && std::abs(aa.y) > 89 * kDeg) continue;  // near the capped poles
            if (c.projection == Projection::Fisheye && aa.y < 1e-4) continue;  // the horizon: pixelOf's edge
            // A tangent frame at d (any will do: the scale is frame-independent).
            glm::dvec3 t1 = glm::normalize(glm::cross(std::abs(d.z) < 0.9 ? glm::dvec3(0, 0, 1) : glm::dvec3(1, 0, 0), d));
            glm::dvec3 t2 = glm::cross(d, t1);
            // Central differences over 1e-6 rad: truncation ~1e-12 relative, rounding ~1e-16 *
            // |pixel| / 1e-6; 1e-6 relative covers both with margin.
            const double h = 1e-6;
            auto fd = [&](const glm::dvec3& t) -> std::optional<glm::dvec2> {
                auto a = c.pixelOf(std::cos(h) * d + std::sin(h) * t), b = c.pixelOf(std::cos(h) * d - std::sin(h) * t);
                if (!a || !b) return std::nullopt;
                glm::dvec2 diff = *a - *b;
                if (c.projection == Projection::Equirect) diff.x -= std::round(diff.x / c.width) * c.width;  // across the seam
                return diff / (2 * h);
            };
            // Within an image size of the frame (far off a perspective frame, near 90 deg from
            // its axis, the pixel position and its derivatives diverge).
            glm::dvec2 p = *c.pixelOf(d);
            if (std::abs(p.x / c.width - 0.5) > 1.5 || std::abs(p.y / c.height - 0.5) > 1.5) continue;
            auto f1 = fd(t1), f2 = fd(t2);
            if (!f1 || !f2) continue;
            const double scale = std::max({glm::length(*f1), glm::length(*f2), 1.0});
            INFO("direction " << d.x << " " << d.y << " " << d.z);
            CHECK(glm::length(*J * t1 - *f1) < 1e-6 * scale);
            CHECK(glm::length(*J * t2 - *f2) < 1e-6 * scale);
            CHECK(glm::length(*J * d) < 1e-9 * scale);  // no radial component
            // Singular values by brute force: the shortest and longest image of a unit tangent,
            // over 720 angles then refined by golden-section search (independent of the closed
            // form in pixelScale(); converged to ~1e-12).
            auto len = [&](double phi) { return glm::length(std::cos(phi) * *f1 + std::sin(phi) * *f2); };
            auto refine = [&](double phi0, double sign) {
                double a = phi0 - M_PI / 720, b = phi0 + M_PI / 720;
                const double g = (std::sqrt(5.0) - 1) / 2;
                for (int it = 0; it < 80; ++it) {
                    double x1 = b - g * (b - a), x2 = a + g * (b - a);
                    if (sign * len(x1) < sign * len(x2)) b = x2; else a = x1;
                }
                return len((a + b) / 2);
            };
            double phiLo = 0, phiHi = 0;
            for (int k = 0; k < 720; ++k) {
                double phi = k * M_PI / 720;  // half a turn: the image of -t is minus that of t
                if (len(phi) < len(phiLo)) phiLo = phi;
                if (len(phi) > len(phiHi)) phiHi = phi;
            }
            const double lo = refine(phiLo, 1), hi = refine(phiHi, -1);
            CHECK(S->x == Approx(lo).epsilon(2e-6));
            CHECK(S->y == Approx(hi).epsilon(2e-6));
            ++checked;
        }
        CHECK(checked > 0);
    }
}

TEST_CASE("pixelScale: the documented closed forms", "[cpu][camera]") {
    Camera p;
    p.width = 400;
    p.height = 200;
    p.verticalFovRad = 50 * kDeg;
    // Perspective, at the view direction: H / (2 tan(fov/2)) both ways.
    auto s = *p.pixelScale(directionFromAzAlt(p.azimuthRad, p.altitudeRad));
    CHECK(s.x == Approx(200 / (2 * std::tan(25 * kDeg))));
    CHECK(s.y == Approx(s.x));
    Camera f;
    f.projection = Projection::Fisheye;
    f.width = f.height = 512;
    // Fisheye (equidistant): radially R/(pi/2) everywhere; along the azimuth R/(pi/2) * theta/sin(theta),
    // so at the zenith both are 2R/pi and at the horizon the azimuthal one is R.
    s = *f.pixelScale({0, 0, 1});
    CHECK(s.x == Approx(512 / M_PI));
    CHECK(s.y == Approx(512 / M_PI));
    s = *f.pixelScale(directionFromAzAlt(2.0, 0.0));
    CHECK(s.x == Approx(512 / M_PI));
    CHECK(s.y == Approx(256.0));
    Camera e;
    e.projection = Projection::Equirect;
    e.width = 720;
    e.height = 360;
    // Equirect: H/pi vertically, W/(2pi cos alt) horizontally.
    s = *e.pixelScale(directionFromAzAlt(1.0, 60 * kDeg));
    CHECK(s.x == Approx(360 / M_PI));
    CHECK(s.y == Approx(720 / (2 * M_PI * 0.5)));
    // At the pole the horizontal scale is capped at cos alt = 1e-6 rather than infinite.
    CHECK(e.pixelScale({0, 0, 1})->y == Approx(720 / (2 * M_PI * 1e-6)));
}
