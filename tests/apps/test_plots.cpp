// The benchmarks' plots (apps/welkin/plot.hpp): scripts/plots/plot_bench_sky.py run by Python 3
// with matplotlib on a small CSV in the format `welkin bench sky` writes. Without python3 and
// matplotlib the drawing test fails (scripts/setup.sh installs them).
#include <catch2/catch.hpp>

#include "cli_runner.hpp"
#include "plot.hpp"

#include <welkin/csv.hpp>
#include <welkin/image.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

using namespace welkin;

namespace {

const std::vector<std::string> kBenchColumns = {"preset", "wavelengths", "sun_alt_deg", "all_luts_ms", "sun_luts_ms",
                                                "frame_1280x720_ms", "trivial_1280x720_ms", "frame_512x256_ms",
                                                "trivial_512x256_ms", "ratio_1280x720", "ratio_512x256", "rms_rel",
                                                "max_rel", "mean_dxy"};

/// A bench CSV: presets 0, 2 and 3 (3 without a 1280x720 frame, as by default) at two Sun
/// altitudes, with or without the error columns (--timing-only).
void writeBenchCsv(const std::string& path, bool withErrors) {
    CsvWriter w(path, kBenchColumns);
    w.comment("test data");
    const double nan = NAN;
    for (int preset : {0, 2, 3})
        for (double alt : {20.0, -4.0}) {
            const bool big = preset != 3;
            const double ratio = preset == 3 ? 2000.0 : 2.0 + preset * 0.2;
            const double rms = withErrors ? 0.04 / (1 + preset) : nan;
            w.row(preset, 3, alt, 25.0 * (1 + preset), 10.0, big ? 12.0 : nan, 5.0, 2.0 * ratio, 1.0, big ? ratio : nan, ratio, rms,
                  withErrors ? 3 * rms : nan, withErrors ? 0.001 : nan);
        }
    w.close();
}

/// Share of pixels that are clearly coloured (not grey): markers and target lines.
double colouredFraction(const Image& img) {
    std::size_t n = 0;
    for (int y = 0; y < img.height; ++y)
        for (int x = 0; x < img.width; ++x) {
            const float r = img.at(x, y, 0), g = img.at(x, y, 1), b = img.at(x, y, 2);
            if (std::max({r, g, b}) - std::min({r, g, b}) > 0.3f) ++n;
        }
    return double(n) / (double(img.width) * img.height);
}

}  // namespace

TEST_CASE("plot_bench_sky.py draws a PNG from a bench CSV", "[cpu][plot]") {
    if (!cli::findPythonWithMatplotlib()) FAIL("no python3 with matplotlib (Debian: python3-matplotlib)" << ": install it (scripts/setup.sh installs it; a missing file fails, never skips)");
    REQUIRE(cli::findPlotScript("plot_bench_sky.py"));
    const std::string dir = test::scratchDir("plots");
    for (bool withErrors : {true, false}) {
        INFO((withErrors ? "error against cost" : "timing only"));
        const std::string csv = dir + (withErrors ? "/full.csv" : "/timing.csv");
        const std::string png = dir + (withErrors ? "/full.png" : "/timing.png");
        writeBenchCsv(csv, withErrors);
        const cli::PlotResult r = cli::drawPlot("plot_bench_sky.py", csv, png);
        INFO(r.message);
        REQUIRE(r.drawn);
        CHECK(r.message == "wrote " + png);
        REQUIRE(std::filesystem::file_size(png) > 10000);  // axes, labels and legends: tens of kB
        const Image img = readImage(png);
        CHECK(img.width == 850);  // 8.5 x 5.0 in at 100 dpi
        CHECK(img.height == 500);
        // Some coloured marks (the preset colours), on a mostly white-and-grey figure: a blank or
        // all-black image fails. Measured ~0.5 % (errors) and ~0.6 % (timing lines).
        const double c = colouredFraction(img);
        CHECK(c > 0.001);
        CHECK(c < 0.2);
    }
    // A CSV without the bench's columns: the script exits with status 2, no PNG.
    const std::string bad = dir + "/bad.csv";
    std::ofstream(bad) << "a,b\n1,2\n";
    const cli::PlotResult r = cli::drawPlot("plot_bench_sky.py", bad, dir + "/bad.png");
    CHECK_FALSE(r.drawn);
    CHECK(r.message.find("exited with status 2") != std::string::npos);
    CHECK_FALSE(std::filesystem::exists(dir + "/bad.png"));
}

TEST_CASE("Bench plots without python3: one line saying how to draw them", "[cpu][plot]") {
    const cli::PlotResult r = cli::drawPlot("plot_bench_sky.py", "b.csv", "b.png", {"/nonexistent/python3"});
    CHECK_FALSE(r.drawn);
    CHECK(r.message.find("plot not drawn: no python3 with matplotlib (Debian: apt-get install python3-matplotlib); draw it with: "
                         "python3 ") == 0);
    CHECK(r.message.find("plot_bench_sky.py b.csv b.png") != std::string::npos);
    CHECK(r.message.find('\n') == std::string::npos);
    const cli::PlotResult missing = cli::drawPlot("no_such_plot.py", "b.csv", "b.png");
    CHECK_FALSE(missing.drawn);
    CHECK(missing.message.find("no_such_plot.py not found") != std::string::npos);
}
