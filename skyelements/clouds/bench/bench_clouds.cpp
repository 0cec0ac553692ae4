// The Clouds' benchmark (welkin bench all): mid-morning at Malta looking east 15 deg up, and the
// cost against the ray-march samples per view ray (reprojection off, so every pixel marches).
#include <welkin/bench.hpp>

namespace {
welkin::bench::WorkPoint samples(const char* n, double work) {
    return {.vars = {{"clouds.reprojection", "false"}, {"clouds.samples", n}}, .work = work};
}

welkin::bench::ElementBenchRegistrar reg({
    .element = "clouds",
    .description = "Malta 2026-06-21 08:00 UTC, looking east 15 deg up, 60 deg field, default clouds",
    .scene = {.time = "2026-06-21T08:00:00Z", .azimuthDeg = 90, .altitudeDeg = 15},
    .sweeps = {{.name = "cloud samples per ray",
                .unit = "samples",
                .points = {samples("8", 8), samples("16", 16), samples("32", 32), samples("64", 64)}}},
});
}  // namespace
