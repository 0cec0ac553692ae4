// Stars: apparent places against the astronomy code, colour order, flux from magnitude, the
// limiting magnitude, determinism of the twinkling, finite output at extreme cameras.
#include <catch2/catch.hpp>

#include "gl_test_context.hpp"
#include "star_test_util.hpp"

#include <welkin/astro/astro_keys.hpp>
#include <welkin/astro/bodies.hpp>
#include <welkin/astro/frames.hpp>
#include <welkin/astro/stars.hpp>
#include <welkin/astro/timescales.hpp>
#include <welkin/color.hpp>
#include <welkin/elements/registry.hpp>
#include <welkin/elements/stars.hpp>
#include <welkin/generators/sky_luts.hpp>
#include <welkin/generators/sky_model.hpp>
#include <welkin/keys.hpp>
#include <welkin/processor.hpp>
#include <welkin/time.hpp>

#include <nlohmann/json.hpp>

#include <cmath>
#include <numbers>

using namespace welkin;
using namespace welkin::elements;

namespace {
constexpr double kDeg = std::numbers::pi / 180.0;

// A catalogue star at an ICRS direction given as (ra, dec), no proper motion (star_test_util.hpp).
astro::Star star(double raDeg, double decDeg, double mag, double bv) { return test::catalogueStar(raDeg, decDeg, mag, bv); }

// Sum of linear sRGB x pixel solid angle (lux per channel) in a window around a pixel (the
// solid angle from the camera's own inverse pixel scale, CPU twin of the shader's).
glm::dvec3 integrate(const Image& img, const Camera& cam, glm::dvec2 centre, int half) {
    glm::dvec3 sum(0.0);
    for (int y = int(centre.y) - half; y <= int(centre.y) + half; ++y)
        for (int x = int(centre.x) - half; x <= int(centre.x) + half; ++x) {
            if (x < 0 || y < 0 || x >= img.width || y >= img.height) continue;
            auto d = cam.directionAt({x + 0.5, y + 0.5});
            if (!d) continue;
            glm::dvec2 s = *cam.pixelScale(*d);
            const double omega = 1.0 / (s.x * s.y);
            for (int c = 0; c < 3; ++c) sum[c] += img.at(x, y, c) * omega;
        }
    return sum;
}

ProcessorOptions noAstronomy() { return ProcessorOptions{.astronomy = false}; }

void quiet(SkyVars& v) {  // a steady, halo-free PSF for measurements
    v.set(starkeys::scintillation, 0.0);
    v.set(starkeys::glare, 0.0);
}
}  // namespace

TEST_CASE("Stars: B-V to temperature and colour", "[cpu][stars]") {
    // Ballesteros 2012: the Sun (B-V 0.65) comes out near its 5772 K (the formula's stated
    // accuracy is a few percent over main-sequence stars).
    CHECK(starTemperatureFromBV(0.65) == Approx(5772).epsilon(0.04));
    CHECK(starTemperatureFromBV(-0.3) > starTemperatureFromBV(0.0));
    CHECK(starTemperatureFromBV(0.0) > starTemperatureFromBV(1.5));
    // Luminance 1 by construction; a 6500 K black body is close to D65's white (within the
    // black-body locus' distance from D65, 0.003 in xy).
    glm::dvec3 w = blackBodyLinearSrgb(6504);
    CHECK(color::luminance(w) == Approx(1.0).epsilon(1e-9));
    glm::dvec2 xy = color::chromaticity(color::linearSrgbToXyz(w));
    CHECK(std::abs(xy.x - 0.3127) < 0.005);
    CHECK(std::abs(xy.y - 0.3290) < 0.01);
    CHECK_THROWS_WITH(blackBodyLinearSrgb(100), Catch::Contains("not in [500, 1e6] K"));
}

TEST_CASE("Stars: the limiting magnitude follows the background (Schaefer 1990)", "[cpu][stars]") {
    // Dark site, 22 mag/arcsec^2 = 1.7e-4 cd/m^2: Schaefer's model gives ~6.5-6.7 (his paper: 6.5
    // for a typical dark-adapted observer).
    CHECK(limitingMagnitude(1.7e-4) == Approx(6.6).margin(0.15));
    // Daylight zenith (~5e3 cd/m^2): only Venus (-4.5) can be seen; Sirius (-1.46) cannot.
    CHECK(limitingMagnitude(5e3) < -3.0);
    CHECK(limitingMagnitude(5e3) > -5.0);
    // Monotonic through the twilight range (the stars appear one by one as the sky darkens).
    double prev = 100;
    for (double L = 1e-5; L < 1e5; L *= 3) {
        CHECK(limitingMagnitude(L) < prev);
        prev = limitingMagnitude(L);
    }
    CHECK_THROWS(limitingMagnitude(-1));
    // Scintillation grows towards the horizon and is capped.
    CHECK(scintillationAmplitude(90 * kDeg, 1) == Approx(0.02).epsilon(0.01));
    CHECK(scintillationAmplitude(10 * kDeg, 1) > 5 * scintillationAmplitude(60 * kDeg, 1));
    CHECK(scintillationAmplitude(0, 100) == 0.8);
}

TEST_CASE("Stars: integrated flux follows the magnitude and equals E x transmittance", "[gl][stars]") {
    test::glContext();
    SkyProcessor p(SkyVars::earth(), Logger(), noAstronomy());
    Camera cam;  // looking at azimuth 0 (north; ENU y), altitude 60 deg, 2 deg wide: 0.94 arcmin/px
    cam.projection = Projection::Perspective;
    cam.azimuthRad = 0;
    cam.altitudeRad = 60 * kDeg;
    cam.verticalFovRad = 2 * kDeg;
    cam.width = cam.height = 128;
    p.setCamera(cam);
    // Identity star frame (no astronomy): ICRS axes = ENU, so (ra 90, dec 60) is north at 60 deg
    // (geometric; refraction lifts it by ~0.6'). The two stars 0.5 deg apart in azimuth.
    std::vector<astro::Star> cat = {star(90, 60, 3.0, 0.65), star(90 + 0.5 / std::cos(60 * kDeg), 60, 8.0, 0.65),
                                    star(90 - 0.5 / std::cos(60 * kDeg), 60, 0.0, 1.2)};
    p.add(std::make_unique<Stars>(cat));
    quiet(p.vars());
    p.vars().set(starkeys::glare, 0.1);  // on for the 0-mag star: its halo must keep the integral
    p.vars().set(starkeys::adaptiveLimit, false);
    p.renderFrame();
    Image img = p.readHdr();
    auto place = [&](const astro::Star& s) {
        glm::dvec3 d = astro::starDirectionJ2000(s);
        double h = std::asin(d.z), hApp = astro::apparentFromGeometricAltitude(h, 1013.25, 10.0);
        glm::dvec2 sc = glm::dvec2(d) / glm::length(glm::dvec2(d));
        return *cam.pixelOf(glm::dvec3(sc * std::cos(hApp), std::sin(hApp)));
    };
    const glm::dvec3 a = integrate(img, cam, place(cat[0]), 6), b = integrate(img, cam, place(cat[1]), 6);
    // 5 magnitudes = 100x (the 5 %; both have the same colour and extinction).
    CHECK(color::luminance(a) / color::luminance(b) == Approx(100.0).epsilon(0.05));
    // Absolute: E(m) x the atmosphere's transmittance towards 60 deg (CPU, per channel), within
    // 2 % (float PSF sums, the extinction table's interpolation, the pixel solid angle's variation).
    const auto m = generators::SkyModel::fromVars(p.vars());
    const glm::dvec3 T = generators::cpu::transmittanceToTop(m, 0.0, std::sin(60 * kDeg), 512);
    const glm::dvec3 expectA = astro::magnitude::illuminanceLux(3.0) * starColourFromBV(0.65) * T;
    CHECK(color::luminance(a) == Approx(color::luminance(expectA)).epsilon(0.02));
    // The glare star (halo radius 8 x 2 x FWHM = 32 px at the 2 px minimum): the integral holds.
    // Its window also holds star 0 (32 px away, whole), subtracted.
    const glm::dvec3 c = integrate(img, cam, place(cat[2]), 34) - a;
    const glm::dvec3 expectC = astro::magnitude::illuminanceLux(0.0) * starColourFromBV(1.2) * T;
    CHECK(color::luminance(c) == Approx(color::luminance(expectC)).epsilon(0.03));
    nlohmann::json j = p.stats();
    CHECK(j["stars"]["drawn"].get<int>() == 3);
}

TEST_CASE("Stars: Rigel, Sirius, Arcturus, Betelgeuse go blue, white, orange, red", "[gl][stars]") {
    test::glContext();
    std::vector<astro::Star> all = astro::loadKStarsCatalogue();
    const char* names[4] = {"Rigel", "Sirius", "Arcturus", "Betelgeuse"};
    std::vector<astro::Star> cat;
    for (int i = 0; i < 4; ++i) {
        auto it = std::find_if(all.begin(), all.end(), [&](const astro::Star& s) { return s.name == names[i]; });
        REQUIRE(it != all.end());
        // Their catalogue colours, each put at altitude 45 deg, azimuths 0, 90, 180, 270 deg.
        cat.push_back(star(90 - 90 * i, 45, 1.0, it->colorBV));
    }
    SkyProcessor p(SkyVars::earth(), Logger(), noAstronomy());
    Camera cam;
    cam.projection = Projection::Fisheye;
    cam.width = cam.height = 128;
    p.setCamera(cam);
    p.add(std::make_unique<Stars>(cat));
    quiet(p.vars());
    p.renderFrame();
    Image img = p.readHdr();
    double blueOverRed[4];
    for (int i = 0; i < 4; ++i) {
        glm::dvec3 c = integrate(img, cam, *cam.pixelOf(astro::starDirectionJ2000(cat[i])), 5);
        REQUIRE(color::luminance(c) > 0);
        blueOverRed[i] = c.b / c.r;
    }
    CHECK(blueOverRed[0] > 1.0);                        // Rigel: blue
    CHECK(blueOverRed[0] > blueOverRed[1]);
    CHECK(blueOverRed[1] > blueOverRed[2]);
    CHECK(blueOverRed[2] > blueOverRed[3]);
    CHECK(blueOverRed[2] < 0.7);                        // Arcturus: orange
    CHECK(blueOverRed[3] < 0.4);                        // Betelgeuse: red
}

TEST_CASE("Stars: pixels land within 1 px of the astronomy's apparent places (1024 fisheye)", "[gl][stars]") {
    test::glContext();
    const UtcInstant t = UtcInstant::parse("2026-08-12T22:00:00Z");
    const astro::Site site{35.9 * kDeg, 14.5 * kDeg, 0.0};
    SkyProcessor p;
    p.setObserver({.latitudeRad = site.latitudeRad, .longitudeRad = site.longitudeRad, .heightMeters = 0});
    p.setTime(t);
    Camera cam;
    cam.projection = Projection::Fisheye;
    cam.width = cam.height = 1024;
    p.setCamera(cam);
    auto stars = std::make_unique<Stars>();
    p.add(std::move(stars));
    quiet(p.vars());
    p.vars().set(starkeys::magnitudeLimit, 2.5);
    p.renderFrame();
    Image img = p.readHdr();
    const astro::ObserverFrame f = astro::observerFrame(site, astro::timeScales(t), astro::Path::Fast);
    const astro::StarFrame sf = astro::starFrame(f);
    std::vector<astro::Star> cat = astro::loadKStarsCatalogue(astro::kKStarsCatalogue, 2.5);
    int checked = 0;
    for (const astro::Star& s : cat) {
        glm::dvec3 p0 = astro::starDirectionJ2000(s), pm = astro::starProperMotion(s);
        astro::Topocentric tp = astro::topocentricFromIcrs(f, glm::normalize(p0 + sf.yearsSinceJ2000 * pm));
        if (tp.altitudeRad < 5 * kDeg) continue;
        const glm::dvec2 px = *cam.pixelOf(directionFromAzAlt(tp.azimuthRad, tp.altitudeRad));
        // Luminance-weighted centroid in a 7 x 7 window (the 2 px FWHM PSF is within 3 px).
        double w = 0;
        glm::dvec2 c(0.0);
        for (int y = int(px.y) - 3; y <= int(px.y) + 3; ++y)
            for (int x = int(px.x) - 3; x <= int(px.x) + 3; ++x) {
                double Y = 0.2126 * img.at(x, y, 0) + 0.7152 * img.at(x, y, 1) + 0.0722 * img.at(x, y, 2);
                w += Y;
                c += Y * glm::dvec2(x + 0.5, y + 0.5);
            }
        REQUIRE(w > 0);
        INFO(s.name << " predicted " << px.x << ", " << px.y << " drawn " << c.x / w << ", " << c.y / w);
        CHECK(glm::length(c / w - px) < 1.0);
        ++checked;
    }
    CHECK(checked >= 20);  // about a third of the ~90 stars brighter than 2.5 are 5 deg up or more
    nlohmann::json j = p.stats();
    CHECK(j["stars"]["drawn"].get<int>() == int(cat.size()));
    CHECK(j["stars"]["limiting_magnitude"].get<double>() == 2.5);
}

TEST_CASE("Stars: scintillation is deterministic for a seed and a time", "[gl][stars]") {
    test::glContext();
    auto render = [](int seed, const char* when) {
        SkyProcessor p;
        p.setObserver({.latitudeRad = 0.6, .longitudeRad = 0.25, .heightMeters = 0});
        p.setTime(UtcInstant::parse(when));
        Camera cam;
        cam.projection = Projection::Fisheye;
        cam.width = cam.height = 64;
        p.setCamera(cam);
        p.add(std::make_unique<Stars>(std::vector<astro::Star>{star(10, 20, 1, 0.5), star(100, 50, 1, 0.5), star(200, -10, 1, 0.5),
                                                               star(300, 70, 1, 0.5), star(250, 30, 1, 0.5)}));
        p.vars().set(starkeys::scintillation, 5.0);
        p.vars().set(starkeys::seed, seed);
        p.renderFrame();
        return p.readHdr().pixels;
    };
    auto a = render(3, "2026-08-12T22:00:00Z");
    double total = 0;
    for (float v : a) total += v;
    REQUIRE(total > 0);
    CHECK(render(3, "2026-08-12T22:00:00Z") == a);
    CHECK(render(4, "2026-08-12T22:00:00Z") != a);
    CHECK(render(3, "2026-08-12T22:00:01Z") != a);
}

TEST_CASE("Stars: every pixel finite at FOV 0.5 and 180 deg, 1x1 to 2048x2048", "[gl][stars]") {
    test::glContext();
    // 2048 rather than the 4096: a 4096^2 float read-back is 256 MB on llvmpipe; the
    // shader has no size-dependent branch between the two.
    struct Case { Projection proj; double fov; int size; };
    for (Case k : {Case{Projection::Perspective, 0.5 * kDeg, 1}, Case{Projection::Perspective, 0.5 * kDeg, 2048},
                   Case{Projection::Fisheye, 0, 1}, Case{Projection::Fisheye, 0, 2048}, Case{Projection::Equirect, 0, 1}}) {
        SkyProcessor p;
        p.setObserver({.latitudeRad = 0.6, .longitudeRad = 0.25, .heightMeters = 0});
        p.setTime(UtcInstant::parse("2026-08-12T22:00:00Z"));
        Camera cam;
        cam.projection = k.proj;
        cam.altitudeRad = 1.2;  // Polaris region
        if (k.fov > 0) cam.verticalFovRad = k.fov;
        cam.width = cam.height = k.size;
        p.setCamera(cam);
        p.add(makeElement("stars"));
        p.renderFrame();
        Image img = p.readHdr();
        size_t bad = 0;
        for (float v : img.pixels) bad += !std::isfinite(v) || v < 0;
        INFO(toString(k.proj) << " " << k.size);
        CHECK(bad == 0);
    }
}

TEST_CASE("Stars: daylight hides them, in twilight they appear one by one", "[gl][stars]") {
    test::glContext();
    SkyProcessor p(SkyVars::earth(), Logger(), noAstronomy());
    Camera cam;
    cam.projection = Projection::Fisheye;
    cam.width = cam.height = 32;
    p.setCamera(cam);
    p.add(makeElement("stars"));
    p.add(makeElement("sky"));
    int prev = -1;
    for (double sunAlt : {30.0, -4.0, -8.0, -12.0, -18.0}) {
        p.vars().set(keys::sunDirection, directionFromAzAlt(M_PI, sunAlt * kDeg));
        p.renderFrame();
        nlohmann::json j = p.stats();
        const int drawn = j["stars"]["drawn"].get<int>();
        INFO("Sun at " << sunAlt << " deg: " << drawn << " stars, limit " << j["stars"]["limiting_magnitude"].get<double>());
        if (sunAlt > 0) CHECK(drawn == 0);  // no catalogue star is brighter than ~-4 (Venus is a planet)
        CHECK(drawn > prev);
        prev = drawn;
    }
    CHECK(prev > 2000);  // a dark sky: to magnitude ~6.5, a few thousand stars
}
