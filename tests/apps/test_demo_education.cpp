// welkin demo education: every image written, each the image of the `welkin render` command it
// prints; the planets' labels (name and magnitude) where `welkin astro` puts the bodies; bad
// options as one-line errors.
#include <catch2/catch.hpp>

#include "cli_runner.hpp"
#include "elements_present.hpp"
#include "gl_test_context.hpp"
#include "label_boxes.hpp"

#include <welkin/elements/registry.hpp>
#include <welkin/gl/text.hpp>
#include <welkin/image.hpp>
#include <welkin/processor.hpp>

#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <numbers>
#include <sstream>

using namespace welkin;

namespace {
constexpr double kDeg = std::numbers::pi / 180.0;
constexpr const char* kScenes[] = {"moon-mars-2300", "moon-mars-0100", "moon-mars-0400", "jupiter-2300"};

[[maybe_unused]] std::string fmt1(double m) {  // used by the planet cases (compiled where skyelements/planet is)
    if (std::abs(m) < 0.05) m = 0.0;
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.1f", m);
    return buf;
}
}  // namespace

// The demo's scenes draw nightsky,sky,stars,planet,constellations,grid (by name): the cases that
// run them are compiled where every one of those folders is (without one the demo stops with
// "unknown element '<name>'").
#if defined(WELKIN_HAS_ELEMENT_nightsky) && defined(WELKIN_HAS_ELEMENT_stars) && defined(WELKIN_HAS_ELEMENT_planet) && \
    defined(WELKIN_HAS_ELEMENT_constellations) && defined(WELKIN_HAS_ELEMENT_grid)
TEST_CASE("welkin demo education writes every scene, each the image of the render command it prints", "[gl][demo][education]") {
    const std::string dir = test::scratchDir("demo-education") + "/shots";  // created by the demo
    const test::CliResult r = test::runCli("demo education --out '" + dir + "' --size 96x54");
    INFO(r.output);
    REQUIRE(r.status == 0);
    std::string firstCommand;
    for (const char* id : kScenes) {
        const std::string path = dir + "/" + id + ".png";
        REQUIRE(std::filesystem::exists(path));
        const Image img = readImage(path);
        CHECK(img.width == 96);
        CHECK(img.height == 54);
        CHECK(r.output.find(path + "\n") != std::string::npos);
    }
    // No temporary file is left beside the images.
    int files = 0;
    for (const auto& e : std::filesystem::directory_iterator(dir)) files += e.is_regular_file() ? 1 : 0;
    CHECK(files == 4);
    // The printed command for the first scene renders the same image (deterministic output).
    std::istringstream lines(r.output);
    for (std::string line; std::getline(lines, line);)
        if (line.rfind("  welkin render ", 0) == 0 && line.find(kScenes[0]) != std::string::npos) firstCommand = line.substr(9);
    REQUIRE(!firstCommand.empty());
    CHECK(firstCommand.find("--time 2018-07-01T23:00:00+02:00 --lat 35.9 --lon 14.51") != std::string::npos);
    const std::string again = dir + "/../again.png";
    const std::string cmd = firstCommand.substr(0, firstCommand.find(" --out ")) + " --out '" + again + "'";
    const test::CliResult r2 = test::runCli(cmd);
    INFO(cmd << "\n" << r2.output);
    REQUIRE(r2.status == 0);
    const Image a = readImage(dir + "/" + kScenes[0] + ".png"), b = readImage(again);
    REQUIRE(a.pixels.size() == b.pixels.size());
    CHECK(a.pixels == b.pixels);
    // The scenes are not blank: the labels and lines make some pixels bright.
    float peak = 0;
    for (float v : a.pixels) peak = std::max(peak, v);
    CHECK(peak > 0.5f);
}

#endif

TEST_CASE("welkin demo education: bad options are one-line errors and write nothing", "[cpu][demo][education]") {
    const std::string dir = test::scratchDir("demo-education-bad");
    const std::string file = dir + "/a-file";
    { std::FILE* f = std::fopen(file.c_str(), "w"); if (f) std::fclose(f); }
    const auto failures = test::badOptionFailures(
        "demo education", {{"--planet-scale 0 --out '" + dir + "'", "--planet-scale 0 not in [1, 100]"},
                           {"--limiting-magnitude 12", "--limiting-magnitude 12 not in [-2, 9]"},
                           {"--star-label-magnitude 7", "--star-label-magnitude 7 not in [-2, 6]"},
                           {"--size 0x10", "--size 0x10: width and height must be in [1, 16384]"},
                           {"--scenes moon", "--scenes: unknown scene 'moon' (accepted: all, moon-mars-2300, moon-mars-0100, moon-mars-0400, jupiter-2300)"},
                           {"--exposure auto", "--exposure 'auto' is neither an EV100 number nor scene"},
#if defined(WELKIN_HAS_ELEMENT_nightsky) && defined(WELKIN_HAS_ELEMENT_stars) && defined(WELKIN_HAS_ELEMENT_planet) && \
    defined(WELKIN_HAS_ELEMENT_constellations) && defined(WELKIN_HAS_ELEMENT_grid)
                           // checked after the scene's elements (without one: "unknown element")
                           {"--out '" + file + "'", "--out '" + file + "' exists and is not a directory"},
#endif
                          });
    std::string all;
    for (const auto& f : failures) all += f + "\n";
    INFO(all);
    CHECK(failures.empty());
    // Nothing was written by the failed runs.
    int files = 0;
    for (const auto& e : std::filesystem::directory_iterator(dir)) files += e.is_regular_file() ? 1 : 0;
    CHECK(files == 1);
}

#ifdef WELKIN_HAS_ELEMENT_planet  // the Planet element, by name
TEST_CASE("welkin demo education labels the planets with name and magnitude where welkin astro puts them", "[gl][demo][education][planet]") {
    if (!std::filesystem::exists(gl::kDefaultFontPath)) FAIL("no font at " << gl::kDefaultFontPath << " (apt install fonts-dejavu-core)");
    // The first scene: 23:00 CEST over Valletta looking south-east, at 320x180, bodies x 4.
    const char* iso = "2018-07-01T23:00:00+02:00";
    const test::CliResult astro = test::runCli(std::string("astro --time ") + iso + " --lat 35.90 --lon 14.51 --bodies moon,mars,saturn --json");
    REQUIRE(astro.status == 0);
    const nlohmann::json bodies = nlohmann::json::parse(astro.output)["bodies"];
    test::glContext();
    Camera cam;
    cam.azimuthRad = 130 * kDeg;
    cam.altitudeRad = 14 * kDeg;
    cam.verticalFovRad = 50 * kDeg;
    cam.width = 320;
    cam.height = 180;
    const double sizeFactor = 4.0, emPx = 12.0;
    // One frame without labels, then one per body with its label only (the Moon's and Mars'
    // labels overlap at this size): the label's pixels are where the second is brighter.
    auto render = [&](const std::string& bodyList, bool labels) {
        SkyProcessor p(SkyVars::earth(), test::testLogger());
        p.setAnimationTime(0.0);
        p.setTime(UtcInstant::parse(iso));
        p.setObserver({35.90 * kDeg, 14.51 * kDeg, 0.0});
        p.setCamera(cam);
        p.setExposure({.automatic = false, .ev100 = 0.0});
        p.add(elements::makeElement("planet"));
        auto number = [](double v) {
            char b[32];
            std::snprintf(b, sizeof b, "%.17g", v);
            return std::string(b);
        };
        p.vars().setFromString("planet.bodies", bodyList);  // its options by name: no Planet header
        p.vars().setFromString("planet.labels", labels ? "true" : "false");
        p.vars().setFromString("planet.label_magnitude", "true");
        p.vars().setFromString("planet.size_factor", number(sizeFactor));
        p.vars().setFromString("planet.label_size_px", number(emPx));
        p.vars().setFromString("planet.label_luminance_cd_m2", "1");  // far above the bodies' PSF wings a few px away
        p.renderFrame();
        return std::pair{p.readHdr(), p.stats()};
    };
    const auto [off, statsOff] = render("moon,mars,saturn", false);
    CHECK(statsOff["planet"]["labels"] == 0);
    const gl::Font font = gl::Font::load();
    for (const char* name : {"moon", "mars", "saturn"}) {
        const auto [on, statsOn] = render(name, true);
        CHECK(statsOn["planet"]["labels"] == 1);
        const nlohmann::json& b = bodies[name];
        const glm::dvec3 dir = directionFromAzAlt(b["az_deg"].get<double>() * kDeg, b["alt_deg"].get<double>() * kDeg);
        const auto px = cam.pixelOf(dir);
        REQUIRE(px);
        REQUIRE(px->x > 0);
        REQUIRE(px->x < cam.width);
        // The planet's rule: the label starts 0.4 em right of the disk's edge (the Moon: its
        // apparent radius x the size factor, in pixels there), or of its 2-px point image (1 px).
        const auto s = cam.pixelScale(dir);
        const double diskPx = 0.5 * b["angular_diameter_deg"].get<double>() * kDeg * sizeFactor * std::sqrt(s->x * s->y);
        const double radiusPx = 2.0 * diskPx >= 2.0 ? diskPx : 1.0;
        std::string text = name;
        text[0] = char(std::toupper(text[0]));
        text += " " + fmt1(b["magnitude"].get<double>());
        const test::Box want = test::expectedInk(font, text, float(emPx), *px, radiusPx + 0.4 * emPx);
        // Label pixels: where the label adds at least 0.1 cd/m^2 (a tenth of a covered pixel).
        const test::Box got = test::inkIn(on, off, want.grown(8), 0.1);
        INFO(text << " at pixel (" << px->x << ", " << px->y << "): expected ink " << want.str() << ", found " << got.str());
        // 2 px: the bound; the text engine snaps anchor and pen to whole pixels and a
        // glyph's faint antialiased rim may fall either side of the 0.1 threshold (<= 1 px).
        CHECK(got.within(want, 2));
        // Nothing else was written: every label pixel is in the box.
        int stray = 0;
        for (int y = 0; y < cam.height; ++y)
            for (int x = 0; x < cam.width; ++x)
                if (test::luminanceAt(on, x, y) - test::luminanceAt(off, x, y) > 0.1 && !want.grown(2).contains(x, y)) ++stray;
        CHECK(stray == 0);
    }
}

#endif

#if defined(WELKIN_HAS_ELEMENT_nightsky) && defined(WELKIN_HAS_ELEMENT_stars) && defined(WELKIN_HAS_ELEMENT_planet) && \
    defined(WELKIN_HAS_ELEMENT_constellations) && defined(WELKIN_HAS_ELEMENT_grid)
TEST_CASE("welkin demo education --view starts welkin view with the scene's options", "[cpu][demo][education]") {
    // Without a display the viewer parses every option (a bad one would be CLI11's parse error)
    // and then stops at the window: its own one-line error proves it was the viewer that ran.
    const test::CliResult r = test::runCli("demo education --view --scenes jupiter-2300 --size 64x36", "env -u DISPLAY -u WAYLAND_DISPLAY");
    INFO(r.output);
    CHECK(r.output.find("welkin view --time 2018-07-01T23:00:00+02:00 --lat 35.9 --lon 14.51 --elements nightsky,sky,stars,planet,constellations,grid --az 215") == 0);
    CHECK(r.output.find("--var grid.ecliptic=true") != std::string::npos);
    CHECK(r.output.find("welkin view: WindowContext: GLFW cannot start") != std::string::npos);
    CHECK(r.status == 1);
}
#endif
