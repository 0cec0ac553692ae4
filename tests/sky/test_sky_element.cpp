// The Sky element and the real-time model against physics and the reference integrator.
#include <catch2/catch.hpp>

#include "gl_test_context.hpp"

#include <welkin/elements/sky.hpp>
#include <welkin/elements/sky_offline.hpp>
#include <welkin/generators/atmosphere.hpp>
#include <welkin/generators/sky_luts.hpp>
#include <welkin/keys.hpp>

#if __has_include(<welkin/generators/reference_sky.hpp>)
#include <welkin/generators/reference_sky.hpp>
#define WELKIN_HAVE_REFERENCE 1
#endif

#include <cmath>
#include <cstdio>

using namespace welkin;
using namespace welkin::generators;

namespace {
constexpr double kDeg = M_PI / 180;
double Y(const glm::dvec3& c) { return 0.2126 * c.r + 0.7152 * c.g + 0.0722 * c.b; }
}  // namespace

#ifdef WELKIN_HAVE_REFERENCE
TEST_CASE("Sky diagnostics: CPU twin against the reference integrator", "[.diag]") {
    auto atm = atmosphere::Atmosphere::earthClear();
    atmosphere::ReferenceOptions ro;
    ro.mode = atmosphere::SpectralMode::Rgb;
    ro.threads = 2;
    for (int orders : {1, 60}) {
        ro.maxOrders = orders;
        atmosphere::ReferenceSky ref(atm, ro);
        SkyVars vars = SkyVars::earth();
        vars.set(atmosphere::kAtmosphere, std::make_shared<const atmosphere::Atmosphere>(atm));
        SkyModel m = SkyModel::fromVars(vars);
        SkyQuality q = SkyQuality::preset(2);
        Lut2D T = cpu::transmittanceLut(m, q);
        cpu::MsField MS = cpu::msField(m, q, T);
        if (orders == 1) {
            for (auto& t : MS.psi.texels) t = glm::dvec3(0.0);
            for (auto& l : MS.sh)
                for (auto& t : l.texels) t = glm::dvec3(0.0);
        }
        for (double sunAlt : {60.0, 20.0, 5.0, -4.0, -10.0, -18.0}) {
            glm::dvec3 sun = directionFromAzAlt(0.0, sunAlt * kDeg);
            for (auto [az, alt] : {std::pair{180.0, 45.0}, {90.0, 10.0}, {0.0, 90.0}, {0.0, 5.0}, {180.0, 5.0}, {30.0, 20.0}}) {
                glm::dvec3 d = directionFromAzAlt(az * kDeg, alt * kDeg);
                glm::dvec3 r = ref.radiance(0.0, d, sun);
                glm::dvec3 c = cpu::skyRadiance(m, T, MS, 0.0, d, sun, m.solarIlluminance, 512, m.sunAngularRadius);
                std::printf("orders %2d sun %6.1f view az %5.1f alt %4.1f: ref %.4g cpu %.4g ratio %.4f\n", orders, sunAlt, az, alt,
                            Y(r), Y(c), Y(c) / Y(r));
            }
        }
    }
}
#endif
