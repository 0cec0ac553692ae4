// Civil date and time in UTC, parsed from ISO 8601, and Julian dates held as two doubles.
//
//   auto t = welkin::UtcInstant::parse("2026-06-21T14:30:00+02:00");   // 12:30 UTC
//   welkin::JulianDate jd = t.julianDate();                              // jd.day + jd.fraction
//   std::string iso = t.toIso();                                         // "2026-06-21T12:30:00Z"
//
// Time scales beyond UTC (TAI, TT, UT1, Delta T) live in <welkin/astro/timescales.hpp>.
#pragma once
#include <string>
#include <string_view>

namespace welkin {

/// Calendar used to read and write civil dates. Gregorian is proleptic (extended before
/// 1582-10-15); Julian is accepted on request for historical dates.
enum class Calendar { Gregorian, Julian };

/// A Julian date split into two doubles for precision: value = day + fraction.
/// `day` is a whole number + 0.5 (the preceding midnight), `fraction` in [0, 1) days.
struct JulianDate {
    double day = 2451544.5;  ///< days (midnight-based), e.g. 2451544.5 = 2000-01-01T00:00
    double fraction = 0.0;   ///< days, [0, 1)
    double value() const { return day + fraction; }
    /// Normalise so that `fraction` is in [0, 1) and `day` ends in .5.
    JulianDate normalized() const;
    /// This date plus `days` (may be negative), normalised.
    JulianDate plusDays(double days) const;
};

/// Days between two Julian dates (b - a), computed without losing precision.
double daysBetween(const JulianDate& a, const JulianDate& b);

/// Broken-down civil date-time. Years use astronomical numbering (year 0 = 1 BC, -2000 = 2001 BC).
struct DateTime {
    int year = 2000;      ///< [-4000, 10000]
    int month = 1;        ///< [1, 12]
    int day = 1;          ///< [1, days in month]
    int hour = 0;         ///< [0, 23]
    int minute = 0;       ///< [0, 59]
    double second = 0.0;  ///< [0, 61): 60.x only during a leap second
};

/// True if `year` is a leap year in `calendar`.
bool isLeapYear(int year, Calendar calendar = Calendar::Gregorian);
/// Days in `month` (1..12) of `year`.
int daysInMonth(int year, int month, Calendar calendar = Calendar::Gregorian);

/// Julian date of a calendar date-time (no validation; see UtcInstant for validated input).
JulianDate toJulianDate(const DateTime& dt, Calendar calendar = Calendar::Gregorian);
/// Calendar date-time of a Julian date (seconds rounded to the microsecond).
DateTime fromJulianDate(const JulianDate& jd, Calendar calendar = Calendar::Gregorian);

/// An instant on the UTC time scale (UT1 is approximated by UTC here; see astro/timescales).
class UtcInstant {
public:
    UtcInstant() = default;
    /// Validates the fields (throws welkin::Error naming the field and range, e.g. "time: day 30
    /// not in [1, 28] for 2026-02").
    static UtcInstant fromDateTime(const DateTime& utc, Calendar calendar = Calendar::Gregorian);
    static UtcInstant fromJulianDate(const JulianDate& jdUtc);

    /// Parses ISO 8601: `YYYY-MM-DD[THH:MM[:SS[.fff]]][Z|±HH[:MM]]`; a leading sign on the year
    /// allows negative years (`-2000-03-21T06:00:00Z`). No offset means UTC. Throws welkin::Error
    /// with a one-line message naming what is wrong.
    static UtcInstant parse(std::string_view iso, Calendar calendar = Calendar::Gregorian);

    const DateTime& utc() const { return utc_; }
    Calendar calendar() const { return calendar_; }
    /// Julian date on the UTC scale (days).
    JulianDate julianDate() const { return jd_; }
    /// ISO 8601 in UTC with a trailing Z; milliseconds shown only when non-zero.
    std::string toIso() const;
    /// This instant plus `seconds` (finite, may be negative); throws welkin::Error if the result
    /// leaves the supported years [-4000, 10000].
    UtcInstant plusSeconds(double seconds) const;

private:
    DateTime utc_{};
    Calendar calendar_ = Calendar::Gregorian;
    JulianDate jd_{};
};

}  // namespace welkin
