// Grid element, equatorial frame (grid.frame = equatorial): the celestial pole where the latitude
// puts it, due north, and an hour circle through a star's apparent place, against the astronomy's
// own observer frame and refraction.
#include <catch2/catch.hpp>

#include "gl_test_context.hpp"
#include "malta_night.hpp"

#include <welkin/astro/earth.hpp>
#include <welkin/astro/frames.hpp>
#include <welkin/astro/timescales.hpp>
#include <welkin/elements/grid.hpp>
#include <welkin/image.hpp>
#include <welkin/processor.hpp>
#include <welkin/time.hpp>

#include <cmath>
#include <numbers>

using namespace welkin;
using namespace welkin::elements;

namespace {
constexpr double kDeg = std::numbers::pi / 180.0;

using test::atMalta;
using test::fisheye;
using test::lum;
using Sky = test::MaltaSky;
const UtcInstant kWhen = test::kMaltaNight;
const double kLat = test::kMaltaLatRad, kLon = test::kMaltaLonRad;
Sky maltaSky() { return test::maltaSky(); }
}  // namespace

TEST_CASE("Grid: the equatorial grid puts the celestial pole at the latitude, due north, and hour circles through the stars",
          "[gl][grid]") {
    test::glContext();
    const Camera cam = fisheye(1024);
    SkyProcessor p;
    atMalta(p, cam);
    GridOptions o;
    o.frame = "equatorial";
    o.luminanceCdM2 = 1.0;
    o.markers = false;
    p.add(std::make_unique<Grid>(o));
    p.renderFrame();
    Image img = p.readHdr();
    // Along the north meridian (the centre column, x = 512 between columns 511 and 512) the
    // circle of declination +80 deg crosses at altitudes lat - 10 and lat + 10 (+ refraction,
    // ~1.3'), and its centre is the pole: an equidistant fisheye maps altitude linearly, so the
    // mid-point of the two crossings is the pole's altitude.
    const double R = 512.0, pxPerRad = R / (0.5 * std::numbers::pi);
    auto rowOfAlt = [&](double alt) { return 512.0 - (0.5 * std::numbers::pi - alt) * pxPerRad; };
    auto peakRow = [&](double altLo, double altHi) {
        double w = 0, m = 0;
        for (int y = int(rowOfAlt(altLo)); y <= int(rowOfAlt(altHi)); ++y) {  // north is up: rows grow with altitude
            const double L = lum(img, 511, y) + lum(img, 512, y);
            w += L;
            m += L * (y + 0.5);
        }
        REQUIRE(w > 0.5);
        return m / w;
    };
    // The J2000 pole is 0.36 deg from the pole of date (precession since 2000), which is where
    // the latitude puts it: windows of +-3 deg hold each crossing either way.
    const double yLow = peakRow((35.9 - 13) * kDeg, (35.9 - 7) * kDeg);
    const double yHigh = peakRow((35.9 + 7) * kDeg, (35.9 + 13) * kDeg);
    const double poleAlt = 0.5 * std::numbers::pi - (512.0 - 0.5 * (yLow + yHigh)) / pxPerRad;
    // Reference: the ICRS pole (0, 0, 1) through the astronomy's own frame, then refraction.
    const Sky sky = maltaSky();
    const glm::dvec3 pole = sky.apparent(glm::dvec3(0, 0, 1));
    const glm::dvec2 polePx = *cam.pixelOf(pole);
    INFO("pole drawn at row " << 0.5 * (yLow + yHigh) << ", predicted " << polePx.y << "; altitude " << poleAlt / kDeg);
    CHECK(std::abs(0.5 * (yLow + yHigh) - polePx.y) < 1.0);  // the pixel check
    // The pole of date is exactly at the latitude; the J2000 pole within its 0.36 deg precession
    // shift (2 px here) of it.
    CHECK(std::abs(poleAlt - kLat) < 0.4 * kDeg);
    // Due north: the predicted pixel is within 2 px (the 0.36 deg shift) of the centre column.
    CHECK(std::abs(polePx.x - 512.0) < 2.5);

    // An hour circle through a star: no bright star sits on a whole hour of J2000 RA (Alpheratz,
    // 00h08m23s, is 2.1 deg off the 0 h circle), so the RA step is set to Vega's RA (18h36m56.3s,
    // i.e. -80.7653 deg) so that the circle at -1 step is Vega's hour circle.
    const double vegaRa = 279.23473 * kDeg, vegaDec = 38.78369 * kDeg;
    p.vars().set(gridkeys::raStep, 2 * std::numbers::pi - vegaRa);  // circles at 0, +-80.77, +-161.5 deg
    p.vars().set(gridkeys::decStep, 45 * kDeg);  // hour circles stop at +-45 deg; Vega (+38.8) is 35 px from that circle
    p.renderFrame();
    img = p.readHdr();
    const glm::dvec2 vega = *cam.pixelOf(sky.apparent(astro::directionFromRaDec(vegaRa, vegaDec)));
    // Luminance-weighted centre across the hour circle near Vega, along the image row (the
    // circle runs roughly north-south there): within a pixel of Vega.
    double w = 0, m = 0;
    for (int x = int(vega.x) - 6; x <= int(vega.x) + 6; ++x) {
        const double L = lum(img, x, int(vega.y));
        w += L;
        m += L * (x + 0.5);
    }
    INFO("Vega at " << vega.x << ", " << vega.y << ", hour circle at x = " << m / w);
    REQUIRE(w > 0.5);
    CHECK(std::abs(m / w - vega.x) < 1.0);

    // grid.frame is an enumerated key: refused where it is set.
    CHECK_THROWS_WITH(p.vars().set(gridkeys::frame, std::string("galactic")), "key 'grid.frame': 'galactic' is not one of horizontal, equatorial, both");
}
