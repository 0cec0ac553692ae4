// Frame-time statistics of `welkin bench display`: the swap log written by the swap-timing shim
// (apps/frame_shim/swap_timer_shim.c, one CLOCK_MONOTONIC time in nanoseconds a line) and the
// median frame time and frame rate over a fixed window after a warm-up.
//
//   std::vector<std::int64_t> ns = welkin::cli::parseSwapLog(text, "swaps.txt");
//   welkin::cli::FrameWindow w = welkin::cli::frameWindow(ns, 5.0, 10.0);  // 5 s warm-up, 10 s window
//   std::printf("%.1f fps, median %.1f ms\n", w.fps, w.medianMs);
#pragma once
#include <welkin/error.hpp>

#include <algorithm>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

namespace welkin::cli {

/// Swap times (nanoseconds, any monotonic origin) from the shim's log: one non-negative integer a
/// line; blank lines are skipped, and a last line without its newline (the process ended while
/// writing) is dropped. Anything else throws naming `what` and the line. Sorted on return.
inline std::vector<std::int64_t> parseSwapLog(const std::string& text, const std::string& what) {
    std::vector<std::int64_t> ns;
    size_t pos = 0;
    int lineNo = 0;
    while (pos < text.size()) {
        const size_t end = text.find('\n', pos);
        if (end == std::string::npos) break;  // a torn last line
        ++lineNo;
        const std::string line = text.substr(pos, end - pos);
        pos = end + 1;
        if (line.empty()) continue;
        if (line.size() > 19 || !std::all_of(line.begin(), line.end(), [](char c) { return c >= '0' && c <= '9'; }))
            throw Error(what + ": line " + std::to_string(lineNo) + " '" + line.substr(0, 40) + "' is not a time in ns");
        ns.push_back(std::stoll(line));
    }
    std::sort(ns.begin(), ns.end());
    return ns;
}

/// The frames of one fixed window.
struct FrameWindow {
    int frames = 0;         ///< swaps inside the window
    double seconds = 0;     ///< from the window's first swap to its last, s
    double fps = 0;         ///< (frames - 1) / seconds: frames per second (0 with fewer than 2 frames)
    double medianMs = 0;    ///< median interval between consecutive swaps in the window, ms
    double p90Ms = 0;       ///< 90th percentile of those intervals, ms (the slow frames)
    bool complete = false;  ///< the log reaches the window's end (the program ran long enough)
};

/// When the window starts, s on the log's clock: warmupS after the first swap, and not before the
/// swap number `warmupFrames` (1-based; a slow start's first frames take seconds each on a loaded
/// machine). NaN until the log holds that many swaps.
inline double windowStart(const std::vector<std::int64_t>& ns, double warmupS, int warmupFrames = 5) {
    const size_t k = size_t(std::max(warmupFrames, 1));
    if (ns.size() < k) return std::numeric_limits<double>::quiet_NaN();
    return std::max(double(ns.front()) * 1e-9 + warmupS, double(ns[k - 1]) * 1e-9);
}

/// Statistics of the swaps in [start, start + windowS], start = windowStart() (warmupS >= 0,
/// windowS > 0, seconds).
inline FrameWindow frameWindow(const std::vector<std::int64_t>& ns, double warmupS, double windowS, int warmupFrames = 5) {
    FrameWindow w;
    const double t0 = windowStart(ns, warmupS, warmupFrames), t1 = t0 + windowS;
    if (!(t0 == t0)) return w;  // too few swaps
    std::vector<double> t;
    for (std::int64_t v : ns) {
        const double s = double(v) * 1e-9;
        if (s >= t0 && s <= t1) t.push_back(s);
    }
    w.complete = double(ns.back()) * 1e-9 >= t1;
    w.frames = int(t.size());
    if (t.size() < 2) return w;
    w.seconds = t.back() - t.front();
    w.fps = w.seconds > 0 ? double(t.size() - 1) / w.seconds : 0;
    std::vector<double> dt;
    for (size_t i = 1; i < t.size(); ++i) dt.push_back((t[i] - t[i - 1]) * 1e3);
    std::sort(dt.begin(), dt.end());
    w.medianMs = dt.size() % 2 ? dt[dt.size() / 2] : 0.5 * (dt[dt.size() / 2 - 1] + dt[dt.size() / 2]);
    w.p90Ms = dt[std::min(dt.size() - 1, size_t(0.9 * double(dt.size())))];
    return w;
}

/// Median of a non-empty list (the mean of the middle two for an even count); 0 when empty.
inline double medianOf(std::vector<double> v) {
    if (v.empty()) return 0;
    std::sort(v.begin(), v.end());
    return v.size() % 2 ? v[v.size() / 2] : 0.5 * (v[v.size() / 2 - 1] + v[v.size() / 2]);
}

}  // namespace welkin::cli
