// welkin bench rainbow: options checked before any table is built or frame rendered.
#include <catch2/catch.hpp>

#include "cli_runner.hpp"

#include <string>

TEST_CASE("welkin bench rainbow: bad options are one-line errors", "[cpu][cli][bench]") {
    const auto failures = welkin::test::badOptionFailures(
        "bench rainbow", {{"--repeats 0", "--repeats 0 not in [1, 1000]"},
                          {"--repeats 1001", "--repeats 1001 not in [1, 1000]"},
                          {"--qualities low,ultra", "--qualities: 'ultra' is not one of low, default, high"},
                          {"--csv /nonexistent-dir/x.csv", "--csv '/nonexistent-dir/x.csv': no directory '/nonexistent-dir'"}});
    std::string report;
    for (const auto& f : failures) report += f + "\n";
    INFO(report);
    CHECK(failures.empty());
}
