// Issue 23 item 5, the extreme grid: every registered element at once (the list comes from the
// registry: a new element is swept without editing this file) over the extremes of every input
// — latitude, longitude, year, observer height, the Sun and the Moon at zenith, horizon and
// nadir (places found with the astronomy code), fields of view, projections and image sizes —
// with every HDR and tone-mapped pixel finite; and every bad value of those inputs refused by
// `welkin render` with a one-line error naming the option.
//
// Sampling: not the Cartesian product (5 x 3 x 4 x 5 x 6 x 3 x 2 = 10,800 frames), but each axis
// swept with the others at their defaults, plus corners that combine the extremes; every value
// of every axis is visited.
#include <catch2/catch.hpp>

#include "cli_runner.hpp"
#include "elements_present.hpp"
#include "gl_test_context.hpp"

#include <welkin/astro/bodies.hpp>
#include <welkin/astro/timescales.hpp>
#include <welkin/elements/registry.hpp>
#include <welkin/keys.hpp>
#include <welkin/processor.hpp>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

using namespace welkin;

namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

struct GridCase {
    std::string what;
    std::string time = "2026-06-21T12:00:00Z";
    double latDeg = 48.0, lonDeg = 11.0, heightM = 0.0;
    Projection projection = Projection::Perspective;
    double azDeg = 180.0, altDeg = 20.0, fovDeg = 90.0;
    int cubeFace = 0;
    int width = 16, height = 8;
    // The body the case puts at a place in the sky, checked against sun.direction / moon.direction
    // after the frame (the case's own set-up must be right): 'S' Sun, 'M' Moon, 0 none.
    char body = 0;
    double bodyAltDeg = 0.0;
};

// Moves a point on the sphere by `distRad` along the great circle leaving it at azimuth `azRad`
// (negative: the other way).
void moveAlong(double& latRad, double& lonRad, double azRad, double distRad) {
    const double lat2 = std::asin(std::clamp(std::sin(latRad) * std::cos(distRad) + std::cos(latRad) * std::sin(distRad) * std::cos(azRad), -1.0, 1.0));
    const double lon2 = lonRad + std::atan2(std::sin(azRad) * std::sin(distRad) * std::cos(latRad),
                                            std::cos(distRad) - std::sin(latRad) * std::sin(lat2));
    latRad = lat2;
    lonRad = std::remainder(lon2, 2 * std::numbers::pi);
}

// A place (on the ground) where `body` stands at apparent altitude `targetAltDeg` at `iso`,
// from the astronomy code: start under the body (its geocentric declination, and its right
// ascension less Greenwich sidereal time), then move the observer toward the body's azimuth by
// the altitude still missing (a step of the observer moves the zenith by as much); converges in
// a few steps (the Moon's parallax, up to 1 deg, is the only correction).
GridCase bodyAt(astro::Body body, double targetAltDeg, const std::string& iso, const std::string& what) {
    const UtcInstant t = UtcInstant::parse(iso);
    const astro::TimeScales ts = astro::timeScales(t);
    astro::Site site{};
    astro::BodyState s = astro::computeBody(body, astro::observerFrame(site, ts, astro::Path::Fast));
    double lat = s.decRad, lon = std::remainder(s.raRad - astro::observerFrame(site, ts, astro::Path::Fast).lastRad, 2 * std::numbers::pi);
    for (int i = 0; i < 8; ++i) {
        site.latitudeRad = lat;
        site.longitudeRad = lon;
        s = astro::computeBody(body, astro::observerFrame(site, ts, astro::Path::Fast));
        moveAlong(lat, lon, s.topo.azimuthRad, targetAltDeg * kDeg - s.topo.altitudeRad);
    }
    site.latitudeRad = lat;
    site.longitudeRad = lon;
    s = astro::computeBody(body, astro::observerFrame(site, ts, astro::Path::Fast));
    GridCase c;
    c.what = what;
    c.time = iso;
    c.latDeg = lat / kDeg;
    c.lonDeg = lon / kDeg;
    c.azDeg = s.topo.azimuthRad / kDeg;
    c.altDeg = std::clamp(s.topo.altitudeRad / kDeg, -90.0, 90.0);  // the camera looks at the body
    c.body = body == astro::Body::Sun ? 'S' : 'M';
    c.bodyAltDeg = targetAltDeg;
    return c;
}

std::vector<GridCase> gridCases() {
    std::vector<GridCase> cases;
    auto add = [&](std::string what, auto&& edit) {
        GridCase c;
        c.what = std::move(what);
        edit(c);
        cases.push_back(c);
    };
    for (double lat : {-90.0, -66.56, 0.0, 66.56, 90.0})
        add("lat " + std::to_string(lat), [&](GridCase& c) { c.latDeg = lat; });
    for (double lon : {-180.0, 0.0, 180.0})
        add("lon " + std::to_string(lon), [&](GridCase& c) { c.lonDeg = lon; });
    // The astronomy's years [-2000, 6000] (VSOP87's span) and the Gregorian calendar's first day.
    for (const char* t : {"-2000-01-01T12:00:00Z", "1582-10-15T12:00:00Z", "2026-06-21T12:00:00Z", "6000-12-31T12:00:00Z"})
        add(std::string("time ") + t, [&](GridCase& c) { c.time = t; });
    for (double h : {-10.0, 0.0, 8848.0, 100e3, 36000e3})
        add("height " + std::to_string(h), [&](GridCase& c) {
            c.heightM = h;
            c.altDeg = -30;  // from orbit the Earth is below the horizon: look down at it too
        });
    // The Sun and the Moon at zenith, horizon and nadir, the camera looking straight at them
    // (at zenith and nadir: straight up and down, where the camera's azimuth is degenerate).
    for (auto [body, name, iso] : {std::tuple{astro::Body::Sun, "Sun", "2026-03-20T12:00:00Z"},
                                   std::tuple{astro::Body::Moon, "Moon", "2026-07-29T20:00:00Z"}})
        for (auto [alt, where] : {std::pair{90.0, "zenith"}, std::pair{0.0, "horizon"}, std::pair{-90.0, "nadir"}})
            cases.push_back(bodyAt(body, alt, iso, std::string(name) + " at " + where));
    // Fields of view: 0.5 deg and 90 deg perspective, nearly 180 deg perspective (its limit is
    // open), and 180 deg as the fisheye's all-sky field.
    for (double fov : {0.5, 90.0, 179.9})
        add("fov " + std::to_string(fov), [&](GridCase& c) { c.fovDeg = fov; });
    add("fov 180 (fisheye)", [](GridCase& c) { c.projection = Projection::Fisheye; });
    add("equirect", [](GridCase& c) { c.projection = Projection::Equirect; });
    for (int face = 0; face < 6; ++face)
        add("cube face " + std::to_string(face), [&](GridCase& c) {
            c.projection = Projection::CubeFace;
            c.cubeFace = face;
            c.width = c.height = 4;
        });
    add("size 1x1", [](GridCase& c) { c.width = c.height = 1; });
    add("size 4096x64", [](GridCase& c) {
        c.width = 4096;
        c.height = 64;
    });
    // Corners: the extremes together.
    add("corner: south pole, -2000, -10 m, 0.5 deg straight down, 1x1", [](GridCase& c) {
        c.latDeg = -90;
        c.lonDeg = -180;
        c.time = "-2000-01-01T00:00:00Z";
        c.heightM = -10;
        c.fovDeg = 0.5;
        c.altDeg = -90;
        c.width = c.height = 1;
    });
    add("corner: north pole, 6000, 36,000 km, fisheye", [](GridCase& c) {
        c.latDeg = 90;
        c.lonDeg = 180;
        c.time = "6000-12-31T23:00:00Z";
        c.heightM = 36000e3;
        c.projection = Projection::Fisheye;
    });
    add("corner: polar circle, 1582, Everest, 179.9 deg straight up", [](GridCase& c) {
        c.latDeg = 66.56;
        c.lonDeg = 0;
        c.time = "1582-10-15T00:00:00Z";
        c.heightM = 8848;
        c.fovDeg = 179.9;
        c.altDeg = 90;
    });
    add("corner: antarctic circle, 100 km, 4096x64 equirect", [](GridCase& c) {
        c.latDeg = -66.56;
        c.lonDeg = 180;
        c.heightM = 100e3;
        c.projection = Projection::Equirect;
        c.width = 4096;
        c.height = 64;
    });
    return cases;
}

// The first non-finite value in `img` ("(x, y) channel c = nan"), or "".
std::string firstNonFinite(const Image& img) {
    for (size_t i = 0; i < img.pixels.size(); ++i)
        if (!std::isfinite(img.pixels[i])) {
            const size_t px = i / size_t(img.channels);
            return "(" + std::to_string(px % size_t(img.width)) + ", " + std::to_string(px / size_t(img.width)) + ") channel " +
                   std::to_string(i % size_t(img.channels)) + " = " + std::to_string(img.pixels[i]);
        }
    return {};
}

}  // namespace

TEST_CASE("Extreme grid: every registered element, every extreme input, every pixel finite", "[gl][extreme]") {
    test::glContext();
    Logger log;  // warnings (e.g. the below-ground clamp at -10 m) are expected here
    SkyProcessor sky(SkyVars::earth(), log);
    const std::vector<std::string> names = elements::knownElements();
    // Every element folder present (the [registry] test checks this list against the folders; all
    // of them: sky, planet, stars, nightsky, clouds, rainbow, grid, constellations, halos).
    REQUIRE(!names.empty());
    for (const std::string& n : names) sky.add(elements::makeElement(n));
    // Rain in the user's curtain and under the clouds, so the rainbow has drops to draw.
    // Every element's precomputed tables at their "low" quality (any key named *.table_quality,
    // so a new element's is found too): the grid checks finiteness, not table accuracy, and the
    // halos' default tables take a minute to trace on 2 cores.
    for (const std::string& k : sky.vars().names())
        if (k.size() > 14 && k.compare(k.size() - 14, 14, ".table_quality") == 0) sky.setOption(k, "low");
#ifdef WELKIN_HAS_ELEMENT_rainbow  // its option (the Rainbow's folder may be absent)
    sky.setOption("rain.rate_mm_h", "5");
#endif
#ifdef WELKIN_HAS_ELEMENT_clouds
    sky.setOption("clouds.rain_density", "0.5");
#endif
    sky.setExposure({.automatic = true});
    sky.setAnimationTime(0.0);

    const std::vector<GridCase> cases = gridCases();
    for (const GridCase& c : cases) {
        INFO(c.what << ": " << c.time << " lat " << c.latDeg << " lon " << c.lonDeg << " height " << c.heightM << " m, az " << c.azDeg
                    << " alt " << c.altDeg << " fov " << c.fovDeg << ", " << c.width << "x" << c.height);
        sky.setTime(UtcInstant::parse(c.time));
        sky.setObserver({c.latDeg * kDeg, c.lonDeg * kDeg, c.heightM});
        Camera cam;
        cam.projection = c.projection;
        cam.azimuthRad = c.azDeg * kDeg;
        cam.altitudeRad = c.altDeg * kDeg;
        cam.verticalFovRad = c.fovDeg * kDeg;
        cam.cubeFace = c.cubeFace;
        cam.width = c.width;
        cam.height = c.height;
        sky.setCamera(cam);
        sky.renderFrame();
        CHECK(firstNonFinite(sky.readHdr()) == "");
        CHECK(firstNonFinite(sky.readToneMapped()) == "");
        CHECK(std::isfinite(sky.lastEv100()));
        if (c.body) {
            const glm::dvec3 d = sky.vars().get(c.body == 'S' ? keys::sunDirection : keys::moonDirection);
            // The place search converges to 1e-6 rad; 0.05 deg allows for the generator's own
            // refraction and parallax model against the astronomy code's (both are the same code:
            // this checks that the case puts the body where it says).
            CHECK(std::asin(std::clamp(d.z, -1.0, 1.0)) / kDeg == Approx(c.bodyAltDeg).margin(0.05));
        }
    }
}

TEST_CASE("Extreme grid: every bad value is refused with one line naming the option", "[cpu][cli][extreme]") {
    // A good command line; each case replaces one option's value (CLI11 refuses an option given twice).
    const std::vector<std::pair<std::string, std::string>> good = {
        {"--time", "2026-06-21T12:00:00Z"}, {"--lat", "48"}, {"--lon", "11"}, {"--size", "4x4"},
        {"--out", "/tmp/welkin-extreme-grid-never-written.exr"}};
    struct Bad {
        std::string option;  // replaced (or added), and named by the one-line message
        std::string value;
        std::string extra = {};  // other options the case needs
    };
    const std::vector<Bad> bad = {
        {"--lat", "90.01"},     {"--lat", "-91"},       {"--lat", "nan"},        {"--lat", "inf"},
        {"--lon", "180.5"},     {"--lon", "-181"},      {"--lon", "nan"},        {"--height", "-10001"},
        {"--height", "1.1e9"},  {"--height", "nan"},    {"--fov", "0"},          {"--fov", "180"},
        {"--fov", "-5"},        {"--fov", "nan"},       {"--size", "0x4"},       {"--size", "4x0"},
        {"--size", "16385x1"},  {"--size", "4"},        {"--size", "4x4x4"},     {"--size", "-4x4"},
        {"--alt", "90.5"},      {"--az", "nan"},        {"--face", "6", "--projection cube"},
        {"--exposure", "31"},   {"--exposure", "nan"},
        // Years the astronomy does not support (VSOP87's span, [-2000, 6000]) and impossible dates.
        {"--time", "-2001-06-21T12:00:00Z"}, {"--time", "6001-01-01T00:00:00Z"},
        {"--time", "2026-02-30T00:00:00Z"},  {"--time", "2026-06-21T24:00:00Z"}, {"--time", "yesterday"},
    };
    std::vector<std::string> failures;
    for (const Bad& b : bad) {
        std::string args = "render";
        for (const auto& [option, value] : good)
            if (option != b.option) args += " " + option + " " + value;
        args += " " + b.option + " " + b.value + (b.extra.empty() ? "" : " " + b.extra);
        const test::CliResult r = test::runCli(args);
        std::string text = r.output;
        while (!text.empty() && text.back() == '\n') text.pop_back();
        const bool oneLine = !text.empty() && text.find('\n') == std::string::npos;
        if (r.status != 1 || !oneLine || text.rfind("welkin render: ", 0) != 0 || text.find(b.option) == std::string::npos)
            failures.push_back(args + " -> status " + std::to_string(r.status) + ": " + r.output);
    }
    std::string report;
    for (const auto& f : failures) report += f + "\n";
    INFO(report);
    CHECK(failures.empty());
}
