// Star labels (stars.labels): the proper names of the bright stars, each beside its star where the
// astronomy places it.
#include <catch2/catch.hpp>

#include "gl_test_context.hpp"
#include "label_boxes.hpp"

#include <welkin/astro/bodies.hpp>
#include <welkin/astro/frames.hpp>
#include <welkin/astro/stars.hpp>
#include <welkin/astro/timescales.hpp>
#include <welkin/elements/registry.hpp>
#include <welkin/elements/star_labels.hpp>
#include <welkin/elements/stars.hpp>
#include <welkin/processor.hpp>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <filesystem>
#include <numbers>

using namespace welkin;
namespace starkeys = welkin::elements::starkeys;

namespace {
constexpr double kDeg = std::numbers::pi / 180.0;
}

TEST_CASE("Star labels: proper names only, from the kstars catalogue", "[cpu][stars]") {
    CHECK(elements::isProperStarName("Vega"));
    CHECK(elements::isProperStarName("Al Na'ir"));
    CHECK_FALSE(elements::isProperStarName("alp Lyr"));
    CHECK_FALSE(elements::isProperStarName("61 Cyg"));
    CHECK_FALSE(elements::isProperStarName(""));
    CHECK_FALSE(elements::isProperStarName("Alp Lyr"));   // BSC5 / HYG designations
    CHECK_FALSE(elements::isProperStarName("Bet1Sco"));
    CHECK(elements::isProperStarName("Kaus Australis"));
    CHECK(elements::isProperStarName("Zubenelgenubi"));
    if (!std::filesystem::exists(astro::kKStarsCatalogue)) FAIL("no star catalogue at " << astro::kKStarsCatalogue << " (apt install kstars-data)");
    const auto named = elements::namedStars(astro::loadKStarsCatalogue(astro::kKStarsCatalogue, 3.0));
    // The bright named stars (V < 1.5): about 20 of the 21 first-magnitude stars (alp Cen and
    // alp TrA carry only their designations in stars.dat).
    int bright = 0;
    bool vega = false, antares = false;
    for (const auto& s : named) {
        bright += s.magnitudeV < 1.5 ? 1 : 0;
        vega = vega || s.name == "Vega";
        antares = antares || s.name == "Antares";
    }
    CHECK(vega);
    CHECK(antares);
    CHECK(bright >= 15);
    CHECK(bright <= 25);
    for (size_t i = 1; i < named.size(); ++i) CHECK(named[i - 1].magnitudeV <= named[i].magnitudeV);
}

TEST_CASE("Star labels sit beside their stars as the astronomy places them", "[gl][stars]") {
    if (!std::filesystem::exists(gl::kDefaultFontPath)) FAIL("no font at " << gl::kDefaultFontPath << " (apt install fonts-dejavu-core)");
    if (!std::filesystem::exists(astro::kKStarsCatalogue)) FAIL("no star catalogue at " << astro::kKStarsCatalogue << " (apt install kstars-data)");
    // Malta, 1 July 2018 23:00 CEST, looking south (Antares, Saturn's neighbour, in view).
    const UtcInstant t = UtcInstant::parse("2018-07-01T23:00:00+02:00");
    const double latRad = 35.90 * kDeg, lonRad = 14.51 * kDeg;
    test::glContext();
    Camera cam;
    cam.azimuthRad = 170 * kDeg;
    cam.altitudeRad = 30 * kDeg;
    cam.verticalFovRad = 60 * kDeg;
    cam.width = 256;
    cam.height = 144;
    const double emPx = 11.0;
    auto render = [&](bool labels) {
        SkyProcessor p(SkyVars::earth(), test::testLogger());
        p.setAnimationTime(0.0);
        p.setTime(t);
        p.setObserver({latRad, lonRad, 0.0});
        p.setCamera(cam);
        p.setExposure({.automatic = false, .ev100 = -8.0});
        p.add(elements::makeElement("stars"));
        p.vars().set(starkeys::labels, labels);
        p.vars().set(starkeys::labelMagnitude, 1.5);
        p.vars().set(starkeys::labelSize, emPx);
        p.vars().set(starkeys::labelLuminance, 1.0);  // cd/m^2, far above a star's PSF a few px away
        p.renderFrame();
        return std::pair{p.readHdr(), p.stats()};
    };
    const auto [off, statsOff] = render(false);
    const auto [on, statsOn] = render(true);
    CHECK(statsOff["stars"]["labels"] == 0);

    // Independently: the catalogue's named stars placed by the astronomy API (star frame of the
    // fast path, the processor's default; refraction at 1013.25 hPa, 10 C, the defaults).
    const astro::Site site{latRad, lonRad, 0.0};
    const astro::StarFrame sf = astro::starFrame(astro::observerFrame(site, astro::timeScales(t), astro::Path::Fast));
    const gl::Font font = gl::Font::load();
    std::vector<test::Box> wanted;
    std::vector<std::string> names;
    for (const astro::Star& s : astro::loadKStarsCatalogue(astro::kKStarsCatalogue, 1.5)) {
        if (!elements::isProperStarName(s.name)) continue;
        const glm::dvec3 g = astro::starEnu(sf, astro::starDirectionJ2000(s), astro::starProperMotion(s));
        const astro::Horizontal h = astro::horizontalFromEnu(g);
        if (h.altitudeRad < 0) continue;
        const glm::dvec3 d = astro::enuFromHorizontal(h.azimuthRad, astro::apparentFromGeometricAltitude(h.altitudeRad, 1013.25, 10.0));
        const auto px = cam.pixelOf(d);
        if (!px) continue;
        const test::Box want = test::expectedInk(font, s.name, float(emPx), *px, elements::starLabelGapPx(emPx));
        wanted.push_back(want);  // a star just outside the image may write its label into it
        if (px->x < 0 || px->y < 0 || px->x >= cam.width || px->y >= cam.height) continue;
        const test::Box got = test::inkIn(on, off, want.grown(6), 0.1);
        INFO(s.name << " at pixel (" << px->x << ", " << px->y << "): expected ink " << want.str() << ", found " << got.str());
        // 2 px: anchor and pen snap to whole pixels; antialiased glyph rims (<= 1 px) fall either
        // side of the 0.1 cd/m^2 threshold.
        CHECK(got.within(want, 2));
        names.push_back(s.name);
    }
    INFO("named in view: " << names.size());
    CHECK(std::find(names.begin(), names.end(), "Antares") != names.end());
    CHECK(statsOn["stars"]["labels"] == int(names.size()));
    // No other label: every label pixel lies in one of the boxes.
    int stray = 0;
    test::Box strayBox;
    for (int y = 0; y < cam.height; ++y)
        for (int x = 0; x < cam.width; ++x) {
            if (test::luminanceAt(on, x, y) - test::luminanceAt(off, x, y) <= 0.1) continue;
            bool inside = false;
            for (const test::Box& w : wanted) inside = inside || w.grown(2).contains(x, y);
            if (!inside) ++stray, strayBox.add(x, y);
        }
    INFO("label pixels outside the expected boxes: " << strayBox.str());
    CHECK(stray == 0);
}
