// welkin bench display (issue 22 items 1 and 6, docs/BENCHMARKS.md "Displayed frames"): its
// argument checking and its frame-time statistics. The measurement itself (an X server, welkin
// view, Stellarium, seconds of frames) is `welkin bench display`, never run by the test suite.
#include <catch2/catch.hpp>

#include "cli_runner.hpp"
#include "frame_times.hpp"

#include <cstdint>
#include <string>
#include <vector>

using welkin::cli::frameWindow;
using welkin::cli::parseSwapLog;

TEST_CASE("welkin bench display: bad options give one-line errors naming the option", "[cpu][cli][bench]") {
    // Each is refused by the option check, before any X display, window or Stellarium is needed.
    const std::vector<std::string> failures = welkin::test::badOptionFailures(
        "bench display", {{"--seconds 0", "--seconds 0 not in [1, 600]"},
                          {"--warmup -1", "--warmup -1 not in [0, 600]"},
                          {"--rounds 0", "--rounds 0 not in [1, 20]"},
                          {"--budget-frames 0", "--budget-frames 0 not in [1, 1000]"},
                          {"--start-timeout 5", "--start-timeout 5 not in [10, 3600]"},
                          {"--scenes day,noon", "--scenes 'noon' is not one of day, twilight, moonlit, moonless"},
                          {"--scenes ''", "--scenes is empty"},
                          {"--rates 0,-1", "--rates '-1' is not a time rate in [0, 1e5]"},
                          {"--rates 1x", "--rates '1x' is not a time rate in [0, 1e5]"},
                          {"--size 0x720", "--size 0x720: width and height must be in [1, 16384]"},
                          {"--budget-sizes 1280", "--budget-sizes '1280' is not WIDTHxHEIGHT"},
                          {"--stellarium /nonexistent/stellarium", "--stellarium '/nonexistent/stellarium' is not auto, off or an executable"},
                          {"--out /nonexistent/B.md", "--out '/nonexistent/B.md' is not an existing file"}});
    for (const std::string& f : failures) INFO(f);
    CHECK(failures.empty());
    // One line: the error and nothing else.
    const welkin::test::CliResult r = welkin::test::runCli("bench display --seconds 0");
    CHECK(r.output == "welkin bench display: --seconds 0 not in [1, 600]\n");
}

TEST_CASE("bench display: the swap log is parsed, torn last lines dropped, garbage refused", "[cpu][bench]") {
    const std::vector<std::int64_t> ns = parseSwapLog("300\n100\n\n200\n45", "log");
    REQUIRE(ns.size() == 3);  // "45" has no newline: the process ended while writing it
    CHECK(ns[0] == 100);      // sorted
    CHECK(ns[2] == 300);
    CHECK(parseSwapLog("", "log").empty());
    CHECK_THROWS_WITH(parseSwapLog("100\n12a\n", "swaps.txt"), "swaps.txt: line 2 '12a' is not a time in ns");
    CHECK_THROWS_WITH(parseSwapLog("-5\n", "swaps.txt"), "swaps.txt: line 1 '-5' is not a time in ns");
}

TEST_CASE("bench display: frames in the window after the warm-up, their median and rate", "[cpu][bench]") {
    // A worked example: a slow start (10 frames 200 ms apart, the warm-up) then frames every
    // 40 ms, except every 5th which takes 100 ms. Window [2.5 s, 12.5 s] after the first swap.
    std::vector<std::int64_t> ns;
    std::int64_t t = 1'000'000'000'000;  // any origin
    for (int i = 0; i < 10; ++i, t += 200'000'000) ns.push_back(t);
    for (int i = 0; i < 400; ++i) {
        ns.push_back(t);
        t += (i % 5 == 4) ? 100'000'000 : 40'000'000;
    }
    const welkin::cli::FrameWindow w = frameWindow(ns, 2.5, 10.0);
    CHECK(w.complete);
    // The pattern repeats every 260 ms (four 40 ms frames and one 100 ms frame): 5 frames per
    // 0.26 s = 19.23 fps; the median interval is 40 ms and the 90th percentile 100 ms. The window
    // holds whole and part periods, so the rate is exact only to within one frame in ~190
    // (0.6 %), the tolerance.
    CHECK(w.fps == Approx(5.0 / 0.26).epsilon(0.006));
    CHECK(w.medianMs == Approx(40.0).epsilon(1e-9));  // exact intervals: only rounding
    CHECK(w.p90Ms == Approx(100.0).epsilon(1e-9));
    CHECK(w.frames > 180);
    CHECK(w.frames < 200);
    // The warm-up frames (200 ms apart) are outside the window: with no warm-up at all (window
    // from the first swap) they pull the rate down to ~16.3 fps (164 frames in 10 s).
    CHECK(frameWindow(ns, 0.0, 10.0, 1).fps < w.fps * 0.9);
    // A log that stops before the window's end is flagged incomplete.
    CHECK_FALSE(frameWindow(ns, 2.5, 1000.0).complete);
    // Fewer than two frames: no rate.
    CHECK(frameWindow({}, 0, 1).fps == 0);
    CHECK(frameWindow({5}, 0, 1).fps == 0);
}

TEST_CASE("bench display: a slow start's first frames stay out of the window", "[cpu][bench]") {
    // A first swap at window creation, then 20 s of start-up (a loaded machine building tables),
    // then frames every 50 ms: the window must begin at the 5th swap, not 5 s after the first
    // (which would fall in the gap and count the stall).
    std::vector<std::int64_t> ns = {0, 20'000'000'000};
    for (int i = 1; i <= 300; ++i) ns.push_back(20'000'000'000 + std::int64_t(i) * 50'000'000);
    CHECK(welkin::cli::windowStart(ns, 5.0) == Approx(20.15).epsilon(1e-12));  // the 5th swap, s
    const welkin::cli::FrameWindow w = frameWindow(ns, 5.0, 10.0);
    CHECK(w.fps == Approx(20.0).epsilon(1e-9));  // exact 50 ms intervals: only rounding
    CHECK(w.medianMs == Approx(50.0).epsilon(1e-9));
    CHECK(w.complete);
    // Fewer swaps than the warm-up frames: no window yet.
    CHECK(frameWindow({0, 1'000'000'000, 2'000'000'000}, 0.0, 1.0).frames == 0);
}
