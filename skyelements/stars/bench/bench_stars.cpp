// The Stars' benchmark (welkin bench all): a moonless winter night at Malta looking south, and
// its cost against the number of stars drawn (the magnitude limit swept, the adaptive limit off).
#include <welkin/bench.hpp>

namespace {
welkin::bench::WorkPoint limit(const char* mag) { return {.vars = {{"stars.adaptive_limit", "false"}, {"stars.magnitude_limit", mag}}}; }

welkin::bench::ElementBenchRegistrar reg({
    .element = "stars",
    .description = "Malta 2026-01-15 22:00 UTC, looking south 40 deg up, 60 deg field",
    .scene = {.time = "2026-01-15T22:00:00Z", .azimuthDeg = 180, .altitudeDeg = 40},
    .sweeps = {{.name = "stars drawn",
                .unit = "stars",
                .workStat = "/stars/drawn",
                .points = {limit("3"), limit("4"), limit("5"), limit("6"), limit("7")}}},
});
}  // namespace
