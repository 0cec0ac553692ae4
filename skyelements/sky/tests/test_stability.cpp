// Issue 4 item 11: every output of the sky finite and non-negative over a grid of extreme
// configurations (and on Mars), the below-ground clamp warns, and no band at the horizon (radiance across the
// horizon direction follows the direct ray march, at twilight too).
#include <catch2/catch.hpp>

#include "gl_test_context.hpp"

#include <epoxy/gl.h>

#include <welkin/elements/sky.hpp>
#include <welkin/elements/sky_offline.hpp>
#include <welkin/generators/atmosphere.hpp>
#include <welkin/generators/sky_luts.hpp>
#include <welkin/keys.hpp>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

using namespace welkin;
using namespace welkin::generators;

namespace {
constexpr double kDeg = M_PI / 180;

atmosphere::Atmosphere scaledMie(double k) {
    atmosphere::Atmosphere a = atmosphere::Atmosphere::earthClear();
    for (auto& v : a.mieScattering) v *= k;
    for (auto& v : a.mieExtinction) v *= k;
    return a;
}

bool finiteNonNegative(const glm::dvec3& v) {
    for (int c = 0; c < 3; ++c)
        if (!std::isfinite(v[c]) || v[c] < 0) return false;
    return true;
}

bool textureOk(const TextureRef& t, const char* what, std::string& why) {
    std::vector<float> px(size_t(t.width) * t.height * std::max(t.depth, 1) * 4);
    glGetTextureImage(t.id, 0, GL_RGBA, GL_FLOAT, GLsizei(px.size() * sizeof(float)), px.data());
    for (float f : px)
        if (!std::isfinite(f) || f < 0) {
            why = std::string(what) + " has " + std::to_string(f);
            return false;
        }
    return true;
}
}  // namespace

TEST_CASE("Sky stability: finite, non-negative outputs over extreme configurations", "[gl][sky]") {
    test::glContext();
    struct Atm {
        const char* name;
        atmosphere::Atmosphere a;
    } atmospheres[] = {{"clear", atmosphere::Atmosphere::earthClear()},
                       {"mie x0", scaledMie(0.0)},
                       {"mie x20", scaledMie(20.0)},
                       {"ozone off", atmosphere::Atmosphere::earthClear().withOzoneColumn(0.0)},
                       {"mars", atmosphere::Atmosphere::mars()}};
    const double heights[] = {0.0, -0.001, 60e3, 1000e3, 36000e3};
    const double sunAlts[] = {90.0, 0.0, -18.0, -90.0};

    std::vector<std::string> warnings;
    Logger log([&](LogLevel l, std::string_view m) {
        if (l == LogLevel::Warning) warnings.emplace_back(m);
    });
    SkyVars vars = SkyVars::earth();
    vars.set(generators::skykeys::aerialVolume, true);  // these tests look at the aerial volume too
    elements::OfflineRenderer proc(vars, log);
    SkyLuts luts = SkyLuts::obtain(vars);
    for (SkyGenerator* g : {(SkyGenerator*)luts.transmittance.get(), (SkyGenerator*)luts.multiScattering.get(),
                            (SkyGenerator*)luts.sunView.get(), (SkyGenerator*)luts.moonView.get(),
                            (SkyGenerator*)luts.aerial.get(), (SkyGenerator*)luts.irradiance.get()})
        g->setFixedQuality(SkyQuality::tiny());
    elements::Sky sky;
    Camera cam;
    cam.projection = Projection::Equirect;  // the whole sphere: zenith, horizon, grazing rays, nadir
    cam.width = 64;
    cam.height = 32;

    int renders = 0;
    for (auto& atm : atmospheres) {
        vars.set(atmosphere::kAtmosphere, std::make_shared<const atmosphere::Atmosphere>(atm.a));
        for (double h : heights) {
            vars.set(keys::observerHeight, h);
            for (double alt : sunAlts) {
                vars.set(keys::sunDirection, directionFromAzAlt(2.0, alt * kDeg));
                vars.set(keys::moonDirection, directionFromAzAlt(5.0, 20 * kDeg));
                Image img = proc.render(sky, cam);
                ++renders;
                INFO(atm.name << ", observer " << h << " m, Sun " << alt << " deg, per pixel " << sky.perPixel());
                int bad = 0;
                for (float f : img.pixels)
                    if (!std::isfinite(f) || f < 0) ++bad;
                CHECK(bad == 0);
                std::string why;
                const SkyVars& v = vars;
                CHECK(textureOk(v.get(skykeys::transmittanceLut), "transmittance", why));
                CHECK(textureOk(v.get(skykeys::multiScatteringLut), "multiple scattering", why));
                CHECK(textureOk(v.get(skykeys::sunViewLut), "sun view", why));
                CHECK(textureOk(v.get(skykeys::sunViewMieLut), "sun view Mie", why));
                CHECK(textureOk(v.get(skykeys::aerialInscatter), "aerial", why));
                INFO(why);
                CHECK(finiteNonNegative(v.get(skykeys::horizontalIlluminance)));
                CHECK(finiteNonNegative(v.get(lightkeys::sunDiskRadiance)));
                CHECK(finiteNonNegative(v.get(lightkeys::moonIlluminance)));
                CHECK(std::isfinite(v.get(skykeys::zenithLuminance)));
                // Above the atmosphere the per-pixel path must be the one used.
                if (h > 100e3) CHECK(sky.perPixel());
            }
        }
    }
    CHECK(renders == 100);
    // The 1 mm below ground observer was clamped with a warning naming the height.
    bool warned = false;
    for (auto& w : warnings) warned = warned || (w.find("-0.001 m") != std::string::npos && w.find("clamped") != std::string::npos);
    CHECK(warned);
    sky.release();
    proc.release();
}

TEST_CASE("Sky stability: no band at the horizon, day and twilight", "[gl][sky]") {
    // A narrow perspective view straddling the horizon (0.05 deg per row), 90 deg in azimuth from
    // the Sun, rendered from the medium sky-view LUT, against the CPU twin marching every ray
    // (no sky-view LUT). A band would show as rows departing from the march.
    test::glContext();
    SkyVars vars = SkyVars::earth();
    vars.set(generators::skykeys::aerialVolume, true);  // these tests look at the aerial volume too
    vars.set(atmosphere::kAtmosphere, std::make_shared<const atmosphere::Atmosphere>(atmosphere::Atmosphere::earthClear()));
    elements::OfflineRenderer proc(vars, test::testLogger());
    elements::Sky sky(elements::SkyOptions{.quality = 1, .moon = false});
    Camera cam;
    cam.projection = Projection::Perspective;
    cam.width = 4;
    cam.height = 60;
    cam.verticalFovRad = 3.0 * kDeg;
    const double sunAz = 2.0;
    cam.azimuthRad = sunAz + M_PI / 2;
    SkyModel m = SkyModel::fromVars(vars);
    SkyQuality q = SkyQuality::preset(1);
    Lut2D T = cpu::transmittanceLut(m, q);
    cpu::MsField MS = cpu::msField(m, q, T);
    for (double h : {0.0, 1000.0}) {
        for (double sunAlt : {5.0, -4.0, -10.0}) {
            vars.set(keys::observerHeight, h);
            glm::dvec3 sun = directionFromAzAlt(sunAz, sunAlt * kDeg);
            vars.set(keys::sunDirection, sun);
            // Look at the observer's horizon (which dips below 0 deg at 1000 m).
            double dip = std::acos(m.bottomRadius / (m.bottomRadius + h));
            cam.altitudeRad = -dip;
            Image img = proc.render(sky, cam);
            glm::dvec3 E = vars.get(lightkeys::sunIlluminance);
            double worst = 0, worstUpper = 0;
            for (int y = 0; y < cam.height; ++y) {
                auto dir = cam.directionAt({2.0, y + 0.5});
                glm::dvec3 ref = cpu::skyRadiance(m, T, MS, h, *dir, sun, E, 256, m.sunAngularRadius);
                double Yg = 0.2126 * img.at(2, y, 0) + 0.7152 * img.at(2, y, 1) + 0.0722 * img.at(2, y, 2);
                double Yr = 0.2126 * ref.r + 0.7152 * ref.g + 0.0722 * ref.b;
                double e = std::abs(Yg - Yr) / std::max(Yr, 1e-12);
                worst = std::max(worst, e);
                if (std::getenv("WELKIN_DEBUG_HORIZON")) std::printf("h %g sun %g row %d alt %.4f gpu %g ref %g e %.4f\n", h, sunAlt, y, std::asin(dir->z) / kDeg, Yg, Yr, e);
                if (dir->z > -std::sin(dip)) worstUpper = std::max(worstUpper, e);
            }
            INFO("h " << h << " m, Sun " << sunAlt << " deg: worst row error " << worst << " (sky side " << worstUpper << ")");
            // The LUT (192x108, 32 steps) against the 256-step march: measured <= 0.8 % on every
            // row just above and below the horizon; 2 % bound. A band (rows of a blend of ground
            // and sky) would be off by tens of percent.
            CHECK(worstUpper < 0.02);
            CHECK(worst < 0.02);
        }
    }
    sky.release();
    proc.release();
}
