// The night sky's folded texture (README "Cost", 2026-11-27): the per-pixel pass fetches one
// texture, the panorama's Milky Way with its floor and the zodiacal light summed over the
// panorama's mapping and mips. It must be that sum, and its rebuild when the Sun's ecliptic
// longitude moves, spread over frames while the old texture is drawn, must end with the texture
// (and the image) a whole rebuild gives.
#include <catch2/catch.hpp>

#include "gl_test_context.hpp"
#include "malta_night.hpp"

#include <welkin/elements/nightsky.hpp>
#include <welkin/keys.hpp>
#include <welkin/processor.hpp>
#include <welkin/time.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <numbers>

using namespace welkin;

namespace {
constexpr double kDeg = std::numbers::pi / 180.0;
const char* kPanorama = "/usr/share/stellarium/textures/milkyway.png";

Camera southView(int w, int h) {
    Camera cam;
    cam.projection = Projection::Perspective;
    cam.azimuthRad = std::numbers::pi;
    cam.altitudeRad = 30 * kDeg;
    cam.verticalFovRad = 60 * kDeg;
    cam.width = w;
    cam.height = h;
    return cam;
}

// The GL bilinear filter of the baked zodiacal table (256 x 128, row 0 the top) at (s, t), s
// repeating, t clamped to the edge, computed in double: the independent twin of the fold pass's
// textureLod(u_zodiTex, ..., 0).
double zodiBilinear(const std::vector<float>& tab, int W, int H, double s, double t) {
    const double x = s * W - 0.5, y = t * H - 0.5;
    const int x0 = int(std::floor(x)), y0 = int(std::floor(y));
    const double fx = x - x0, fy = y - y0;
    auto at = [&](int i, int j) {
        i = ((i % W) + W) % W;
        j = std::clamp(j, 0, H - 1);
        return double(tab[size_t(j) * W + i]);
    };
    return (1 - fy) * ((1 - fx) * at(x0, y0) + fx * at(x0 + 1, y0)) + fy * ((1 - fx) * at(x0, y0 + 1) + fx * at(x0 + 1, y0 + 1));
}

struct Night {
    SkyProcessor p;
    elements::NightSky* n = nullptr;
    explicit Night(long budget, const char* when, int w = 64, int h = 36) {
        test::atMalta(p, southView(w, h));
        p.setTime(UtcInstant::parse(when));
        auto e = std::make_unique<elements::NightSky>();
        e->setFoldBudget(int(budget));
        n = e.get();
        p.add(std::move(e));
        p.vars().set(keys::interactive, true);  // frames one after another: the rebuild may be spread
        // Drawn whatever the exposure: at the default manual EV 15 the pass would be skipped as
        // invisible (README "Twilight: the pass skipped where it cannot show"), and the fold with it.
        p.vars().set(elements::nightkeys::skipInvisible, false);
    }
};
}  // namespace

TEST_CASE("NightSky: the folded texture is the panorama, its floor and the zodiacal light", "[gl][nightsky]") {
    if (!std::filesystem::exists(kPanorama)) FAIL("no " << kPanorama << " (Debian: stellarium-data): install it (a missing file fails, never skips)");
    test::glContext();
    Night night(elements::kNightFoldTexelsPerFrame, "2026-08-12T22:00:00Z");
    night.p.renderFrame();
    elements::NightSky& n = *night.n;
    REQUIRE(n.milkyWayLoaded());
    CHECK(n.foldBuilds() == 1);
    CHECK_FALSE(n.foldInProgress());
    const std::vector<float>& tab = n.foldedZodiacalTable();
    const int TW = elements::NightSky::zodiacalTableWidth(), TH = elements::NightSky::zodiacalTableHeight();
    REQUIRE(tab.size() == size_t(TW) * TH);
    const glm::vec3 zf = n.foldZodiacalFactor(), floorL = n.foldFloor();
    const double mws = n.foldMilkyWayScale();
    CHECK(mws == 1.0);
    // The factors are the model's: the zodiacal unit x the Sun's colour (luminance 1) and the
    // floor's 23.0 mag/arcsec^2, both x 1e4 (the texture's storage scale).
    CHECK(0.2126 * zf.r + 0.7152 * zf.g + 0.0722 * zf.b == Approx(1e4 * elements::zodiacalUnitCdM2()).epsilon(1e-5));
    CHECK(0.2126 * floorL.r + 0.7152 * floorL.g + 0.0722 * floorL.b == Approx(1e4 * n.milkyWayFloorCdM2()).epsilon(1e-5));
    const int W0 = 2048, H0 = 1024;
    for (int level : {0, 1, 4, 8, 11}) {
        const int w = std::max(W0 >> level, 1), h = std::max(H0 >> level, 1);
        const std::vector<float> fold = n.readFolded(level), pan = n.readPanorama(level);
        REQUIRE(fold.size() == size_t(w) * h * 4);
        REQUIRE(pan.size() == fold.size());
        double maxRel = 0, zodiMax = 0, mwMax = 0;
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x) {
                const size_t i = (size_t(y) * w + x) * 4;
                const double z = zodiBilinear(tab, TW, TH, (x + 0.5) / w, (y + 0.5) / h);
                zodiMax = std::max(zodiMax, z);
                for (int c = 0; c < 3; ++c) {
                    const double want = floorL[c] + zf[c] * z + mws * pan[i + c];
                    mwMax = std::max(mwMax, double(pan[i + c]));
                    maxRel = std::max(maxRel, std::abs(fold[i + c] - want) / want);
                }
            }
        std::printf("nightsky fold, level %d (%dx%d): max relative difference from panorama + floor + zodiacal %.3g\n", level, w, h, maxRel);
        INFO("level " << level << ": max relative difference " << maxRel);
        CHECK(zodiMax > 50.0);   // the zodiacal light is in it (Table 17: 77 units at the poles, more near the ecliptic)
        if (level == 0) CHECK(mwMax > 1.0);  // and the Milky Way (x 1e4: ~1e-4 cd/m^2 and more)
        // Float rounding: three float products and sums (a few 6e-8), and the GL filter's
        // coordinates in float (s x 256 to ~3e-5 texel, times the table's steepest relative step
        // between neighbouring texels, ~5 %: ~2e-6). A wrong texel, row order or level moves the
        // zodiacal term by its own gradient, percents.
        CHECK(maxRel < 1e-5);
    }
}

TEST_CASE("NightSky: a rebuild of the folded texture spread over frames ends bit for bit as a whole one", "[gl][nightsky]") {
    test::glContext();
    // The Sun moves 0.25 deg along the ecliptic in 6 h (more than the 0.1 deg tolerance).
    const char* t1 = "2026-08-12T16:00:00Z";
    const char* t2 = "2026-08-12T22:00:00Z";
    Night whole(0, t1), spread(elements::kNightFoldTexelsPerFrame, t1);
    whole.p.renderFrame();
    spread.p.renderFrame();
    const double lon1 = spread.n->foldedSunLongitude();
    REQUIRE(std::isfinite(lon1));
    CHECK(spread.n->foldBuilds() == 1);
    whole.p.setTime(UtcInstant::parse(t2));
    spread.p.setTime(UtcInstant::parse(t2));
    whole.p.renderFrame();
    CHECK(whole.n->foldBuilds() == 2);  // at once
    CHECK_FALSE(whole.n->foldInProgress());
    const double lon2 = whole.n->foldedSunLongitude();
    // 0.24 deg of the Sun's motion; the element takes the longitude of the apparent Sun, which
    // at 16:00 UTC (28 deg up) is lifted by 2' of refraction: measured 0.217 deg.
    CHECK(std::abs(lon2 - lon1) / kDeg == Approx(0.23).margin(0.03));
    // Without render.interactive (welkin render, a timelapse) every frame is complete: the same
    // budget rebuilds the whole texture in the frame that needs it.
    {
        Night offline(elements::kNightFoldTexelsPerFrame, t1);
        offline.p.vars().set(keys::interactive, false);
        offline.p.renderFrame();
        offline.p.setTime(UtcInstant::parse(t2));
        offline.p.renderFrame();
        CHECK(offline.n->foldBuilds() == 2);
        CHECK_FALSE(offline.n->foldInProgress());
        CHECK(offline.n->foldedSunLongitude() == lon2);
    }
    int frames = 0;
    do {
        spread.p.renderFrame();
        ++frames;
        if (spread.n->foldInProgress()) CHECK(spread.n->foldedSunLongitude() == lon1);  // the old one drawn meanwhile
    } while (spread.n->foldInProgress() && frames < 100);
    std::printf("nightsky fold: a spread rebuild took %d frames\n", frames);
    // The bake's own frame, then 2.8 M texels (2048 x 1024 and its mips) at 131,072 a frame:
    // 16 + 4 + 2 (+ the small levels) frames.
    CHECK(frames >= 20);
    CHECK(frames <= 26);
    CHECK(spread.n->foldBuilds() == 2);
    CHECK(spread.n->foldedSunLongitude() == lon2);
    int levels = 0;
    for (int level = 0; level < 12; ++level) {
        const std::vector<float> a = whole.n->readFolded(level), b = spread.n->readFolded(level);
        REQUIRE(a.size() == b.size());
        CHECK(std::memcmp(a.data(), b.data(), a.size() * sizeof(float)) == 0);
        ++levels;
    }
    CHECK(levels == 12);
    // And the frame drawn from it: the same pixels.
    whole.p.renderFrame();
    spread.p.renderFrame();
    const Image ia = whole.p.readHdr(), ib = spread.p.readHdr();
    REQUIRE(ia.pixels.size() == ib.pixels.size());
    CHECK(std::memcmp(ia.pixels.data(), ib.pixels.data(), ia.pixels.size() * sizeof(float)) == 0);
    // Time moving again in the middle of a rebuild: the rebuild under way ends first (for the
    // longitude it began with), then the next one starts by itself; the texture never starves.
    spread.p.setTime(UtcInstant::parse("2026-08-13T04:00:00Z"));
    spread.p.renderFrame();
    REQUIRE(spread.n->foldInProgress());
    spread.p.setTime(UtcInstant::parse("2026-08-13T10:00:00Z"));
    frames = 0;
    while (spread.n->foldBuilds() < 4 && frames < 200) {
        spread.p.renderFrame();
        ++frames;
    }
    CHECK(spread.n->foldBuilds() == 4);
    CHECK(frames < 60);
}
