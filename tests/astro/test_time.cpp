// Time scales: Julian dates (Meeus ch. 7), leap seconds against ERFA eraDat, Delta T model.
#include <welkin/astro/timescales.hpp>
#include <welkin/error.hpp>

#include <catch2/catch.hpp>
#include <erfa.h>

#include <cmath>
#include <random>

using namespace welkin;
using namespace welkin::astro;

TEST_CASE("Julian day: Meeus examples 7.a and 7.b", "[cpu][astro]") {
    // Meeus, Astronomical Algorithms (2nd ed.), ex. 7.a: 1957 October 4.81 = JD 2436116.31.
    DateTime sputnik{1957, 10, 4, 19, 26, 24.0};  // 0.81 d = 19:26:24
    CHECK(toJulianDate(sputnik).value() == Approx(2436116.31).margin(1e-9));
    // Ex. 7.b: 333 January 27.5 (Julian calendar) = JD 1842713.0.
    DateTime d333{333, 1, 27, 12, 0, 0.0};
    CHECK(toJulianDate(d333, Calendar::Julian).value() == Approx(1842713.0).margin(1e-9));
}

TEST_CASE("TAI-UTC agrees with ERFA eraDat 1960-2030", "[cpu][astro]") {
    std::mt19937_64 rng(7);
    std::uniform_real_distribution<double> mjd(36934.0, 62502.0);  // 1960-01-01 .. 2030-01-01
    int n = 0;
    for (int i = 0; i < 2000; ++i) {
        JulianDate jd{2400000.5 + std::floor(mjd(rng)), 0.0};
        jd.fraction = std::uniform_real_distribution<double>(0.0, 0.999)(rng);
        DateTime dt = fromJulianDate(jd);
        double fd = jd.fraction, dat = 0;
        REQUIRE(eraDat(dt.year, dt.month, dt.day, fd, &dat) >= 0);
        // eraDat's drift formula reads the MJD at the given fraction, as ours does: the same
        // numbers to rounding (1e-9 s).
        CHECK(taiMinusUtc(jd) == Approx(dat).margin(1e-9));
        TimeScales ts = timeScales(jd);
        CHECK(ts.taiMinusUtcSeconds == Approx(dat).margin(1e-9));
        CHECK(daysBetween(ts.utc, ts.tt) * 86400.0 == Approx(dat + 32.184).margin(1e-5));  // 1e-5 s: day-fraction rounding
        ++n;
    }
    CHECK(n == 2000);
}

TEST_CASE("Time scales: today, a leap second, round trip from TT", "[cpu][astro]") {
    TimeScales ts = timeScales(UtcInstant::parse("2026-06-21T12:00:00Z"));
    CHECK(ts.deltaTSeconds == Approx(69.184).margin(1e-9));  // 37 leap seconds + 32.184 s
    CHECK(daysBetween(ts.utc, ts.ut1) == 0.0);                  // UT1 = UTC in the leap-second era
    CHECK(daysBetween(ts.utc, ts.tt) * 86400.0 == Approx(69.184).margin(1e-6));

    // 2016-12-31T23:59:60.5Z: TAI-UTC was 36 s until the end of the leap second, so TAI =
    // 2017-01-01T00:00:36.5 (IERS Bulletin C 52).
    TimeScales leap = timeScales(UtcInstant::parse("2016-12-31T23:59:60.5Z"));
    JulianDate expectTai = toJulianDate(DateTime{2017, 1, 1, 0, 0, 36.5});
    CHECK(std::abs(daysBetween(leap.tai, expectTai)) * 86400.0 < 1e-5);
    // One second later the table says 37 s and TAI = 00:00:37.5: continuous through the leap.
    TimeScales after = timeScales(UtcInstant::parse("2017-01-01T00:00:00.5Z"));
    CHECK(daysBetween(leap.tai, after.tai) * 86400.0 == Approx(1.0).margin(1e-5));

    // DUT1 moves UT1 only: Delta T = TT - UT1 drops by it.
    TimeScales d = timeScales(UtcInstant::parse("2026-06-21T12:00:00Z"), 0.25);
    CHECK(daysBetween(d.utc, d.ut1) * 86400.0 == Approx(0.25).margin(1e-6));
    CHECK(d.deltaTSeconds == Approx(69.184 - 0.25).margin(1e-9));
    CHECK(daysBetween(d.tt, ts.tt) == 0.0);
    CHECK_THROWS_AS(timeScales(UtcInstant::parse("2026-06-21T12:00:00Z"), 1.5), Error);

    std::mt19937_64 rng(11);
    std::uniform_real_distribution<double> jd(toJulianDate(DateTime{-2000, 1, 1}).value(), toJulianDate(DateTime{6000, 1, 1}).value());
    for (int i = 0; i < 300; ++i) {
        JulianDate utc = JulianDate{std::floor(jd(rng)) + 0.5, 0.37}.normalized();
        TimeScales a = timeScales(utc);
        TimeScales b = timeScalesFromTT(a.tt);
        CHECK(std::abs(daysBetween(a.utc, b.utc)) * 86400.0 < 1e-6);  // round trip < 1 us
        CHECK(std::isfinite(a.deltaTSeconds));
    }
}

TEST_CASE("Delta T: Espenak-Meeus model against observed values and its own continuity", "[cpu][astro]") {
    // Observed Delta T (Morrison & Stephenson 2004; IERS): the polynomials fit them within ~1 s.
    CHECK(deltaT(1900.0) == Approx(-2.7).margin(1.0));
    CHECK(deltaT(1950.0) == Approx(29.1).margin(1.0));
    CHECK(deltaT(1980.0) == Approx(50.5).margin(1.0));
    CHECK(deltaT(2000.0) == Approx(63.8).margin(1.0));
    // Historical estimates (Five Millennium Canon table): year 1000: 1570 s, year 0: 10580 s,
    // -500: 17190 s; the polynomials reproduce their own table within 20 s.
    CHECK(deltaT(1000.0) == Approx(1570.0).margin(20.0));
    CHECK(deltaT(0.0) == Approx(10580.0).margin(20.0));
    CHECK(deltaT(-500.0) == Approx(17190.0).margin(20.0));
    // Long-term parabola outside -500 .. 2150.
    CHECK(deltaT(-2000.0) == Approx(-20.0 + 32.0 * std::pow((-2000.0 - 1820.0) / 100.0, 2)).epsilon(1e-12));
    CHECK(deltaT(6000.0) == Approx(-20.0 + 32.0 * std::pow((6000.0 - 1820.0) / 100.0, 2)).epsilon(1e-12));
    // The pieces join within 2 s at every boundary (their published continuity).
    for (double y : {-500.0, 500.0, 1600.0, 1700.0, 1800.0, 1860.0, 1900.0, 1920.0, 1941.0, 1961.0, 1986.0, 2005.0, 2050.0, 2150.0})
        CHECK(std::abs(deltaT(y - 1e-9) - deltaT(y)) < 2.0);
    CHECK_THROWS_AS(deltaT(std::nan("")), Error);

    // The time scales join the model without a jump at the ends of the tabulated era.
    auto dT = [](int y, int m, int d) { return timeScales(toJulianDate(DateTime{y, m, d})).deltaTSeconds; };
    CHECK(std::abs(dT(1960, 1, 1) - timeScales(toJulianDate(DateTime{1959, 12, 31, 23, 59, 59.0})).deltaTSeconds) < 0.1);
    CHECK(std::abs(dT(2035, 1, 1) - timeScales(toJulianDate(DateTime{2034, 12, 31, 23, 59, 59.0})).deltaTSeconds) < 1e-3);
    CHECK(dT(2100, 1, 1) > 69.184);  // the model keeps growing after 2035
}
