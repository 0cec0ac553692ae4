// The compiled-in lunar and planetary series at any date (the Meeus ch. 47 ELP-2000/82 terms,
// welkin/astro/elp.hpp; the truncated VSOP87, vsop87.hpp): the date is the only input these
// tables see. 8 bytes are read as a double (Julian centuries of TT from J2000.0); inside the
// supported years (|T| <= 80 for the Moon, the years -6000 .. 10000; |T| <= 40 for the
// planets, -2000 .. 6000) every output is finite and the distances lie in their physical ranges.
#include "fuzz_common.hpp"

#include <welkin/astro/elp.hpp>
#include <welkin/astro/vsop87.hpp>

#include <cstring>
#include <numbers>

using namespace welkin;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    if (size < 8) return 0;
    double T;
    std::memcpy(&T, data, 8);
    const astro::MoonEcliptic m = astro::moonMeeus(T);  // any double: must not crash
    if (!(std::abs(T) <= 80.0)) return 0;
    FUZZ_CHECK(std::isfinite(m.longitude) && m.longitude >= 0.0 && m.longitude <= 2.0 * std::numbers::pi);
    FUZZ_CHECK(std::isfinite(m.latitude) && std::abs(m.latitude) < 0.1);  // 5.1 deg inclination + terms
    // Perigee 356,400 km .. apogee 406,700 km; the truncated series stay within 1,000 km of it
    // over the supported span (the polynomial terms in T grow far from J2000).
    FUZZ_CHECK(m.distanceKm > 350000.0 && m.distanceKm < 410000.0);
    const double t = T / 10.0;  // millennia
    if (!(std::abs(t) <= 4.0)) return 0;  // the truncated VSOP87's span: years -2000 .. 6000
    for (int p = 0; p < 8; ++p) {
        const astro::VsopState s = astro::evaluate(astro::vsop87Truncated(astro::VsopPlanet(p), t), t, true);
        FUZZ_CHECK(std::isfinite(s.lbr.x) && std::isfinite(s.lbr.y) && std::isfinite(s.lbr.z));
        FUZZ_CHECK(s.lbr.z > 0.3 && s.lbr.z < 31.0);  // au: Mercury's perihelion 0.31 .. Neptune's aphelion 30.4
    }
    return 0;
}
