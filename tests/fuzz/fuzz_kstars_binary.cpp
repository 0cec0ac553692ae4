// kstars' binary star files (namedstars.dat, unnamedstars.dat; welkin/astro/stars.hpp
// parseKStarsBinaryStars): header, field table, trixel index and 32-byte records, all
// little-endian offsets and counts taken from the file.
#include "fuzz_common.hpp"

#include <welkin/astro/stars.hpp>

using namespace welkin;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    const std::string bytes = fuzz::text(data, size);
    fuzz::accepts([&] {
        const std::vector<astro::Star> stars = astro::parseKStarsBinaryStars(bytes, "namedstars.dat");
        for (const astro::Star& s : stars) {
            FUZZ_CHECK(std::isfinite(s.raJ2000Rad) && std::isfinite(s.decJ2000Rad));
            FUZZ_CHECK(s.hd >= 0);
        }
    });
    return 0;
}
