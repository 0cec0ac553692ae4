// One VSOP87 series file as kstars-data ships it (<planet>.<L|B|R><0-5>.vsop, "A B C" per line;
// welkin/astro/vsop87.hpp parseVsop87Series), then the series evaluated as the L0 series of a body
// at the ends and middle of its span: accepted terms are finite and sorted by decreasing |A|,
// and the value and rate of an accepted series are finite.
#include "fuzz_common.hpp"

#include <welkin/astro/vsop87.hpp>

using namespace welkin;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    const std::string text = fuzz::text(data, size);
    fuzz::accepts([&] {
        const std::vector<astro::VsopTerm> terms = astro::parseVsop87Series(text, "earth.L0.vsop");
        for (size_t i = 0; i < terms.size(); ++i) {
            FUZZ_CHECK(std::isfinite(terms[i].a) && std::isfinite(terms[i].b) && std::isfinite(terms[i].c));
            if (i) FUZZ_CHECK(std::fabs(terms[i - 1].a) >= std::fabs(terms[i].a));
        }
        astro::VsopBody body;
        body.L[0] = {terms.empty() ? nullptr : terms.data(), int(terms.size())};
        for (double t : {-4.0, 0.0, 0.26, 4.0}) {  // the span the series serve: years -2000 .. 6000
            const astro::VsopState s = astro::evaluate(body, t, true);
            FUZZ_CHECK(std::isfinite(s.lbr.x) && std::isfinite(s.rate.x));
        }
    });
    return 0;
}
