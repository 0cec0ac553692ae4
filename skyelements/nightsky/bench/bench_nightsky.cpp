// The NightSky's benchmark (welkin bench all): the Milky Way, airglow and zodiacal light on a moonless
// winter night at Malta, looking south 40 deg up. The image's reuse (nightsky.reuse, README
// "Reusing the image") is off here: bench all compares the frames with time running against a
// still frame, and that is the pass drawn; with the reuse a still frame is a copy (measured by
// bench display and the hidden test [night_reuse_timing]), and every frame with the sky turning
// faster than 0.05 px a frame draws, so the ratio would compare the drawing with the copy.
#include <welkin/bench.hpp>

namespace {
welkin::bench::ElementBenchRegistrar reg({
    .element = "nightsky",
    .description = "Malta 2026-01-15 22:00 UTC, looking south 40 deg up, 60 deg field, the image drawn every frame (nightsky.reuse false)",
    .scene = {.time = "2026-01-15T22:00:00Z", .azimuthDeg = 180, .altitudeDeg = 40, .vars = {{"nightsky.reuse", "false"}}},
});
}  // namespace
