// The Sky element and the real-time model against physics and the reference integrator.
#include <catch2/catch.hpp>

#include <welkin/astro/astro_keys.hpp>
#include <welkin/astro/bodies.hpp>

#include "gl_test_context.hpp"
#include "uniform_field.hpp"

#include <epoxy/gl.h>

#include <welkin/elements/aerial_perspective.hpp>
#include <welkin/elements/sky.hpp>
#include <welkin/elements/sky_offline.hpp>
#include <welkin/generators/atmosphere.hpp>
#include <welkin/generators/sky_luts.hpp>
#include <welkin/embedded/engine_shaders.hpp>
#include <welkin/gl/shader.hpp>
#include <welkin/glsl_cpp.hpp>
#include <welkin/keys.hpp>
#include <welkin/processor.hpp>

#if __has_include(<welkin/generators/reference_sky.hpp>)
#include <welkin/generators/reference_sky.hpp>
#define WELKIN_HAVE_REFERENCE 1
#endif

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <optional>
#include <cstdio>

using namespace welkin;
using namespace welkin::generators;

namespace {
constexpr double kDeg = M_PI / 180;
double Y(const glm::dvec3& c) { return 0.2126 * c.r + 0.7152 * c.g + 0.0722 * c.b; }
}  // namespace

namespace {
struct SkyRig {
    SkyVars vars = SkyVars::earth();
    elements::OfflineRenderer r{vars, test::testLogger()};
    elements::Sky sky;
    explicit SkyRig(int quality = 1, bool moon = true, bool aerial = false)
        : sky(elements::SkyOptions{.quality = quality, .moon = moon, .aerialPerspective = aerial}) {
        test::glContext();
        vars.set(atmosphere::kAtmosphere, std::make_shared<const atmosphere::Atmosphere>(atmosphere::Atmosphere::earthClear()));
        vars.set(keys::moonDirection, glm::dvec3(0, 0, -1));
    }
    Image render(double sunAltDeg, double h = 0.0, int w = 32, int hgt = 16) {
        vars.set(keys::sunDirection, directionFromAzAlt(3.0, sunAltDeg * kDeg));
        vars.set(keys::observerHeight, h);
        Camera c;
        c.projection = Projection::Equirect;
        c.width = w;
        c.height = hgt;
        return r.render(sky, c);
    }
    ~SkyRig() {
        sky.release();
        r.release();
    }
};
}  // namespace

// The Sky's azimuth for its tables over absolute azimuth: the shader's text, compiled in double.
namespace sky_atan_shared {
using namespace welkin::glsl::dp;
#include "../shaders/sky_atan.shared.glsl"
}  // namespace sky_atan_shared

TEST_CASE("Sky: the tables' azimuth (skyAtan2, no builtin atan) is atan2 within 1.2e-5 rad", "[cpu][sky]") {
    // Every direction of the circle at 1e-4 rad steps, at three radii (the function sees
    // unnormalised components), and the axes; the angle difference is taken modulo 2 pi (at
    // y = -0 the builtin says -pi, this +pi: the same azimuth, u wraps).
    double worst = 0;
    for (double radius : {1e-6, 1.0, 1e6})
        for (int i = 0; i < 62832; ++i) {
            const double az = -std::numbers::pi + 1e-4 * i;
            const double x = radius * std::cos(az), y = radius * std::sin(az);
            double d = sky_atan_shared::skyAtan2(y, x) - std::atan2(y, x);
            d = std::remainder(d, 2.0 * std::numbers::pi);
            worst = std::max(worst, std::abs(d));
        }
    INFO("largest error " << worst << " rad");
    // A&S 4.4.49 states |error| <= 1e-5 on [0, 1]; its coefficients as printed (7 digits) give
    // 1.15e-5 here. 1.2e-5 rad is the bound the shader's comment and the README rely on (2e-6 of
    // the table's turn, ~1e-3 of a texel): a larger error is a defect of the polynomial.
    CHECK(worst <= 1.2e-5);
    CHECK(worst > 1e-7);  // an approximation, not the builtin: the bound is what the shader relies on
    CHECK(sky_atan_shared::skyAtan2(0.0, 0.0) == 0.0);  // the zenith and nadir: any u, 0 by definition
    CHECK(sky_atan_shared::skyAtan2(1.0, 0.0) == Approx(std::numbers::pi / 2).margin(1e-12));  // east: a quarter turn
    CHECK(sky_atan_shared::skyAtan2(0.0, -1.0) == Approx(std::numbers::pi).margin(1e-12));     // south
}

TEST_CASE("Sky: horizontal illuminance against published clear-sky values", "[gl][sky]") {
    // Published orders of magnitude (e.g. the IES Lighting Handbook; Schlyter's table of
    // twilight illuminance): ~1e5 lx with the Sun high, a few hundred lux at sunset, a few lux at
    // the end of civil twilight (-6 deg), < 0.01 lx at the end of astronomical twilight.
    SkyRig rig(1, false);
    struct Case {
        double alt, lo, hi;
    } cases[] = {{60, 7e4, 1.3e5}, {0, 150, 2000}, {-6, 0.5, 20}, {-18, 1e-6, 0.01}};
    double last = 1e9;
    for (auto c : cases) {
        rig.render(c.alt);
        glm::dvec3 e = rig.vars.get(skykeys::horizontalIlluminance);
        INFO("Sun " << c.alt << " deg: global " << e.x << " lx, direct " << e.y << ", diffuse " << e.z);
        CHECK(e.x >= c.lo);
        CHECK(e.x <= c.hi);
        CHECK(e.x == Approx(e.y + e.z));  // global = direct + diffuse
        CHECK(e.x < last / 50);           // falls by orders of magnitude between the cases
        last = e.x;
    }
}

#ifdef WELKIN_HAVE_REFERENCE
TEST_CASE("Sky: rendered radiance and illuminance against the reference integrator", "[gl][sky]") {
    // The real-time path (medium) against the brute-force reference (RGB mode, all orders,
    // ReferenceOptions::fast(): ~1-2 % by day) at a few directions by day and at -4 deg.
    SkyRig rig(1, false);
    atmosphere::ReferenceSky ref(atmosphere::Atmosphere::earthClear(), atmosphere::ReferenceOptions::fast());
    Camera cam;
    cam.projection = Projection::Equirect;
    cam.width = 32;
    cam.height = 16;
    for (double sunAlt : {60.0, 20.0, 5.0, -4.0}) {
        Image img = rig.render(sunAlt, 0.0, cam.width, cam.height);
        glm::dvec3 sun = directionFromAzAlt(3.0, sunAlt * kDeg);
        double s2 = 0;
        int n = 0;
        for (int y = 1; y < 7; ++y)
            for (int x = 0; x < cam.width; x += 3) {
                auto d = cam.directionAt({x + 0.5, y + 0.5});
                if (glm::dot(*d, sun) > std::cos(5 * kDeg)) continue;
                double g = Y(glm::dvec3(img.at(x, y, 0), img.at(x, y, 1), img.at(x, y, 2)));
                double r = Y(ref.radiance(0.0, *d, sun));
                s2 += (g - r) * (g - r) / (r * r);
                ++n;
            }
        double rms = std::sqrt(s2 / n);
        atmosphere::SkyIlluminance e = ref.illuminance(0.0, sun, {}, 8, 8);
        glm::dvec3 ours = rig.vars.get(skykeys::horizontalIlluminance);
        INFO("Sun " << sunAlt << " deg: RMS luminance error " << rms << " over " << n << " directions; diffuse " << ours.z
                    << " vs " << e.diffuse << " lx; direct " << ours.y << " vs " << e.direct);
        // Measured 1.6-3.5 % (60, 20, 5, -4 deg: 3.5, 2.5, 2.4, 1.6 %; 2026-11-23) with medium's
        // directional multiple scattering (SH l <= 4, one pass, delta-M) and the sky-lit ground;
        // 5 % leaves room for the coarse reference (1-2 %) and the LUT. The l <= 2 model before
        // measured 3-5 % (fails at 5 deg), Hillaire's isotropic approximation alone 9-12 %.
        CHECK(rms < 0.05);
        // Diffuse illuminance measured within 1 % by day and +2.6 % at -4 deg.
        CHECK(ours.z == Approx(e.diffuse).epsilon(sunAlt > 0 ? 0.04 : 0.08));
        CHECK(ours.y == Approx(e.direct).epsilon(0.03).margin(1e-3));  // same transmittance model
    }
}
#endif

#ifdef WELKIN_HAVE_REFERENCE
TEST_CASE("Sky: the ground is lit by the sky as well as by the Sun", "[gl][sky]") {
    // Looking straight down from 0 m the ray ends on the ground at once: the pixel is the
    // ground's own radiance, albedo / pi x (direct + sky irradiance). The reference integrator
    // adds the sky's irradiance (all orders) to the direct light. With the Sun at -2 deg there
    // is no direct light at all, so a ground lit by the Sun alone would be black; at 30 deg the
    // sky gives 23 % of the ground's light (reference: 13 100 of 56 100 lx).
    SkyRig rig(1, false);
    atmosphere::ReferenceSky ref(atmosphere::Atmosphere::earthClear(), atmosphere::ReferenceOptions::fast());
    Camera cam;
    cam.projection = Projection::Equirect;
    cam.width = 32;
    cam.height = 16;
    for (double sunAlt : {30.0, -2.0}) {
        Image img = rig.render(sunAlt, 0.0, cam.width, cam.height);
        glm::dvec3 sun = directionFromAzAlt(3.0, sunAlt * kDeg);
        for (int x : {0, 8, 16, 24}) {
            auto d = cam.directionAt({x + 0.5, 15.5});  // 84 deg below the horizon
            REQUIRE(d);
            double g = Y(glm::dvec3(img.at(x, 15, 0), img.at(x, 15, 1), img.at(x, 15, 2)));
            double r = Y(ref.radiance(0.0, *d, sun));
            INFO("Sun " << sunAlt << " deg, ground pixel " << x << ": " << g << " cd/m^2, reference " << r);
            CHECK(g > 0.0);
            // Measured (medium, one SH pass; 2026-11-23): +1.6 % at 30 deg, +0.05 % at -2 deg.
            // ReferenceOptions::fast()'s own sky irradiance is 4.5 % low at -2 deg. 8 % fails a
            // ground lit by the Sun only (-23 % at 30 deg, and 0 at -2 deg).
            CHECK(g == Approx(r).epsilon(0.08));
        }
    }
}
#endif

TEST_CASE("Sky: the Moon lights a faint blue night sky that follows its phase", "[gl][sky]") {
    // The one lunar law (astro::magnitude::moon, Allen): full Moon at the mean distance
    // V = -12.74 -> 0.316 lx; quarter (90 deg) 2.6 mag fainter.
    auto moonLux = [](double phaseRad, double distM) {
        return astro::magnitude::illuminanceLux(astro::magnitude::moon(1.0, distM / 1.495978707e11, phaseRad * 180 / M_PI));
    };
    CHECK(moonLux(0.0, 384400e3) == Approx(0.316).epsilon(0.005));
    CHECK(moonLux(M_PI / 2, 384400e3) / moonLux(0.0, 384400e3) ==
          Approx(std::pow(10.0, -0.4 * (0.026 * 90 + 4e-9 * std::pow(90.0, 4)))).epsilon(1e-9));
    // Perigee (356 500 km) is brighter than apogee (406 700 km) by (406.7/356.5)^2 = 1.30.
    CHECK(moonLux(0, 356500e3) / moonLux(0, 406700e3) == Approx(1.3015).epsilon(1e-3));

    SkyRig rig(0, true);
    const Key<double> phase{"moon.phase_angle_rad", Range{0, M_PI}};
    rig.vars.set(phase, 0.0);
    rig.vars.set(keys::moonDirection, directionFromAzAlt(1.0, 45 * kDeg));
    Image night = rig.render(-30.0);
    glm::dvec3 Em = rig.vars.get(lightkeys::moonIlluminance);
    // No astronomy in this rig: the lights generator applies the same law to the phase key.
    CHECK(Y(Em) == Approx(moonLux(0.0, 384400e3)).epsilon(1e-6));
    CHECK(Em.r > Em.b);  // moonlight is redder than sunlight (regolith reflectance rises with wavelength)
    // The same sky by day with the Sun where the Moon is, scaled by the illuminance ratio.
    SkyRig day(0, false);
    day.vars.set(keys::sunDirection, directionFromAzAlt(1.0, 45 * kDeg));
    Camera c;
    c.projection = Projection::Equirect;
    c.width = 32;
    c.height = 16;
    day.vars.set(keys::observerHeight, 0.0);
    Image sunlit = day.r.render(day.sky, c);
    glm::dvec3 Es = day.vars.get(lightkeys::sunIlluminance);
    const glm::dvec3 ratio = Em / Es;  // per channel: moonlight has its own colour
    int x = 5, y = 2;  // a sky pixel well away from both lights' directions
    glm::dvec3 n(night.at(x, y, 0), night.at(x, y, 1), night.at(x, y, 2));
    glm::dvec3 d(sunlit.at(x, y, 0), sunlit.at(x, y, 1), sunlit.at(x, y, 2));
    INFO("night " << Y(n) << " cd/m^2, day " << Y(d) << " x ratio " << Y(ratio));
    // Linear in the light, channel by channel; the Sun at -30 adds nothing. 2 %: the two renders
    // differ only by fp16 LUT rounding and the Moon's own sky-view LUT resolution.
    CHECK(Y(n) == Approx(Y(d * ratio)).epsilon(0.02));
    CHECK(Y(n) > 1e-4);   // a moonlit sky: ~1e-3 cd/m^2
    CHECK(Y(n) < 3e-2);
    // Blue (Rayleigh) away from the Moon's aureole, even in the redder moonlight: a pixel ~105 deg
    // from the Moon (azimuth 4.2 rad, altitude 39 deg).
    glm::dvec3 far(night.at(21, 4, 0), night.at(21, 4, 1), night.at(21, 4, 2));
    CHECK(far.b > far.r);
    // Phase: a quarter Moon's sky is 10^(-0.4 * 2.6) as bright.
    rig.vars.set(phase, M_PI / 2);
    Image quarter = rig.render(-30.0);
    glm::dvec3 q(quarter.at(x, y, 0), quarter.at(x, y, 1), quarter.at(x, y, 2));
    CHECK(Y(q) / Y(n) == Approx(moonLux(M_PI / 2, 384400e3) / moonLux(0.0, 384400e3)).epsilon(0.02));
}

TEST_CASE("Sky: from orbit the Earth is lit below and space is black above", "[gl][sky]") {
    SkyRig rig(0, false);
    Image img = rig.render(60.0, 1000e3, 32, 16);
    CHECK(rig.sky.perPixel());
    double up = 0, down = 0;
    for (int x = 0; x < 32; ++x) {
        up += Y(glm::dvec3(img.at(x, 0, 0), img.at(x, 0, 1), img.at(x, 0, 2)));
        down += Y(glm::dvec3(img.at(x, 15, 0), img.at(x, 15, 1), img.at(x, 15, 2)));
    }
    CHECK(up == 0.0);   // rays that never enter the atmosphere
    // Nadir: sunlit ground (albedo 0.1, Sun at 60 deg) seen through the air: a few thousand cd/m^2
    // (albedo/pi x 1.1e5 lx x sin 60 = 3e3, plus haze).
    CHECK(down / 32 > 1000);
    CHECK(down / 32 < 1e4);
}

TEST_CASE("Sky: stats report the sky's physical quantities", "[gl][sky]") {
    SkyRig rig(0, false);
    rig.render(30.0);
    nlohmann::json j;
    rig.sky.stats(j);
    glm::dvec3 e = rig.vars.get(skykeys::horizontalIlluminance);
    CHECK(j["sky"]["horizontal_illuminance_lux"].get<double>() == Approx(e.x));
    CHECK(j["sky"]["sun_illuminance_lux"].get<double>() == Approx(e.y));
    CHECK(j["sky"]["diffuse_illuminance_lux"].get<double>() == Approx(e.z));
    CHECK(j["sky"]["zenith_luminance_cd_m2"].get<double>() > 1000);  // blue zenith, Sun at 30 deg
    // The Sun's disk: E T / (pi alpha^2) ~ 1e9 cd/m^2 at 30 deg.
    glm::dvec3 disk = rig.vars.get(lightkeys::sunDiskRadiance);
    CHECK(Y(disk) > 5e8);
    CHECK(Y(disk) < 2e9);
    glm::dvec3 t = rig.vars.get(lightkeys::sunTransmittance);
    CHECK(t.r > t.b);  // reddened
}

TEST_CASE("Sky: aerial perspective over a host's depth buffer", "[gl][sky]") {
    // A host frame of 1000 cd/m^2 everywhere; its depth buffer empty (far plane) on the left half
    // and at 20 km along each pixel's ray on the right half. After apply(): left unchanged, right
    // = 1000 T + L with T and L from the CPU march of the same 20 km segment.
    {  // Without sky.aerial_volume the volume is not built, and apply() says how to ask for it.
        SkyRig plain(1, false);
        plain.render(20.0, 200.0);
        CHECK_FALSE(plain.vars.has(generators::skykeys::aerialInscatter));
    }
    SkyRig rig(1, false, true);
    rig.render(20.0, 200.0);  // runs the generators (aerial volume)
    Camera cam;
    cam.projection = Projection::Perspective;
    cam.width = 16;
    cam.height = 8;
    cam.azimuthRad = 1.0;
    cam.altitudeRad = 0.02;
    cam.verticalFovRad = 10 * kDeg;
    const double n = 1.0, f = 1e5, dist = 20e3;
    std::vector<float> depth(size_t(cam.width) * cam.height);
    for (int y = 0; y < cam.height; ++y)
        for (int x = 0; x < cam.width; ++x) {
            // GL rows are bottom-up: pixel row (top-down) py = height - 1 - y.
            auto d = cam.directionAt({x + 0.5, cam.height - 1 - y + 0.5});
            double zEye = dist * glm::dot(*d, cam.basis()[2]);
            double zNdc = ((f + n) - 2 * n * f / zEye) / (f - n);
            depth[size_t(y) * cam.width + x] = x < cam.width / 2 ? 1.0f : float(0.5 * zNdc + 0.5);
        }
    gl::Texture2D depthTex(cam.width, cam.height, GL_DEPTH_COMPONENT32F);
    depthTex.upload(GL_DEPTH_COMPONENT, GL_FLOAT, depth.data());
    gl::Texture2D colour(cam.width, cam.height, GL_RGBA32F);
    gl::Framebuffer fbo = gl::Framebuffer::create();
    fbo.attach(GL_COLOR_ATTACHMENT0, colour);
    fbo.checkComplete("AP test");
    const float bg[4] = {1000, 1000, 1000, 1};
    glClearNamedFramebufferfv(fbo.id(), GL_COLOR, 0, bg);
    elements::AerialPerspective ap;
    ap.apply(rig.vars, cam, {.depthTexture = depthTex.id(), .nearM = n, .farM = f}, fbo.id());
    std::vector<float> px = colour.readRgbaFloat();
    SkyModel m = SkyModel::fromVars(rig.vars);
    SkyQuality q = SkyQuality::preset(1);
    Lut2D T = cpu::transmittanceLut(m, q);
    cpu::MsField MS = cpu::msField(m, q, T);
    glm::dvec3 sun = rig.vars.get(keys::sunDirection);
    glm::dvec3 E = rig.vars.get(lightkeys::sunIlluminance);
    for (int x : {2, 12}) {
        int y = 4;
        glm::dvec3 g(px[(size_t(y) * cam.width + x) * 4], px[(size_t(y) * cam.width + x) * 4 + 1], px[(size_t(y) * cam.width + x) * 4 + 2]);
        if (x < cam.width / 2) {
            CHECK(g.g == 1000.0f);  // nothing drawn there: untouched
            continue;
        }
        glm::dvec3 d = *cam.directionAt({x + 0.5, cam.height - 1 - y + 0.5});
        double nu = glm::dot(d, sun);
        cpu::Scattering s = cpu::integrate(m, T, MS, 200.0, d.z, sun.z, nu, dist, 128, true, m.sunAngularRadius);
        glm::dvec3 expect = 1000.0 * s.transmittance + cpu::radiance(m, s, nu) * E;
        INFO("pixel " << x << ": " << g.g << " vs " << expect.g);
        // The volume (32 slices, quadratic in distance, 32x32 directions) against a 128-step
        // march: 3 % (interpolation in direction and distance).
        CHECK(g.g == Approx(expect.g).epsilon(0.03));
        CHECK(g.b == Approx(expect.b).epsilon(0.03));
        CHECK(std::abs(g.g - 1000.0) > 50.0);  // 20 km of air changes the background noticeably
    }
    ap.release();
}

TEST_CASE("Sky: what is behind the sky is attenuated by the ray's transmittance", "[gl][sky]") {
    test::glContext();
    // The same sky alone (first element: the variant without the transmittance output) and over
    // a backdrop (the variant with it): the difference is B T, T the transmittance of the ray to
    // the top of the atmosphere (0 where the ray hits the ground). In RGB mode and in spectral
    // mode (6 wavelengths: T is the solar-weighted combination of the per-wavelength
    // transmittances, SpectralSampling::combine()), at the ground and from 3000 m (where the
    // horizon dips by 1.76 deg), over the whole sphere and in a narrow view across the horizon.
    const auto [wavelengths, h] = GENERATE(std::pair{3, 0.0}, std::pair{6, 0.0}, std::pair{3, 3000.0});
    INFO("wavelengths " << wavelengths << ", observer at " << h << " m");
    Camera sphere;
    sphere.projection = Projection::Equirect;
    sphere.width = 32;
    sphere.height = 16;
    Camera horizon;  // 2.4 x 4.8 deg around the horizon (or the dipped one), rows 0.15 deg apart
    horizon.projection = Projection::Perspective;
    horizon.width = 16;
    horizon.height = 32;
    horizon.verticalFovRad = 4.8 * kDeg;
    const glm::vec3 B(1000.0f, 2000.0f, 3000.0f);
    const auto atm = atmosphere::Atmosphere::earthClear();
    const SkyModel m = SkyModel::fromVars([&] {
        SkyVars v = SkyVars::earth();
        v.set(atmosphere::kAtmosphere, std::make_shared<const atmosphere::Atmosphere>(atm));
        return v;
    }());
    std::optional<SpectralSampling> sp;
    if (wavelengths != 3) sp = SpectralSampling::make(atm, wavelengths);
    auto want = [&](const glm::dvec3& d) {
        if (cpu::rayIntersectsGround(m, h, d.z)) return glm::dvec3(0.0);
        if (!sp) return cpu::transmittanceToTop(m, h, d.z, 512);
        std::vector<glm::dvec3> t;
        for (const SkyModel& mk : sp->models) t.push_back(cpu::transmittanceToTop(mk, h, d.z, 512));
        return glm::max(sp->combine(t), glm::dvec3(0.0));
    };
    const double dip = std::acos(m.bottomRadius / (m.bottomRadius + h));
    horizon.azimuthRad = 0.0;
    horizon.altitudeRad = -dip;
    for (const Camera* cam : {&sphere, &horizon}) {
        auto render = [&](bool backdrop) {
            SkyProcessor p(SkyVars::earth(), Logger(), ProcessorOptions{.astronomy = false});
            p.vars().set(atmosphere::kAtmosphere, std::make_shared<const atmosphere::Atmosphere>(atm));
            p.vars().set(keys::sunDirection, directionFromAzAlt(M_PI, 30 * kDeg));
            p.vars().set(keys::moonDirection, glm::dvec3(0, 0, -1));
            p.setObserver({.latitudeRad = 0.8, .longitudeRad = 0.0, .heightMeters = h});
            p.setCamera(*cam);
            if (backdrop) p.add(std::make_unique<test::UniformField>(B, "backdrop"));
            p.add(std::make_unique<elements::Sky>(elements::SkyOptions{.quality = 1, .wavelengths = wavelengths}));
            p.renderFrame();
            return p.readHdr();
        };
        Image alone = render(false), over = render(true);
        int checked = 0;
        double worstHorizon = 0;
        for (int y = 0; y < cam->height; ++y)
            for (int x = 0; x < cam->width; x += 4) {
                auto d = cam->directionAt({x + 0.5, y + 0.5});
                REQUIRE(d);
                const glm::dvec3 w = want(*d);
                const double altDeg = std::asin(d->z) / kDeg;
                for (int c = 0; c < 3; ++c) {
                    double T = (over.at(x, y, c) - alone.at(x, y, c)) / B[c];
                    INFO("pixel " << x << "," << y << " alt " << altDeg << " deg, channel " << c << ": " << T << " vs " << w[c]);
                    if (cam == &sphere) {
                        // The 1-D view-transmittance row (float) against a 512-step double march:
                        // ~1e-3 away from the horizon (the LUT tests bound the transmittance to
                        // 2e-5 per texel; interpolation adds the rest); the radiance difference
                        // cancels to float precision (~1e-7 relative).
                        CHECK(T == Approx(w[c]).margin(3e-3));
                    } else {
                        // Across the horizon T falls from ~0.1-0.3 to 0 within a degree; the row
                        // has a texel exactly on the horizon and dense ones next to it: measured
                        // <= 1.5e-4 absolute (RGB and spectral, 0 and 3000 m); 2e-3 is the bound
                        // away from it, and 0 exactly on the ground side.
                        worstHorizon = std::max(worstHorizon, std::abs(T - w[c]));
                        CHECK(T == Approx(w[c]).margin(2e-3));
                        if (w[c] == 0.0) CHECK(T == Approx(0.0).margin(1e-6));
                    }
                }
                ++checked;
            }
        INFO("worst absolute error across the horizon " << worstHorizon);
        CHECK(checked == cam->height * cam->width / 4);
    }
}

TEST_CASE("Sky: below -21 deg the Sun's term is skipped; just above it adds < 1e-3 of a night sky", "[gl][sky]") {
    test::glContext();
    // A night-sky backdrop (1e-3 cd/m^2, the natural night sky near the horizon; 2e-4 at the
    // zenith) behind the Sky; no Moon. With the Sun at -20.9 deg the Sun's term is drawn, at
    // -21.1 deg skipped (kSkySunNightAltitudeRad): the two frames differ by the Sun's sky-view
    // term at -20.9 deg, which must be below 1e-3 of the backdrop in every pixel (the claim the
    // threshold rests on), and the transmittance (the backdrop's dimming) must be the same.
    const float B = 1e-3f;
    Camera cam;
    cam.projection = Projection::Fisheye;
    cam.width = cam.height = 48;
    auto render = [&](double sunAltDeg, bool& sunTerm) {
        SkyProcessor p(SkyVars::earth(), Logger(), ProcessorOptions{.astronomy = false});
        p.vars().set(keys::sunDirection, directionFromAzAlt(M_PI, sunAltDeg * kDeg));
        p.vars().set(keys::moonDirection, glm::dvec3(0, 0, -1));
        p.setCamera(cam);
        p.add(std::make_unique<test::UniformField>(glm::vec3(B), "backdrop"));
        p.add(std::make_unique<elements::Sky>(elements::SkyOptions{.quality = 1}));
        p.renderFrame();
        sunTerm = p.stats()["sky"]["sun_term"].get<bool>();
        return p.readHdr();
    };
    bool drawn = false, skipped = true;
    const Image a = render(-20.9, drawn), b = render(-21.1, skipped);
    CHECK(drawn);
    CHECK_FALSE(skipped);
    double maxDiff = 0, maxB = 0;
    for (size_t i = 0; i < a.pixels.size(); ++i) {
        maxDiff = std::max(maxDiff, double(std::abs(a.pixels[i] - b.pixels[i])));
        maxB = std::max(maxB, double(b.pixels[i]));
    }
    INFO("max |drawn - skipped| " << maxDiff << " cd/m^2, brightest pixel " << maxB);
    CHECK(maxB > 0.5 * B);  // the backdrop shows through (the zenith transmits ~0.8)
    CHECK(maxDiff < 1e-3 * B);
}

TEST_CASE("Sky: no program is built after the first frame from day through a Moon-lit jump to night", "[gl][sky]") {
    // The element counts the programs it builds (programBuilds(), stats sky.program_builds). A run
    // of the LUT path over a backdrop (the transmittance output and the night multiply in play):
    // day with the Moon down, then jumps: twilight with a full Moon up (the Moon's term switches
    // on), night with the Moon up (the Sun's term off), a moonless night (the multiply pass), and
    // day again. With sky.prebuild_programs (the default) every variant these switch to is built
    // and drawn in the first frame: the count must not move after it. The same run with it off
    // must build more after the first frame (else this run would not exercise the switches and
    // the first check could not fail).
    test::glContext();
    Camera cam;
    cam.projection = Projection::Fisheye;
    cam.width = cam.height = 32;
    struct Step {
        double sunAlt, moonAlt;  // deg
    };
    const Step steps[] = {{30, -40}, {30, -40}, {-10, 40}, {-10, 40}, {-30, 40}, {-30, -40}, {30, -40}};
    auto run = [&](bool prebuild, std::vector<int>& builds) {
        SkyProcessor p(SkyVars::earth(), Logger(), ProcessorOptions{.astronomy = false});
        p.vars().set(elements::skyPrebuildPrograms, prebuild);
        p.vars().set(astro::keys::moonPhaseAngle, 0.0);  // full Moon: 0.32 lx
        p.setCamera(cam);
        p.add(std::make_unique<test::UniformField>(glm::vec3(1e-3f), "backdrop"));
        auto& sky = p.emplace<elements::Sky>(elements::SkyOptions{.quality = 1});
        bool sawMoon = false, sawNight = false, sawMultiply = false;
        for (const Step& s : steps) {
            p.vars().set(keys::sunDirection, directionFromAzAlt(M_PI, s.sunAlt * kDeg));
            p.vars().set(keys::moonDirection, directionFromAzAlt(0.0, s.moonAlt * kDeg));
            p.renderFrame();
            const nlohmann::json st = p.stats();
            builds.push_back(st["sky"]["program_builds"].get<int>());
            CHECK(builds.back() == sky.programBuilds());
            sawMoon = sawMoon || (s.moonAlt > 0 && s.sunAlt > -21 && st["sky"]["sun_term"].get<bool>());
            sawNight = sawNight || !st["sky"]["sun_term"].get<bool>();
            sawMultiply = sawMultiply || st["sky"]["night_multiply"].get<bool>();
        }
        CHECK(sawMoon);
        CHECK(sawNight);
        CHECK(sawMultiply);
    };
    std::vector<int> pre, lazy;
    run(true, pre);
    run(false, lazy);
    INFO("builds per frame, prebuilt: " << pre.front() << " .. " << pre.back() << "; at first use: " << lazy.front() << " .. " << lazy.back());
    REQUIRE(pre.size() == std::size(steps));
    for (size_t i = 1; i < pre.size(); ++i) CHECK(pre[i] == pre[0]);
    CHECK(lazy.back() > lazy.front());  // the switches happen: at first use they build later
    CHECK(pre[0] >= lazy.back());       // the first frame built at least every variant the run used
}

TEST_CASE("Sky: by day the Moon's term is skipped; it is below 1e-4 of the Sun's sky", "[gl][sky]") {
    // The claim the skip rests on, in its worst cases: the Sun just above the threshold
    // (kMoonSkySunAltitudeRad, 2 deg: +0.05 deg above it), the Moon at several places over the
    // sky away from the Sun (where the Sun's sky is darkest), each with the phase its place
    // gives (phase angle = pi - elongation, the parallax neglected: the full Moon only opposite
    // the Sun; the lights generator's lunar law then sets its illuminance). The frame with the
    // Moon's term (sky.moon_by_day = true) and the default (skipped) must differ by < 1e-4 of the
    // image in every pixel and channel (the brief's bound), and by something (the term is there:
    // else the check could not fail); just below the threshold the default draws it.
    test::glContext();
    Camera cam;
    cam.projection = Projection::Equirect;  // every direction, the ground's too
    cam.width = 64;
    cam.height = 32;
    constexpr double kThresholdDeg = 6.0;  // kMoonSkySunAltitudeRad in sky.cpp
    auto render = [&](double sunAltDeg, double moonAz, double moonAltDeg, bool moonByDay, bool& skipped) {
        SkyProcessor p(SkyVars::earth(), Logger(), ProcessorOptions{.astronomy = false});
        const glm::dvec3 sun = directionFromAzAlt(M_PI, sunAltDeg * kDeg), moon = directionFromAzAlt(moonAz, moonAltDeg * kDeg);
        p.vars().set(astro::keys::moonPhaseAngle, M_PI - std::acos(std::clamp(glm::dot(sun, moon), -1.0, 1.0)));
        p.vars().set(elements::skyMoonByDay, moonByDay);
        p.vars().set(keys::sunDirection, sun);
        p.vars().set(keys::moonDirection, moon);
        p.setCamera(cam);
        p.add(std::make_unique<elements::Sky>(elements::SkyOptions{.quality = 1}));
        p.renderFrame();
        skipped = p.stats()["sky"]["moon_term_skipped_by_day"].get<bool>();
        return p.readHdr();
    };
    auto maxRel = [](const Image& with, const Image& without) {
        double worst = 0;
        for (size_t i = 0; i < with.pixels.size(); ++i)
            worst = std::max(worst, double(std::abs(with.pixels[i] - without.pixels[i])) / std::max(double(without.pixels[i]), 1e-30));
        return worst;
    };
    struct Moon {
        double az, altDeg;
    };
    double worstDay = 0;
    for (const Moon mo : {Moon{0.0, 1.0}, Moon{0.0, 15.0}, Moon{0.0, 30.0}, Moon{0.0, 45.0}, Moon{0.0, 60.0}, Moon{0.0, 85.0},
                          Moon{M_PI / 2, 10.0}, Moon{M_PI / 2, 30.0}}) {
        bool s1 = false, s2 = true, s3 = true, s4 = true;
        const double up = kThresholdDeg + 0.05, down = kThresholdDeg - 0.05;
        const Image dayWith = render(up, mo.az, mo.altDeg, true, s1), daySkipped = render(up, mo.az, mo.altDeg, false, s2);
        const Image duskWith = render(down, mo.az, mo.altDeg, true, s3), duskDefault = render(down, mo.az, mo.altDeg, false, s4);
        CHECK_FALSE(s1);
        CHECK(s2);
        CHECK_FALSE(s3);
        CHECK_FALSE(s4);
        const double day = maxRel(dayWith, daySkipped);
        worstDay = std::max(worstDay, day);
        INFO("Moon at az " << mo.az << " rad, alt " << mo.altDeg << " deg: the Moon's term by day, max relative " << day);
        CHECK(day < 1e-4);   // the brief's bound: skipping changes no pixel beyond 1e-4 relative
        CHECK(day > 1e-6);   // the term is there to skip (a full Moon's is ~1e-4 of the Sun's sky)
        CHECK(maxRel(duskWith, duskDefault) == 0.0);  // below the threshold the default draws it: the same frame
    }
}
