// Rise, set, twilight, polar day/night and Moon quarters.
#include <welkin/astro/events.hpp>
#include <welkin/error.hpp>

#include <catch2/catch.hpp>

#include <cmath>
#include <numbers>

using namespace welkin;
using namespace welkin::astro;

namespace {
constexpr double kDegE = std::numbers::pi / 180.0;
double secondsBetween(const UtcInstant& a, const UtcInstant& b) { return daysBetween(a.julianDate(), b.julianDate()) * 86400.0; }
BodyState at(const UtcInstant& t, const Site& site, Body b, Path path = Path::Fast) {
    return computeBody(b, observerFrame(site, timeScales(t), path));
}
}  // namespace

TEST_CASE("Rise and set: Meeus example 15.a (Venus at Boston)", "[cpu][astro][events]") {
    // 1988 March 20, Boston (42d20'N, 71d05'W), h0 = -0.5667 deg: rising 12h25m UT, setting
    // 2h55m UT (Meeus' interpolated values, given to the minute; his accurate m are 0.51766 and
    // 0.12130 d = 12h25m26s and 2h54m40s). 60 s covers the rounding.
    Site boston{42.3333 * kDegE, -71.0833 * kDegE, 0.0};
    const UtcInstant start = UtcInstant::parse("1988-03-20T00:00:00Z");
    for (Path path : {Path::Fast, Path::Precise}) {
        auto rise = findCrossing(boston, start, path, Body::Venus, -0.5667 * kDegE, +1);
        auto set = findCrossing(boston, start, path, Body::Venus, -0.5667 * kDegE, -1);
        REQUIRE(rise);
        REQUIRE(set);
        CHECK(std::fabs(secondsBetween(UtcInstant::parse("1988-03-20T12:25:26Z"), *rise)) < 60.0);
        CHECK(std::fabs(secondsBetween(UtcInstant::parse("1988-03-20T02:54:40Z"), *set)) < 60.0);
    }
}

TEST_CASE("Sunrise, sunset and twilights at a mid-latitude site", "[cpu][astro][events]") {
    // Berlin, 2026 June 21: published (timeanddate.com, USNO method, -0.833 deg) sunrise 04:43,
    // sunset 21:33 CEST = 02:43 and 19:33 UTC, to the minute: 90 s.
    Site berlin{52.52 * kDegE, 13.405 * kDegE, 34.0};
    const UtcInstant start = UtcInstant::parse("2026-06-21T00:00:00Z");
    DayEvents ev = findDayEvents(berlin, start, Path::Fast);
    REQUIRE(ev.sunrise);
    REQUIRE(ev.sunset);
    CHECK(std::fabs(secondsBetween(UtcInstant::parse("2026-06-21T02:43:00Z"), *ev.sunrise)) < 90.0);
    CHECK(std::fabs(secondsBetween(UtcInstant::parse("2026-06-21T19:33:00Z"), *ev.sunset)) < 90.0);
    CHECK(ev.polar == PolarState::None);
    // Midsummer at 52.5 N: the Sun never reaches -18 deg (no astronomical twilight), it does
    // reach -12 deg (nautical dusk then dawn after midnight).
    CHECK_FALSE(ev.astronomicalDawn);
    CHECK_FALSE(ev.astronomicalDusk);
    REQUIRE(ev.civilDawn);
    REQUIRE(ev.civilDusk);
    CHECK(secondsBetween(*ev.civilDawn, *ev.sunrise) > 0);
    CHECK(secondsBetween(*ev.sunset, *ev.civilDusk) > 0);
    // The defining altitudes hold at the reported instants (to the 1 s rounding: the Sun moves
    // < 0.004 deg per second of time... 0.0042 deg/s at most).
    CHECK(at(*ev.sunrise, berlin, Body::Sun).topo.altitudeGeometricRad / kDegE == Approx(-0.8333).margin(0.005));
    CHECK(at(*ev.civilDusk, berlin, Body::Sun).topo.altitudeGeometricRad / kDegE == Approx(-6.0).margin(0.005));
    // Equinox at the equator: all four twilights exist, in order, each a few tens of minutes.
    Site quito{0.0, -78.5 * kDegE, 0.0};
    DayEvents eq = findDayEvents(quito, UtcInstant::parse("2026-03-20T00:00:00Z"), Path::Precise);
    REQUIRE(eq.astronomicalDawn);
    REQUIRE(eq.nauticalDawn);
    REQUIRE(eq.civilDawn);
    REQUIRE(eq.sunrise);
    CHECK(secondsBetween(*eq.astronomicalDawn, *eq.nauticalDawn) == Approx(24 * 60).margin(120));  // 6 deg at 15 deg/h: 24 min
    CHECK(secondsBetween(*eq.nauticalDawn, *eq.civilDawn) == Approx(24 * 60).margin(120));
}

TEST_CASE("Moonrise and moonset include parallax and semi-diameter", "[cpu][astro][events]") {
    Site site{35.0 * kDegE, 139.7 * kDegE, 0.0};
    const UtcInstant start = UtcInstant::parse("2026-06-25T00:00:00Z");
    DayEvents fast = findDayEvents(site, start, Path::Fast);
    DayEvents precise = findDayEvents(site, start, Path::Precise);
    REQUIRE(fast.moonrise);
    REQUIRE(fast.moonset);
    REQUIRE(precise.moonrise);
    // Fast and Precise agree within 5 s (positions agree to < 1"; the Moon rises at ~0.004 deg/s).
    CHECK(std::fabs(secondsBetween(*fast.moonrise, *precise.moonrise)) < 5.0);
    // At moonrise the upper limb is at -34' (standard refraction): topocentric geometric centre
    // altitude = -34' - semi-diameter. The geocentric altitude is about one horizontal parallax
    // (~0.95 deg) higher, which a geocentric computation would get wrong by ~4 minutes.
    BodyState m = at(*fast.moonrise, site, Body::Moon);
    CHECK(m.topo.altitudeGeometricRad / kDegE + 0.5 * m.angularDiameterRad / kDegE == Approx(-34.0 / 60.0).margin(0.006));
}

TEST_CASE("Polar day and polar night", "[cpu][astro][events]") {
    Site tromso{69.65 * kDegE, 18.96 * kDegE, 0.0};
    DayEvents summer = findDayEvents(tromso, UtcInstant::parse("2026-06-21T00:00:00Z"), Path::Fast);
    CHECK(summer.polar == PolarState::Day);
    CHECK_FALSE(summer.sunrise);
    CHECK_FALSE(summer.sunset);
    DayEvents winter = findDayEvents(tromso, UtcInstant::parse("2026-12-21T00:00:00Z"), Path::Fast);
    CHECK(winter.polar == PolarState::Night);
    CHECK_FALSE(winter.sunrise);
    // ... but the Sun comes within 3 deg of the horizon at noon: civil twilight exists.
    CHECK(winter.civilDawn);
    CHECK(winter.civilDusk);
    for (double lon : {-180.0, 180.0}) {
        DayEvents north = findDayEvents(Site{90.0 * kDegE, lon * kDegE, 0.0}, UtcInstant::parse("2026-12-21T00:00:00Z"), Path::Fast);
        CHECK(north.polar == PolarState::Night);
        CHECK_FALSE(north.astronomicalDawn);  // the Sun stays near -23.4 deg
        DayEvents south = findDayEvents(Site{-90.0 * kDegE, lon * kDegE, 0.0}, UtcInstant::parse("2026-12-21T00:00:00Z"), Path::Fast);
        CHECK(south.polar == PolarState::Day);
    }
}

TEST_CASE("Grazing sunrise near the polar circle is found", "[cpu][astro][events]") {
    // Choose the latitude where the Sun's noon geometric altitude on 2026-12-21 exceeds the
    // sunrise altitude by only 0.02 deg: it is up for ~20 minutes, possibly between two
    // 10-minute samples; the extremum search must still find both crossings.
    const UtcInstant noon = UtcInstant::parse("2026-12-21T12:00:00Z");
    const BodyState sun = at(noon, Site{}, Body::Sun);
    const double lat = 90.0 + sun.decRad / kDegE + 0.8333 - 0.02;
    Site site{lat * kDegE, 0.0, 0.0};
    DayEvents ev = findDayEvents(site, UtcInstant::parse("2026-12-21T00:00:00Z"), Path::Fast);
    REQUIRE(ev.sunrise);
    REQUIRE(ev.sunset);
    const double up = secondsBetween(*ev.sunrise, *ev.sunset);
    CHECK(up > 5 * 60);
    CHECK(up < 40 * 60);
    CHECK(ev.polar == PolarState::None);
}

TEST_CASE("Moon quarters: Meeus example 49.a", "[cpu][astro][events]") {
    // New Moon of 1977 February 18: 3h37m42s TD (Meeus; 3h37m40s from ELP-2000/82 in his text).
    // TD - UTC = 48.184 s in 1977: 03:36:52 UTC. Our Sun and Moon are good to 1": 10 s.
    UtcInstant nm = nextMoonQuarter(UtcInstant::parse("1977-02-10T00:00:00Z"), MoonQuarter::New, Path::Fast);
    CHECK(std::fabs(secondsBetween(UtcInstant::parse("1977-02-18T03:36:52Z"), nm)) < 10.0);
    // Quarters follow in order, 6.5 .. 8.5 days apart; a full moon has phase angle ~0.
    const UtcInstant start = UtcInstant::parse("2026-06-01T00:00:00Z");
    UtcInstant fq = nextMoonQuarter(start, MoonQuarter::FirstQuarter, Path::Fast);
    UtcInstant full = nextMoonQuarter(fq, MoonQuarter::Full, Path::Fast);
    UtcInstant lq = nextMoonQuarter(full, MoonQuarter::LastQuarter, Path::Fast);
    for (double gap : {secondsBetween(fq, full), secondsBetween(full, lq)}) {
        CHECK(gap > 6.5 * 86400);
        CHECK(gap < 8.5 * 86400);
    }
    // At full Moon the phase angle is the Moon's ecliptic latitude plus the parallax: < 5.5 deg.
    CHECK(at(full, Site{}, Body::Moon).phaseAngleRad / kDegE < 5.5);
    CHECK(at(fq, Site{}, Body::Moon).illuminatedFraction == Approx(0.5).margin(0.01));
}

TEST_CASE("Events: bad input is an error", "[cpu][astro][events]") {
    CHECK_THROWS_AS(findDayEvents(Site{2.0, 0.0, 0.0}, UtcInstant::parse("2026-06-21T00:00:00Z"), Path::Fast), welkin::Error);
    CHECK_THROWS_WITH(findDayEvents(Site{}, UtcInstant::parse("2026-06-21T00:00:00Z"), Path::Fast, 100.0), Catch::Contains("not in [1, 48]"));
}
