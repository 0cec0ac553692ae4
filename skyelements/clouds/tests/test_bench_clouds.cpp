// welkin bench clouds: options checked before any rendering, and a tiny run writes one CSV row
// per (samples, reprojection) and the moving row, with the target judged.
#include <catch2/catch.hpp>

#include "cli_runner.hpp"
#include "plot.hpp"

#include <welkin/csv.hpp>
#include <welkin/image.hpp>

#include <welkin/elements/registry.hpp>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <string>

using welkin::test::runCli;

TEST_CASE("welkin bench cloud-doc-images: --out must be an existing directory", "[cpu][cli][bench]") {
    const auto failures = welkin::test::badOptionFailures(
        "bench cloud-doc-images", {{"--out /nonexistent-dir", "--out '/nonexistent-dir': not an existing directory"}});
    std::string report;
    for (const auto& f : failures) report += f + "\n";
    INFO(report);
    CHECK(failures.empty());
}

TEST_CASE("welkin bench clouds: bad options are one-line errors", "[cpu][cli][bench]") {
    const auto failures = welkin::test::badOptionFailures(
        "bench clouds", {{"--repeats 0", "--repeats 0 not in [1, 1000]"},
                         {"--warmup -1", "--warmup -1 not in [0, 1000]"},
                         {"--samples 8,x", "--samples: 'x' not an integer in [1, 4096]"},
                         {"--sizes 800x", "--sizes: '800x' not WxH with 16 <= W, H <= 8192"},
                         {"--reference-samples 0", "--reference-samples 0 not in [1, 4096]"},
                         {"--sky-shadow-repeats -1", "--sky-shadow-repeats -1 not in [0, 1000]"},
                         {"--csv /nonexistent-dir/x.csv", "--csv '/nonexistent-dir/x.csv': no directory '/nonexistent-dir'"}});
    std::string report;
    for (const auto& f : failures) report += f + "\n";
    INFO(report);
    CHECK(failures.empty());
}

TEST_CASE("welkin bench clouds: a tiny run writes its rows and judges the target", "[gl][cli][bench][slow]") {
    if (!welkin::elements::findDescriptor("clouds")) FAIL("no clouds element in this build" << ": this test needs skyelements/clouds");
    const std::string dir = welkin::test::scratchDir("bench_clouds");
    // 64x36, two sample counts, one timed frame each, a 32-sample reference: seconds on llvmpipe.
    const auto r = runCli("bench clouds --sizes 64x36 --samples 4,8 --repeats 1 --warmup 1 --moving-frames 2 --reference-samples 32 --sky-shadow-repeats 2 --csv '" +
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
    // The sky-shadow table: one row for the size, with the Sky pass timed both ways and the loss
    // table rebuilt (every time > 0 ms; the ratio positive).
    const size_t at = r.output.find("\n| 64x36 | ", r.output.find("The clouds' shadow on the sky"));
    REQUIRE(at != std::string::npos);
    double off = 0, on = 0, ratio = 0, frameOff = 0, frameOn = 0, loss = 0;
    REQUIRE(std::sscanf(r.output.c_str() + at, "\n| 64x36 | %lf | %lf | %lf | %lf | %lf | %lf |", &off, &on, &ratio, &frameOff, &frameOn, &loss) == 6);
    CHECK(off > 0.0);
    CHECK(on > 0.0);
    CHECK(loss > 0.0);
    CHECK(ratio > 0.0);
}

TEST_CASE("plot_bench_clouds.py draws a PNG from a bench clouds CSV", "[cpu][plot][bench]") {
    if (!welkin::cli::findPythonWithMatplotlib()) FAIL("no python3 with matplotlib (Debian: python3-matplotlib)" << ": install it (scripts/setup.sh installs it; a missing file fails, never skips)");
    const std::string dir = welkin::test::scratchDir("plot_bench_clouds");
    {
        welkin::CsvWriter w(dir + "/c.csv", {"size", "mode", "samples", "reprojection", "frame_ms", "trivial_ms", "sky_ms", "ratio_trivial",
                                             "ratio_sky", "rms_rel"});
        w.comment("test data");
        for (int reproj : {0, 1})
            for (int n : {8, 16, 32}) w.row(std::string("800x450"), std::string("static"), n, reproj, 10.0 * n, 1.0, 20.0, 10.0 * n, 0.5 * n, 0.5 / n);
        w.row(std::string("800x450"), std::string("moving"), 0, 1, 300.0, 1.0, 20.0, 300.0, 15.0, double(NAN));
        w.close();
    }
    const welkin::cli::PlotResult r = welkin::cli::drawPlot("plot_bench_clouds.py", dir + "/c.csv", dir + "/c.png");
    INFO(r.message);
    REQUIRE(r.drawn);
    const welkin::Image img = welkin::readImage(dir + "/c.png");
    CHECK(img.width == 750);  // 7.5 x 4.8 in at 100 dpi
    CHECK(img.height == 480);
    // A CSV without the bench's columns: status 2, no PNG.
    std::ofstream(dir + "/bad.csv") << "a,b\n1,2\n";
    const welkin::cli::PlotResult bad = welkin::cli::drawPlot("plot_bench_clouds.py", dir + "/bad.csv", dir + "/bad.png");
    CHECK_FALSE(bad.drawn);
    CHECK(bad.message.find("exited with status 2") != std::string::npos);
}

TEST_CASE("welkin bench clouds --breakdown: a moving frame's parts and its CPU time", "[gl][cli][bench][slow]") {
    if (!welkin::elements::findDescriptor("clouds")) FAIL("no clouds element in this build" << ": this test needs skyelements/clouds");
    // 64x36, one warm-up frame (the cache's whole fill), two moving frames: the moving row and its
    // instrumented repeat. Seconds on llvmpipe.
    const auto r = runCli("bench clouds --sizes 64x36 --samples 4 --repeats 1 --warmup 1 --moving-frames 2 --reference-samples 8 "
                          "--sky-shadow-repeats 0 --csv '' --plot '' --breakdown");
    INFO(r.output);
    REQUIRE(r.status == 0);
    // The moving row's CPU line: at 64x36 the frame with clouds marches the cache's 2,048 rays a
    // frame and the sky frame marches none, so its CPU time is the larger (by far: a fixed ray
    // count against 2,304 pixels of table look-ups).
    const size_t cpu = r.output.find("64x36 moving, CPU time");
    REQUIRE(cpu != std::string::npos);
    double withClouds = 0, sky = 0, ratio = 0;
    REQUIRE(std::sscanf(r.output.c_str() + r.output.find("frame with clouds", cpu), "frame with clouds %lf ms, sky frame %lf ms: x sky %lf", &withClouds,
                        &sky, &ratio) == 3);
    CHECK(sky > 0.0);
    CHECK(withClouds > sky);
    // The ratio is of the unrounded times; the ms are printed with one decimal, so a sky frame of
    // ~1 ms at this size recomputes it to within ~5 % (0.05 / 1) + the ratio's own 0.005: 10 %.
    CHECK(std::abs(ratio - withClouds / sky) <= 0.1 * ratio + 0.005);
    // The breakdown: the clouds' render timed on both frames (glFinish around it: > 0 ms), the
    // Sky element's too, and the frames without a rebuild counted with their CPU time.
    const size_t clouds = r.output.find("| element clouds, render | 2 | ");
    REQUIRE(clouds != std::string::npos);
    double ms = 0;
    REQUIRE(std::sscanf(r.output.c_str() + clouds, "| element clouds, render | 2 | %lf |", &ms) == 1);
    CHECK(ms > 0.0);
    CHECK(r.output.find("| element sky, render | 2 | ") != std::string::npos);
    CHECK(r.output.find("process CPU time (all threads) per frame: median") != std::string::npos);
}
