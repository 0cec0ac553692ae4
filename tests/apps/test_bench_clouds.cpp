// welkin bench clouds: options checked before any rendering, and a tiny run writes one CSV row
// per (samples, reprojection) and the moving row, with the target judged.
#include <catch2/catch.hpp>

#include "cli_runner.hpp"

#include <welkin/elements/registry.hpp>

#include <cmath>
#include <fstream>
#include <string>

using welkin::test::runCli;

TEST_CASE("welkin bench clouds: bad options are one-line errors", "[cpu][cli][bench]") {
    struct Case {
        const char* args;
        const char* message;
    };
    for (Case c : {Case{"--repeats 0", "--repeats 0 not in [1, 1000]"}, Case{"--warmup -1", "--warmup -1 not in [0, 1000]"},
                   Case{"--samples 8,x", "--samples: 'x' not an integer in [1, 4096]"},
                   Case{"--sizes 800x", "--sizes: '800x' not WxH with 16 <= W, H <= 8192"},
                   Case{"--reference-samples 0", "--reference-samples 0 not in [1, 4096]"},
                   Case{"--csv /nonexistent-dir/x.csv", "--csv '/nonexistent-dir/x.csv': no directory '/nonexistent-dir'"}}) {
        const auto r = runCli(std::string("bench clouds ") + c.args);
        INFO(c.args << " -> " << r.output);
        CHECK(r.status == 1);
        CHECK(r.output.find(std::string("welkin bench clouds: ") + c.message) != std::string::npos);
    }
}

TEST_CASE("welkin bench clouds: a tiny run writes its rows and judges the target", "[gl][cli][bench][slow]") {
    if (!welkin::elements::findDescriptor("clouds")) {
        WARN("no clouds element in this build: test skipped");
        return;
    }
    const std::string dir = welkin::test::scratchDir("bench_clouds");
    // 64x36, two sample counts, one timed frame each, a 32-sample reference: seconds on llvmpipe.
    const auto r = runCli("bench clouds --sizes 64x36 --samples 4,8 --repeats 1 --warmup 1 --moving-frames 2 --reference-samples 32 --csv '" +
                          dir + "/c.csv' --plot ''");
    INFO(r.output);
    REQUIRE(r.status == 0);
    CHECK(r.output.find("targets: ") != std::string::npos);
    std::ifstream f(dir + "/c.csv");
    std::string line;
    int statics = 0, moving = 0, finiteErrors = 0;
    while (std::getline(f, line)) {
        if (line.empty() || line[0] == '#' || line.rfind("size,", 0) == 0) continue;
        statics += line.find(",static,") != std::string::npos;
        moving += line.find(",moving,") != std::string::npos;
        const double rms = std::stod(line.substr(line.rfind(',') + 1));
        finiteErrors += std::isfinite(rms) && rms >= 0.0;
    }
    CHECK(statics == 4);  // 2 sample counts x reprojection off/on
    CHECK(moving == 1);
    CHECK(finiteErrors == 4);  // every static row has an error against the reference
}
