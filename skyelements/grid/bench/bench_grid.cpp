// The Grid's benchmark (welkin bench all): the coordinate grid on a moonless
// winter night at Malta, looking south 40 deg up.
#include <welkin/bench.hpp>

namespace {
welkin::bench::ElementBenchRegistrar reg({
    .element = "grid",
    .description = "Malta 2026-01-15 22:00 UTC, looking south 40 deg up, 60 deg field",
    .scene = {.time = "2026-01-15T22:00:00Z", .azimuthDeg = 180, .altitudeDeg = 40},
});
}  // namespace
