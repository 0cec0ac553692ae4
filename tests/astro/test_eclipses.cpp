// Solar eclipses' local circumstances and lunar eclipses' contacts against published predictions,
// and the Earth's shadow model the Moon's light follows.
//
// Sources of the reference numbers (transcribed):
// - Lunar eclipse 2025-09-07 and 2026-03-03: contacts and magnitudes from F. Espenak's NASA
//   predictions (Five Millennium Canon of Lunar Eclipses conventions, Danjon's shadow), as quoted
//   in the Wikipedia articles "September 2025 lunar eclipse" / "March 2026 lunar eclipse"
//   (infobox and parameter table), times UT.
// - Solar eclipse 2027-08-02 at Luxor: totality from 13:02 local time (UTC+3 in August: 10:02 UT;
//   eladelantado.com, "the eclipse of the century"), ~6 min 20 s long (solareclipseegypt.com: the
//   city's duration "just under 3 s shorter" than the eclipse's 6 min 23 s maximum, which lies
//   ~60 km south-east). NASA's greatest eclipse, 10:07:50 TD = ~10:06:40 UT, is at that point
//   further along the track, not at Luxor.
// - Solar eclipse 2026-08-12: total in Burgos (42.34 N, 3.70 W) around 18:29 UT; greatest eclipse
//   off western Iceland at 65.2 N 25.2 W, 2 min 18 s (NASA, Wikipedia "Solar eclipse of August
//   12, 2026").
//
// Tolerances: the Fast path's Moon (Meeus ch. 47) is good to ~10" in longitude and ~4" in
// latitude against the Precise path (docs/astronomy-bodies.md); the Moon moves ~0.5"/s relative to
// the Sun and the Earth's shadow, so a contact where the limbs cross squarely is off by up to ~20 s,
// a penumbral contact (limbs crossing obliquely, shadow edge ill-defined) by up to ~40 s. The
// references themselves are rounded to 1 s and use the JPL ephemerides.
#include <catch2/catch.hpp>

#include "cli_runner.hpp"

#include <welkin/astro/eclipses.hpp>

#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdio>
#include <numbers>

using namespace welkin;
using namespace welkin::astro;
using welkin::test::runCli;

namespace {
constexpr double kDeg = std::numbers::pi / 180.0;

double secondsBetween(const UtcInstant& a, const char* iso) {
    return daysBetween(UtcInstant::parse(iso).julianDate(), a.julianDate()) * 86400.0;
}

Site site(double latDeg, double lonDeg, double heightM = 0.0) { return Site{latDeg * kDeg, lonDeg * kDeg, heightM}; }
}  // namespace

TEST_CASE("Lunar eclipses 2025-09-07 and 2026-03-03: contacts and magnitudes against NASA's", "[cpu][astro][eclipse]") {
    const auto list = findLunarEclipses(site(0.0, 60.0), UtcInstant::parse("2025-09-01T00:00:00Z"),
                                        UtcInstant::parse("2026-03-10T00:00:00Z"), Path::Fast);
    REQUIRE(list.size() == 2);
    struct Ref {
        const char *p1, *u1, *u2, *greatest, *u3, *u4, *p4;
        double umbral, penumbral;
    };
    const Ref refs[2] = {
        {"2025-09-07T15:28:21Z", "2025-09-07T16:27:02Z", "2025-09-07T17:30:41Z", "2025-09-07T18:11:43Z", "2025-09-07T18:52:47Z",
         "2025-09-07T19:56:26Z", "2025-09-07T20:55:00Z", 1.3638, 2.3459},
        {"2026-03-03T08:44:22Z", "2026-03-03T09:50:00Z", "2026-03-03T11:04:26Z", "2026-03-03T11:33:37Z", "2026-03-03T12:02:45Z",
         "2026-03-03T13:17:10Z", "2026-03-03T14:22:59Z", 1.1526, -1.0},  // penumbral magnitude not found in the sources
    };
    for (int i = 0; i < 2; ++i) {
        const LunarEclipse& e = list[i];
        const Ref& r = refs[i];
        INFO("eclipse " << i);
        REQUIRE(e.type == LunarEclipseType::Total);
        REQUIRE(e.u1);
        REQUIRE(e.u2);
        REQUIRE(e.u3);
        REQUIRE(e.u4);
        std::printf("lunar %s: P1 %+.0f U1 %+.0f U2 %+.0f max %+.0f U3 %+.0f U4 %+.0f P4 %+.0f s; umbral %.4f (%.4f) penumbral %.4f (%.4f)\n",
                    r.greatest, secondsBetween(e.p1.time, r.p1), secondsBetween(e.u1->time, r.u1), secondsBetween(e.u2->time, r.u2),
                    secondsBetween(e.greatest.time, r.greatest), secondsBetween(e.u3->time, r.u3), secondsBetween(e.u4->time, r.u4),
                    secondsBetween(e.p4.time, r.p4), e.umbralMagnitude, r.umbral, e.penumbralMagnitude, r.penumbral);
        CHECK(std::abs(secondsBetween(e.u1->time, r.u1)) < 30.0);  // umbral contacts: see the tolerance note above
        CHECK(std::abs(secondsBetween(e.u2->time, r.u2)) < 30.0);
        CHECK(std::abs(secondsBetween(e.u3->time, r.u3)) < 30.0);
        CHECK(std::abs(secondsBetween(e.u4->time, r.u4)) < 30.0);
        CHECK(std::abs(secondsBetween(e.greatest.time, r.greatest)) < 30.0);
        CHECK(std::abs(secondsBetween(e.p1.time, r.p1)) < 60.0);  // penumbral contacts: oblique, +-40 s and margin
        CHECK(std::abs(secondsBetween(e.p4.time, r.p4)) < 60.0);
        // Magnitudes: 10" of Moon position / the Moon's 31' diameter ~ 0.005.
        CHECK(e.umbralMagnitude == Approx(r.umbral).margin(0.01));
        if (r.penumbral > 0) CHECK(e.penumbralMagnitude == Approx(r.penumbral).margin(0.01));
    }
    // 2025-09-07 from 60 E on the equator: the Moon high at greatest eclipse (local ~22:11);
    // 2026-03-03 (greatest ~11:34 UT, local ~15:34): the Moon below the horizon until the end of
    // the partial phase (it rises near P4, local ~18:23).
    CHECK(list[0].visible);
    CHECK(list[0].greatest.altitudeRad > 30 * kDeg);
    CHECK(list[1].greatest.altitudeRad < -30 * kDeg);
    CHECK(list[1].u4->altitudeRad < 0.0);
}

TEST_CASE("Solar eclipse 2027-08-02 from Luxor: total, maximum and duration", "[cpu][astro][eclipse]") {
    const auto list = findSolarEclipses(site(25.70, 32.64, 80.0), UtcInstant::parse("2027-07-01T00:00:00Z"),
                                        UtcInstant::parse("2027-09-01T00:00:00Z"), Path::Fast);
    REQUIRE(list.size() == 1);
    const SolarEclipseLocal& e = list[0];
    REQUIRE(e.type == SolarEclipseType::Total);
    REQUIRE(e.c2);
    REQUIRE(e.c3);
    std::printf("Luxor 2027-08-02: C1 %s C2 %s max %s C3 %s C4 %s, %.1f s, magnitude %.4f, Sun at %.1f deg\n", e.c1.time.toIso().c_str(),
                e.c2->time.toIso().c_str(), e.maximum.time.toIso().c_str(), e.c3->time.toIso().c_str(), e.c4.time.toIso().c_str(),
                e.durationSeconds, e.magnitude, e.maximum.altitudeRad / kDeg);
    CHECK(e.visible);
    // Second contact "13:02" local = 10:02 UT, given to the minute: 10:02:30 +- 30 s, + 30 s for
    // the ephemeris (see above).
    CHECK(std::abs(secondsBetween(e.c2->time, "2027-08-02T10:02:30Z")) < 60.0);
    // And the maximum before NASA's greatest eclipse (10:06:40 UT) further down the track.
    CHECK(secondsBetween(e.maximum.time, "2027-08-02T10:06:40Z") < 0.0);
    // 6 min 20 s: near the central line the duration hardly depends on the Moon's position error
    // (the path is ~250 km wide); the Moon's radius and relative speed set it: +-5 s.
    CHECK(e.durationSeconds == Approx(380.0).margin(5.0));
    CHECK(e.magnitude > 1.0);
    CHECK(e.obscuration == 1.0);
    CHECK(e.maximum.altitudeRad > 75 * kDeg);  // the Sun near the zenith at noon in August at 25.7 N
    // The contacts bracket the maximum, C2/C3 symmetric about it to a few seconds.
    CHECK(secondsBetween(e.c2->time, e.c1.time.toIso().c_str()) > 3600.0);
    CHECK(std::abs(secondsBetween(e.maximum.time, e.c2->time.toIso().c_str()) - 0.5 * e.durationSeconds) < 3.0);
}

TEST_CASE("Solar eclipse 2026-08-12: total at Burgos around 18:29 UT, partial at Madrid", "[cpu][astro][eclipse]") {
    const UtcInstant from = UtcInstant::parse("2026-08-01T00:00:00Z"), to = UtcInstant::parse("2026-08-31T00:00:00Z");
    const auto burgos = findSolarEclipses(site(42.34, -3.70, 860.0), from, to, Path::Fast);
    REQUIRE(burgos.size() == 1);
    const SolarEclipseLocal& e = burgos[0];
    std::printf("Burgos 2026-08-12: max %s, %s, magnitude %.4f, duration %.1f s, Sun at %.1f deg\n", e.maximum.time.toIso().c_str(),
                toString(e.type), e.magnitude, e.durationSeconds, e.maximum.altitudeRad / kDeg);
    CHECK(e.type == SolarEclipseType::Total);
    CHECK(std::abs(secondsBetween(e.maximum.time, "2026-08-12T18:29:00Z")) < 90.0);  // the reference is "around 18:29"
    CHECK(e.durationSeconds > 0.0);
    CHECK(e.maximum.altitudeRad > 5 * kDeg);  // low in the west in the evening, but up
    CHECK(e.maximum.altitudeRad < 20 * kDeg);
    // Madrid (40.42 N, 3.70 W) lies just outside the path (Wikipedia): a deep partial eclipse.
    const auto madrid = findSolarEclipses(site(40.42, -3.70, 650.0), from, to, Path::Fast);
    REQUIRE(madrid.size() == 1);
    CHECK(madrid[0].type == SolarEclipseType::Partial);
    CHECK(madrid[0].magnitude > 0.95);
    CHECK(madrid[0].magnitude < 1.0);
    CHECK(madrid[0].obscuration < 1.0);
    CHECK_FALSE(madrid[0].c2);
    // Over 95 % of the diameter covered by a Moon larger than the Sun: most of the area too.
    CHECK(madrid[0].obscuration > 0.9);
    // Sydney never sees it.
    CHECK(findSolarEclipses(site(-33.87, 151.21), from, to, Path::Fast).empty());
}

TEST_CASE("Lens fraction and the Earth's shadow on the Moon", "[cpu][astro][eclipse]") {
    // Uniform disk: concentric equal disks hide all; a disk of half the radius hides a quarter.
    CHECK(lensVisibleFraction(1e-3, 1e-3, 0.0) == 0.0);
    CHECK(lensVisibleFraction(1e-3, 0.5e-3, 0.0) == Approx(0.75).margin(1e-12));
    CHECK(lensVisibleFraction(1e-3, 1e-3, 2e-3) == 1.0);
    // Two equal disks with centres one radius apart: lens area = 2 r^2 (pi/3 - sqrt(3)/4).
    const double lens = 2.0 * (std::numbers::pi / 3.0 - std::sqrt(3.0) / 4.0);
    CHECK(lensVisibleFraction(1.0, 1.0, 1.0) == Approx(1.0 - lens / std::numbers::pi).margin(1e-9));
    // The umbra's edge from the Earth's centre is at 1.01 pi_M - s_S + pi_S (Danjon): a point on
    // the anti-solar axis at the Moon's mean distance is in the umbra (direct 0, refracted at the
    // centre value); 1.05 x that edge's radius off the axis it is in the penumbra.
    const glm::dvec3 sun(1.496e11, 0.0, 0.0);
    const double dMoon = 3.844e8;
    const ShadowLight axisLight = earthShadowLight(glm::dvec3(-dMoon, 0, 0), sun);
    CHECK(axisLight.direct == 0.0);
    CHECK(axisLight.refracted == Approx(kUmbraRefractedCentre).epsilon(1e-6));
    const double piM = std::asin(kEarthEquatorialRadiusMeters / dMoon), piS = std::asin(kEarthEquatorialRadiusMeters / 1.496e11);
    const double sS = std::asin(bodyRadiusMeters(Body::Sun) / 1.496e11);
    const double umbra = kEarthShadowFactor * piM - sS + piS;
    const ShadowLight inside = earthShadowLight(dMoon * glm::dvec3(-std::cos(0.98 * umbra), std::sin(0.98 * umbra), 0), sun);
    const ShadowLight outside = earthShadowLight(dMoon * glm::dvec3(-std::cos(1.05 * umbra), std::sin(1.05 * umbra), 0), sun);
    CHECK(inside.direct == 0.0);
    CHECK(outside.direct > 0.0);
    CHECK(outside.direct < 0.5);
    // Far away: full sunlight.
    const ShadowLight free = moonShadowLight(glm::dvec3(0, dMoon, 0), sun);
    CHECK(free.direct == 1.0);
    CHECK(free.refracted == 0.0);
}

TEST_CASE("welkin astro --events: eclipses in the window, JSON and text; bad windows", "[cpu][astro][cli][eclipse]") {
    auto r = runCli("astro --time 2026-08-12T00:00:00Z --lat 42.34 --lon -3.70 --events --to 2026-08-20T00:00:00Z --json");
    INFO(r.output);
    REQUIRE(r.status == 0);
    const nlohmann::json j = nlohmann::json::parse(r.output);
    REQUIRE(j["eclipses"]["solar"].size() == 1);
    const auto& s = j["eclipses"]["solar"][0];
    CHECK(s["type"] == "total");
    CHECK(s["visible"] == true);
    for (const char* k : {"c1", "c2", "maximum", "c3", "c4"}) {
        INFO(k);
        REQUIRE(s[k].is_object());
        CHECK(s[k]["time"].get<std::string>().rfind("2026-08-12T", 0) == 0);
        CHECK(s[k]["sun_alt_deg"].is_number());
    }
    CHECK(s["magnitude"].get<double>() > 1.0);
    CHECK(s["obscuration"].get<double>() == 1.0);
    CHECK(j["eclipses"]["lunar"].empty());  // 2026-08-28's partial lunar eclipse is after --to

    auto t = runCli("astro --time 2026-08-01T00:00:00Z --lat 42.34 --lon -3.70 --events --to 2026-09-01T00:00:00Z");
    INFO(t.output);
    REQUIRE(t.status == 0);
    CHECK(t.output.find("total") != std::string::npos);
    CHECK(t.output.find("C2") != std::string::npos);
    CHECK(t.output.find("partial") != std::string::npos);  // the lunar eclipse of 2026-08-28
    CHECK(t.output.find("U1") != std::string::npos);

    auto bad = runCli("astro --time 2026-08-01T00:00:00Z --lat 0 --lon 0 --events --to 2025-01-01T00:00:00Z");
    CHECK(bad.status != 0);
    CHECK(bad.output.find("--to") != std::string::npos);
    auto noEvents = runCli("astro --time 2026-08-01T00:00:00Z --lat 0 --lon 0 --from 2026-08-01T00:00:00Z");
    CHECK(noEvents.status != 0);
    CHECK(noEvents.output.find("--events") != std::string::npos);
}
