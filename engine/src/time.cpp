#include <welkin/error.hpp>
#include <welkin/time.hpp>

#include <charconv>
#include <cstdlib>
#include <cmath>
#include <cstdio>

namespace welkin {

JulianDate JulianDate::normalized() const {
    // Bring `day` onto a .5 boundary and `fraction` into [0, 1).
    double whole = std::floor(day - 0.5);
    double f = (day - 0.5 - whole) + fraction;
    double carry = std::floor(f);
    return {whole + carry + 0.5, f - carry};
}

JulianDate JulianDate::plusDays(double days) const { return JulianDate{day, fraction + days}.normalized(); }

double daysBetween(const JulianDate& a, const JulianDate& b) { return (b.day - a.day) + (b.fraction - a.fraction); }

bool isLeapYear(int year, Calendar calendar) {
    if (calendar == Calendar::Julian) return year % 4 == 0;  // also right for negative years
    return (year % 4 == 0 && year % 100 != 0) || year % 400 == 0;
}

int daysInMonth(int year, int month, Calendar calendar) {
    static constexpr int kDays[12] = {31, 28, 31, 30, 31, 30, 31, 31, 30, 31, 30, 31};
    if (month < 1 || month > 12) return 0;
    return month == 2 && isLeapYear(year, calendar) ? 29 : kDays[month - 1];
}

namespace {
// Day number (JD at noon) of a calendar date; integer arithmetic valid for negative years
// (Fliegel & van Flandern style with floor division).
long long floorDiv(long long a, long long b) { return a / b - ((a % b != 0) && ((a < 0) != (b < 0))); }

long long julianDayNumber(int year, int month, int day, Calendar calendar) {
    long long a = floorDiv(14 - month, 12);
    long long y = (long long)year + 4800 - a;
    long long m = month + 12 * a - 3;
    if (calendar == Calendar::Gregorian)
        return day + floorDiv(153 * m + 2, 5) + 365 * y + floorDiv(y, 4) - floorDiv(y, 100) + floorDiv(y, 400) - 32045;
    return day + floorDiv(153 * m + 2, 5) + 365 * y + floorDiv(y, 4) - 32083;
}

void civilFromDayNumber(long long jdn, Calendar calendar, int& year, int& month, int& day) {
    long long b, c;
    if (calendar == Calendar::Gregorian) {
        long long a = jdn + 32044;
        b = floorDiv(4 * a + 3, 146097);
        c = a - floorDiv(146097 * b, 4);
    } else {
        b = 0;
        c = jdn + 32082;
    }
    long long d = floorDiv(4 * c + 3, 1461);
    long long e = c - floorDiv(1461 * d, 4);
    long long m = floorDiv(5 * e + 2, 153);
    day = int(e - floorDiv(153 * m + 2, 5) + 1);
    month = int(m + 3 - 12 * floorDiv(m, 10));
    year = int(100 * b + d - 4800 + floorDiv(m, 10));
}
}  // namespace

JulianDate toJulianDate(const DateTime& dt, Calendar calendar) {
    long long jdn = julianDayNumber(dt.year, dt.month, dt.day, calendar);
    double frac = (dt.hour * 3600.0 + dt.minute * 60.0 + dt.second) / 86400.0;
    return JulianDate{double(jdn) - 0.5, frac}.normalized();
}

DateTime fromJulianDate(const JulianDate& jdIn, Calendar calendar) {
    JulianDate jd = jdIn.normalized();
    // Round to the microsecond first so that 59.9999999 s does not print as 60.
    double micros = std::round(jd.fraction * 86400e6);
    long long jdn = (long long)(jd.day + 0.5);
    if (micros >= 86400e6) {
        micros -= 86400e6;
        ++jdn;
    }
    DateTime dt;
    civilFromDayNumber(jdn, calendar, dt.year, dt.month, dt.day);
    double s = micros / 1e6;
    dt.hour = int(s / 3600.0);
    s -= dt.hour * 3600.0;
    dt.minute = int(s / 60.0);
    dt.second = s - dt.minute * 60.0;
    return dt;
}

namespace {
[[noreturn]] void fail(std::string_view iso, const std::string& what) {
    throw Error("'" + std::string(iso) + "': " + what);
}
void checkRange(std::string_view iso, const char* field, double v, double lo, double hi, const std::string& extra = {}) {
    if (!(v >= lo && v <= hi)) {
        char buf[160];
        std::snprintf(buf, sizeof buf, "%s %g not in [%g, %g]%s", field, v, lo, hi, extra.c_str());
        fail(iso, buf);
    }
}
void validate(std::string_view iso, const DateTime& dt, Calendar calendar) {
    checkRange(iso, "year", dt.year, -4000, 10000);
    checkRange(iso, "month", dt.month, 1, 12);
    char ym[40];
    std::snprintf(ym, sizeof ym, " for %04d-%02d", dt.year, dt.month);
    checkRange(iso, "day", dt.day, 1, daysInMonth(dt.year, dt.month, calendar), ym);
    checkRange(iso, "hour", dt.hour, 0, 23);
    checkRange(iso, "minute", dt.minute, 0, 59);
    if (!(dt.second >= 0.0 && dt.second < 61.0)) checkRange(iso, "second", dt.second, 0, 60.999);
    // A leap second (60.x) can only end a UTC day (at 23:59 UTC; with an offset, the local
    // minute that corresponds to it).
    if (dt.second >= 60.0 && dt.minute != 59) checkRange(iso, "second", dt.second, 0, 59.999);
}
}  // namespace

UtcInstant UtcInstant::fromDateTime(const DateTime& utc, Calendar calendar) {
    validate("(fields)", utc, calendar);
    UtcInstant t;
    t.utc_ = utc;
    t.calendar_ = calendar;
    t.jd_ = toJulianDate(utc, calendar);
    return t;
}

namespace {
// Julian dates of -4000-01-01 and 10001-01-01 (Gregorian): the supported span.
constexpr double kMinJd = 260089.5, kMaxJd = 5373850.5;
void checkJd(const JulianDate& jd, const char* where) {
    double v = jd.day + jd.fraction;
    if (!std::isfinite(v) || v < kMinJd || v >= kMaxJd) {
        char buf[160];
        std::snprintf(buf, sizeof buf, "%s: Julian date %.10g outside the supported years [-4000, 10000]", where, v);
        throw Error(buf);
    }
}
}  // namespace

UtcInstant UtcInstant::fromJulianDate(const JulianDate& jdUtc) {
    checkJd(jdUtc, "UtcInstant::fromJulianDate()");
    UtcInstant t;
    t.jd_ = jdUtc.normalized();
    t.utc_ = welkin::fromJulianDate(t.jd_, Calendar::Gregorian);
    return t;
}

UtcInstant UtcInstant::parse(std::string_view iso, Calendar calendar) {
    const char* const expected = "is not ISO 8601 (expected YYYY-MM-DDTHH:MM:SS[.fff][Z|+HH:MM])";
    size_t pos = 0;
    auto digits = [&](int count, int& out) {
        if (pos + count > iso.size()) fail(iso, expected);
        for (int i = 0; i < count; ++i)
            if (iso[pos + i] < '0' || iso[pos + i] > '9') fail(iso, expected);
        std::from_chars(iso.data() + pos, iso.data() + pos + count, out);
        pos += count;
    };
    auto expect = [&](char c) {
        if (pos >= iso.size() || iso[pos] != c) fail(iso, expected);
        ++pos;
    };
    DateTime dt;
    int sign = 1;
    if (pos < iso.size() && (iso[pos] == '-' || iso[pos] == '+')) sign = iso[pos++] == '-' ? -1 : 1;
    // Year: 4 or more digits.
    size_t yEnd = pos;
    while (yEnd < iso.size() && iso[yEnd] >= '0' && iso[yEnd] <= '9') ++yEnd;
    if (yEnd - pos < 4 || yEnd - pos > 5) fail(iso, expected);
    digits(int(yEnd - pos), dt.year);
    dt.year *= sign;
    expect('-');
    digits(2, dt.month);
    expect('-');
    digits(2, dt.day);
    int offsetMinutes = 0;
    if (pos < iso.size()) {
        if (iso[pos] != 'T' && iso[pos] != 't' && iso[pos] != ' ') fail(iso, expected);
        ++pos;
        digits(2, dt.hour);
        expect(':');
        digits(2, dt.minute);
        if (pos < iso.size() && iso[pos] == ':') {
            ++pos;
            int s = 0;
            digits(2, s);
            dt.second = s;
            if (pos < iso.size() && (iso[pos] == '.' || iso[pos] == ',')) {
                ++pos;
                double scale = 0.1;
                size_t start = pos;
                while (pos < iso.size() && iso[pos] >= '0' && iso[pos] <= '9') {
                    dt.second += (iso[pos] - '0') * scale;
                    scale *= 0.1;
                    ++pos;
                }
                if (pos == start) fail(iso, expected);
            }
        }
        if (pos < iso.size()) {
            char c = iso[pos];
            if (c == 'Z' || c == 'z') {
                ++pos;
            } else if (c == '+' || c == '-') {
                ++pos;
                int oh = 0, om = 0;
                digits(2, oh);
                if (pos < iso.size() && iso[pos] == ':') {
                    ++pos;
                    digits(2, om);  // "+05:" with nothing after the colon is malformed
                } else if (pos < iso.size()) {
                    digits(2, om);
                }
                checkRange(iso, "UTC offset hours", oh, 0, 18);
                checkRange(iso, "UTC offset minutes", om, 0, 59);
                offsetMinutes = (c == '-' ? -1 : 1) * (oh * 60 + om);
            } else {
                fail(iso, expected);
            }
        }
        if (pos != iso.size()) fail(iso, expected);
    }
    validate(iso, dt, calendar);
    UtcInstant t;
    t.calendar_ = calendar;
    JulianDate local = toJulianDate(dt, calendar);
    if (offsetMinutes == 0) {
        t.utc_ = dt;
        t.jd_ = local;
    } else {
        t.jd_ = local.plusDays(-offsetMinutes / 1440.0);
        t.utc_ = welkin::fromJulianDate(t.jd_, calendar);
        checkRange(iso, "UTC year", t.utc_.year, -4000, 10000);
    }
    return t;
}

std::string UtcInstant::toIso() const {
    // Digits written by hand, not snprintf: the processor publishes time.iso every frame while
    // time runs, and snprintf's format parsing was ~5,000 instructions of the framework's frame
    // (docs/hardening.md). Same text: [-]YYYY-MM-DDThh:mm:ss[.mmm]Z, the year at least 4 digits.
    const DateTime& d = utc_;
    int whole = int(std::floor(d.second));
    int millis = int(std::lround((d.second - whole) * 1000.0));
    if (millis == 1000) millis = 999;  // never print 60.000 for 59.9996
    std::string out;
    out.reserve(32);
    auto put = [&out](long long v, int width) {
        char digits[24];
        int n = 0;
        do {
            digits[n++] = char('0' + v % 10);
            v /= 10;
        } while (v > 0);
        while (n < width) digits[n++] = '0';
        while (n > 0) out.push_back(digits[--n]);
    };
    if (d.year < 0) out.push_back('-');
    put(std::llabs(d.year), 4);
    out.push_back('-');
    put(d.month, 2);
    out.push_back('-');
    put(d.day, 2);
    out.push_back('T');
    put(d.hour, 2);
    out.push_back(':');
    put(d.minute, 2);
    out.push_back(':');
    put(whole, 2);
    if (millis) {
        out.push_back('.');
        put(millis, 3);
    }
    out.push_back('Z');
    return out;
}

UtcInstant UtcInstant::plusSeconds(double seconds) const {
    if (!std::isfinite(seconds)) throw Error("UtcInstant::plusSeconds(): seconds must be finite");
    UtcInstant t;
    t.calendar_ = calendar_;
    t.jd_ = jd_.plusDays(seconds / 86400.0);
    checkJd(t.jd_, "UtcInstant::plusSeconds()");
    t.utc_ = welkin::fromJulianDate(t.jd_, calendar_);
    return t;
}

}  // namespace welkin
