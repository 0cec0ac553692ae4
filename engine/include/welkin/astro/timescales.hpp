// Time scales: UTC -> TAI -> TT, UT1, and Delta T (= TT - UT1).
//
//   auto t  = welkin::UtcInstant::parse("2026-06-21T12:30:00Z");
//   welkin::astro::TimeScales ts = welkin::astro::timeScales(t);
//   double T = ts.centuriesTT();          // Julian centuries of TT since J2000.0
//   double dT = ts.deltaTSeconds;         // 69.184 s in 2026
//
// Model (see docs/astronomy-time-and-frames.md):
// - 1972-01-01 .. 2035-01-01 (the leap-second era): TAI - UTC from the leap-second table
//   (10 s in 1972 .. 37 s since 2017-01-01), TT = TAI + 32.184 s, and UT1 = UTC: |UT1 - UTC| is
//   kept below 0.9 s by the IERS, which is the documented error of this approximation.
// - 1960-01-01 .. 1972-01-01: TAI - UTC from the published drift formulae (UTC then ran at an
//   offset rate); UT1 = UTC (within 0.1 s by construction).
// - Before 1960: the civil time given is read as UT (= UT1), and TT = UT1 + Delta T with
//   Delta T from the Espenak-Meeus polynomials (-1999 .. +3000) and the long-term parabola
//   -20 + 32 u^2 s, u = (year - 1820) / 100, beyond them.
// - From 2035-01-01 (no leap-second table; leap seconds are to be abandoned by 2035): UT1 = UTC
//   is kept and Delta T = 69.184 s + [model(year) - model(2035.0)], i.e. the model's growth is
//   continued from today's value without a jump.
// In every era UT1 = UTC + DUT1 with DUT1 = 0 unless given ("civil time tracks the Earth's
// rotation"); `deltaTSeconds` and `taiMinusUtcSeconds` report what the model implies.
#pragma once
#include <welkin/time.hpp>

namespace welkin::astro {

/// Which implementation to use: Fast (analytic series, allocation-free, microseconds) or Precise
/// (ERFA: IAU 2006/2000A, eraEpv00, ...). Both have the same interface; accuracies are measured
/// in tests/astro and documented in docs/astronomy-time-and-frames.md.
enum class Path { Fast, Precise };

/// TT - TAI, seconds (exact by definition).
inline constexpr double kTTMinusTAI = 32.184;
/// Julian date of J2000.0 (2000-01-01T12:00 TT).
inline constexpr double kJ2000 = 2451545.0;
/// Days per Julian century.
inline constexpr double kDaysPerCentury = 36525.0;

/// One instant on the time scales astronomy needs. All Julian dates are two-double, normalised.
struct TimeScales {
    JulianDate utc;                   ///< Coordinated Universal Time
    JulianDate tai;                   ///< International Atomic Time
    JulianDate tt;                    ///< Terrestrial Time (also used for TDB: |TDB - TT| < 2 ms)
    JulianDate ut1;                   ///< Universal Time (Earth rotation)
    double deltaTSeconds = 0;         ///< TT - UT1, seconds
    double taiMinusUtcSeconds = 0;    ///< TAI - UTC, seconds

    /// Julian centuries of TT since J2000.0.
    double centuriesTT() const { return ((tt.day - kJ2000) + tt.fraction) / kDaysPerCentury; }
    /// Days of UT1 since J2000.0 (2000-01-01T12:00 UT1).
    double daysUT1() const { return (ut1.day - kJ2000) + ut1.fraction; }
    /// Julian years of TT since J2000.0 (for proper motion).
    double yearsTT() const { return centuriesTT() * 100.0; }
};

/// The time scales at a UTC instant (model above). `ut1MinusUtcSeconds` (DUT1, IERS Bulletin A,
/// [-1, 1] s) is 0 by default, which is the documented approximation UT1 = UTC (error < 0.9 s,
/// i.e. up to 13.5" of Earth rotation); give it when arc-second sidereal time matters. Throws
/// welkin::Error only for DUT1 outside [-1, 1] s or not finite.
TimeScales timeScales(const UtcInstant& utc, double ut1MinusUtcSeconds = 0.0);
/// The same from a Julian date on the UTC scale.
TimeScales timeScales(const JulianDate& jdUtc, double ut1MinusUtcSeconds = 0.0);
/// The time scales at a TT Julian date (inverse of the model above; exact to < 1 microsecond).
TimeScales timeScalesFromTT(const JulianDate& jdTT, double ut1MinusUtcSeconds = 0.0);

/// Delta T = TT - UT1 in seconds from the Espenak-Meeus polynomials (NASA Five Millennium Canon)
/// for years -1999 .. +3000 and -20 + 32 u^2, u = (year - 1820) / 100, outside them. Pure model:
/// it does not use the leap-second table. `decimalYear` e.g. 2026.47; any finite value.
double deltaT(double decimalYear);

/// TAI - UTC in seconds at a UTC Julian date: the leap-second table from 1972, the drift formulae
/// 1960 .. 1972; 0 before 1960 (UTC undefined; see timeScales for what is used instead); 37 s
/// after the last leap second (2017-01-01).
double taiMinusUtc(const JulianDate& jdUtc);

/// Decimal (Julian-calendar-length) year of a Julian date: 2000.0 + (jd - 2451544.5) / 365.25 is
/// NOT used; this is the calendar year plus the elapsed fraction of it (Gregorian), e.g. 2026.47.
double decimalYear(const JulianDate& jd);

}  // namespace welkin::astro
