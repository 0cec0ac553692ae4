// Point sources as people see them (render.point_sources, welkin/point_source.hpp): Venus in
// civil twilight over Malta stands out on screen in the perceptual mode and not in the physical
// one; the stars drawn are those the eye's threshold admits; a star the eye cannot see is not
// drawn; the physical mode is the library's default and unchanged.
#include <catch2/catch.hpp>

#include "cli_runner.hpp"
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
#include <welkin/error.hpp>
#include <welkin/generators/sky_model.hpp>
#include <welkin/image.hpp>
#include <welkin/keys.hpp>
#include <welkin/point_source.hpp>
#include <welkin/processor.hpp>
#include <welkin/time.hpp>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <cmath>
#include <numbers>
#include <vector>

using namespace welkin;
using namespace welkin::elements;

namespace {
constexpr double kDeg = std::numbers::pi / 180.0;

// A catalogue star at an ICRS direction given as (ra, dec), no proper motion (star_test_util.hpp).
astro::Star star(double raDeg, double decDeg, double mag, double bv) { return test::catalogueStar(raDeg, decDeg, mag, bv); }

double lumaAt(const Image& img, int x, int y) {
    return 0.2126 * img.at(x, y, 0) + 0.7152 * img.at(x, y, 1) + 0.0722 * img.at(x, y, 2);
}

// Displayed (sRGB-encoded) contrast of a point at `px`: the brightest pixel within 1 px of it
// over the median of the ring 5..9 px around it (the sky beside it), minus 1.
double displayedContrast(const Image& img, glm::dvec2 px) {
    const int cx = int(px.x), cy = int(px.y);
    double peak = 0;
    for (int y = cy - 1; y <= cy + 1; ++y)
        for (int x = cx - 1; x <= cx + 1; ++x) peak = std::max(peak, lumaAt(img, x, y));
    std::vector<double> ring;
    for (int y = cy - 9; y <= cy + 9; ++y)
        for (int x = cx - 9; x <= cx + 9; ++x) {
            const double r = std::hypot(x - cx, y - cy);
            if (r >= 5 && r <= 9) ring.push_back(lumaAt(img, x, y));
        }
    std::nth_element(ring.begin(), ring.begin() + long(ring.size() / 2), ring.end());
    const double bg = ring[ring.size() / 2];
    INFO("peak " << peak << " sky " << bg);
    REQUIRE(bg > 0.0);
    return peak / bg - 1.0;
}
}  // namespace

TEST_CASE("Point sources: Venus in civil twilight over Malta is seen in the perceptual mode", "[gl][points]") {
    // The case: 2026-08-12 18:10 UTC, Malta (35.9 N, 14.5 E), a 512 x 512 fisheye of the
    // default elements, automatic (eye) exposure, medium quality: what `welkin render --out x.png`
    // renders. Venus (mag -4.4) is 19 deg up at azimuth 251, the Sun 3.4 deg below the horizon.
    test::glContext();
    SkyProcessor p(SkyVars::earth(), Logger());
    p.setAnimationTime(0.0);
    p.vars().set(keys::quality, 1);
    p.setObserver({.latitudeRad = 35.9 * kDeg, .longitudeRad = 14.5 * kDeg, .heightMeters = 0});
    p.setTime(UtcInstant::parse("2026-08-12T18:10:00Z"));
    Camera cam;
    cam.projection = Projection::Fisheye;
    cam.width = cam.height = 512;
    p.setCamera(cam);
    p.setExposure({.automatic = true});
    for (auto& n : defaultElements()) p.add(makeElement(n));

    REQUIRE(pointSourceMode(p.vars()) == PointSourceMode::Physical);  // the library's default
    p.renderFrame();
    const Image physical = p.readToneMapped();
    // Venus' pixel from the astronomy (its apparent direction) through the camera's projection.
    const glm::dvec3 venus = glm::normalize(p.vars().get(astro::keys::planetDirection(astro::Body::Venus)));
    REQUIRE(std::asin(venus.z) / kDeg == Approx(19.3).margin(0.2));  // `welkin astro`: 19.28 deg
    const glm::dvec2 px = *cam.pixelOf(venus);
    // The eye's verdict, independently of the drawing: Venus' illuminance at the eye (its
    // magnitude through the atmosphere's transmittance towards it) against the sky beside it in
    // the HDR image (the ring's median luminance), through Schaefer's threshold.
    const Image hdr = p.readHdr();
    std::vector<double> ring;
    for (int y = int(px.y) - 9; y <= int(px.y) + 9; ++y)
        for (int x = int(px.x) - 9; x <= int(px.x) + 9; ++x)
            if (std::hypot(x - int(px.x), y - int(px.y)) >= 5 && std::hypot(x - int(px.x), y - int(px.y)) <= 9) ring.push_back(lumaAt(hdr, x, y));
    std::nth_element(ring.begin(), ring.begin() + long(ring.size() / 2), ring.end());
    const double skyCdM2 = ring[ring.size() / 2];
    const generators::SkyModel model = generators::SkyModel::fromVars(p.vars());
    const double T = color::luminance(generators::cpu::transmittanceToTop(model, 0.0, venus.z, 256));
    const double eyeLux = astro::magnitude::illuminanceLux(p.vars().get(astro::keys::planetMagnitude(astro::Body::Venus))) * T;
    const PerceptualPoint eye = perceptualPoint(eyeLux, skyCdM2);
    INFO("sky beside Venus " << skyCdM2 << " cd/m^2, Venus at the eye " << eyeLux << " lx, threshold " << pointThresholdLux(skyCdM2)
                             << " lx: " << eye.ratio << " x");
    REQUIRE(eye.visible);  // every observer sees it (the issue): the model agrees

    p.vars().set(keys::pointSources, std::string("perceptual"));
    p.renderFrame();
    const Image perceptual = p.readToneMapped();

    // The physical mode set explicitly draws the default's HDR image bit for bit.
    p.vars().set(keys::pointSources, std::string("physical"));
    p.renderFrame();
    const bool identical = p.readHdr().pixels == hdr.pixels;  // (not the vectors in CHECK: -s prints them)
    CHECK(identical);

    const double cPhys = displayedContrast(physical, px), cPerc = displayedContrast(perceptual, px);
    INFO("Venus at pixel " << px.x << ", " << px.y << ": displayed contrast physical " << cPhys << ", perceptual " << cPerc);
    // Physical: ~1 % (the "+3 % bump", in the sRGB-encoded value), under the ~2 % Weber
    // fraction of photopic vision: lost. Perceptual: over 25 times that (0.7 measured).
    CHECK(cPhys < 0.02);
    CHECK(cPerc > 0.5);
}

TEST_CASE("Point sources: the stars drawn are those above the eye's threshold", "[gl][points]") {
    // The Stars alone (no Sky: the element applies the extinction, the background is the night
    // floor, raised to 1e-2 cd/m^2, a bright suburban sky: limiting magnitude ~4.2, a few hundred
    // stars above the horizon), a 512 x 512 fisheye (0.35 deg per pixel), Malta 2026-08-12 22:00
    // UTC, no twinkling, no glare. The prediction is independent of the drawing: the catalogue's
    // apparent places from the astronomy (topocentricFromIcrs), each star's illuminance at the eye
    // through the CPU transmittance of the atmosphere, against Schaefer's threshold.
    test::glContext();
    const double floorCdM2 = 1e-2;
    const UtcInstant t = UtcInstant::parse("2026-08-12T22:00:00Z");
    const astro::Site site{35.9 * kDeg, 14.5 * kDeg, 0.0};
    SkyProcessor p;
    p.setObserver({.latitudeRad = site.latitudeRad, .longitudeRad = site.longitudeRad, .heightMeters = 0});
    p.setTime(t);
    Camera cam;
    cam.projection = Projection::Fisheye;
    cam.width = cam.height = 512;
    p.setCamera(cam);
    p.add(std::make_unique<Stars>());
    p.vars().set(starkeys::scintillation, 0.0);
    p.vars().set(starkeys::glare, 0.0);
    p.vars().set(starkeys::backgroundFloor, floorCdM2);
    p.vars().set(keys::pointSources, std::string("perceptual"));
    p.renderFrame();
    const Image img = p.readHdr();
    const double limit = limitingMagnitude(floorCdM2);
    CHECK(p.stats()["stars"]["limiting_magnitude"].get<double>() == Approx(limit));  // the mode's own limit
    const double thresholdLux = pointThresholdLux(floorCdM2);

    // Predicted: every catalogue star to the limit (fainter ones are not even instanced), with its
    // pixel and its illuminance at the eye over the threshold (in magnitudes: > 0 visible).
    const astro::ObserverFrame f = astro::observerFrame(site, astro::timeScales(t), astro::Path::Fast);
    const astro::StarFrame sf = astro::starFrame(f);
    const generators::SkyModel model = generators::SkyModel::fromVars(p.vars());
    struct Predicted {
        glm::dvec2 px;
        double marginMag;  // 2.5 log10(E_eye / threshold)
    };
    std::vector<Predicted> pred;
    for (const astro::Star& s : astro::loadKStarsCatalogue(astro::kKStarsCatalogue, limit + 0.01)) {
        const glm::dvec3 p0 = astro::starDirectionJ2000(s), pm = astro::starProperMotion(s);
        const astro::Topocentric tp = astro::topocentricFromIcrs(f, glm::normalize(p0 + sf.yearsSinceJ2000 * pm));
        if (tp.altitudeRad <= 0.0) continue;
        const glm::dvec3 T = generators::cpu::transmittanceToTop(model, 0.0, std::sin(tp.altitudeRad), 256);
        const double eyeLux = astro::magnitude::illuminanceLux(s.magnitudeV) * color::luminance(color::starColourFromBV(s.colorBV) * T);
        pred.push_back({*cam.pixelOf(directionFromAzAlt(tp.azimuthRad, tp.altitudeRad)), 2.5 * std::log10(eyeLux / thresholdLux)});
    }
    // Drawn: local maxima of the luminance above a tenth of the faintest drawn peak (a star at the
    // threshold peaks at render.point_contrast x the background = 0.5 x 1e-2; sampled off centre
    // at >= 0.7 of it: see the Gaussian's 0.85 px sigma), larger than the 8 neighbours (ties: the
    // first in reading order).
    std::vector<glm::dvec2> drawn;
    const double floorPeak = 0.1 * 0.5 * floorCdM2;
    for (int y = 1; y < img.height - 1; ++y)
        for (int x = 1; x < img.width - 1; ++x) {
            const double c = lumaAt(img, x, y);
            if (c < floorPeak) continue;
            bool peak = true;
            for (int dy = -1; dy <= 1 && peak; ++dy)
                for (int dx = -1; dx <= 1 && peak; ++dx) {
                    if (!dx && !dy) continue;
                    const double o = lumaAt(img, x + dx, y + dy);
                    peak = dy < 0 || (dy == 0 && dx < 0) ? c > o : c >= o;
                }
            if (peak) drawn.push_back({x + 0.5, y + 0.5});
        }
    // Stars within 0.03 mag of the threshold may go either way (the shader's float arithmetic and
    // its 64-sample extinction table against the CPU's 256-step march: < 0.01 mag above 5 deg).
    // Stars with a predicted star within 4 px merge with it (FWHM 2-4 px): matched only alone.
    auto nearest = [](const std::vector<glm::dvec2>& pts, glm::dvec2 q) {
        double d = 1e9;
        for (auto& x : pts) d = std::min(d, glm::length(x - q));
        return d;
    };
    int visible = 0, seen = 0, hidden = 0, shown = 0, ambiguous = 0;
    for (size_t i = 0; i < pred.size(); ++i) {
        bool alone = true;
        for (size_t j = 0; j < pred.size() && alone; ++j)
            alone = i == j || pred[j].marginMag < -0.03 || glm::length(pred[j].px - pred[i].px) > 4.0;
        if (std::abs(pred[i].marginMag) <= 0.03) {
            ++ambiguous;
            continue;
        }
        if (pred[i].marginMag > 0) ++visible;
        if (!alone) continue;
        const bool found = nearest(drawn, pred[i].px) < 1.5;  // a maximum within 1.5 px (places: < 1 px, test_stars)
        if (pred[i].marginMag > 0) {
            if (found) ++seen;
            else INFO("missed a star at " << pred[i].px.x << ", " << pred[i].px.y << " margin " << pred[i].marginMag);
        } else {
            ++hidden;
            if (found) ++shown;
        }
    }
    int unexplained = 0;  // drawn maxima with no star predicted visible (or ambiguous) within 1.5 px
    for (auto& d : drawn) {
        bool ok = false;
        for (auto& q : pred) ok = ok || (q.marginMag >= -0.03 && glm::length(q.px - d) < 1.5);
        if (!ok) ++unexplained;
    }
    INFO("limit " << limit << " mag: " << pred.size() << " catalogue stars up, " << visible << " visible to the eye, " << ambiguous
                  << " at the threshold; " << drawn.size() << " maxima drawn; isolated: " << seen << " of the visible found, " << shown
                  << " of " << hidden << " invisible drawn; " << unexplained << " maxima unexplained");
    CHECK(visible > 100);  // the test has a population to judge: a few hundred stars up to ~4.2
    CHECK(hidden > 20);    // and stars to the limit that the extinction puts under the threshold
    CHECK(shown == 0);     // nothing the eye cannot see is drawn
    CHECK(unexplained == 0);
    // Every isolated visible star is drawn; the count of maxima is the visible count less the
    // merged pairs (each close pair may lose one: at most the non-isolated ones).
    int isolatedVisible = 0;
    for (size_t i = 0; i < pred.size(); ++i) {
        if (pred[i].marginMag <= 0.03) continue;
        bool alone = true;
        for (size_t j = 0; j < pred.size() && alone; ++j)
            alone = i == j || pred[j].marginMag < -0.03 || glm::length(pred[j].px - pred[i].px) > 4.0;
        isolatedVisible += alone ? 1 : 0;
    }
    CHECK(seen == isolatedVisible);
    CHECK(int(drawn.size()) <= visible + ambiguous);
    CHECK(int(drawn.size()) >= isolatedVisible);
}

TEST_CASE("Point sources: the threshold, the drawn size and contrast, the mode's key", "[cpu][points]") {
    // The threshold is the Stars' limiting magnitude as an illuminance: the two conventions'
    // constants (2.54e-6 lx at magnitude 0; Schaefer's -16.57 with 10.764 lx per foot-candle)
    // agree to 0.2 %.
    for (double B : {1e-5, 1.7e-4, 1e-2, 3.0, 5e3})
        CHECK(pointThresholdLux(B) == Approx(astro::magnitude::illuminanceLux(limitingMagnitude(B))).epsilon(0.005));
    CHECK_THROWS_AS(pointThresholdLux(-1.0), Error);
    // Under the threshold: nothing; at it: the contrast and size at the threshold; above: both
    // grow with the decades (x10: +2 c0 in contrast, +0.5 f0 in FWHM), the size capped at 8 f0.
    const double B = 30.0, I = pointThresholdLux(B);
    CHECK_FALSE(perceptualPoint(0.99 * I, B).visible);
    CHECK(perceptualPoint(0.99 * I, B).fwhmPx == 0.0);
    const PerceptualPoint at = perceptualPoint(I, B, 0.5, 2.0);
    CHECK(at.visible);
    CHECK(at.contrast == Approx(0.5));
    CHECK(at.fwhmPx == Approx(2.0));
    const PerceptualPoint ten = perceptualPoint(10 * I, B, 0.5, 2.0);
    CHECK(ten.contrast == Approx(1.5));
    CHECK(ten.fwhmPx == Approx(3.0));
    CHECK(perceptualPoint(1e30 * I, B, 0.5, 2.0).fwhmPx == Approx(16.0));
    // Venus (-4.4, ~50 % through the air at 19 deg) on a 67 cd/m^2 civil-twilight sky: ~40 x.
    CHECK(perceptualPoint(astro::magnitude::illuminanceLux(-4.4) * 0.5, 67.0).ratio == Approx(40).epsilon(0.25));
    // A magnitude 6 star by day (5e3 cd/m^2): far under the threshold.
    CHECK(perceptualPoint(astro::magnitude::illuminanceLux(6.0), 5e3).ratio < 1e-3);
    // The key: physical by default, two values, anything else an error naming them.
    SkyProcessor p;
    CHECK(p.vars().get(keys::pointSources) == "physical");
    CHECK(pointSourceMode(p.vars()) == PointSourceMode::Physical);
    p.vars().set(keys::pointSources, std::string("perceptual"));
    CHECK(pointSourceMode(p.vars()) == PointSourceMode::Perceptual);
    // An enumerated key: names are exact, and anything else is refused where it is set.
    CHECK_THROWS_WITH(p.vars().set(keys::pointSources, std::string("Perceptual")), "key 'render.point_sources': 'Perceptual' is not one of physical, perceptual");
    CHECK(pointSourceMode(p.vars()) == PointSourceMode::Perceptual);
}

TEST_CASE("Point sources: by day a magnitude 6 star is not drawn, a magnitude -6 one is", "[gl][points]") {
    // The Stars (the sky's limiting magnitude off, so both are instanced) under the Sky, the Sun
    // 30 deg up in the south; a 2 deg wide view north at 60 deg. Two catalogues: the bright star
    // alone, and with a magnitude 6 star 0.5 deg beside it.
    test::glContext();
    auto render = [](std::vector<astro::Star> cat, const char* mode, Camera& cam) {
        SkyProcessor p(SkyVars::earth(), Logger(), ProcessorOptions{.astronomy = false});
        cam.projection = Projection::Perspective;
        cam.azimuthRad = 0;
        cam.altitudeRad = 60 * kDeg;
        cam.verticalFovRad = 2 * kDeg;
        cam.width = cam.height = 64;
        p.setCamera(cam);
        p.add(std::make_unique<Stars>(std::move(cat)));
        p.add(makeElement("sky"));
        p.vars().set(keys::sunDirection, directionFromAzAlt(std::numbers::pi, 30 * kDeg));
        p.vars().set(starkeys::adaptiveLimit, false);
        p.vars().set(starkeys::scintillation, 0.0);
        p.vars().set(starkeys::glare, 0.0);
        p.vars().set(keys::pointSources, std::string(mode));
        p.renderFrame();
        return p.readHdr();
    };
    // Identity star frame (no astronomy): (ra 90, dec 60) is north at 60 deg.
    const astro::Star bright = star(90, 60, -6.0, 0.6), faint = star(90 + 0.5 / std::cos(60 * kDeg), 60, 6.0, 0.6);
    Camera cam;
    for (const char* mode : {"physical", "perceptual"}) {
        const Image one = render({bright}, mode, cam), two = render({bright, faint}, mode, cam);
        // The faint star's window: the right half of the image (the bright star is at the centre,
        // its perceptual FWHM under 5 px; the faint one 16 px to the side).
        double diff = 0;
        for (int y = 0; y < 64; ++y)
            for (int x = 0; x < 64; ++x)
                if (std::abs(x - 32) > 8 || std::abs(y - 32) > 8) diff = std::max(diff, std::abs(lumaAt(two, x, y) - lumaAt(one, x, y)));
        // The bright star: its peak over the sky beside it.
        double peak = 0;
        for (int y = 28; y < 36; ++y)
            for (int x = 28; x < 36; ++x) peak = std::max(peak, lumaAt(one, x, y));
        const double sky = lumaAt(one, 2, 2);
        INFO(mode << ": the faint star changes the image by " << diff << " cd/m^2 on a " << sky << " cd/m^2 sky; the bright star peaks at "
                  << peak / sky - 1.0 << " over it");
        if (std::string(mode) == "physical") {
            CHECK(diff > 0.0);  // the physical mode keeps its flux, however invisible
        } else {
            CHECK(diff == 0.0);  // the eye cannot see it: not drawn at all
            // Seen (mag -6 by day: a few times the threshold): its peak is the sky plus at least
            // render.point_contrast (0.5) x 0.7 (the peak pixel up to 0.7 px off the centre of a
            // Gaussian of sigma >= 0.85 px).
            CHECK(peak / sky - 1.0 > 0.35);
        }
    }
}

TEST_CASE("welkin render: perceptual point sources in a PNG, physical in an EXR, --var overrides", "[gl][cli][points]") {
    const std::string dir = test::scratchDir("points_cli");
    const std::string base = "render --time 2026-08-12T22:00:00Z --lat 35.9 --lon 14.5 --elements stars --size 16x16 ";
    struct Case {
        std::string args;
        const char* mode;
    } cases[] = {{"--out " + dir + "/a.png", "perceptual"},
                 {"--out " + dir + "/a.exr", "physical"},
                 {"--out " + dir + "/b.png --var render.point_sources=physical", "physical"},
                 {"--out " + dir + "/b.exr --var render.point_sources=perceptual", "perceptual"}};
    for (auto& c : cases) {
        auto r = test::runCli(base + c.args + " --stats " + dir + "/s.json");
        INFO("welkin " << base << c.args << "\n" << r.output);
        REQUIRE(r.status == 0);
        std::ifstream in(dir + "/s.json");
        const nlohmann::json j = nlohmann::json::parse(in);
        CHECK(j["stars"]["point_sources"].get<std::string>() == c.mode);
    }
    auto r = test::runCli(base + "--out " + dir + "/c.png --var render.point_sources=eye");
    INFO(r.output);
    CHECK(r.status != 0);
    CHECK_THAT(r.output, Catch::Contains("key 'render.point_sources': 'eye' is not one of physical, perceptual"));
    CHECK(std::count(r.output.begin(), r.output.end(), '\n') <= 2);
    CHECK_FALSE(std::filesystem::exists(dir + "/c.png"));
}
