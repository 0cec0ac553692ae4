// kstars clines.dat (welkin/elements/constellations.hpp parseConstellationLines): "C <culture>"
// headers, "# name" comments, "M <HD>" / "D <HD>" lines; the figures are then resolved against a
// few stars whose HD numbers the seeds use (Orion's).
#include "fuzz_common.hpp"

#include <welkin/elements/constellations.hpp>

using namespace welkin;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    const std::string text = fuzz::text(data, size);
    static const std::vector<astro::Star> stars = [] {
        std::vector<astro::Star> s;
        const int hds[] = {39801, 35468, 37128, 36486, 37742, 34085, 38771};  // Betelgeuse ... Saiph
        for (int i = 0; i < 7; ++i) {
            astro::Star star;
            star.raJ2000Rad = 1.3 + 0.05 * i;
            star.decJ2000Rad = -0.2 + 0.04 * i;
            star.hd = hds[i];
            s.push_back(star);
        }
        return s;
    }();
    fuzz::accepts([&] {
        const auto figures = elements::parseConstellationLines(text, "clines.dat", "western");
        int unresolved = -1;
        const auto segments = elements::resolveConstellationSegments(figures, stars, &unresolved);
        size_t numbers = 0;
        for (const auto& f : figures) {
            FUZZ_CHECK(!f.polylines.empty());
            for (const auto& poly : f.polylines) {
                FUZZ_CHECK(!poly.empty());
                for (int hd : poly) FUZZ_CHECK(hd > 0);
                numbers += poly.size();
            }
        }
        FUZZ_CHECK(unresolved >= 0 && size_t(unresolved) <= numbers);
        FUZZ_CHECK(segments.size() <= numbers);
    });
    return 0;
}
