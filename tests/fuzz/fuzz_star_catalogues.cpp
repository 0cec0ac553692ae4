// The text star catalogues: kstars stars.dat, the Yale Bright Star Catalogue and the HYG CSV
// (welkin/astro/stars.hpp). The first byte picks the parser, the rest is the file. Every star
// accepted must have a position in range and finite numbers.
#include "fuzz_common.hpp"

#include <welkin/astro/stars.hpp>

#include <numbers>

using namespace welkin;

namespace {
void checkStars(const std::vector<astro::Star>& stars, double maxMagnitude) {
    for (const astro::Star& s : stars) {
        FUZZ_CHECK(s.raJ2000Rad >= 0.0 && s.raJ2000Rad <= 2.0 * std::numbers::pi + 1e-9);
        FUZZ_CHECK(std::abs(s.decJ2000Rad) <= std::numbers::pi / 2 + 1e-9);
        FUZZ_CHECK(std::isfinite(s.pmRaMasPerYear) && std::isfinite(s.pmDecMasPerYear));
        FUZZ_CHECK(std::isfinite(s.magnitudeV) && s.magnitudeV <= maxMagnitude);
        FUZZ_CHECK(std::isfinite(s.colorBV));
        FUZZ_CHECK(s.hip >= 0 && s.hd >= 0);
        const glm::dvec3 p = astro::starDirectionJ2000(s), pm = astro::starProperMotion(s);
        FUZZ_CHECK(std::isfinite(p.x + p.y + p.z) && std::isfinite(pm.x + pm.y + pm.z));
    }
}
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    if (size < 1) return 0;
    const int which = data[0] % 3;
    const std::string text = fuzz::text(data + 1, size - 1);
    const double maxMag = 99.0;
    fuzz::accepts([&] {
        switch (which) {
        case 0: checkStars(astro::parseKStarsCatalogue(text, "stars.dat", maxMag), maxMag); break;
        case 1: checkStars(astro::parseYaleBrightStarCatalogue(text, "catalog", maxMag), maxMag); break;
        default: checkStars(astro::parseHygCsv(text, "hyg.csv", maxMag), maxMag); break;
        }
    });
    return 0;
}
