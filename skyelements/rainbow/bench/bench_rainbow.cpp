// The Rainbow's benchmark (welkin bench all): a 5 mm/h shower at Malta in the evening, looking
// east towards the anti-solar point with the Sun low in the west.
#include <welkin/bench.hpp>

namespace {
welkin::bench::ElementBenchRegistrar reg({
    .element = "rainbow",
    .description = "Malta 2026-06-21 17:00 UTC (Sun ~12 deg up in the west), looking east 20 deg up, 5 mm/h rain",
    .scene = {.time = "2026-06-21T17:00:00Z", .azimuthDeg = 90, .altitudeDeg = 20, .vars = {{"rain.rate_mm_h", "5"}}},
});
}  // namespace
