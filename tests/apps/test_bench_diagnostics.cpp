// welkin bench sky-twin (a diagnostic moved out of the test suite): its options are checked before
// any work, with one-line errors. (A run takes 8-60 s on llvmpipe: scripts/doc-images.sh and
// skyelements/sky/README.md run it.) The Clouds' bench cloud-doc-images is checked in its folder.
#include <catch2/catch.hpp>

#include "cli_runner.hpp"

#include <string>

TEST_CASE("welkin bench sky-twin: bad options are one-line errors", "[cpu][cli][bench]") {
    const auto failures = welkin::test::badOptionFailures(
        "bench sky-twin", {{"--threads 0", "--threads 0 not in [1, 64]"},
                           {"--orders 1,x", "--orders '1,x': each entry an integer in [1, 500]"},
                           {"--orders 501", "--orders '501': each entry an integer in [1, 500]"},
                           {"--tables twin,map", "--tables 'twin,map': a list of twin, departure"},
                           {"--tables ,", "--tables ',': a list of twin, departure"}});
    std::string report;
    for (const auto& f : failures) report += f + "\n";
    INFO(report);
    CHECK(failures.empty());
}

