// The real-time Sky element (medium) against the reference integrator at directions and Sun
// positions of the Kider et al. 2013 measured skies (issue 4 item 12; `welkin bench
// sky-measured` scores both against the measurements). The data are in the repository
// (skyelements/sky/tests/data/kider2013, SOURCE.md there); without them the test fails.
#include <catch2/catch.hpp>

#include "gl_test_context.hpp"

#include <epoxy/gl.h>

#include <welkin/camera.hpp>
#include <welkin/csv.hpp>
#include <welkin/elements/sky.hpp>
#include <welkin/elements/sky_offline.hpp>
#include <welkin/generators/atmosphere.hpp>
#include <welkin/generators/reference_sky.hpp>
#include <welkin/keys.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

using namespace welkin;

namespace {

constexpr double kDeg = M_PI / 180;
double lum(const glm::dvec3& c) { return 0.2126 * c.r + 0.7152 * c.g + 0.0722 * c.b; }

}  // namespace

TEST_CASE("Sky medium against the reference integrator at Kider 2013 directions", "[gl][sky]") {
    const std::string dir = std::string(WELKIN_SOURCE_DIR) + "/skyelements/sky/tests/data/kider2013";
    REQUIRE(std::filesystem::exists(dir + "/kider2013_scans.csv"));  // kept in the repository: never skipped
    test::glContext();
    // The bench's "welkin" atmosphere: AERONET AOD 0.11 at 500 nm, alpha 0.9, asymmetry 0.64.
    const auto atm = atmosphere::Atmosphere::earthClear()
                         .withAerosolOpticalDepth(0.11 * std::pow(550.0 / 500.0, -0.9), 0.9)
                         .withAerosolAsymmetry(0.64);
    // RGB mode: the real-time path's model and channels, so the difference is the LUTs' error.
    const atmosphere::ReferenceSky ref(atm, atmosphere::ReferenceOptions::fast());
    SkyVars vars = SkyVars::earth();
    vars.set(keys::observerHeight, 0.0);
    vars.set(keys::moonDirection, glm::dvec3(0, 0, -1));
    vars.set(atmosphere::kAtmosphere, std::make_shared<const atmosphere::Atmosphere>(atm));
    elements::OfflineRenderer r(vars, test::testLogger());
    elements::Sky sky(elements::SkyOptions{.quality = 1, .moon = false});
    Camera cam;
    cam.projection = Projection::Equirect;
    cam.width = 360;  // 1 deg per pixel; read at pixel centres below, so no interpolation error
    cam.height = 180;

    const std::vector<std::string> names = {"kider2013_20130527_0930.csv", "kider2013_20130527_1100.csv",
                                            "kider2013_20130527_1330.csv"};
    double s2 = 0, worst = 0;
    int n = 0;
    for (const std::string& name : names) {
        const std::string path = dir + "/" + name;
        const CsvTable table = CsvTable::load(path);
        const auto az = table.numbers("sample_az_deg"), alt = table.numbers("sample_alt_deg");
        const double sunAlt = table.numbers("sun_alt_deg").at(0);
        // The scans' symmetry azimuth differs from the astronomical one (README), but the
        // comparison here is model against model: any Sun position of the day serves.
        const glm::dvec3 sun = directionFromAzAlt(table.numbers("sun_az_deg").at(0) * kDeg, sunAlt * kDeg);
        vars.set(keys::sunDirection, sun);
        const Image img = r.render(sky, cam);
        for (std::size_t i = 1; i < az.size(); i += 8) {  // 10 of the 80 usable samples
            const glm::dvec3 d0 = directionFromAzAlt(az[i] * kDeg, alt[i] * kDeg);
            // The nearest pixel centre, and the direction exactly through it for the reference.
            const glm::dvec2 p = *cam.pixelOf(d0);
            const int x = std::clamp(int(p.x), 0, cam.width - 1), y = std::clamp(int(p.y), 0, cam.height - 1);
            const glm::dvec3 d = *cam.directionAt({x + 0.5, y + 0.5});
            if (glm::dot(d, sun) > std::cos(10 * kDeg)) continue;  // the bench scores > 10 deg from the Sun
            const double g = lum(glm::dvec3(img.at(x, y, 0), img.at(x, y, 1), img.at(x, y, 2)));
            const double e = lum(ref.radiance(0.0, d, sun));
            const double rel = (g - e) / e;
            INFO(name << " sample " << i << " az " << az[i] << " alt " << alt[i] << ": real-time " << g << " reference " << e
                      << " cd/m2");
            // Per direction: worst 2.2 % measured (2026-11-22); 5 % leaves room for the coarse
            // fast() reference (1-2 %) and the sky-view LUT's resolution towards the aureole.
            CHECK(std::abs(rel) < 0.05);
            s2 += rel * rel;
            worst = std::max(worst, std::abs(rel));
            ++n;
        }
    }
    const double rms = std::sqrt(s2 / n);
    INFO("RMS " << rms << " worst " << worst << " over " << n << " directions");
    CHECK(n >= 25);  // the 10-deg exclusion drops at most a few of the 30
    // Measured 0.9 % RMS here (bench sky-measured: 1.05 % over all 15 scans against the spectral
    // reference); 3 % is still well below the model-measurement differences the bench reports
    // (7 % RMS after removing the level), so a regression that matters fails.
    CHECK(rms < 0.03);
    sky.release();
    r.release();
}
