// Timing helpers shared by the `welkin bench` subcommands. GL timer queries mean nothing on
// llvmpipe: passes are timed on the CPU clock, bracketed by glFinish so GPU work is included.
//
//   double ms = welkin::cli::medianMs(10, [&] { processor.renderFrame(); });
#pragma once
#include <epoxy/gl.h>

#include <algorithm>
#include <chrono>
#include <functional>
#include <vector>

namespace welkin::cli {

/// Median wall time of `repeats` (>= 1) calls of `fn`, milliseconds, each bracketed by glFinish.
inline double medianMs(int repeats, const std::function<void()>& fn) {
    std::vector<double> t;
    for (int i = 0; i < std::max(repeats, 1); ++i) {
        glFinish();
        auto t0 = std::chrono::steady_clock::now();
        fn();
        glFinish();
        t.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
    }
    std::sort(t.begin(), t.end());
    return t[t.size() / 2];
}

}  // namespace welkin::cli
