#include "heritage.hpp"

#include <welkin/astro/bodies.hpp>
#include <welkin/astro/events.hpp>
#include <welkin/error.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>

namespace welkin::heritage {

namespace {
constexpr double kDeg = std::numbers::pi / 180.0;
constexpr double kRiseSetAltitudeDeg = -0.8333;  // the Sun's centre when its upper limb is on the horizon
constexpr astro::Path kPath = astro::Path::Fast; // the sky's default path (astro.precise = false)

UtcInstant midnightUtc(const Date& d) { return UtcInstant::fromDateTime({d.year, d.month, d.day, 0, 0, 0.0}); }

// Local mean midnight of the site's day `d`: UTC midnight minus longitude / 15 deg hours.
UtcInstant localMidnight(const astro::Site& site, const Date& d) {
    return midnightUtc(d).plusSeconds(-site.longitudeRad / kDeg / 15.0 * 3600.0);
}

astro::BodyState sunState(const astro::Site& site, const UtcInstant& t) {
    return astro::computeBody(astro::Body::Sun, astro::observerFrame(site, astro::timeScales(t), kPath));
}

double wrap360(double deg) {
    deg = std::fmod(deg, 360.0);
    return deg < 0 ? deg + 360.0 : deg;
}
}  // namespace

// ------------------------------------------------------------------ dates

std::string Date::iso() const {
    char b[32];
    std::snprintf(b, sizeof b, "%04d-%02d-%02d", year, month, day);
    return b;
}

Date parseDate(const std::string& text) {
    int y = 0, m = 0, d = 0;
    char tail = 0;
    const std::string what = "--date '" + text + "' must be a date YYYY-MM-DD with the year in [1000, 3000]";
    if (text.size() != 10 || std::sscanf(text.c_str(), "%4d-%2d-%2d%c", &y, &m, &d, &tail) != 3 || text[4] != '-' || text[7] != '-')
        throw Error(what);
    if (y < 1000 || y > 3000 || m < 1 || m > 12 || d < 1 || d > daysInMonth(y, m)) throw Error(what);
    return {y, m, d};
}

Date addDays(const Date& d, int days) {
    const DateTime dt = fromJulianDate(toJulianDate({d.year, d.month, d.day, 12, 0, 0.0}).plusDays(days));
    return {dt.year, dt.month, dt.day};
}

// ------------------------------------------------------------------ sites

const std::vector<SiteInfo>& sites() {
    static const std::vector<SiteInfo> list = [] {
        std::vector<SiteInfo> v;
        SiteInfo k;
        k.id = "kalabsha";
        k.title = "the temple of Kalabsha (Mandulis), New Kalabsha, Aswan";
        k.buildingNode = "kalabsha_temple";
        k.modelFile = "kalabsha.gltf";
        // New Kalabsha, the promontory by the west end of the Aswan High Dam where the temple
        // was re-erected in 1961-63 (German Archaeological Institute with Hochtief; "Khor Ingi,
        // about a kilometre north of the High Dam" per dainst.blog, "1.5 km south-west of the
        // dam" per madainproject.com): about 23.961 N, 32.866 E, good to ~0.005 deg. Ground
        // about 190 m above the ellipsoid (Lake Nasser stands at ~175-180 m).
        k.latitudeDeg = 23.9610, k.longitudeDeg = 32.8656, k.heightM = 190.0;
        // The temple faces the lake to the east, its pylon and causeway towards the water (the
        // original at Bab al-Kalabsha faced the Nile the same way). We found no surveyed azimuth
        // of the re-erected axis: 100 deg (a little south of east) is this model's assumption,
        // uncertain by at least +-10 deg (make_heritage.py turns the model by the same number).
        k.axisAzimuthDeg = 100.0;
        k.axisName = "Kalabsha's axis";
        k.outside = {18.0, 30.0, 52.0, -34.0, 9.0, -4.0, 50.0};
        k.inside = {-26.8, 1.7, 0.0, -60.0, 3.4, 0.0, 65.0};
        k.hasAlignmentView = true;
        k.alignment = {-51.0, 1.6, 0.0, 150.0, 1.6 + 201.0 * std::tan(1.2 * kDeg), 0.0, 40.0};
        v.push_back(k);

        SiteInfo c;
        c.id = "kiti";
        c.title = "Panagia Angeloktisti, Kiti, Cyprus";
        c.buildingNode = "kiti_church";
        c.modelFile = "kiti.gltf";
        // The church at the north-west edge of the village of Kiti, ~12 km south-west of
        // Larnaca (en.wikipedia.org/wiki/Panagia_tis_Angeloktistis, myguidecyprus.com): about
        // 34.848 N, 33.571 E (good to ~0.003 deg), ~25 m above sea level.
        c.latitudeDeg = 34.8480, c.longitudeDeg = 33.5710, c.heightM = 25.0;
        // The apse points east, as in Byzantine churches; taken as 90 deg (the real bearing was
        // not found and may differ by +-15 deg).
        c.axisAzimuthDeg = 90.0;
        c.axisName = "the apse of Kiti's church";
        c.outside = {20.0, 5.5, 21.0, -1.5, 4.8, 0.0, 50.0};
        c.inside = {-5.7, 1.6, 0.0, 8.0, 3.6, 0.0, 66.0};
        v.push_back(c);
        return v;
    }();
    return list;
}

const SiteInfo& site(std::string_view id) {
    for (const auto& s : sites())
        if (s.id == id) return s;
    throw Error("--site '" + std::string(id) + "' is not one of kalabsha, kiti, all");
}

astro::Site astroSite(const SiteInfo& s) {
    return astro::Site{.latitudeRad = s.latitudeDeg * kDeg, .longitudeRad = s.longitudeDeg * kDeg, .heightMeters = s.heightM};
}

// ------------------------------------------------------------------ the Sun

double sunEclipticLongitudeRad(const UtcInstant& t) {
    // Geocentric apparent place: the site does not matter.
    const astro::ObserverFrame f = astro::observerFrame(astro::Site{}, astro::timeScales(t), kPath);
    const astro::BodyState sun = astro::computeBody(astro::Body::Sun, f);
    const double eps = f.earth.trueObliquity;
    const double lambda = std::atan2(std::sin(sun.raRad) * std::cos(eps) + std::tan(sun.decRad) * std::sin(eps), std::cos(sun.raRad));
    return lambda < 0 ? lambda + 2.0 * std::numbers::pi : lambda;
}

UtcInstant nextEquinox(const UtcInstant& t) {
    // sin(lambda) changes sign only where lambda crosses 0 or 180 deg; it moves ~1 deg a day,
    // so daily samples bracket each crossing, then bisection to half a second.
    auto s = [](const UtcInstant& u) { return std::sin(sunEclipticLongitudeRad(u)); };
    UtcInstant a = t;
    double sa = s(a);
    for (int day = 1; day <= 200; ++day) {
        const UtcInstant b = t.plusSeconds(86400.0 * day);
        const double sb = s(b);
        if ((sa < 0) != (sb < 0)) {
            UtcInstant lo = a, hi = b;
            double slo = sa;
            while (daysBetween(lo.julianDate(), hi.julianDate()) * 86400.0 > 0.5) {
                const UtcInstant mid = lo.plusSeconds(0.5 * daysBetween(lo.julianDate(), hi.julianDate()) * 86400.0);
                const double sm = s(mid);
                if ((sm < 0) == (slo < 0)) lo = mid, slo = sm;
                else hi = mid;
            }
            return hi;
        }
        a = b, sa = sb;
    }
    throw Error("no equinox within 200 days of " + t.toIso());  // cannot happen: they are ~186 days apart
}

SunPosition sunPosition(const astro::Site& site, const UtcInstant& t) {
    const astro::BodyState sun = sunState(site, t);
    return {wrap360(sun.topo.azimuthRad / kDeg), sun.topo.altitudeRad / kDeg};
}

Sunrise sunriseOn(const astro::Site& site, const Date& d) {
    const auto t = astro::findCrossing(site, localMidnight(site, d), kPath, astro::Body::Sun, kRiseSetAltitudeDeg * kDeg, +1, 24.0);
    if (!t) throw Error("the Sun does not rise on " + d.iso() + " at this site");
    return {d, *t, sunPosition(site, *t).azimuthDeg};
}

SunDay sunDay(const SiteInfo& s, const Date& d) {
    const astro::Site site = astroSite(s);
    const astro::DayEvents ev = astro::findDayEvents(site, localMidnight(site, d), kPath, 24.0);
    if (!ev.sunrise || !ev.sunset || daysBetween(ev.sunrise->julianDate(), ev.sunset->julianDate()) <= 0)
        throw Error("the Sun does not rise and set on " + d.iso() + " at " + s.id);
    SunDay day;
    day.sunrise = *ev.sunrise;
    day.sunset = *ev.sunset;
    // Culmination: golden-section search for the maximum geometric altitude (unimodal between
    // rise and set) to a second.
    auto alt = [&](double sec) { return sunState(site, day.sunrise.plusSeconds(sec)).topo.altitudeGeometricRad; };
    double a = 0.0, b = daysBetween(day.sunrise.julianDate(), day.sunset.julianDate()) * 86400.0;
    const double g = 0.5 * (std::sqrt(5.0) - 1.0);
    double c = b - g * (b - a), e = a + g * (b - a), fc = alt(c), fe = alt(e);
    while (b - a > 1.0) {
        if (fc > fe) b = e, e = c, fe = fc, c = b - g * (b - a), fc = alt(c);
        else a = c, c = e, fc = fe, e = a + g * (b - a), fe = alt(e);
    }
    day.noon = day.sunrise.plusSeconds(0.5 * (a + b));
    // Night: two hours after astronomical dusk (the first dusk after this day's sunset).
    const auto dusk = astro::findCrossing(site, day.sunset, kPath, astro::Body::Sun, -18.0 * kDeg, -1, 12.0);
    day.night = dusk ? dusk->plusSeconds(7200.0) : day.sunset.plusSeconds(4.0 * 3600.0);
    return day;
}

UtcInstant sunAtAltitude(const astro::Site& site, const Date& d, double apparentAltitudeDeg) {
    const Sunrise r = sunriseOn(site, d);
    const double geometric = astro::geometricFromApparentAltitude(apparentAltitudeDeg * kDeg, site.pressureHpa, site.temperatureC);
    const auto t = astro::findCrossing(site, r.time.plusSeconds(-600.0), kPath, astro::Body::Sun, geometric, +1, 6.0);
    if (!t) throw Error("the Sun does not reach " + std::to_string(apparentAltitudeDeg) + " deg after sunrise on " + d.iso());
    return *t;
}

Alignment alignmentDays(const astro::Site& site, int year, double axisAzimuthDeg) {
    if (!(axisAzimuthDeg > 0.0 && axisAzimuthDeg < 180.0))
        throw Error("axis azimuth " + std::to_string(axisAzimuthDeg) + " deg is not a rising direction, in (0, 180) degrees");
    Alignment out;
    out.axisAzimuthDeg = axisAzimuthDeg;
    // Coarse scan: the rising azimuth of a body of declination delta at the altitude h0 of
    // sunrise, cos Az = (sin delta - sin h0 sin phi) / (cos h0 cos phi), with the Sun's
    // declination at local 6 h (within ~0.1 deg of the exact sunrise azimuth: enough to bracket).
    const double phi = site.latitudeRad, h0 = kRiseSetAltitudeDeg * kDeg;
    std::vector<Date> days;
    std::vector<double> approx;
    for (Date d{year, 1, 1}; d.year == year; d = addDays(d, 1)) {
        const double dec = sunState(site, localMidnight(site, d).plusSeconds(6.0 * 3600.0)).decRad;
        const double c = (std::sin(dec) - std::sin(h0) * std::sin(phi)) / (std::cos(h0) * std::cos(phi));
        days.push_back(d);
        approx.push_back(std::acos(std::clamp(c, -1.0, 1.0)) / kDeg);
    }
    const int n = int(days.size());
    // The exact sunrise azimuth of the day closest to the axis among days [i - 2, i + 3].
    auto refine = [&](int i) {
        Sunrise best;
        double bestErr = 1e9;
        for (int k = std::max(0, i - 2); k <= std::min(n - 1, i + 3); ++k) {
            const Sunrise r = sunriseOn(site, days[size_t(k)]);
            if (std::abs(r.azimuthDeg - axisAzimuthDeg) < bestErr) bestErr = std::abs(r.azimuthDeg - axisAzimuthDeg), best = r;
        }
        return best;
    };
    for (int i = 0; i + 1 < n; ++i)
        if ((approx[size_t(i)] - axisAzimuthDeg < 0) != (approx[size_t(i + 1)] - axisAzimuthDeg < 0)) out.days.push_back(refine(i));
    const auto [mn, mx] = std::minmax_element(approx.begin(), approx.end());
    out.minAzimuthDeg = sunriseOn(site, days[size_t(mn - approx.begin())]).azimuthDeg;
    out.maxAzimuthDeg = sunriseOn(site, days[size_t(mx - approx.begin())]).azimuthDeg;
    if (out.days.empty()) {
        out.exact = false;
        int best = 0;
        for (int i = 1; i < n; ++i)
            if (std::abs(approx[size_t(i)] - axisAzimuthDeg) < std::abs(approx[size_t(best)] - axisAzimuthDeg)) best = i;
        out.days.push_back(refine(std::max(0, best - 1)));
    }
    return out;
}

// ------------------------------------------------------------------ cameras

glm::dvec3 toWorld(const SiteInfo& s, double x, double y, double z) {
    // The model's node turns its frame by (90 - azimuth) deg about +y: local +x -> azimuth.
    const double th = (90.0 - s.axisAzimuthDeg) * kDeg;
    return {std::cos(th) * x + std::sin(th) * z, y, -std::sin(th) * x + std::cos(th) * z};
}

host::FlyCamera camera(const SiteInfo& s, const LocalView& v) {
    const glm::dvec3 eye = toWorld(s, v.x, v.y, v.z);
    const glm::dvec3 d = toWorld(s, v.targetX, v.targetY, v.targetZ) - eye;
    host::FlyCamera c;
    c.position = eye;
    c.yawDeg = wrap360(std::atan2(d.x, -d.z) / kDeg);
    c.pitchDeg = std::asin(d.y / glm::length(d)) / kDeg;
    c.verticalFovDeg = v.verticalFovDeg;
    return c;
}

}  // namespace welkin::heritage
