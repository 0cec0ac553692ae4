// Twilight (issue 22, README "Twilight: the pass skipped where it cannot show"): the night sky's
// pass is skipped when the previous frame's exposure (keys::exposurePrevious) cannot show any of
// it: eye::displaySlopeBound() x exposure x the pass's largest radiance in the camera's cone under
// half an 8-bit code. The skipped frame must be the drawn one within that, and the skip must run
// where the bound says and nowhere else.
#include <catch2/catch.hpp>

#include "elements_present.hpp"
#include "gl_test_context.hpp"

#include <welkin/elements/nightsky.hpp>
#include <welkin/elements/registry.hpp>
#include <welkin/eye.hpp>
#include <welkin/keys.hpp>
#include <welkin/processor.hpp>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <random>
#include <string>

using namespace welkin;

namespace {
constexpr double kDeg = std::numbers::pi / 180.0;
}  // namespace

TEST_CASE("NightSky: the zodiacal light's bound beyond an elongation holds over the table", "[cpu][nightsky]") {
    // The whole sky: the table's largest entry (Leinert Table 17, 11500 units at 15 deg from the Sun).
    CHECK(elements::zodiacalMaxBeyond(0.0) == 11500.0);
    CHECK(elements::zodiacalMaxBeyond(-1.0) == 11500.0);
    // Beyond 44 deg the cells reach back to the 40 deg row at most (its largest entry 1180).
    CHECK(elements::zodiacalMaxBeyond(44 * kDeg) == 1180.0);
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> dl(-std::numbers::pi, std::numbers::pi), sb(-1.0, 1.0);
    for (double e : {10.0, 30.0, 45.0, 60.0, 90.0, 150.0}) {
        const double bound = elements::zodiacalMaxBeyond(e * kDeg);
        double seen = 0.0;
        for (int i = 0; i < 20000; ++i) {
            const double l = dl(rng), b = std::asin(sb(rng));
            if (std::acos(std::cos(l) * std::cos(b)) < e * kDeg) continue;
            seen = std::max(seen, elements::zodiacalTable(l, b));
        }
        CAPTURE(e, bound, seen);
        CHECK(seen <= bound);        // an upper bound
        CHECK(seen >= 0.3 * bound);  // and not a useless one: within a cell's step of the table (the 5-15 deg grid)
    }
    // Non-increasing with the elongation.
    double last = 1e30;
    for (int e = 0; e <= 180; e += 5) {
        const double b = elements::zodiacalMaxBeyond(e * kDeg);
        CHECK(b <= last);
        last = b;
    }
}

#ifdef WELKIN_HAS_ELEMENT_sky
namespace {
struct Shown {
    Image ldr;
    std::vector<bool> skipped;  // per frame: the pass skipped as invisible
    std::vector<double> boundCodes;
    std::string drew;  // the elements that drew in the last frame
};

// bench display's view (south, 30 deg up, 60 deg) over Malta at `when`, the four default
// elements, automatic exposure as welkin view, frames 0.05 s apart; the last frame's display.
Shown frames(const char* when, bool skip, int n, bool automatic = true, bool interactive = true) {
    Camera cam;
    cam.azimuthRad = std::numbers::pi;
    cam.altitudeRad = 30 * kDeg;
    cam.verticalFovRad = 60 * kDeg;
    cam.width = 320;
    cam.height = 180;
    SkyProcessor p;
    p.setObserver({.latitudeRad = 35.9 * kDeg, .longitudeRad = 14.5 * kDeg, .heightMeters = 50});
    p.setTime(UtcInstant::parse(when));
    p.setCamera(cam);
    p.vars().set(keys::interactive, interactive);
    p.setExposure({.automatic = automatic, .ev100 = 7.0});
    elements::NightSky* night = nullptr;
    for (const char* e : {"nightsky", "stars", "planet", "sky"}) {
        auto el = elements::makeElement(e);
        if (std::string(e) == "nightsky") night = static_cast<elements::NightSky*>(el.get());
        p.add(std::move(el));
    }
    p.vars().set(elements::nightkeys::skipInvisible, skip);
    Shown s;
    for (int i = 0; i < n; ++i) {
        p.setAnimationTime(0.05 * i);
        p.renderFrame();
        s.skipped.push_back(night->lastSkippedInvisible());
        s.boundCodes.push_back(night->lastInvisibleBoundCodes());
        CHECK(p.stats()["nightsky"]["skipped_invisible"].get<bool>() == night->lastSkippedInvisible());
    }
    s.ldr = p.readToneMapped();
    for (const auto& e : p.elements())
        if (!e->drewNothing()) s.drew += (s.drew.empty() ? "" : ", ") + e->name();
    return s;
}
}  // namespace

TEST_CASE("NightSky: at twilight the pass skipped where the previous frame's exposure cannot show it equals the drawn one",
          "[gl][nightsky][display]") {
    test::glContext();
    const char* twilight = "2026-08-12T18:10:00Z";  // bench display's twilight: Sun 3.4 deg down, EV100 ~7.2
    const Shown fast = frames(twilight, true, 3), general = frames(twilight, false, 3);
    // The first frame knows no exposure yet (0: unknown): drawn, no bound. The next ones skip.
    CHECK_FALSE(fast.skipped[0]);
    CHECK(fast.boundCodes[0] == 0.0);
    CHECK(fast.skipped[1]);
    CHECK(fast.skipped[2]);
    for (bool s : general.skipped) CHECK_FALSE(s);  // the key off: always drawn
    std::printf("nightsky at twilight: the pass could change a displayed pixel by at most %.3f 8-bit codes (skipped under 0.5)\n",
                fast.boundCodes[2]);
    std::printf("nightsky at twilight: drawn in the last frame: %s (skipped) against %s (drawn)\n", fast.drew.c_str(), general.drew.c_str());
    CHECK(fast.drew.find("nightsky") == std::string::npos);
    CHECK(general.drew.find("nightsky") != std::string::npos);
    CHECK(fast.boundCodes[2] > 0.0);
    CHECK(fast.boundCodes[2] < 0.5);
    CHECK(general.boundCodes[2] == Approx(fast.boundCodes[2]).epsilon(0.05));  // the same bound, the pass drawn
    // The displayed frames: every pixel within one 8-bit code (a change under half a code moves a
    // rounded value by at most one code), and almost all identical.
    REQUIRE(fast.ldr.pixels.size() == general.ldr.pixels.size());
    double maxDiff = 0.0;
    size_t differing = 0;
    for (size_t i = 0; i < fast.ldr.pixels.size(); ++i) {
        const double d = std::abs(double(fast.ldr.pixels[i]) - general.ldr.pixels[i]) * 255.0;
        maxDiff = std::max(maxDiff, d);
        differing += d > 0.5;
    }
    std::printf("nightsky at twilight, skipped against drawn: max %.2f codes, %zu of %zu channel values differ\n", maxDiff, differing,
                fast.ldr.pixels.size());
    CHECK(maxDiff <= 1.0 + 1e-4);  // 1e-4: the float read of k / 255 times 255
    CHECK(double(differing) <= 0.01 * double(fast.ldr.pixels.size()));

    // The moonless night: the pass shows, it is never skipped, and its bound says so.
    const Shown night = frames("2026-08-12T22:00:00Z", true, 3);
    for (bool s : night.skipped) CHECK_FALSE(s);
    CHECK(night.boundCodes[2] >= 0.5);
    // A manual exposure is known from the first frame: at EV100 7 (the twilight's) skipped at once.
    const Shown manual = frames(twilight, true, 1, false);
    CHECK(manual.skipped[0]);
    // Frames not displayed one after another (welkin render, an EXR: render.interactive false)
    // keep every term in their HDR image: never skipped.
    const Shown offline = frames(twilight, true, 3, false, false);
    for (bool sk : offline.skipped) CHECK_FALSE(sk);
}
#endif
