// welkin bench all: bad options are one-line errors before any rendering; a tiny run writes a
// Markdown file with a row for every element of the registry, each with finite positive ratios;
// the growth fit and the plot script. No timing is judged here (this machine is shared).
#include <catch2/catch.hpp>

#include "cli_runner.hpp"
#include "elements_present.hpp"
#include "plot.hpp"

#include <welkin/bench.hpp>
#include <welkin/elements/registry.hpp>
#include <welkin/image.hpp>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

using welkin::test::runCli;

TEST_CASE("welkin bench all: bad options are one-line errors", "[cpu][cli][bench]") {
    const auto failures = welkin::test::badOptionFailures(
        "bench all", {{"--size-override 0x16", "--size-override '0x16' not WIDTHxHEIGHT in [1, 8192]"},
                      {"--size-override 64", "--size-override '64' not WIDTHxHEIGHT in [1, 8192]"},
                      {"--frames 0", "--frames 0 not in [1, 1000]"},
                      {"--framework-frames 1001", "--framework-frames 1001 not in [0, 1000]"},
                      // (--out and --plots given: the defaults under docs/ are checked first, and ctest runs
                      // in the build folder, which has no docs/)
                      {"--only nosuch --plots '' --out '" WELKIN_BINARY_DIR "/b.md'", "--only: unknown element 'nosuch'"},
                      {"--plots /nonexistent-dir/bench --out '" WELKIN_BINARY_DIR "/b.md'", "--plots '/nonexistent-dir/bench': no such directory"},
                      {"--out /nonexistent-dir/b.md", "--out '/nonexistent-dir/b.md': no directory '/nonexistent-dir'"}});
    for (const auto& f : failures) FAIL_CHECK(f);  // (INFO inside a loop would vanish with its scope)
    CHECK(failures.empty());
    const auto fw = welkin::test::badOptionFailures("bench framework", {{"--frames 0", "--frames 0 not in [1, 10000]"},
                                                                         {"--size 8x", "--size '8x' not WIDTHxHEIGHT in [1, 8192]"}});
    for (const auto& f : fw) FAIL_CHECK(f);
    CHECK(fw.empty());
}

TEST_CASE("bench::fitGrowthExponent recovers power laws", "[cpu][bench]") {
    // cost = 3 * work^1.5 exactly: the log-log slope is 1.5 (1e-12: rounding of log/exp only).
    std::vector<double> x = {10, 100, 1000, 5000}, y;
    for (double v : x) y.push_back(3 * std::pow(v, 1.5));
    CHECK(welkin::bench::fitGrowthExponent(x, y) == Approx(1.5).margin(1e-12));
    // Constant cost: exponent 0; one distinct work value: no fit.
    CHECK(welkin::bench::fitGrowthExponent({1, 2, 4}, {7, 7, 7}) == Approx(0.0).margin(1e-12));
    CHECK(std::isnan(welkin::bench::fitGrowthExponent({2, 2}, {1, 3})));
    // Non-positive points are ignored: the remaining two give the slope of y = x^2.
    CHECK(welkin::bench::fitGrowthExponent({-1, 2, 4}, {5, 4, 16}) == Approx(2.0).margin(1e-12));
}

TEST_CASE("bench::parseCallgrind attributes instructions to welkin, the runtime it calls and the driver", "[cpu][bench]") {
    // A hand-written callgrind output in the format valgrind 3.19 writes (compressed names, a
    // "calls=" line followed by the call's inclusive cost, relative positions "+1"): welkin's
    // renderFrame (self 100 + 20) calls malloc (inclusive 40) and the driver's glClear
    // (inclusive 5000, not welkin's); the driver calls malloc too (1000); malloc's self cost is
    // both (1040). All counts are integers: exact comparisons.
    std::istringstream in(R"(version: 1
creator: callgrind-3.19.0
events: Ir
ob=(1) /opt/welkin/bin/welkin
fl=(1) processor.cpp
fn=(1) welkin::SkyProcessor::renderFrame()
10 100
cob=(2) /lib/x86_64-linux-gnu/libc.so.6
cfi=(2) ???
cfn=(2) malloc
calls=2 0
10 40
cob=(3) /usr/lib/x86_64-linux-gnu/libGLX_mesa.so.0
cfn=(3) glClear
calls=1 0
11 5000
+1 20

ob=(2)
fl=(2)
fn=(2)
0 1040

ob=(3)
fn=(3)
0 4000
cob=(2)
cfn=(2)
calls=1 0
0 1000

ob=(4) /usr/lib/x86_64-linux-gnu/libstdc++.so.6.0.30
fn=(4) std::string::append
0 7
totals: 5167
)");
    const welkin::bench::CallgrindCosts c = welkin::bench::parseCallgrind(in, "/opt/welkin/bin/welkin");
    CHECK(c.total == 5167);
    CHECK(c.own == 120);
    CHECK(c.ownCalls == 40);
    CHECK(c.runtime == 1047);
    CHECK(c.total - c.own - c.runtime == 4000);  // the driver's glClear
    REQUIRE(c.byFunction.size() == 1);
    CHECK(c.byFunction.at("welkin::SkyProcessor::renderFrame()") == 160);
}

namespace {
/// Runs `welkin bench all ARGS --out DIR/BENCHMARKS.md` (which must succeed) and returns the file.
[[maybe_unused]] std::string benchAllMarkdown(const std::string& dir, const std::string& args) {
    const std::string out = dir + "/BENCHMARKS.md";
    const auto r = runCli("bench all " + args + " --out '" + out + "'");
    INFO(r.output);
    REQUIRE(r.status == 0);
    std::ifstream f(out);
    REQUIRE(f);
    std::stringstream ss;
    ss << f.rdbuf();
    return ss.str();
}
}  // namespace

TEST_CASE("welkin bench all: it measures every element of the registry", "[cpu][cli][bench]") {
    // --list prints the elements a run measures, one "name: scene" line each: every element of the
    // registry (with its own bench, or the default scene), so a new element folder is measured.
    const auto r = runCli("bench all --list");
    INFO(r.output);
    REQUIRE(r.status == 0);
    std::istringstream in(r.output);
    std::string line;
    std::vector<std::string> listed;
    while (std::getline(in, line))
        if (line.find(": ") != std::string::npos) listed.push_back(line.substr(0, line.find(": ")));
    std::vector<std::string> known = welkin::elements::knownElements();
    std::sort(known.begin(), known.end());
    std::sort(listed.begin(), listed.end());
    CHECK(listed == known);
}

#if defined(WELKIN_HAS_ELEMENT_grid) && defined(WELKIN_HAS_ELEMENT_stars)  // --only grid,stars: both by name
TEST_CASE("welkin bench all: a tiny run writes a row per element with finite positive ratios", "[gl][cli][bench]") {
    // Two elements (the grid: default bench; the stars: their own bench and sweep) at 32x16: the
    // whole registry takes minutes here (the rainbow's Mie table, the clouds' noise volumes).
    const std::string dir = welkin::test::scratchDir("bench_all");
    const std::string md = benchAllMarkdown(dir, "--only grid,stars --size-override 32x16 --frames 1 --framework-frames 0 --plots ''");
    CHECK(md.find("- Date: ") != std::string::npos);
    CHECK(md.find("- Commit: ") != std::string::npos);
    CHECK(md.find("GL renderer: ") != std::string::npos);
    // The cost table: "| name | scene | still | 600x | frame | trivial ms |" for the one size.
    const size_t table = md.find("## Cost per frame");
    REQUIRE(table != std::string::npos);
    std::map<std::string, std::vector<std::string>> rows;
    std::istringstream in(md.substr(table, md.find("\n## ", table + 3) - table));
    std::string line;
    while (std::getline(in, line)) {
        if (line.rfind("| ", 0) != 0 || line.rfind("| element", 0) == 0) continue;
        std::vector<std::string> cells;
        std::istringstream ls(line.substr(1));
        std::string cell;
        while (std::getline(ls, cell, '|')) cells.push_back(cell);
        if (cells.size() >= 5) rows[cells[0].substr(1, cells[0].size() - 2)] = cells;
    }
    CHECK(rows.size() == 2);
    for (const char* name : {"grid", "stars"}) {
        INFO(name);
        REQUIRE(rows.count(name) == 1);
        for (int c = 2; c <= 4; ++c) {  // still, 600x, whole frame: ratios to the trivial pass
            const double v = std::atof(rows[name][c].c_str());
            INFO("column " << c << ": '" << rows[name][c] << "'");
            CHECK(std::isfinite(v));
            CHECK(v > 0.0);
        }
    }
    // The time-running table: still ms, 600x, 1440x for the one size, then the time-starts and
    // time-jumps columns (issue 22), each a finite ratio with its frame count (11 and 72 here).
    {
        const size_t tr = md.find("## Time running");
        REQUIRE(tr != std::string::npos);
        const std::string sec = md.substr(tr, md.find("\n## ", tr + 3) - tr);
        CHECK(sec.find("| time starts (frames) | time jumps (frames) |") != std::string::npos);
        for (const char* name : {"grid", "stars"}) {
            INFO(name);
            const size_t at = sec.find(std::string("| ") + name + " |");
            REQUIRE(at != std::string::npos);
            std::vector<std::string> cells;
            std::istringstream ls(sec.substr(at + 1, sec.find('\n', at) - at - 1));
            std::string cell;
            while (std::getline(ls, cell, '|')) cells.push_back(cell);
            REQUIRE(cells.size() == 6);  // name, still ms, 600x, 1440x, starts, jumps
            for (int c = 2; c <= 5; ++c) {
                const double v = std::atof(cells[size_t(c)].c_str());
                INFO("column " << c << ": '" << cells[size_t(c)] << "'");
                CHECK(std::isfinite(v));
                CHECK(v > 0.0);
            }
            CHECK(cells[5].find("(72)") != std::string::npos);  // 2 jumps x 36 frames
        }
    }
    // The stars' sweep found its statistic and fitted an exponent (a number, not "n/a").
    CHECK(md.find("| stars | stars drawn (stars) |") != std::string::npos);
    CHECK(md.find("Not measured in this run (`--framework-frames 0`)") != std::string::npos);
    // Written atomically: no temporary left beside it.
    CHECK_FALSE(std::ifstream(dir + "/.BENCHMARKS.md.tmp"));
}
#endif

#if defined(WELKIN_HAS_ELEMENT_halos)  // --only halos: its bench command names a report table
TEST_CASE("welkin bench all: an element's report table comes from its own bench's CSV", "[gl][cli][bench]") {
    // The Halos register `welkin bench halos` with a ReportTable (skyelements/halos/bench): bench
    // all runs it with the table's --quick arguments (low tables: seconds) and prints its CSV as a
    // Markdown table under the table's title, with the command that made it.
    const std::string md = benchAllMarkdown(welkin::test::scratchDir("bench_all_reports"),
                                            "--quick --only halos --size-override 32x16 --frames 1 --framework-frames 0 --plots '' "
                                            "--var halos.table_quality=low");
    const size_t at = md.find("### Halos: crystal tables by quality, the pass, and accuracy");
    REQUIRE(at != std::string::npos);
    const std::string section = md.substr(at, md.find("\n## ", at) - at);
    INFO(section);
    CHECK(section.find("Not measured") == std::string::npos);
    // The columns as the table names them, then rows of the bench's CSV: the low tables' trace
    // time in seconds (a positive number) and the pass's ratio to the trivial pass.
    CHECK(section.find("| what | quality, size or rays | value | trivial pass ms | x trivial pass |") != std::string::npos);
    const size_t trace = section.find("| phase tables trace, s | low (");
    REQUIRE(trace != std::string::npos);
    std::vector<std::string> cells;
    {
        std::istringstream ls(section.substr(trace + 1, section.find('\n', trace) - trace - 1));
        for (std::string c; std::getline(ls, c, '|');) cells.push_back(c);
    }
    REQUIRE(cells.size() >= 3);
    const double seconds = std::atof(cells[2].c_str());
    CHECK(seconds > 0.0);
    CHECK(std::isfinite(seconds));
    // The default display (adaptive cells at rest, with its share of fetching pixels) and the
    // display before it (every cell fetching), both at the bench's own 800x450.
    CHECK(section.find("| halo pass, crystal layer tau 0.3 (the default: adaptive cells), ms | 800x450, ") != std::string::npos);
    CHECK(section.find("| halo pass, crystal layer tau 0.3, every cell fetching bilinearly (the display before), ms | 800x450 |") != std::string::npos);
    // The command with the quick arguments, for anyone to repeat it.
    CHECK(section.find("*`welkin bench halos --qualities low --repeats 1 --accuracy-quality low --exact-factor 2 --pass-quality low --csv FILE`") !=
          std::string::npos);
    // The default tables against the brute-force trace (here the low ones: --quick).
    CHECK(section.find("| accuracy, plates: L1(tables - exact) / L1(exact), whole sphere | low tables") != std::string::npos);
}
#endif

TEST_CASE("plot_bench_all.py draws both plots from bench all's CSVs", "[cpu][plot][bench]") {
    if (!welkin::cli::findPythonWithMatplotlib()) FAIL("no python3 with matplotlib (Debian: python3-matplotlib): install it (scripts/setup.sh installs it; a missing module fails, never skips)");
    const std::string dir = welkin::test::scratchDir("plot_bench_all");
    std::ofstream(dir + "/e.csv") << "element,size,pixels,still_ratio,running_ratio,still_ms,trivial_ms\n"
                                     "sky,512x256,131072,2.5,4.0,5,2\nsky,1280x720,921600,2.2,3.1,30,14\n"
                                     "stars,512x256,131072,0.5,0.6,1,2\nstars,1280x720,921600,0.3,0.4,4,14\n";
    std::ofstream(dir + "/w.csv") << "series,unit,work,cost,cost_unit,exponent\n"
                                     "sky,pixels,131072,5,ms,0.98\nsky,pixels,921600,30,ms,0.98\n"
                                     "stars,stars,100,0.2,x trivial pass,0.5\nstars,stars,1000,0.6,x trivial pass,0.5\n";
    for (const char* name : {"e", "w"}) {
        const welkin::cli::PlotResult p = welkin::cli::drawPlot("plot_bench_all.py", dir + "/" + name + ".csv", dir + "/" + name + ".png");
        INFO(p.message);
        REQUIRE(p.drawn);
        const welkin::Image img = welkin::readImage(dir + "/" + name + ".png");
        CHECK(img.width > 200);  // figures of at least 4 in at 60 dpi
        CHECK(img.height > 150);
    }
    std::ofstream(dir + "/bad.csv") << "a,b\n1,2\n";
    const welkin::cli::PlotResult bad = welkin::cli::drawPlot("plot_bench_all.py", dir + "/bad.csv", dir + "/bad.png");
    CHECK_FALSE(bad.drawn);
    CHECK(bad.message.find("exited with status 2") != std::string::npos);
}
