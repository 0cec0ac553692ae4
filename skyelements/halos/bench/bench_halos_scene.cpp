// The Halos' scene for welkin bench all (its cost per frame and with time running): a crystal
// layer of optical depth 0.3 (the common preset) over Malta in the afternoon, looking towards the
// Sun ~30 deg up with a 100 deg field, so the 22 deg halo and the sundogs are in view. (Without
// it the harness measured the default scene, where the element draws nothing.)
#include <welkin/bench.hpp>

namespace {
welkin::bench::ElementBenchRegistrar reg({
    .element = "halos",
    .description = "Malta 2026-06-21 15:00 UTC (Sun ~33 deg up in the west), looking at it with a 100 deg field, crystals of optical depth 0.3",
    .scene = {.time = "2026-06-21T15:00:00Z", .azimuthDeg = 262, .altitudeDeg = 30, .fovDeg = 100, .vars = {{"halos.optical_depth", "0.3"}}},
});
}  // namespace
