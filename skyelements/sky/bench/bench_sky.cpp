// The Sky's benchmark (welkin bench all): mid-morning at Malta looking east (`welkin bench sky`
// measures the presets' tables and accuracy).
#include <welkin/bench.hpp>

namespace {
welkin::bench::ElementBenchRegistrar reg({
    .element = "sky",
    .description = "Malta 2026-06-21 08:00 UTC, looking east 20 deg up, 60 deg field",
    .scene = {.time = "2026-06-21T08:00:00Z", .azimuthDeg = 90, .altitudeDeg = 20},
});
}  // namespace
