// welkin bench night: its options are checked before any rendering, and a run writes one CSV row
// per scene with the targets judged. The bench lives in skyelements/stars/bench; its runs also
// need the night scene's other elements, so they are compiled only where those folders are.
#include <catch2/catch.hpp>

#include "cli_runner.hpp"
#include "elements_present.hpp"

#include <welkin/astro/stars.hpp>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

using welkin::test::runCli;

TEST_CASE("welkin bench night: bad options are one-line errors", "[cpu][cli]") {
    struct Case {
        const char* args;
        const char* message;
    };
    for (Case c : {Case{"--repeats 0", "--repeats 0 not in [1, 1000]"},
                   Case{"--cameras perspective,cube", "--cameras: 'cube' unknown (accepted: perspective, fisheye)"},
                   Case{"--csv /nonexistent-dir/x.csv", "--csv '/nonexistent-dir/x.csv': no directory '/nonexistent-dir'"},
                   Case{"--day-time noon", "--day-time 'noon': is not ISO 8601"},
                   Case{"--small-catalogue-mag 12", "--small-catalogue-mag 12.000000 not in [-2, 9]"}}) {
        const auto r = runCli(std::string("bench night ") + c.args);
        INFO(c.args << " -> " << r.output);
        CHECK(r.status == 1);
        CHECK(r.output.find(std::string("welkin bench night: ") + c.message) != std::string::npos);
    }
}

#if defined(WELKIN_HAS_ELEMENT_nightsky) && defined(WELKIN_HAS_ELEMENT_constellations) && defined(WELKIN_HAS_ELEMENT_planet)
TEST_CASE("welkin bench night: one frame per scene, CSV rows and targets", "[gl][cli][slow]") {
    if (!std::filesystem::exists(welkin::astro::kKStarsCatalogue)) FAIL("no " << welkin::astro::kKStarsCatalogue << " (kstars-data)" << ": install it (scripts/setup.sh installs it; a missing file fails, never skips)");
    const std::string dir = welkin::test::scratchDir("bench_night");
    const auto r = runCli("bench night --repeats 1 --cameras perspective --csv '" + dir + "/n.csv'");
    INFO(r.output);
    REQUIRE(r.status == 0);
    CHECK(r.output.find("targets: ") != std::string::npos);
    std::ifstream f(dir + "/n.csv");
    std::string line;
    int rows = 0, culledByDay = 0;
    while (std::getline(f, line)) {
        if (line.empty() || line[0] == '#' || line.rfind("camera,", 0) == 0) continue;
        ++rows;
        // By day (Sun +30 deg) the Sky's limiting magnitude culls every star of both catalogues.
        if (line.find(",day,") != std::string::npos && line.find("stars + sky") != std::string::npos)
            culledByDay += line.find(",0,") != std::string::npos;
    }
    // Per camera: the Sky alone and stars + sky (9k, full) by day and by night (6), the NightSky
    // alone (1), every star by night (1), the default scene (1), + constellations (1), its
    // instrumented twin (1), with the time running (1).
    CHECK(rows == 12);
    CHECK(culledByDay == 2);
}

TEST_CASE("welkin bench night --planet-only: the Planet element costs nothing with no body in view", "[gl][cli][slow][planet]") {
    if (!std::filesystem::exists(welkin::astro::kKStarsCatalogue)) FAIL("no " << welkin::astro::kKStarsCatalogue << " (kstars-data)");
    const auto r = runCli("bench night --planet-only --repeats 3");
    INFO(r.output);
    REQUIRE(r.status == 0);
    CHECK(r.output.find("targets: ") == std::string::npos);  // the camera rows are not run
    // Each row: | scene | bodies drawn | planet ms | trivial ms | planet / trivial |
    auto row = [&](const std::string& scene) {
        const size_t at = r.output.find("| " + scene);
        REQUIRE(at != std::string::npos);
        std::stringstream ss(r.output.substr(at, r.output.find('\n', at) - at));
        std::string cell;
        std::vector<std::string> cells;
        while (std::getline(ss, cell, '|')) cells.push_back(cell);
        REQUIRE(cells.size() >= 6);
        return std::pair{std::stoi(cells[2]), std::stod(cells[5])};
    };
    const auto none = row("no body in view");
    CHECK(none.first == 0);
    // Issue 22's target, <= 0.2x the trivial pass (0.03x measured: the element returns before any
    // GL call; the margin absorbs a busy machine's timing noise over 3 frames).
    CHECK(none.second <= 0.2);
    CHECK(row("the full Moon in view").first >= 1);
    CHECK(row("the Sun in view").first >= 1);
}
#endif
