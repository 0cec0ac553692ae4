// kstars cnames.dat (welkin/elements/constellations.hpp parseConstellationNames): per culture,
// "HHMMSS+DDMMSSAbb NAME" lines. Accepted labels lie on the sphere and have a name.
#include "fuzz_common.hpp"

#include <welkin/elements/constellations.hpp>

#include <numbers>

using namespace welkin;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    const std::string text = fuzz::text(data, size);
    fuzz::accepts([&] {
        for (const auto& l : elements::parseConstellationNames(text, "cnames.dat", "western")) {
            FUZZ_CHECK(l.raJ2000Rad >= 0.0 && l.raJ2000Rad < 2.0 * std::numbers::pi);
            FUZZ_CHECK(std::abs(l.decJ2000Rad) <= std::numbers::pi / 2);
            FUZZ_CHECK(!l.name.empty());
        }
    });
    return 0;
}
