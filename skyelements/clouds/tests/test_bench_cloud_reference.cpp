// welkin bench cloud-reference (the real-time clouds against the path tracer; a run takes minutes,
// skyelements/clouds/README.md "Path-traced reference"): its options are checked before any work, with
// one-line errors.
#include <catch2/catch.hpp>

#include "cli_runner.hpp"

#include <cmath>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

TEST_CASE("welkin bench cloud-reference: bad options are one-line errors", "[cpu][cli][bench]") {
    const auto failures = welkin::test::badOptionFailures(
        "bench cloud-reference", {{"--width 4", "--width 4 not in [8, 1024]"},
                                  {"--height 2000", "--height 2000 not in [8, 1024]"},
                                  {"--paths 0", "--paths 0 not in [1, 65536]"},
                                  {"--threads 65", "--threads 65 not in [1, 64]"},
                                  {"--scenes deck,tower", "--scenes: 'tower' not one of deck, cumulus-side, cumulus-behind, cumulus-above, fair-noon, fair-sunset, overcast, cumulus-from-above, deck-inside"},
                                  {"--qualities best", "--qualities: 'best' not one of low, default, high"},
                                  {"--cost-size 320", "--cost-size '320': not WxH with W and H in [8, 4096] (empty: no timing)"},
                                  {"--repeats 0", "--repeats 0 not in [1, 1000]"},
                                  {"--max-scatterings 0", "--max-scatterings 0 not in [1, 1000000]"},
                                  {"--slab-photons -1", "--slab-photons -1 not in [0, 1e8]"},
                                  {"--truncate-deg 30", "--truncate-deg 30 not in [0, 20]"},
                                  {"--out /nonexistent-dir", "--out '/nonexistent-dir': not an existing directory"},
                                  {"--ground-albedo 1.5", "--ground-albedo 1.5 not in [0, 1]"}});
    std::string report;
    for (const auto& f : failures) report += f + "\n";
    INFO(report);
    CHECK(failures.empty());
}

namespace {
// mean_ref_cd_m2 and mean_rt_cd_m2 of the CSV's one row.
std::pair<double, double> means(const std::string& path) {
    std::ifstream f(path);
    std::string line;
    while (std::getline(f, line)) {
        if (line.empty() || line[0] == '#' || line.rfind("scene,", 0) == 0) continue;
        std::stringstream ss(line);
        std::string cell;
        std::vector<std::string> c;
        while (std::getline(ss, cell, ',')) c.push_back(cell);
        if (c.size() > 6) return {std::stod(c[5]), std::stod(c[6])};
    }
    return {NAN, NAN};
}
}  // namespace

TEST_CASE("welkin bench cloud-reference: the fair field's reference has the air in front of its clouds", "[gl][cli][bench][slow]") {
    // fair-sunset at 16 x 10 px, 4 paths: the clouds 10-60 km away, 12 deg up towards the low Sun's
    // side. The reference with the air between the camera and the clouds (the default) against the
    // same without it (--no-reference-air): the real-time frame is the same in both.
    const std::string dir = welkin::test::scratchDir("bench_cloud_reference_air");
    const std::string common = "bench cloud-reference --scenes fair-sunset --width 16 --height 10 --paths 4 --truncate-deg 3 --cost-size '' ";
    const auto a = welkin::test::runCli(common + "--csv '" + dir + "/air.csv'");
    const auto b = welkin::test::runCli(common + "--no-reference-air --csv '" + dir + "/none.csv'");
    INFO(a.output << b.output);
    REQUIRE(a.status == 0);
    REQUIRE(b.status == 0);
    const auto [refAir, rtAir] = means(dir + "/air.csv");
    const auto [refNone, rtNone] = means(dir + "/none.csv");
    INFO("reference with air " << refAir << ", without " << refNone << "; real time " << rtAir << " and " << rtNone << " cd/m^2");
    CHECK(rtAir == rtNone);  // the option touches the reference only
    // The air changes what the clouds look like from 10-60 km (its transmittance takes some of their
    // light, the clear air in front adds its own): by more than 3 %, and towards the real-time frame,
    // which has it (measured here: 902 -> 1,067 cd/m^2 against the real time's 1,140; at 40 x 22 px
    // and 64 paths 1,697 -> 1,388 against 1,196: the sign depends on the pixels, the approach not).
    CHECK(std::abs(refAir / refNone - 1.0) > 0.03);
    CHECK(std::abs(std::log(rtAir / refAir)) < std::abs(std::log(rtNone / refNone)));
}

TEST_CASE("welkin bench cloud-reference: a deck's base brightens with the ground's albedo as the path tracer's does", "[gl][cli][bench]") {
    // The deck (tau 10 between 1 and 2 km, the Sun overhead) seen from the ground at 12 x 8 px, 32
    // paths, over a ground of albedo 0.1 and 0.6 (--ground-albedo: the atmosphere's, which the
    // real-time clouds' bases read as the ground's light, atm_groundAlbedoRgb(), and the path
    // tracer's ground). The base brightens by the light the ground sends back up and the deck
    // reflects down again (and the loop between them): the real-time brightening must follow the
    // reference's.
    const std::string dir = welkin::test::scratchDir("bench_cloud_reference_albedo");
    const std::string common = "bench cloud-reference --scenes deck --width 12 --height 8 --paths 32 --truncate-deg 3 --cost-size '' ";
    const auto a = welkin::test::runCli(common + "--ground-albedo 0.1 --csv '" + dir + "/a.csv'");
    const auto b = welkin::test::runCli(common + "--ground-albedo 0.6 --csv '" + dir + "/b.csv'");
    INFO(a.output << b.output);
    REQUIRE(a.status == 0);
    REQUIRE(b.status == 0);
    const auto [refA, rtA] = means(dir + "/a.csv");
    const auto [refB, rtB] = means(dir + "/b.csv");
    const double gainRef = refB / refA, gainRt = rtB / rtA;
    INFO("reference " << refA << " -> " << refB << " cd/m^2 (x" << gainRef << "), real time " << rtA << " -> " << rtB << " (x" << gainRt << ")");
    // The reference's own brightening is real (a deck of tau 10 reflects ~0.5 of the ground's light
    // back: 1 / (1 - 0.6 x 0.5) against 1 / (1 - 0.1 x 0.5), ~1.4x, plus the base's own reflection).
    CHECK(gainRef > 1.2);
    // Tolerance: the real time's gain within 10 % of the reference's. Measured 2026-11-27: reference
    // 28,394 -> 39,311 cd/m^2 (x1.385), real time 26,047 -> 35,378 (x1.358), 0.98 of it; the
    // reference's noise at 32 paths is 23-30 % a pixel, ~3 % in each mean over 96 px (the same
    // seed in both runs: correlated, less in the ratio). About 15 s.
    CHECK(gainRt / gainRef > 0.9);
    CHECK(gainRt / gainRef < 1.1);
}

TEST_CASE("welkin bench cloud-reference: a cumulus seen from above is as bright as the path tracer's", "[gl][cli][bench]") {
    // The cumulus-from-above scene (the single cumulus seen from an aircraft 6 km up, looking 35 deg
    // down, 120 deg from a Sun 60 deg up) at 40 x 22 px, 32 paths: the real-time mean luminance over
    // the cloud pixels against the path tracer's. Before the finite cloud's depth to its far side
    // (cloudcpu::finiteBackDepth: the light diffusing in a cumulus leaks out of its sides) the
    // real-time cumulus was 1.40x the reference (its diffusion that of a slab as deep as the
    // cumulus along the light: reference 9,290, real time 13,021 cd/m^2 at 64 paths; README
    // "Finite clouds").
    const std::string dir = welkin::test::scratchDir("bench_cloud_reference_from_above");
    const auto r = welkin::test::runCli("bench cloud-reference --scenes cumulus-from-above --width 40 --height 22 --paths 32 --truncate-deg 3 --cost-size '' --csv '" + dir + "/a.csv'");
    INFO(r.output);
    REQUIRE(r.status == 0);
    const auto [ref, rt] = means(dir + "/a.csv");
    INFO("reference " << ref << " cd/m^2, real time " << rt);
    REQUIRE(ref > 0.0);
    // Tolerance 0.8-1.2x: the reference's noise at 32 paths is ~25 % a pixel, ~3 % in the mean of
    // its 66 cloud pixels; the rest is the transport's own error on this scene (the slab-fitted
    // diffusion, the ambient's uniform hemispheres). Measured 2026-11-27: real time 9,283,
    // reference 9,591 cd/m^2 (0.97; 1.00 at 64 paths, README). Fails at the former transport's
    // 1.40. About 13 s.
    CHECK(rt / ref > 0.8);
    CHECK(rt / ref < 1.2);
}

TEST_CASE("welkin bench cloud-reference: a cumulus' side lit by a low Sun is as bright as the path tracer's", "[gl][cli][bench]") {
    // The cumulus-side scene (one cumulus 4 km north, lit from the east by a Sun 30 deg up, 90 deg
    // from the view) at 40 x 22 px, 32 paths: the bench's "sunlit" region (the pixels whose visible
    // point has an optical depth below 2 towards the Sun: the side facing it), real time over the
    // path tracer. Before the lit face's cosine (cloudcpu::litFaceCosine) the diffusion term had the
    // light's muL^0.75 for the face's cosine and these pixels were 0.62x the reference (64 paths;
    // README "The lit face").
    const auto r = welkin::test::runCli("bench cloud-reference --scenes cumulus-side --width 40 --height 22 --paths 32 --truncate-deg 3 --cost-size ''");
    INFO(r.output);
    REQUIRE(r.status == 0);
    std::smatch m;
    REQUIRE(std::regex_search(r.output, m, std::regex("sunlit ([0-9]+) px bias ([0-9.]+)")));
    const int px = std::stoi(m[1].str());
    const double bias = std::stod(m[2].str());
    INFO(px << " sunlit px, bias " << bias);
    REQUIRE(px >= 15);
    // Tolerance 0.68-1.3x: the reference's noise at 32 paths is ~33 % a pixel, ~7 % in the mean of
    // the region's 22 pixels (deterministic per seed); the rest is the transport's own (the face's
    // cosine from two depths, the slab table), still too dark here. Measured 2026-11-27: 0.73 at
    // 32 paths (0.75 at 64); the code before the lit face 0.61 at 32 paths (0.62 at 64), which fails.
    CHECK(bias > 0.68);
    CHECK(bias < 1.3);
}

TEST_CASE("welkin bench cloud-reference: a deck seen from inside is as bright as the path tracer's", "[gl][cli][bench]") {
    // The deck-inside scene (the uniform deck of tau 10, the camera in its middle looking along the
    // horizon, the Sun overhead) at 40 x 22 px, 16 paths: the real-time mean over the cloud pixels
    // against the path tracer's. With the transfer table read at the slab's faces only, the
    // diffusion form's light deep inside the deck (about half adding-doubling's) made it 0.75x the
    // reference (64 paths); read at the sample's own depth where the cloud is deck-like
    // (cloudcpu::deckness, tableDepth), 0.95x (README "The transfer table").
    const std::string dir = welkin::test::scratchDir("bench_cloud_reference_deck_inside");
    const auto r = welkin::test::runCli("bench cloud-reference --scenes deck-inside --width 40 --height 22 --paths 16 --truncate-deg 3 --cost-size '' --csv '" + dir + "/a.csv'");
    INFO(r.output);
    REQUIRE(r.status == 0);
    const auto [ref, rt] = means(dir + "/a.csv");
    INFO("reference " << ref << " cd/m^2, real time " << rt);
    REQUIRE(ref > 0.0);
    // Tolerance 0.85-1.15x: the reference's noise at 16 paths is ~40 % a pixel, ~1.5 % in the mean
    // of its 880 pixels; the rest is the table's (adding-doubling's azimuth average, 5 depth nodes)
    // and the deck's thinning base. Measured 2026-11-27: real time 20,709, reference 21,360 cd/m^2
    // (0.97); the code with the table at the faces only 16,451 (0.77), which fails. About 10 s.
    CHECK(rt / ref > 0.85);
    CHECK(rt / ref < 1.15);
}
