// Grid element: the ecliptic (grid.ecliptic) passes through the Sun, along the ecliptic.
#include <catch2/catch.hpp>

#include "gl_test_context.hpp"

#include <welkin/astro/astro_keys.hpp>
#include <welkin/astro/bodies.hpp>
#include <welkin/astro/frames.hpp>
#include <welkin/astro/timescales.hpp>
#include <welkin/elements/grid.hpp>
#include <welkin/processor.hpp>

#include <cmath>
#include <numbers>

using namespace welkin;

namespace {
constexpr double kDeg = std::numbers::pi / 180.0;
double lum(const Image& img, int x, int y) { return 0.2126 * img.at(x, y, 0) + 0.7152 * img.at(x, y, 1) + 0.0722 * img.at(x, y, 2); }
}  // namespace

TEST_CASE("Grid: the ecliptic passes through the Sun's place, along the ecliptic", "[gl][grid]") {
    test::glContext();
    // Malta by day, at the June solstice season and at the March equinox (the ecliptic then
    // highest above the equator and crossing it): the Sun is on the ecliptic by definition.
    const char* instant = GENERATE("2018-07-01T10:00:00Z", "2018-03-20T14:00:00Z");
    const UtcInstant t = UtcInstant::parse(instant);
    const astro::Site site{35.90 * kDeg, 14.51 * kDeg, 0.0};
    astro::Ephemeris eph;  // what `welkin astro` prints
    eph.update(astro::observerFrame(site, astro::timeScales(t), astro::Path::Fast));
    const astro::BodyState& sun = eph[astro::Body::Sun];
    Camera cam;
    cam.azimuthRad = sun.topo.azimuthRad;
    cam.altitudeRad = sun.topo.altitudeRad;
    cam.verticalFovRad = 20 * kDeg;  // 6.4 px per degree
    cam.width = cam.height = 128;
    auto render = [&](bool ecliptic, glm::dmat3* icrsToEnu) {
        SkyProcessor p;
        p.setTime(t);
        p.setObserver({site.latitudeRad, site.longitudeRad, 0.0});
        p.setCamera(cam);
        elements::GridOptions o;
        o.frame = "equatorial";
        o.luminanceCdM2 = 1.0;
        o.ecliptic = ecliptic;
        p.add(std::make_unique<elements::Grid>(o));
        p.renderFrame();
        if (icrsToEnu) *icrsToEnu = p.vars().get(astro::keys::starFrameRotation);
        return p.readHdr();
    };
    glm::dmat3 R(1.0);
    const Image off = render(false, nullptr), on = render(true, &R);
    const glm::dvec2 sunPx = *cam.pixelOf(directionFromAzAlt(sun.topo.azimuthRad, sun.topo.altitudeRad));
    // The ecliptic's pixels within 12 px of the Sun: their luminance-weighted principal axis.
    double sw = 0, sx = 0, sy = 0, sxx = 0, syy = 0, sxy = 0, red = 0, blue = 0;
    int n = 0;
    for (int y = 0; y < cam.height; ++y)
        for (int x = 0; x < cam.width; ++x) {
            const double w = lum(on, x, y) - lum(off, x, y);
            const double dx = x + 0.5 - sunPx.x, dy = y + 0.5 - sunPx.y;
            if (w <= 0.05 || dx * dx + dy * dy > 144) continue;
            ++n;
            red += on.at(x, y, 0), blue += on.at(x, y, 2);
            sw += w, sx += w * dx, sy += w * dy, sxx += w * dx * dx, syy += w * dy * dy, sxy += w * dx * dy;
        }
    INFO(instant << ": " << n << " ecliptic pixels near the Sun at (" << sunPx.x << ", " << sunPx.y << ")");
    REQUIRE(n >= 20);  // a 1.5 px line across a 24 px disk
    const double mx = sx / sw, my = sy / sw;
    const double cxx = sxx / sw - mx * mx, cyy = syy / sw - my * my, cxy = sxy / sw - mx * my;
    const double angle = 0.5 * std::atan2(2 * cxy, cxx - cyy);  // the line's direction, image axes
    const glm::dvec2 u(std::cos(angle), std::sin(angle));
    // The Sun's distance from the fitted line: within 1 px (the Sun is < 1" off the ecliptic of
    // date, itself < 10" from the J2000 ecliptic drawn in 2018: 0.02 px here; the rest is the
    // line's antialiasing, symmetric about its centre).
    const double dist = std::abs(-mx * u.y + my * u.x);
    INFO("line through (" << mx << ", " << my << ") from the Sun, direction " << angle / kDeg << " deg; Sun off by " << dist << " px");
    CHECK(dist < 1.0);
    // Its direction is the ecliptic's: the points 3 deg either side of the Sun along the J2000
    // ecliptic (the Sun's direction turned about the ecliptic pole), projected the same way.
    const double eps = 84381.406 / 3600.0 * kDeg;
    const glm::dvec3 pole = R * glm::dvec3(0.0, -std::sin(eps), std::cos(eps));
    auto along = [&](double a) {
        const glm::dvec3 s = directionFromAzAlt(sun.topo.azimuthRad, sun.topo.altitudeGeometricRad);
        const glm::dvec3 r = s * std::cos(a) + glm::cross(pole, s) * std::sin(a) + pole * glm::dot(pole, s) * (1 - std::cos(a));
        const astro::Horizontal h = astro::horizontalFromEnu(r);
        return *cam.pixelOf(directionFromAzAlt(h.azimuthRad, astro::apparentFromGeometricAltitude(h.altitudeRad, 1013.25, 10.0)));
    };
    const glm::dvec2 e = glm::normalize(along(3 * kDeg) - along(-3 * kDeg));
    const double offAxisDeg = std::asin(std::min(1.0, std::abs(e.x * u.y - e.y * u.x))) / kDeg;
    INFO("ecliptic direction differs by " << offAxisDeg << " deg");
    CHECK(offAxisDeg < 3.0);  // a 24 px segment: 1 px across its end is 5 deg; 3 deg leaves room for the fit
    // The line is the ecliptic's golden one (2, 1.56, 0.4) x the luminance, not a green equatorial line.
    CHECK(red > 2 * blue);
}
