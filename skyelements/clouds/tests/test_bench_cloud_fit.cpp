// welkin bench cloud-fit (skyelements/clouds/README.md, "The fit"): the program that regenerates the
// constants of the lights' transfer (cloudcpu::kLightTransferFit) from the path tracer's slab
// radiances and adding-doubling. A small run must find the committed constants again, within the
// noise of its few paths.
#include <catch2/catch.hpp>

#include "cli_runner.hpp"

#include <welkin/elements/clouds.hpp>

#include <cmath>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <utility>

namespace {
// The CSV's rows: name -> (committed, fitted).
std::map<std::string, std::pair<double, double>> readFit(const std::string& path) {
    std::map<std::string, std::pair<double, double>> m;
    std::ifstream f(path);
    std::string line;
    while (std::getline(f, line)) {
        if (line.empty() || line[0] == '#' || line.rfind("constant,", 0) == 0) continue;
        std::stringstream ss(line);
        std::string name, a, b;
        if (std::getline(ss, name, ',') && std::getline(ss, a, ',') && std::getline(ss, b, ',')) m[name] = {std::stod(a), std::stod(b)};
    }
    return m;
}
// The committed constant of the CSV's name, from the element's header (not from the program).
double committed(const std::string& name) {
    const auto& c = welkin::elements::cloudcpu::kLightTransferFit;
    if (name == "k") return c.k;
    if (name == "c") return c.c;
    if (name == "h") return c.h;
    if (name == "z") return c.z;
    if (name.size() == 2 && (name[0] == 'w' || name[0] == 'g') && name[1] >= '0' && name[1] <= '4')
        return name[0] == 'w' ? c.w[name[1] - '0'] : c.g[name[1] - '0'];
    return NAN;
}
const char* const kConstants[] = {"k", "c", "h", "z", "w0", "w1", "w2", "w3", "w4", "g0", "g1", "g2", "g3", "g4"};
}  // namespace

TEST_CASE("welkin bench cloud-fit: bad options are one-line errors", "[cpu][cli][bench][clouds]") {
    const auto failures = welkin::test::badOptionFailures("bench cloud-fit", {{"--paths 10", "--paths 10 not in [100, 1e7]"},
                                                                              {"--threads 0", "--threads 0 not in [1, 64]"},
                                                                              {"--evaluations 5", "--evaluations 5 not in [100, 1e6]"},
                                                                              {"--passes 0", "--passes 0 not in [1, 20]"},
                                                                              {"--start best", "--start 'best' not one of neutral, committed"},
                                                                              {"--csv /nonexistent-dir/f.csv", "--csv"}});
    std::string report;
    for (const auto& f : failures) report += f + "\n";
    INFO(report);
    CHECK(failures.empty());
}

TEST_CASE("welkin bench cloud-fit: the committed constants are the fit's optimum within a small run's noise", "[cpu][cli][bench][clouds]") {
    // 1000 paths a direction (the path tracer's mean relative error 10.6 %, against 1.5 % at the
    // committed run's 60,000), the fit started at the committed constants, one Nelder-Mead pass of
    // 200 evaluations: about 10 s. The program itself checks that its transfer is the element's
    // (cloudcpu::lightTransfer to 1e-12 with the committed constants) before it fits.
    const std::string dir = welkin::test::scratchDir("bench_cloud_fit_quick");
    const auto r = welkin::test::runCli("bench cloud-fit --paths 1000 --seed 1 --start committed --passes 1 --evaluations 200 --csv '" + dir + "/fit.csv'");
    INFO(r.output);
    REQUIRE(r.status == 0);
    const auto fit = readFit(dir + "/fit.csv");
    REQUIRE(fit.count("objective") == 1);
    for (const char* name : kConstants) {
        REQUIRE(fit.count(name) == 1);
        const double c = committed(name), f = fit.at(name).second;
        INFO(name << ": committed " << c << ", refitted " << f);
        CHECK(fit.at(name).first == Approx(c).epsilon(1e-12));  // the program reads the header's constants
        // Tolerance: measured moves <= 2.2 % (g_2..4; k, c, h, z <= 0.3 %) at this run's noise; 5 %
        // accepts them. The constants before the program (fitted by hand to another set of
        // directions) lie 15-60 % away from the committed ones.
        CHECK(std::abs(f / c - 1.0) < 0.05);
    }
    // The objective (mean squared log ratio to the path tracer + the flux penalty) can fall only by
    // what fitting this run's noise gains: measured 0.09 % (0.07965 -> 0.07958). Accepted: < 1 %.
    // The constants before the program give 0.113 on the committed run's data against its 0.061.
    const auto [atCommitted, refitted] = fit.at("objective");
    CHECK(refitted <= atCommitted);
    CHECK(refitted > 0.99 * atCommitted);
}

TEST_CASE("welkin bench cloud-fit: a small run from the neutral start fits no better than the committed constants", "[cpu][cli][bench][clouds][slow]") {
    // The whole fit at 3000 paths a direction (mean relative error 6.4 %) from the neutral start (the
    // constants before any fit), seed 1: about 5 min on the shared 2-core machine. The constants are
    // not each determined by the data: this run ends at h 0.22 (committed 0.53), w_0 1.13 (0.78), g_0
    // 0.995 (0.9925) with an objective only 2.5 % below the committed constants' on its own data (a
    // flat valley, README "The transfer's constants from the path tracer"). So what must reproduce is
    // the fit's quality: the fresh fit may beat the committed constants on its data by its noise and
    // the valley's flatness (measured 2.5 %; accepted 6 %), and it must reach their quality.
    const std::string dir = welkin::test::scratchDir("bench_cloud_fit_neutral");
    const auto r = welkin::test::runCli("bench cloud-fit --paths 3000 --seed 1 --csv '" + dir + "/fit.csv'");
    INFO(r.output);
    REQUIRE(r.status == 0);
    const auto fit = readFit(dir + "/fit.csv");
    REQUIRE(fit.count("objective") == 1);
    const auto [atCommitted, fitted] = fit.at("objective");
    CHECK(fitted > 0.94 * atCommitted);
    CHECK(fitted < 1.1 * atCommitted);  // the fit reached the committed constants' quality
}

TEST_CASE("welkin bench cloud-table: the committed transfer table is adding-doubling's, for the committed constants", "[cpu][cli][bench][clouds]") {
    // The table (clouds_transfer_table.shared.glsl, cloudcpu::diffusionShape) is regenerated from
    // adding-doubling and the model's own formal solution (about 1 s, deterministic) and compared
    // with the compiled-in one: a table left stale by a new fit (cloudcpu::kLightTransferFit) or an
    // edit of the transfer's text fails here. The program writes 5 decimals: it accepts 2e-5.
    const auto r = welkin::test::runCli("bench cloud-table --check");
    INFO(r.output);
    REQUIRE(r.status == 0);
    CHECK(r.output.find("the committed table matches") != std::string::npos);
    // Writing: the file is the GLSL subset's constant array of 3825 values.
    const std::string dir = welkin::test::scratchDir("bench_cloud_table");
    const auto w = welkin::test::runCli("bench cloud-table --out '" + dir + "/t.glsl'");
    REQUIRE(w.status == 0);
    std::ifstream f(dir + "/t.glsl");
    std::stringstream ss;
    ss << f.rdbuf();
    CHECK(ss.str().find("const real cld_msTable[3825] = ARRAY_OF(real, 3825)") != std::string::npos);
    // A bad output path is a one-line error.
    const auto failures = welkin::test::badOptionFailures("bench cloud-table", {{"--out /nonexistent-dir/t.glsl", "--out: cannot write"}});
    std::string report;
    for (const auto& x : failures) report += x + "\n";
    INFO(report);
    CHECK(failures.empty());
}
