// welkin bench night: its options are checked before any rendering, and a run writes one CSV row
// per scene with the targets judged.
#include <catch2/catch.hpp>

#include "cli_runner.hpp"

#include <welkin/astro/stars.hpp>

#include <filesystem>
#include <fstream>
#include <string>

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
