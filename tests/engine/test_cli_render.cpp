// `welkin render` end to end: the fisheye grid of the issue, and bad input.
#include <catch2/catch.hpp>

#include "cli_runner.hpp"
#include "elements_present.hpp"

#include <welkin/image.hpp>

#include <epoxy/gl.h>

#include <nlohmann/json.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>

using namespace welkin;
namespace fs = std::filesystem;

#ifdef WELKIN_HAS_ELEMENT_grid  // the Grid element, by name
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
    // Cardinal markers: 5x7 glyphs (N red, E/S/W white) centred at altitude 8 deg, scale 4 px per
    // cell at 512 px (Grid: round(512 / 128)). Check every cell of each glyph: set cells are lit
    // with the glyph's colour, unset cells are dark unless a grid line crosses them. This fails
    // for a missing, swapped (N/S), mirrored (E/W) or misplaced glyph.
    static const int kGlyphs[4][7] = {{0x11, 0x19, 0x15, 0x13, 0x11, 0x11, 0x11},   // N
                                      {0x1F, 0x10, 0x10, 0x1E, 0x10, 0x10, 0x1F},   // E
                                      {0x0F, 0x10, 0x10, 0x0E, 0x01, 0x01, 0x1E},   // S
                                      {0x11, 0x11, 0x11, 0x15, 0x15, 0x15, 0x0A}};  // W
    const double rm = 82.0 / 90 * R, scale = 4;
    const char* names[4] = {"N", "E", "S", "W"};
    for (int g = 0; g < 4; ++g) {
        double a = g * M_PI / 2;
        double cx = W / 2 - rm * std::sin(a), cy = W / 2 - rm * std::cos(a);
        int setLit = 0, setCells = 0, unsetDark = 0, unsetCells = 0, redCells = 0;
        for (int row = 0; row < 7; ++row) {
            for (int col = 0; col < 5; ++col) {
                int x = int(cx + (col + 0.5 - 2.5) * scale), y = int(cy + (row + 0.5 - 3.5) * scale);
                double l = luminance(img, x, y);
                if ((kGlyphs[g][row] >> (4 - col)) & 1) {
                    ++setCells;
                    setLit += l > 0.3 * lineL;
                    redCells += img.at(x, y, 0) > 2.0 * img.at(x, y, 2);
                } else {
                    ++unsetCells;
                    unsetDark += l < 0.1 * lineL;
                }
            }
        }
        INFO("marker " << names[g] << " centred at " << cx << ", " << cy);
        CHECK(setLit == setCells);
        // Grid lines (every 10 deg, the cardinal azimuth line through the glyph's centre column)
        // cross a few unset cells; a mirrored or wrong glyph lights many more.
        CHECK(unsetDark >= unsetCells - 8);
        if (g == 0)
            CHECK(redCells == setCells);  // N is red
        else
            CHECK(redCells == 0);  // E, S, W are white
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
#endif

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
        {ok + "--elements '' --out " + dir + "/a.png", "", "empty item"},
        // A bad --stats path fails before anything is written, image included (and before any GL:
        // the Sky renders nothing here).
        {ok + "--elements sky --out " + dir + "/a.png --stats " + dir + "/missing/s.json", "", "--stats"},
        {ok + "--elements sky --out " + dir + "/a.png --stats " + dir, "", "must end in .json"},
        {ok + "--elements sky --out " + dir + "/a.png --lighting " + dir + "/missing/l.json", "", "--lighting"},
        {ok + "--elements sky --out " + dir + "/a.png --lighting " + dir + "/l.txt", "", "--lighting '" + dir + "/l.txt' must end in .json"},
        // Outputs are not inputs: a --var on a key the processor derives or a generator or an
        // element writes every frame is refused, naming what sets it (it used to be accepted
        // and silently overwritten).
        {ok + "--var time.iso=2026 --out " + dir + "/a.png", "", "time.iso is derived from SkyProcessor::setTime() (welkin: --time)"},
        {ok + "--var observer.latitude_rad=1 --out " + dir + "/a.png", "", "(welkin: --lat)"},
        {ok + "--var sun.direction=0,0,1 --out " + dir + "/a.png", "", "sun.direction is an output of the generator 'astronomy'"},
#ifdef WELKIN_HAS_ELEMENT_stars  // a key of the Stars' generator (in the default set when present)
        {ok + "--var stars.frame_icrs_to_enu=1,0,0,0,1,0,0,0,1 --out " + dir + "/a.png", "", "is an output of the generator"},
#endif
#ifdef WELKIN_HAS_ELEMENT_clouds
        // Written by a generator the Clouds attach at init(): refused there, before any image.
        {ok + "--elements sky,clouds --var lights.sun_cloud_transmittance=0.5 --out " + dir + "/a.png", "",
         "lights.sun_cloud_transmittance is"},
#endif
        // No EGL: point glvnd at no vendor library.
        {ok + "--elements sky --out " + dir + "/a.png", "__EGL_VENDOR_LIBRARY_FILENAMES=/nonexistent.json", "EGL"},
    };
    for (auto& c : cases) {
        auto r = test::runCli("render " + c.args, c.env);
        INFO("welkin render " << c.args << "\n" << r.output);
        CHECK(r.status != 0);
        CHECK_THAT(r.output, Catch::Contains(c.message));
        // One line of error.
        CHECK(std::count(r.output.begin(), r.output.end(), '\n') <= 2);
    }
    // A directory named like the stats file.
    fs::create_directory(dir + "/s.json");
    auto r = test::runCli("render " + ok + "--elements sky --out " + dir + "/a.png --stats " + dir + "/s.json");
    CHECK(r.status != 0);
    CHECK_THAT(r.output, Catch::Contains("is a directory"));
    fs::remove(dir + "/s.json");
    // Nothing (not even a temporary file) was left behind.
    CHECK(fs::is_empty(dir));
}

TEST_CASE("welkin render --lighting: the Sun, the Moon, the SH irradiance and the axis lights as JSON", "[gl][cli][lighting]") {
    std::string dir = test::scratchDir("cli_lighting");
    const std::string out = dir + "/a.exr", light = dir + "/l.json", stats = dir + "/s.json";
    auto r = test::runCli("render --time 2026-06-21T09:00:00Z --lat 35.9 --lon 14.5 --elements sky --projection equirect --size 32x16 "
                          "--var lighting.cube_size=16 --out " + out + " --lighting " + light + " --stats " + stats);
    INFO(r.output);
    REQUIRE(r.status == 0);
    nlohmann::json j, s;
    std::ifstream(light) >> j;
    std::ifstream(stats) >> s;
    REQUIRE(j["sh9_irradiance"].size() == 9);
    CHECK(j["about"]["sh9_irradiance"].get<std::string>().find("E_lm = A_l L_lm in lux") != std::string::npos);
    // E(up) from the file's coefficients: Y00, Y10 (z) and Y20 are the only ones nonzero at n = up.
    double e = 0;
    const double y[9] = {0.282094792, 0, 0.488602512, 0, 0, 0, 0.630783131, 0, 0};
    for (int i = 0; i < 9; ++i)
        for (int c = 0; c < 3; ++c) e += y[i] * j["sh9_irradiance"][size_t(i)][size_t(c)].get<double>() * (c == 0 ? 0.2126 : c == 1 ? 0.7152 : 0.0722);
    CHECK(e == Approx(s["lighting"]["irradiance_up_lux"].get<double>()).epsilon(1e-6));  // the same numbers, written twice
    CHECK(e > 5e3);  // a morning sky (Sun ~45 deg): diffuse ~1-2e4 lx on a horizontal surface
    const double sunLux = j["sun"]["illuminance_lux"].get<double>();
    CHECK(sunLux == Approx(s["lighting"]["sun_illuminance_lux"].get<double>()));
    CHECK(sunLux > 5e4);
    CHECK(j["sun"]["direction_enu"][2].get<double>() > 0.5);
    CHECK(j["axis_lights"]["+U"][1].get<double>() > 0);
    CHECK(j["ev100"].is_number());
}

TEST_CASE("welkin --version", "[cpu][cli]") {
    auto r = test::runCli("--version");
    CHECK(r.status == 0);
    CHECK_THAT(r.output, Catch::StartsWith("welkin 0."));
}
