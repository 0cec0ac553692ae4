// welkin bench cloud-reference (the real-time clouds against the path tracer; a run takes minutes,
// skyelements/clouds/README.md "Path-traced reference"): its options are checked before any work, with
// one-line errors.
#include <catch2/catch.hpp>

#include "cli_runner.hpp"

#include <string>

TEST_CASE("welkin bench cloud-reference: bad options are one-line errors", "[cpu][cli][bench]") {
    const auto failures = welkin::test::badOptionFailures(
        "bench cloud-reference", {{"--width 4", "--width 4 not in [8, 1024]"},
                                  {"--height 2000", "--height 2000 not in [8, 1024]"},
                                  {"--paths 0", "--paths 0 not in [1, 65536]"},
                                  {"--threads 65", "--threads 65 not in [1, 64]"},
                                  {"--scenes deck,tower", "--scenes: 'tower' not one of deck, cumulus-side, cumulus-behind, cumulus-above, fair-noon, fair-sunset, overcast"},
                                  {"--qualities best", "--qualities: 'best' not one of low, default, high"},
                                  {"--cost-size 320", "--cost-size '320': not WxH with W and H in [8, 4096] (empty: no timing)"},
                                  {"--repeats 0", "--repeats 0 not in [1, 1000]"},
                                  {"--max-scatterings 0", "--max-scatterings 0 not in [1, 1000000]"},
                                  {"--slab-photons -1", "--slab-photons -1 not in [0, 1e8]"},
                                  {"--truncate-deg 30", "--truncate-deg 30 not in [0, 20]"},
                                  {"--out /nonexistent-dir", "--out '/nonexistent-dir': not an existing directory"}});
    std::string report;
    for (const auto& f : failures) report += f + "\n";
    INFO(report);
    CHECK(failures.empty());
}
