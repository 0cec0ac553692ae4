// `welkin view` in a real GLFW window under Xvfb: renders frames and saves a screenshot.
#include <catch2/catch.hpp>

#include "cli_runner.hpp"

#include <welkin/image.hpp>

#include <cstdlib>
#include <filesystem>

using namespace welkin;

TEST_CASE("welkin view opens a window, renders and saves a screenshot", "[gl][cli][window]") {
    if (std::system("command -v xvfb-run >/dev/null 2>&1") != 0) {
        FAIL("xvfb-run is not installed (scripts/setup.sh installs xvfb)");
    }
    std::string dir = test::scratchDir("cli_view");
    std::string shot = dir + "/view.png";
    // xvfb-run wraps the command: build the command line by hand.
    std::string cmd = "xvfb-run -a '" + std::string(WELKIN_CLI) +
                      "' view --elements grid --projection fisheye --size 128x128 --exposure 0 --frames 3 --screenshot " +
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
    // Bad input still fails cleanly before a window opens.
    auto r = test::runCli("view --lat 95");
    CHECK(r.status != 0);
    CHECK_THAT(r.output, Catch::Contains("--lat 95 not in [-90, 90]"));
}
