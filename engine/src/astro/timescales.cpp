// Time scales: leap seconds, the 1960-1972 drift formulae, and the Espenak-Meeus Delta T model.
#include <welkin/astro/timescales.hpp>
#include <welkin/error.hpp>

#include <cmath>
#include <cstdio>
#include <iterator>

namespace welkin::astro {

namespace {

constexpr double kMjdZero = 2400000.5;
constexpr double kMjd1960 = 36934.0;   // 1960-01-01
constexpr double kMjd1972 = 41317.0;   // 1972-01-01: start of integral leap seconds
constexpr double kMjd2035 = 64328.0;   // 2035-01-01: end of the leap-second era assumed here
constexpr double kDeltaT2035Leap = 37.0 + kTTMinusTAI;  // TT - UTC with the last known table value

// TAI - UTC changes: (MJD of the UTC day it takes effect, seconds). IERS Bulletin C.
struct Leap {
    double mjd;
    double seconds;
};
constexpr Leap kLeaps[] = {
    {41317, 10}, {41499, 11}, {41683, 12}, {42048, 13}, {42413, 14}, {42778, 15}, {43144, 16},
    {43509, 17}, {43874, 18}, {44239, 19}, {44786, 20}, {45151, 21}, {45516, 22}, {46247, 23},
    {47161, 24}, {47892, 25}, {48257, 26}, {48804, 27}, {49169, 28}, {49534, 29}, {50083, 30},
    {50630, 31}, {51179, 32}, {53736, 33}, {54832, 34}, {56109, 35}, {57204, 36}, {57754, 37},
};

// 1960-1972: TAI - UTC = offset + (MJD - mjdRef) * rate (USNO tai-utc.dat).
struct Drift {
    double mjd, offset, mjdRef, rate;
};
constexpr Drift kDrifts[] = {
    {36934, 1.4178180, 37300, 0.0012960}, {37300, 1.4228180, 37300, 0.0012960},
    {37512, 1.3728180, 37300, 0.0012960}, {37665, 1.8458580, 37665, 0.0011232},
    {38334, 1.9458580, 37665, 0.0011232}, {38395, 3.2401300, 38761, 0.0012960},
    {38486, 3.3401300, 38761, 0.0012960}, {38639, 3.4401300, 38761, 0.0012960},
    {38761, 3.5401300, 38761, 0.0012960}, {38820, 3.6401300, 38761, 0.0012960},
    {38942, 3.7401300, 38761, 0.0012960}, {39004, 3.8401300, 38761, 0.0012960},
    {39126, 4.3131700, 39126, 0.0025920}, {39887, 4.2131700, 39126, 0.0025920},
};

double mjdOf(const JulianDate& jd) { return (jd.day - kMjdZero) + jd.fraction; }

// Leap-second-era Delta T model beyond the table: continue the Espenak-Meeus growth from the
// table's value so that there is no jump at 2035-01-01.
double futureDeltaT(double year) { return kDeltaT2035Leap + (deltaT(year) - deltaT(2035.0)); }

TimeScales fromUtcWithOffset(const JulianDate& utc, double taiMinusUtcSeconds) {
    TimeScales ts;
    ts.utc = utc;
    ts.ut1 = utc;
    ts.taiMinusUtcSeconds = taiMinusUtcSeconds;
    ts.tai = utc.plusDays(taiMinusUtcSeconds / 86400.0);
    ts.tt = ts.tai.plusDays(kTTMinusTAI / 86400.0);
    ts.deltaTSeconds = taiMinusUtcSeconds + kTTMinusTAI;
    return ts;
}

}  // namespace

double decimalYear(const JulianDate& jd) {
    DateTime dt = fromJulianDate(jd);
    JulianDate start = toJulianDate(DateTime{dt.year, 1, 1, 0, 0, 0.0});
    JulianDate next = toJulianDate(DateTime{dt.year + 1, 1, 1, 0, 0, 0.0});
    return dt.year + daysBetween(start, jd) / daysBetween(start, next);
}

double deltaT(double y) {
    // Espenak & Meeus, "Five Millennium Canon of Solar Eclipses" (NASA/TP-2006-214141), section 2.6.
    auto parabola = [](double year) {
        double u = (year - 1820.0) / 100.0;
        return -20.0 + 32.0 * u * u;
    };
    if (!std::isfinite(y)) throw Error("astro::deltaT(): year is not finite");
    if (y < -500.0 || y >= 2150.0) return parabola(y);
    if (y < 500.0) {
        double u = y / 100.0;
        return 10583.6 + u * (-1014.41 + u * (33.78311 + u * (-5.952053 + u * (-0.1798452 + u * (0.022174192 + u * 0.0090316521)))));
    }
    if (y < 1600.0) {
        double u = (y - 1000.0) / 100.0;
        return 1574.2 + u * (-556.01 + u * (71.23472 + u * (0.319781 + u * (-0.8503463 + u * (-0.005050998 + u * 0.0083572073)))));
    }
    if (y < 1700.0) {
        double t = y - 1600.0;
        return 120.0 + t * (-0.9808 + t * (-0.01532 + t / 7129.0));
    }
    if (y < 1800.0) {
        double t = y - 1700.0;
        return 8.83 + t * (0.1603 + t * (-0.0059285 + t * (0.00013336 - t / 1174000.0)));
    }
    if (y < 1860.0) {
        double t = y - 1800.0;
        return 13.72 + t * (-0.332447 + t * (0.0068612 + t * (0.0041116 + t * (-0.00037436 + t * (0.0000121272 + t * (-0.0000001699 + t * 0.000000000875))))));
    }
    if (y < 1900.0) {
        double t = y - 1860.0;
        return 7.62 + t * (0.5737 + t * (-0.251754 + t * (0.01680668 + t * (-0.0004473624 + t / 233174.0))));
    }
    if (y < 1920.0) {
        double t = y - 1900.0;
        return -2.79 + t * (1.494119 + t * (-0.0598939 + t * (0.0061966 - t * 0.000197)));
    }
    if (y < 1941.0) {
        double t = y - 1920.0;
        return 21.20 + t * (0.84493 + t * (-0.076100 + t * 0.0020936));
    }
    if (y < 1961.0) {
        double t = y - 1950.0;
        return 29.07 + t * (0.407 + t * (-1.0 / 233.0 + t / 2547.0));
    }
    if (y < 1986.0) {
        double t = y - 1975.0;
        return 45.45 + t * (1.067 + t * (-1.0 / 260.0 - t / 718.0));
    }
    if (y < 2005.0) {
        double t = y - 2000.0;
        return 63.86 + t * (0.3345 + t * (-0.060374 + t * (0.0017275 + t * (0.000651814 + t * 0.00002373599))));
    }
    if (y < 2050.0) {
        double t = y - 2000.0;
        return 62.92 + t * (0.32217 + t * 0.005589);
    }
    return parabola(y) - 0.5628 * (2150.0 - y);
}

double taiMinusUtc(const JulianDate& jdUtc) {
    double mjd = mjdOf(jdUtc);
    if (mjd < kMjd1960) return 0.0;
    if (mjd < kMjd1972) {
        const Drift* d = kDrifts;
        for (const Drift& e : kDrifts)
            if (mjd >= e.mjd) d = &e;
        return d->offset + (mjd - d->mjdRef) * d->rate;
    }
    double s = kLeaps[0].seconds;
    for (const Leap& e : kLeaps)
        if (mjd >= e.mjd) s = e.seconds;
    return s;
}

namespace {
TimeScales withDut1(TimeScales ts, double dut1) {
    if (!(dut1 >= -1.0 && dut1 <= 1.0)) {
        char buf[120];
        std::snprintf(buf, sizeof buf, "astro::timeScales(): UT1-UTC %g s not in [-1, 1]", dut1);
        throw Error(buf);
    }
    if (dut1 != 0.0) {
        ts.ut1 = ts.ut1.plusDays(dut1 / 86400.0);
        ts.deltaTSeconds -= dut1;
    }
    return ts;
}

TimeScales timeScalesNoDut1(const JulianDate& jdUtcIn) {
    JulianDate utc = jdUtcIn.normalized();
    double mjd = mjdOf(utc);
    if (mjd >= kMjd1960 && mjd < kMjd2035) return fromUtcWithOffset(utc, taiMinusUtc(utc));
    // Outside the tabulated era: UT1 = UTC, TT = UT1 + Delta T(model).
    double year = decimalYear(utc);
    double dT = mjd < kMjd1960 ? deltaT(year) : futureDeltaT(year);
    return fromUtcWithOffset(utc, dT - kTTMinusTAI);
}
}  // namespace

TimeScales timeScales(const JulianDate& jdUtc, double dut1) { return withDut1(timeScalesNoDut1(jdUtc), dut1); }

TimeScales timeScales(const UtcInstant& instant, double dut1) {
    const DateTime& dt = instant.utc();
    if (dt.second >= 60.0) {
        // Inside a leap second: the Julian date of 23:59:60.x already reads as the next day;
        // TAI continues from 23:59:59 with the previous offset.
        DateTime base = dt;
        base.second = 59.0;
        JulianDate jd59 = toJulianDate(base, instant.calendar());
        TimeScales ts = timeScalesNoDut1(jd59);
        double extra = (dt.second - 59.0) / 86400.0;
        ts.utc = instant.julianDate();
        ts.ut1 = jd59.plusDays(extra);  // UT1 does not stop for the leap second
        ts.tai = ts.tai.plusDays(extra);
        ts.tt = ts.tt.plusDays(extra);
        return withDut1(ts, dut1);
    }
    return timeScales(instant.julianDate(), dut1);
}

TimeScales timeScalesFromTT(const JulianDate& jdTTIn, double dut1) {
    JulianDate tt = jdTTIn.normalized();
    // Fixed point on UTC: TT(UTC) is monotonic with slope ~1.
    JulianDate utc = tt.plusDays(-69.184 / 86400.0);
    TimeScales ts{};
    for (int i = 0; i < 6; ++i) {
        ts = timeScales(utc, dut1);
        double err = daysBetween(ts.tt, tt);
        if (std::abs(err) < 1e-12) break;
        utc = utc.plusDays(err);
    }
    return ts;
}

}  // namespace welkin::astro
