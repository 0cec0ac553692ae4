// Civil time parsing and Julian dates.
#include <catch2/catch.hpp>

#include <welkin/error.hpp>
#include <welkin/time.hpp>

using namespace welkin;

TEST_CASE("Julian dates of known instants", "[cpu][time]") {
    // Meeus, Astronomical Algorithms, ex. 7.a: 1957 October 4.81 = JD 2436116.31.
    JulianDate jd = toJulianDate({1957, 10, 4, 19, 26, 24.0});
    CHECK(jd.value() == Approx(2436116.31).margin(1e-9));
    // J2000.0: 2000-01-01T12:00 TT is JD 2451545.0 (same formula on any scale).
    CHECK(toJulianDate({2000, 1, 1, 12, 0, 0.0}).value() == 2451545.0);
    // Meeus ex. 7.b: 333 January 27.5 in the Julian calendar = JD 1842713.0.
    CHECK(toJulianDate({333, 1, 27, 12, 0, 0.0}, Calendar::Julian).value() == 1842713.0);
    // Meeus: -1000 July 12.5 (Julian) = 1356001.0 and -4712 January 1.5 (Julian) = 0.0.
    CHECK(toJulianDate({-1000, 7, 12, 12, 0, 0.0}, Calendar::Julian).value() == 1356001.0);
    CHECK(toJulianDate({-4712, 1, 1, 12, 0, 0.0}, Calendar::Julian).value() == 0.0);
    // The Gregorian reform: 1582-10-15 (Gregorian) follows 1582-10-04 (Julian).
    CHECK(toJulianDate({1582, 10, 15, 0, 0, 0.0}).value() - toJulianDate({1582, 10, 4, 0, 0, 0.0}, Calendar::Julian).value() == 1.0);
}

TEST_CASE("Julian date round trip over 8000 years", "[cpu][time]") {
    for (int year = -2000; year <= 6000; year += 37) {
        for (Calendar cal : {Calendar::Gregorian, Calendar::Julian}) {
            DateTime dt{year, 2 + (year & 7), 1 + (year & 15), 13, 47, 12.25};
            DateTime back = fromJulianDate(toJulianDate(dt, cal), cal);
            CHECK(back.year == dt.year);
            CHECK(back.month == dt.month);
            CHECK(back.day == dt.day);
            CHECK(back.hour == dt.hour);
            CHECK(back.minute == dt.minute);
            // Two-double Julian dates keep ~1e-10 day: the microsecond rounding dominates.
            CHECK(back.second == Approx(dt.second).margin(2e-6));
        }
    }
}

TEST_CASE("ISO 8601 parsing with offsets", "[cpu][time]") {
    UtcInstant t = UtcInstant::parse("2026-06-21T14:30:00+02:00");
    CHECK(t.toIso() == "2026-06-21T12:30:00Z");
    CHECK(UtcInstant::parse("2026-01-01T00:30:00+01:00").toIso() == "2025-12-31T23:30:00Z");
    CHECK(UtcInstant::parse("2026-06-21T12:00:00.250Z").toIso() == "2026-06-21T12:00:00.250Z");
    CHECK(UtcInstant::parse("2026-06-21T12:00Z").toIso() == "2026-06-21T12:00:00Z");
    CHECK(UtcInstant::parse("2026-06-21").toIso() == "2026-06-21T00:00:00Z");
    CHECK(UtcInstant::parse("-2000-03-21T06:00:00Z").utc().year == -2000);
    CHECK(UtcInstant::parse("2024-02-29T00:00:00Z").utc().day == 29);
    CHECK(UtcInstant::parse("2016-12-31T23:59:60Z").utc().second == 60.0);  // a leap second
    // Offsets shift the Julian date by exactly offset/1440 days.
    double dz = daysBetween(UtcInstant::parse("2026-03-01T05:00:00-05:30").julianDate(),
                            UtcInstant::parse("2026-03-01T10:30:00Z").julianDate());
    CHECK(std::abs(dz) < 1e-9);
}

TEST_CASE("Impossible dates and malformed strings are errors", "[cpu][time]") {
    CHECK_THROWS_WITH(UtcInstant::parse("2026-02-30T00:00:00Z"), Catch::Contains("day 30 not in [1, 28]"));
    CHECK_THROWS_WITH(UtcInstant::parse("2025-02-29T00:00:00Z"), Catch::Contains("day 29 not in [1, 28]"));
    CHECK_THROWS_WITH(UtcInstant::parse("2026-06-21T25:00:00Z"), Catch::Contains("hour 25 not in [0, 23]"));
    CHECK_THROWS_WITH(UtcInstant::parse("2026-13-01T00:00:00Z"), Catch::Contains("month 13"));
    CHECK_THROWS_WITH(UtcInstant::parse("2026-06-21T12:61:00Z"), Catch::Contains("minute 61"));
    CHECK_THROWS_WITH(UtcInstant::parse("yesterday"), Catch::Contains("not ISO 8601"));
    CHECK_THROWS_WITH(UtcInstant::parse("2026-06-21T12:00:00Q"), Catch::Contains("not ISO 8601"));
    CHECK_THROWS_WITH(UtcInstant::parse("2026-06-21T12:00:00+25:00"), Catch::Contains("offset hours 25"));
    CHECK_THROWS_AS(UtcInstant::parse(""), Error);
    // 1900 is not a leap year in the Gregorian calendar, but is in the Julian one.
    CHECK_THROWS(UtcInstant::parse("1900-02-29"));
    CHECK_NOTHROW(UtcInstant::parse("1900-02-29", Calendar::Julian));
}

TEST_CASE("The supported span and leap-second placement are enforced", "[cpu][time]") {
    // The span's ends are the Julian dates of -4000-01-01 and 10001-01-01 (Gregorian).
    CHECK(toJulianDate({-4000, 1, 1, 0, 0, 0.0}).value() == 260089.5);
    CHECK(toJulianDate({10001, 1, 1, 0, 0, 0.0}).value() == 5373850.5);
    auto t = UtcInstant::parse("2026-06-21T12:00:00Z");
    CHECK_THROWS_WITH(t.plusSeconds(1e300), Catch::Contains("outside the supported years"));
    CHECK_THROWS_WITH(t.plusSeconds(std::nan("")), Catch::Contains("finite"));
    CHECK(t.plusSeconds(86400.0 * 365).utc().year == 2027);
    CHECK_THROWS_WITH(UtcInstant::parse("2026-06-21T12:30:60Z"), Catch::Contains("second 60"));
    CHECK_THROWS_WITH(UtcInstant::parse("2026-06-21T12:30:00+05:"), Catch::Contains("not ISO 8601"));
    CHECK_THROWS_WITH(UtcInstant::parse("10000-12-31T23:00:00-05:00"), Catch::Contains("UTC year 10001"));
}
