// `welkin view` in a real GLFW window under Xvfb: renders frames and saves a screenshot.
#include <catch2/catch.hpp>

#include "cli_runner.hpp"
#include "elements_present.hpp"

#include <welkin/image.hpp>

#include <cstdlib>
#include <filesystem>

using namespace welkin;

TEST_CASE("welkin view: bad input fails cleanly before a window opens", "[cpu][cli][window]") {
    auto r = test::runCli("view --lat 95");
    CHECK(r.status != 0);
    CHECK_THAT(r.output, Catch::Contains("--lat 95 not in [-90, 90]"));
}

// Both windows draw the Grid (by name): cheap, still, and bright lines on black.
#ifdef WELKIN_HAS_ELEMENT_grid
namespace {
// Runs `welkin view ARGS` under xvfb-run; returns the exit status and output.
test::CliResult runView(const std::string& args) {
    std::string cmd = "xvfb-run -a -s '-screen 0 1024x768x24' '" + std::string(WELKIN_CLI) + "' view " + args + " 2>&1";
    test::CliResult r;
    FILE* p = popen(cmd.c_str(), "r");
    if (!p) return r;
    char buf[512];
    while (fgets(buf, sizeof buf, p)) r.output += buf;
    int status = pclose(p);
    r.status = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    return r;
}
}  // namespace

TEST_CASE("welkin view opens a window, renders and saves a screenshot", "[gl][cli][window]") {
    if (std::system("command -v xvfb-run >/dev/null 2>&1") != 0) {
        FAIL("xvfb-run is not installed (scripts/setup.sh installs xvfb)");
    }
    std::string dir = test::scratchDir("cli_view");
    std::string shot = dir + "/view.png";
    // xvfb-run wraps the command: build the command line by hand.
    std::string cmd = "xvfb-run -a '" + std::string(WELKIN_CLI) +
                      "' view --no-panel --elements grid --projection fisheye --size 128x128 --exposure 0 --frames 3 --screenshot " +
                      shot + " 2>&1";
    FILE* p = popen(cmd.c_str(), "r");
    REQUIRE(p);
    std::string out;
    char buf[512];
    while (fgets(buf, sizeof buf, p)) out += buf;
    int status = pclose(p);
    INFO(out);
    REQUIRE(WIFEXITED(status));
    REQUIRE(WEXITSTATUS(status) == 0);
    Image img = readImage(shot);
    CHECK(img.width == 128);
    CHECK(img.height == 128);
    // The fisheye grid: the centre region has lines, the corners (outside the circle) are black.
    CHECK(img.at(1, 1, 0) == 0.0f);
    float brightest = 0;
    for (float v : img.pixels) brightest = std::max(brightest, v);
    CHECK(brightest > 0.5f);
}

TEST_CASE("welkin view draws its panel, and the screenshot shows it", "[gl][cli][window]") {
    if (std::system("command -v xvfb-run >/dev/null 2>&1") != 0) {
        FAIL("xvfb-run is not installed (scripts/setup.sh installs xvfb)");
    }
    std::string dir = test::scratchDir("cli_view_panel");
    // The screenshot is what the window displays, the panel included (docs/viewer.md).
    const std::string scene = "--elements grid --projection fisheye --size 400x300 --exposure 0 --frames 3 --screenshot ";
    // --panel-expand opens every section and the grid's keys: each editor is built and drawn.
    auto withPanel = runView("--panel-expand " + scene + dir + "/panel.png");
    INFO(withPanel.output);
    REQUIRE(withPanel.status == 0);
    auto without = runView("--no-panel " + scene + dir + "/plain.png");
    INFO(without.output);
    REQUIRE(without.status == 0);
    const Image a = readImage(dir + "/panel.png"), b = readImage(dir + "/plain.png");
    REQUIRE(a.width == 400);
    REQUIRE(a.height == 300);
    REQUIRE(b.width == 400);
    REQUIRE(b.height == 300);
    // The panel's place: 8 px from the top left, 40 % of the width but at least 240 px wide, the
    // height less 16 px (view_panel.cpp): x in [8, 248), y in [8, 292).
    auto differs = [&](int x, int y) {
        for (int c = 0; c < 3; ++c)
            if (std::abs(a.at(x, y, c) - b.at(x, y, c)) > 2.5f / 255) return true;  // beyond 8-bit rounding
        return false;
    };
    int inside = 0, insideDiff = 0, outside = 0, outsideDiff = 0, text = 0;
    for (int y = 0; y < 300; ++y)
        for (int x = 0; x < 400; ++x) {
            const bool in = x >= 8 && x < 248 && y >= 8 && y < 292;
            const bool out = x >= 256;  // clear of the panel and its border
            if (in) {
                ++inside;
                insideDiff += differs(x, y);
                // The panel's text: light grey to white glyphs (ImGui's dark style) where the
                // panel-less frame is dark.
                text += a.at(x, y, 0) > 0.8f && a.at(x, y, 1) > 0.8f && a.at(x, y, 2) > 0.8f && b.at(x, y, 1) < 0.5f;
            } else if (out) {
                ++outside;
                outsideDiff += differs(x, y);
            }
        }
    // Most of the panel's rectangle changed (its translucent background darkens the grid) and it
    // carries text; the rest of the window is the same sky (the grid does not move with time).
    CHECK(insideDiff > inside / 2);
    CHECK(text > 200);
    CHECK(outsideDiff == 0);
}
#endif
