// `welkin render` end to end: the fisheye grid of the issue, and bad input.
#include <catch2/catch.hpp>

#include "cli_runner.hpp"

#include <welkin/image.hpp>

#include <nlohmann/json.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>

using namespace welkin;
namespace fs = std::filesystem;

namespace {
double luminance(const Image& img, int x, int y) {
    return 0.2126 * img.at(x, y, 0) + 0.7152 * img.at(x, y, 1) + 0.0722 * img.at(x, y, 2);
}
// Largest luminance in a (2r+1)^2 window.
double windowMax(const Image& img, double cx, double cy, int r) {
    double m = 0;
    for (int y = int(cy) - r; y <= int(cy) + r; ++y)
        for (int x = int(cx) - r; x <= int(cx) + r; ++x)
            if (x >= 0 && y >= 0 && x < img.width && y < img.height) m = std::max(m, luminance(img, x, y));
    return m;
}
}  // namespace

TEST_CASE("welkin render: fisheye grid EXR puts the horizon and the cardinal markers where the convention says", "[gl][cli]") {
    std::string dir = test::scratchDir("cli_render");
    std::string out = dir + "/g.exr", stats = dir + "/g.json";
    auto r = test::runCli("render --time 2026-06-21T12:00:00Z --lat 0 --lon 0 --elements grid --projection fisheye "
                          "--size 512x512 --out " + out + " --stats " + stats);
    INFO(r.output);
    REQUIRE(r.status == 0);
    Image img = readImage(out);
    REQUIRE(img.width == 512);
    REQUIRE(img.height == 512);
    REQUIRE(img.channels == 3);
    const double W = 512, R = W / 2;
    // The grid's line luminance follows the exposure key (15 EV): ~0.8 * 1.2 * 2^15 cd/m^2.
    const double lineL = 0.8 * 1.2 * std::pow(2.0, 15);
    // Horizon: r = R. Just inside the circle the horizon line (3 px wide) covers the pixel.
    int onHorizon = 0;
    for (int k = 0; k < 72; ++k) {
        double az = (k * 5 + 2.5) * M_PI / 180;  // between azimuth lines
        double rr = R - 0.75;
        double x = W / 2 - rr * std::sin(az), y = W / 2 - rr * std::cos(az);
        if (luminance(img, int(x), int(y)) > 0.3 * lineL) ++onHorizon;
    }
    CHECK(onHorizon >= 68);  // a few samples may land on pixels only partly covered by the ring
    // The altitude circle at 30 deg: r = (90 - 30)/90 * R; midway between circles (35 deg) is dark.
    double r30 = 60.0 / 90 * R, r35 = 55.0 / 90 * R;
    double az = 17 * M_PI / 180;  // not on an azimuth line (every 10 deg)
    CHECK(windowMax(img, W / 2 - r30 * std::sin(az), W / 2 - r30 * std::cos(az), 1) > 0.5 * lineL);
    CHECK(luminance(img, int(W / 2 - r35 * std::sin(az)), int(W / 2 - r35 * std::cos(az))) < 0.05 * lineL);
    // Cardinal markers at altitude 8 deg: N top, E left, S bottom, W right. Their glyphs are bright
    // near the expected pixel and the markers' pixels elsewhere on that circle are not.
    double rm = 82.0 / 90 * R;
    struct M {
        const char* name;
        double azDeg;
    } markers[] = {{"N", 0}, {"E", 90}, {"S", 180}, {"W", 270}};
    for (auto& m : markers) {
        double a = m.azDeg * M_PI / 180;
        double x = W / 2 - rm * std::sin(a), y = W / 2 - rm * std::cos(a);
        INFO("marker " << m.name << " at " << x << ", " << y);
        CHECK(windowMax(img, x, y, 6) > 0.5 * lineL);
        // 45 deg away along the same circle there is no glyph: only thin grid lines at most.
        double a2 = a + M_PI / 4 + 0.05;
        double x2 = W / 2 - rm * std::sin(a2), y2 = W / 2 - rm * std::cos(a2);
        CHECK(luminance(img, int(x2), int(y2) ) < 0.05 * lineL);
    }
    // Outside the image circle nothing is drawn.
    CHECK(luminance(img, 3, 3) == 0.0);
    // Stats: inputs and per-element cost.
    std::ifstream f(stats);
    auto j = nlohmann::json::parse(f);
    CHECK(j["inputs"]["time"] == "2026-06-21T12:00:00Z");
    CHECK(j["elements"][0]["name"] == "grid");
    CHECK(j["elements"][0]["render_ms"].get<double>() > 0.0);
}

TEST_CASE("welkin render: bad input exits non-zero with one line and writes nothing", "[gl][cli]") {
    std::string dir = test::scratchDir("cli_bad");
    const std::string ok = "--time 2026-06-21T12:00:00Z --lat 0 --lon 0 --size 32x32 ";
    struct Case {
        std::string args;
        std::string env;
        std::string message;
    } cases[] = {
        {ok + "--elements nebula --out " + dir + "/a.png", "", "unknown element 'nebula' (known: "},
        {"--time 2026-06-21T12:00:00Z --lat 91 --lon 0 --out " + dir + "/a.png", "", "--lat 91 not in [-90, 90]"},
        {"--time 2026-02-30T12:00:00Z --lat 0 --lon 0 --out " + dir + "/a.png", "", "day 30 not in [1, 28]"},
        {"--time noon --lat 0 --lon 0 --out " + dir + "/a.png", "", "not ISO 8601"},
        {"--time 2026-06-21T12:00:00Z --lat 0 --lon 0 --size 0x0 --out " + dir + "/a.png", "", "--size 0x0"},
        {ok + "--out " + dir + "/missing/a.png", "", "does not exist"},
        {ok + "--out " + dir + "/a.bmpx", "", "unsupported extension"},
        {ok + "--exposure 99 --out " + dir + "/a.png", "", "--exposure 99 not in [-20, 30]"},
        {ok + "--quality ultra --out " + dir + "/a.png", "", "--quality 'ultra' unknown"},
        {ok + "--projection mercator --out " + dir + "/a.png", "", "perspective, fisheye, equirect, cube"},
        // No EGL: point glvnd at no vendor library.
        {ok + "--elements grid --out " + dir + "/a.png", "__EGL_VENDOR_LIBRARY_FILENAMES=/nonexistent.json", "EGL"},
    };
    for (auto& c : cases) {
        auto r = test::runCli("render " + c.args, c.env);
        INFO("welkin render " << c.args << "\n" << r.output);
        CHECK(r.status != 0);
        CHECK_THAT(r.output, Catch::Contains(c.message));
        // One line of error.
        CHECK(std::count(r.output.begin(), r.output.end(), '\n') <= 2);
    }
    // Nothing (not even a temporary file) was left behind.
    CHECK(fs::is_empty(dir));
}

TEST_CASE("welkin --version", "[cpu][cli]") {
    auto r = test::runCli("--version");
    CHECK(r.status == 0);
    CHECK_THAT(r.output, Catch::StartsWith("welkin 0."));
}
