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

#include <welkin/astro/bodies.hpp>
#include <welkin/astro/eclipses.hpp>
#include <welkin/astro/lunar_limb.hpp>

#include <nlohmann/json.hpp>

#include <algorithm>
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

TEST_CASE("Contacts with the lunar limb's profile: the margin against a brute-force scan of the Sun's limb", "[cpu][astro][eclipse]") {
    // The independent scan: points of the Sun's boundary circle every 0.0036 deg of its own angle
    // (100,000), each tested against the profiled limb at its own position angle from the Moon's
    // centre (atan2, no ray-circle formula). The Moon's centre is inside the Sun's disk near a
    // total eclipse's C2, so a ray from it meets the boundary once and the disk is covered exactly
    // when the boundary is.
    const double D = 3.70e8, rs = 0.2627 * kDeg, pa = 1.3;
    auto brute = [&](double d) {
        double worst = -1e30;
        const double cx = d * std::sin(pa), cy = d * std::cos(pa);  // east, north from the Moon's centre
        for (int i = 0; i < 100000; ++i) {
            const double phi = 2.0 * std::numbers::pi * i / 100000.0;
            const double x = cx + rs * std::sin(phi), y = cy + rs * std::cos(phi);
            const double r = std::hypot(x, y), theta = std::atan2(x, y);
            worst = std::max(worst, r - std::asin((kMoonMeanRadiusMeters + lunarLimbHeightMeters(theta)) / D));
        }
        return worst;
    };
    const double rm = std::asin(kMoonMeanRadiusMeters / D);
    for (double d : {0.2 * (rm - rs), 0.8 * (rm - rs), rm - rs, 1.2 * (rm - rs)}) {
        const LimbGeometry g{.separationRad = d, .sunPaRad = pa, .sunRadiusRad = rs, .moonDistanceM = D};
        INFO("separation " << d / kDeg << " deg: margin " << limbCoverMargin(g) * D << " m, brute force " << brute(d) * D << " m");
        // 20 m at the Moon: the margin's 0.05 deg scan against the brute force's 0.0036 deg on a
        // profile whose steepest slope is ~100 m per 0.05 deg at the limb (measured < 5 m).
        CHECK(std::abs(limbCoverMargin(g) - brute(d)) * D < 20.0);
        // The smooth limb's margin is the closed form.
        CHECK(limbCoverMargin({.separationRad = d, .sunPaRad = pa, .sunRadiusRad = rs, .moonDistanceM = D, .profile = false}) ==
              Approx(d + rs - rm).margin(1e-12));
    }
    // Where the last bead vanishes: the separation at which each margin crosses 0 (bisection),
    // the same within 20 m / the distance.
    auto zero = [&](auto f) {
        double a = 0.0, b = 2.0 * (rm - rs);  // covered at a (f < 0), not at b
        for (int i = 0; i < 40; ++i) (f(0.5 * (a + b)) < 0.0 ? a : b) = 0.5 * (a + b);
        return 0.5 * (a + b);
    };
    const double dMargin = zero([&](double d) { return limbCoverMargin({.separationRad = d, .sunPaRad = pa, .sunRadiusRad = rs, .moonDistanceM = D}); });
    const double dBrute = zero(brute);
    CHECK(std::abs(dMargin - dBrute) * D < 20.0);
    // It lies within the profile's extremes of the smooth limb's (d = rm - rs), -4.3 .. +2.7 km.
    double lo = 1e9, hi = -1e9;
    for (float h : lunarLimbProfileMeters()) lo = std::min(lo, double(h)), hi = std::max(hi, double(h));
    CHECK((dMargin - (rm - rs)) * D >= lo - 20.0);
    CHECK((dMargin - (rm - rs)) * D <= hi + 20.0);
}

TEST_CASE("Contacts with the lunar limb's profile: Luxor 2027 and Burgos 2026, within the profile's extremes in time", "[cpu][astro][eclipse]") {
    double lo = 1e9, hi = -1e9;
    for (float h : lunarLimbProfileMeters()) lo = std::min(lo, double(h)), hi = std::max(hi, double(h));
    struct Case {
        Site s;
        const char* from;
        const char* to;
    };
    for (const Case& c : {Case{site(25.70, 32.64, 80.0), "2027-08-01T00:00:00Z", "2027-08-03T00:00:00Z"},
                          Case{site(42.34, -3.70, 860.0), "2026-08-11T00:00:00Z", "2026-08-13T00:00:00Z"}}) {
        const auto list = findSolarEclipses(c.s, UtcInstant::parse(c.from), UtcInstant::parse(c.to), Path::Fast);
        REQUIRE(list.size() == 1);
        const SolarEclipseLocal& e = list[0];
        REQUIRE(e.c2);
        REQUIRE(e.c2Limb);
        REQUIRE(e.c3Limb);
        // The rate at which the separation changes at C2 and C3 (rad/s, numerically over +-1 s),
        // times the Moon's distance: how fast the limb advances over the Sun's, m/s.
        auto rate = [&](const UtcInstant& t) {
            auto sep = [&](double dt) {
                const ObserverFrame f = observerFrame(c.s, timeScales(t.plusSeconds(dt)), Path::Fast);
                const BodyState sun = computeBody(Body::Sun, f), moon = computeBody(Body::Moon, f);
                const glm::dvec3 a = glm::normalize(sun.topo.enuGeometric), b = glm::normalize(moon.topo.enuGeometric);
                return std::pair{std::atan2(glm::length(glm::cross(a, b)), glm::dot(a, b)), moon.topo.distanceMeters};
            };
            return std::abs(sep(1.0).first - sep(-1.0).first) / 2.0 * sep(0.0).second;
        };
        const double v2 = rate(e.c2->time), v3 = rate(e.c3->time);
        std::printf("%s: C2 %s, with the limb profile %s (%+.2f s against a smooth limb at the mean radius, which is %+.2f s from C2); "
                    "C3 %s, with the profile %s (%+.2f s, %+.2f s); the limb advances %.0f / %.0f m/s\n",
                    c.from, e.c2->time.toIso().c_str(), e.c2Limb->time.toIso().c_str(), e.c2LimbShiftSeconds, e.c2MeanShiftSeconds,
                    e.c3->time.toIso().c_str(), e.c3Limb->time.toIso().c_str(), e.c3LimbShiftSeconds, e.c3MeanShiftSeconds, v2, v3);
        // At C2 the smooth margin falls at v: a valley of depth |lo| keeps a bead until the smooth
        // limb is |lo| past the Sun's (later), a mountain of height hi covers it hi before; C3
        // the mirror. Tolerance 0.15 s: the bisections' 0.05 s, the margin's 20 m scan.
        CHECK(e.c2LimbShiftSeconds >= -hi / v2 - 0.15);
        CHECK(e.c2LimbShiftSeconds <= -lo / v2 + 0.15);
        CHECK(e.c3LimbShiftSeconds >= lo / v3 - 0.15);
        CHECK(e.c3LimbShiftSeconds <= hi / v3 + 0.15);
        // The mean radius (1737.4 km) is 0.74 km above the Canon's C2/C3 radius (k = 0.272281):
        // its C2 comes earlier and C3 later, by 0.74 km / v.
        CHECK(e.c2MeanShiftSeconds == Approx(-740.0 / v2).margin(0.15));
        CHECK(e.c3MeanShiftSeconds == Approx(740.0 / v3).margin(0.15));
        // The profile changes the contacts (a valley or a mountain is under the contact point).
        CHECK(std::abs(e.c2LimbShiftSeconds) + std::abs(e.c3LimbShiftSeconds) > 0.1);
    }
}
