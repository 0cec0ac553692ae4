// Observer frames: WGS84 site, Earth velocity and aberration, horizontal coordinates, refraction.
#include <welkin/astro/frames.hpp>
#include <welkin/error.hpp>

#include <erfa.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>

namespace welkin::astro {

namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kTwoPi = 2.0 * kPi;
constexpr double kDeg = kPi / 180.0;
constexpr double kArcsec = kDeg / 3600.0;
constexpr double kAuPerDayOverC = kAstronomicalUnit / 86400.0 / kSpeedOfLight;  // 1 au/day in units of c

double wrap(double a) {
    double w = std::fmod(a, kTwoPi);
    return w < 0 ? w + kTwoPi : w;
}

void checkField(const char* name, double v, double lo, double hi) {
    if (!(v >= lo && v <= hi)) {
        char buf[160];
        std::snprintf(buf, sizeof buf, "astro::Site: %s %g not in [%g, %g]", name, v, lo, hi);
        throw Error(buf);
    }
}

// --- Fast Earth velocity: Keplerian orbits (Standish, "Keplerian Elements for Approximate
// Positions of the Major Planets", JPL, Table 1, 1800-2050; mean ecliptic and equinox J2000).
struct Elements {
    double a, e, i, L, peri, node;        // au, -, deg, deg, deg, deg
    double da, de, di, dL, dperi, dnode;  // per Julian century
};
constexpr Elements kEmb{1.00000261, 0.01671123, -0.00001531, 100.46457166, 102.93768193, 0.0,
                        0.00000562, -0.00004392, -0.01294668, 35999.37244981, 0.32327364, 0.0};
constexpr Elements kJupiter{5.20288700, 0.04838624, 1.30439695, 34.39644051, 14.72847983, 100.47390909,
                            -0.00011607, -0.00013253, -0.00183714, 3034.74612775, 0.21252668, 0.20469106};
constexpr Elements kSaturn{9.53667594, 0.05386179, 2.48599187, 49.95424423, 92.59887831, 113.66242448,
                           -0.00125060, -0.00050991, 0.00193609, 1222.49362201, -0.41897216, -0.28867794};
constexpr double kMassJupiter = 1.0 / 1047.3486;  // solar masses
constexpr double kMassSaturn = 1.0 / 3497.898;

// Heliocentric position (au) and velocity (au/day), ecliptic J2000 axes.
void keplerian(const Elements& el, double t, glm::dvec3& pos, glm::dvec3& vel) {
    const double a = el.a + el.da * t, e = el.e + el.de * t;
    const double inc = (el.i + el.di * t) * kDeg, L = (el.L + el.dL * t) * kDeg;
    const double peri = (el.peri + el.dperi * t) * kDeg, node = (el.node + el.dnode * t) * kDeg;
    const double M = std::remainder(L - peri, kTwoPi);
    double E = M + e * std::sin(M);
    for (int k = 0; k < 4; ++k) E -= (E - e * std::sin(E) - M) / (1.0 - e * std::cos(E));
    const double sE = std::sin(E), cE = std::cos(E), b = std::sqrt(1.0 - e * e);
    const double n = el.dL * kDeg / kDaysPerCentury;  // rad/day
    const double k = a * n / (1.0 - e * cE);
    const glm::dmat3 toEcliptic = rotationZ(-node) * rotationX(-inc) * rotationZ(-(peri - node));
    pos = toEcliptic * glm::dvec3(a * (cE - e), a * b * sE, 0.0);
    vel = toEcliptic * glm::dvec3(-k * sE, k * b * cE, 0.0);
}

// Earth's barycentric velocity (units of c), heliocentric direction and distance, ICRS axes.
void earthFast(double t, glm::dvec3& velocityOverC, glm::dvec3& sunToEarth, double& distanceAu) {
    glm::dvec3 pe, ve, pj, vj, ps, vs;
    keplerian(kEmb, t, pe, ve);
    keplerian(kJupiter, t, pj, vj);
    keplerian(kSaturn, t, ps, vs);
    // The Sun's reflex motion about the barycentre.
    const glm::dvec3 vSun = -(kMassJupiter * vj + kMassSaturn * vs) / (1.0 + kMassJupiter + kMassSaturn);
    // The Earth about the Earth-Moon barycentre: circular lunar orbit at the Moon's mean longitude
    // (Meeus 47.1), speed 2 pi 384400 km / 27.321662 d.
    const double Lm = (218.3164477 + 481267.88123421 * t) * kDeg;
    const double vMoon = kTwoPi * 384400e3 / kAstronomicalUnit / 27.321662;  // au/day
    const double muEarth = 1.0 / (1.0 + 81.300568);
    const glm::dvec3 vEarthAboutEmb = -muEarth * vMoon * glm::dvec3(-std::sin(Lm), std::cos(Lm), 0.0);
    const glm::dmat3 eclipticToIcrs = rotationX(-84381.406 * kArcsec);
    velocityOverC = eclipticToIcrs * (ve + vSun + vEarthAboutEmb) * kAuPerDayOverC;
    distanceAu = glm::length(pe);
    sunToEarth = eclipticToIcrs * (pe / distanceAu);
}

void earthPrecise(const TimeScales& ts, glm::dvec3& velocityOverC, glm::dvec3& sunToEarth, double& distanceAu) {
    double pvh[2][3], pvb[2][3];
    eraEpv00(ts.tt.day, ts.tt.fraction, pvh, pvb);  // TDB ~ TT (< 2 ms)
    velocityOverC = glm::dvec3(pvb[1][0], pvb[1][1], pvb[1][2]) * kAuPerDayOverC;
    glm::dvec3 h(pvh[0][0], pvh[0][1], pvh[0][2]);
    distanceAu = glm::length(h);
    sunToEarth = h / distanceAu;
}

// --- Refraction ---------------------------------------------------------------------------------
constexpr double kGreenFrom = 25.0 * kDeg;  // pure Green model above
constexpr double kSaemTo = 15.0 * kDeg;     // pure Saemundsson below
constexpr double kFadeTop = -1.0 * kDeg;    // below: fade to zero
constexpr double kFadeBottom = -5.0 * kDeg; // zero below

// Green's refraction constants (as ERFA eraRefco: optical, dry air, 0.55 um), radians.
void greenConstants(double p, double tc, double& A, double& B) {
    const double tk = tc + 273.15, wlsq = 0.55 * 0.55;
    const double gamma = (77.53484e-6 + (4.39108e-7 + 3.666e-9 / wlsq) / wlsq) * p / tk;
    const double beta = 4.4474e-6 * tk;
    A = gamma * (1.0 - beta);
    B = -gamma * (beta - gamma / 2.0);
}

// A tan z + B tan^3 z on the observed zenith distance, solved by one Newton step from the
// geometric one (as ERFA eraAtioq).
double refractionGreen(double h, double p, double tc) {
    double A, B;
    greenConstants(p, tc, A, B);
    const double s = std::max(std::sin(h), 0.05), c = std::cos(h);
    const double tz = c / s, w = B * tz * tz;
    return (A + w) * tz / (1.0 + (A + 3.0 * w) / (s * s));
}

// Saemundsson (Sky & Telescope 1986), scaled for pressure and temperature (Meeus ch. 16), rad.
double refractionSaemundsson(double h, double p, double tc) {
    const double hd = h / kDeg;
    const double arcmin = 1.02 / std::tan((hd + 10.3 / (hd + 5.11)) * kDeg);
    return arcmin / 60.0 * kDeg * (p / 1010.0) * (283.0 / (273.0 + tc));
}

double smoothstep(double u) {
    u = std::clamp(u, 0.0, 1.0);
    return u * u * (3.0 - 2.0 * u);
}

void checkFinite(const char* fn, double a, double p, double t) {
    if (!std::isfinite(a) || !std::isfinite(p) || !std::isfinite(t))
        throw Error(std::string("astro::") + fn + "(): arguments must be finite");
}

}  // namespace

void validate(const Site& s) {
    checkField("latitudeRad", s.latitudeRad, -kPi / 2, kPi / 2);
    checkField("longitudeRad", s.longitudeRad, -kTwoPi, kTwoPi);
    checkField("heightMeters", s.heightMeters, -1e4, 1e8);
    checkField("pressureHpa", s.pressureHpa, 0, 2000);
    checkField("temperatureC", s.temperatureC, -100, 100);
}

glm::dvec3 siteItrs(const Site& s) {
    const double e2 = kWgs84F * (2.0 - kWgs84F);
    const double sp = std::sin(s.latitudeRad), cp = std::cos(s.latitudeRad);
    const double n = kWgs84A / std::sqrt(1.0 - e2 * sp * sp);
    return {(n + s.heightMeters) * cp * std::cos(s.longitudeRad), (n + s.heightMeters) * cp * std::sin(s.longitudeRad),
            (n * (1.0 - e2) + s.heightMeters) * sp};
}

glm::dmat3 itrsToEnu(const Site& s) {
    const double sp = std::sin(s.latitudeRad), cp = std::cos(s.latitudeRad);
    const double sl = std::sin(s.longitudeRad), cl = std::cos(s.longitudeRad);
    const glm::dvec3 east(-sl, cl, 0.0), north(-sp * cl, -sp * sl, cp), up(cp * cl, cp * sl, sp);
    return glm::transpose(glm::dmat3(east, north, up));  // rows = east, north, up
}

glm::dvec3 earthVelocity(const TimeScales& ts, Path path) {
    glm::dvec3 v, e;
    double d;
    if (path == Path::Precise)
        earthPrecise(ts, v, e, d);
    else
        earthFast(ts.centuriesTT(), v, e, d);
    return v;
}

ObserverFrame observerFrame(const Site& site, const TimeScales& ts, Path path) { return observerFrame(site, ts, path, nullptr); }

ObserverFrame observerFrame(const Site& site, const TimeScales& ts, Path path, EarthSeriesCache* cache) {
    validate(site);
    ObserverFrame f;
    f.site = site;
    f.time = ts;
    f.path = path;
    f.earth = earthOrientation(ts, path, cache);
    const glm::dmat3 todToItrs = rotationZ(f.earth.gast);
    const glm::dmat3 itrsToTod = glm::transpose(todToItrs);
    f.trueOfDateToEnu = itrsToEnu(site) * todToItrs;
    f.icrsToEnu = f.trueOfDateToEnu * f.earth.celestialToTrueOfDate;
    const glm::dvec3 r = siteItrs(site);
    f.sitePositionTod = itrsToTod * r;
    f.siteVelocityTod = itrsToTod * glm::dvec3(-kEarthRotationRate * r.y, kEarthRotationRate * r.x, 0.0);
    if (path == Path::Precise)
        earthPrecise(ts, f.earthVelocityIcrs, f.sunFromEarthIcrs, f.sunDistanceAu);
    else
        earthFast(ts.centuriesTT(), f.earthVelocityIcrs, f.sunFromEarthIcrs, f.sunDistanceAu);
    f.observerVelocityIcrs =
        f.earthVelocityIcrs + glm::transpose(f.earth.celestialToTrueOfDate) * f.siteVelocityTod / kSpeedOfLight;
    f.lastRad = wrap(f.earth.gast + site.longitudeRad);
    f.lmstRad = wrap(f.earth.gmst + site.longitudeRad);
    return f;
}

glm::dvec3 aberrate(const glm::dvec3& p, const glm::dvec3& v, Path path, double sunDistanceAu) {
    if (path == Path::Precise) {
        double pn[3] = {p.x, p.y, p.z}, vv[3] = {v.x, v.y, v.z}, out[3];
        eraAb(pn, vv, sunDistanceAu, std::sqrt(1.0 - glm::dot(v, v)), out);
        return glm::normalize(glm::dvec3(out[0], out[1], out[2]));
    }
    return glm::normalize(p + v);
}

Horizontal horizontalFromEnu(const glm::dvec3& enu) {
    const double r = std::hypot(enu.x, enu.y);
    Horizontal h;
    h.azimuthRad = r > 0 ? wrap(std::atan2(enu.x, enu.y)) : 0.0;
    h.altitudeRad = std::atan2(enu.z, r);
    return h;
}

glm::dvec3 enuFromHorizontal(double az, double alt) {
    const double ca = std::cos(alt);
    return {ca * std::sin(az), ca * std::cos(az), std::sin(alt)};
}

double refraction(double h, double pressureHpa, double temperatureC) {
    checkFinite("refraction", h, pressureHpa, temperatureC);
    const double p = std::clamp(pressureHpa, 0.0, 10000.0);
    const double tc = std::clamp(temperatureC, -150.0, 200.0);
    if (p <= 0.0) return 0.0;
    h = std::clamp(h, -kPi / 2, kPi / 2);
    if (h >= kGreenFrom) return refractionGreen(h, p, tc);
    if (h >= kSaemTo) {
        const double w = smoothstep((h - kSaemTo) / (kGreenFrom - kSaemTo));
        return w * refractionGreen(h, p, tc) + (1.0 - w) * refractionSaemundsson(h, p, tc);
    }
    if (h >= kFadeTop) return refractionSaemundsson(h, p, tc);
    if (h <= kFadeBottom) return 0.0;
    return refractionSaemundsson(kFadeTop, p, tc) * smoothstep((h - kFadeBottom) / (kFadeTop - kFadeBottom));
}

double apparentFromGeometricAltitude(double h, double p, double t) {
    return std::min(h + refraction(h, p, t), kPi / 2);
}

double geometricFromApparentAltitude(double a, double pressureHpa, double temperatureC) {
    checkFinite("geometricFromApparentAltitude", a, pressureHpa, temperatureC);
    a = std::clamp(a, -kPi / 2, kPi / 2);
    if (pressureHpa <= 0.0) return a;
    // h + R(h) is strictly increasing and R >= 0: bisect on [a - Rmax, a].
    const double k = std::clamp(pressureHpa, 0.0, 10000.0) / 1010.0 * 283.0 / (273.0 + std::clamp(temperatureC, -150.0, 200.0));
    double lo = std::max(a - (k * 1.0 + 0.01) * kDeg, -kPi / 2), hi = a;
    for (int i = 0; i < 60 && hi - lo > 1e-12; ++i) {
        const double mid = 0.5 * (lo + hi);
        if (mid + refraction(mid, pressureHpa, temperatureC) > a)
            hi = mid;
        else
            lo = mid;
    }
    return 0.5 * (lo + hi);
}

namespace {
Topocentric finish(const ObserverFrame& f, const glm::dvec3& tod, double distance) {
    Topocentric out;
    const glm::dvec3 u = glm::normalize(tod);
    raDecFromDirection(u, out.raTopocentricRad, out.decTopocentricRad);
    out.distanceMeters = distance;
    out.enuGeometric = glm::normalize(f.trueOfDateToEnu * u);
    const Horizontal h = horizontalFromEnu(out.enuGeometric);
    out.azimuthRad = h.azimuthRad;
    out.altitudeGeometricRad = h.altitudeRad;
    out.altitudeRad = apparentFromGeometricAltitude(h.altitudeRad, f.site.pressureHpa, f.site.temperatureC);
    const double r = std::hypot(out.enuGeometric.x, out.enuGeometric.y);
    if (r > 0) {
        const double ca = std::cos(out.altitudeRad) / r;
        out.enu = glm::dvec3(out.enuGeometric.x * ca, out.enuGeometric.y * ca, std::sin(out.altitudeRad));
    } else {
        out.enu = out.enuGeometric;
    }
    return out;
}
}  // namespace

Topocentric topocentric(const ObserverFrame& f, double ra, double dec, double distance) {
    const glm::dvec3 u = directionFromRaDec(ra, dec);
    if (distance > 0 && std::isfinite(distance)) {
        const glm::dvec3 v = distance * u - f.sitePositionTod;
        return finish(f, v, glm::length(v));
    }
    return finish(f, u, 0.0);
}

Topocentric topocentricFromIcrs(const ObserverFrame& f, const glm::dvec3& icrs) {
    glm::dvec3 p = glm::normalize(icrs);
    if (f.path == Path::Precise) {
        double pin[3] = {p.x, p.y, p.z}, e[3] = {f.sunFromEarthIcrs.x, f.sunFromEarthIcrs.y, f.sunFromEarthIcrs.z}, out[3];
        eraLdsun(pin, e, f.sunDistanceAu, out);
        p = glm::dvec3(out[0], out[1], out[2]);
    }
    p = aberrate(p, f.observerVelocityIcrs, f.path, f.sunDistanceAu);
    return finish(f, f.earth.celestialToTrueOfDate * p, 0.0);
}

}  // namespace welkin::astro
