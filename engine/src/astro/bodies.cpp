// Apparent places of the Sun, Moon and planets (see bodies.hpp for the two paths).
//
// The pipeline for a planet, in ICRS axes and au:
//   E(t)             heliocentric Earth (VSOP87B, rotated from the J2000 ecliptic to the equator)
//   P(t - tau)       heliocentric planet at the time the light left it; tau = |P - E| / c
//   g = P - E        astrometric geocentric vector (the Sun's barycentric motion during tau,
//                    13 m/s, moves g by < 0.01" and is ignored)
//   u = aberrate(g)  annual aberration with the Earth's barycentric velocity (frames.hpp)
//   M u              true equator and equinox of date (bias-precession-nutation, earth.hpp)
//   topocentric()    diurnal parallax and refraction (frames.hpp)
// The Moon needs no annual aberration: seen from the geocentre its apparent direction is its
// geocentric position at t - tau (the Earth's heliocentric motion cancels to first order).
#include <welkin/astro/bodies.hpp>
#include <welkin/astro/elp.hpp>
#include <welkin/astro/vsop87.hpp>
#include <welkin/error.hpp>

#include <erfa.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <numbers>

namespace welkin::astro {

namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kDeg = kPi / 180.0;
/// Light time for one au, days.
constexpr double kLightDaysPerAu = kAstronomicalUnit / kSpeedOfLight / 86400.0;

VsopPlanet vsopOf(Body b) {
    switch (b) {
        case Body::Mercury: return VsopPlanet::Mercury;
        case Body::Venus: return VsopPlanet::Venus;
        case Body::Mars: return VsopPlanet::Mars;
        case Body::Jupiter: return VsopPlanet::Jupiter;
        case Body::Saturn: return VsopPlanet::Saturn;
        case Body::Uranus: return VsopPlanet::Uranus;
        case Body::Neptune: return VsopPlanet::Neptune;
        default: return VsopPlanet::Earth;
    }
}

double wrap2Pi(double a) {
    a = std::fmod(a, 2 * kPi);
    return a < 0 ? a + 2 * kPi : a;
}
double wrapPi(double a) {
    a = wrap2Pi(a);
    return a > kPi ? a - 2 * kPi : a;
}
double angleBetween(const glm::dvec3& a, const glm::dvec3& b) {
    // atan2 form: accurate for small and large angles alike.
    return std::atan2(glm::length(glm::cross(a, b)), glm::dot(a, b));
}

void checkValidity(const ObserverFrame& f) {
    const double year = 2000.0 + f.time.centuriesTT() * 100.0;
    if (!(year >= kEphemerisFirstYear && year < kEphemerisLastYear + 1.0))
        throw Error("astro::computeBody(): year " + std::to_string(static_cast<long long>(std::floor(year))) +
                    " outside the ephemerides' validity range [-2000, 6000]");
}

const VsopBody& series(VsopPlanet p, bool precise, double t) { return precise ? vsop87Full(p) : vsop87Truncated(p, t); }

/// State shared by the bodies of one evaluation.
struct Shared {
    const ObserverFrame* frame = nullptr;
    bool precise = false;
    double tMillennia = 0;   // TT from J2000
    bool haveEarth = false;
    glm::dvec3 earth{0.0};   // heliocentric Earth, au, ICRS axes (VSOP87)
    // Ephemeris::update's reuse of the last full VSOP87 evaluations (Fast path), or null.
    std::array<Ephemeris::VsopCache, 8>* vsopCache = nullptr;
    Ephemeris::MoonCache* moonCache = nullptr;
    bool haveSun = false;
    glm::dvec3 sunGeo{0.0};  // geometric geocentric Sun, au, ICRS axes
    double sunRa = 0, sunDec = 0;  // apparent geocentric Sun, of date
    BodyState sun;

    /// VSOP87 coordinates of `p` at tMillennia (with rates when `rates`). With a cache (Fast path
    /// only), once two full evaluations lie within Ephemeris::kVsopReuseDays of each other, later
    /// times within the span of the last are extrapolated linearly along their secant. (Not
    /// evaluate()'s rates: those keep only the terms above 1e-4, enough for light time, and over
    /// 5 minutes that moves the Earth by ~0.01".) The error of a secant over D extrapolated by dt
    /// is 0.5 L'' dt (dt + D); Mercury's |L''| reaches ~1e-2 rad/day^2 near perihelion (h / r^2
    /// changing fastest), so < 1.2e-7 rad heliocentric at dt = D = 5 minutes and < 0.015" seen
    /// from the Earth; the other planets and the Earth far less.
    VsopState vsop(VsopPlanet p, bool rates) {
        if (!vsopCache || precise) return evaluate(series(p, precise, tMillennia), tMillennia, rates);
        Ephemeris::VsopCache& c = (*vsopCache)[std::size_t(p)];
        const double span = Ephemeris::kVsopReuseDays / 365250.0;
        std::array<double, 3> lbr;
        if (c.reuse(tMillennia, span, lbr))
            // The rates returned are the full evaluation's (they serve the light time, and over 5
            // minutes they change by < 1e-5 relative): a reused state differs from a full one
            // only by the extrapolation.
            return VsopState{glm::dvec3(lbr[0], lbr[1], lbr[2]), c.lightRate};
        const VsopState st = evaluate(series(p, false, tMillennia), tMillennia, rates);
        c.record(tMillennia, span, {st.lbr.x, st.lbr.y, st.lbr.z});
        c.lightRate = st.rate;
        return st;
    }

    /// moonMeeus(T) for the Fast path; with a cache, extrapolated like vsop() along the secant
    /// of the last two full evaluations within Ephemeris::kVsopReuseDays (angles unwrapped,
    /// results reduced as moonMeeus reduces them). The neglected term, 0.5 lambda'' dt (dt + D)
    /// with |lambda''| below ~1e-2 rad/day^2 (the elliptic term and the variation), is < 0.03"
    /// at dt = D = 5 minutes.
    MoonEcliptic moon(double T) {
        if (!vsopCache || !moonCache) return moonMeeus(T);
        auto pack = [](const MoonEcliptic& m) {
            return std::array<double, 9>{m.longitude, m.latitude, m.distanceKm, m.meanElongation, m.ascendingNode,
                                         m.argumentLatitude, m.sunMeanAnomaly, m.moonMeanAnomaly, m.eccentricityFactor};
        };
        // The angles (MoonCache::angle) are unwrapped for the slope and reduced after.
        Ephemeris::MoonCache& c = *moonCache;
        const double span = Ephemeris::kVsopReuseDays / 36525.0;
        std::array<double, 9> x;
        if (c.reuse(T, span, x)) return MoonEcliptic{x[0], x[1], x[2], x[3], x[4], x[5], x[6], x[7], x[8]};
        const MoonEcliptic m = moonMeeus(T);
        c.record(T, span, pack(m));
        return m;
    }

    const glm::dvec3& earthHelio() {
        if (!haveEarth) {
            earth = vsopToEquatorialJ2000(vsop(VsopPlanet::Earth, false).lbr);
            haveEarth = true;
        }
        return earth;
    }
};

// Body-independent finishing: RA/Dec of date, topocentric place, size, phase, bright limb.
void finish(BodyState& s, const Shared& sh, const glm::dvec3& tod, double distanceAu) {
    const ObserverFrame& f = *sh.frame;
    raDecFromDirection(tod, s.raRad, s.decRad);
    s.distanceMeters = distanceAu * kAstronomicalUnit;
    s.topo = topocentric(f, s.raRad, s.decRad, s.distanceMeters);
    const double d = s.topo.distanceMeters > 0 ? s.topo.distanceMeters : s.distanceMeters;
    s.angularDiameterRad = 2.0 * std::asin(std::min(1.0, bodyRadiusMeters(s.body) / d));
    s.illuminatedFraction = 0.5 * (1.0 + std::cos(s.phaseAngleRad));
    if (s.body != Body::Sun) {
        // Meeus (48.5): position angle of the bright limb from the Sun's and the body's places.
        const double da = sh.sunRa - s.raRad;
        s.brightLimbAngleRad = wrap2Pi(std::atan2(std::cos(sh.sunDec) * std::sin(da),
                                                  std::sin(sh.sunDec) * std::cos(s.decRad) -
                                                      std::cos(sh.sunDec) * std::sin(s.decRad) * std::cos(da)));
    }
}

void computeSun(Shared& sh) {
    const ObserverFrame& f = *sh.frame;
    BodyState s;
    s.body = Body::Sun;
    glm::dvec3 g;
    // eraEpv00 is a fit to the ephemerides over 1900-2100 and degrades away from it (~45" at
    // year -2000); outside that span the Precise path uses the full VSOP87 Earth instead.
    const double year = 2000.0 + f.time.centuriesTT() * 100.0;
    if (sh.precise && year >= 1900.0 && year <= 2100.0) {
        // eraEpv00: heliocentric and barycentric Earth, BCRS (ICRS axes), au and au/day (TDB ~ TT).
        double pvh[2][3], pvb[2][3];
        eraEpv00(f.time.tt.day, f.time.tt.fraction, pvh, pvb);
        const glm::dvec3 sunB(pvb[0][0] - pvh[0][0], pvb[0][1] - pvh[0][1], pvb[0][2] - pvh[0][2]);
        const glm::dvec3 sunV(pvb[1][0] - pvh[1][0], pvb[1][1] - pvh[1][1], pvb[1][2] - pvh[1][2]);
        const glm::dvec3 earthB(pvb[0][0], pvb[0][1], pvb[0][2]);
        g = sunB - earthB;
        const double tau = glm::length(g) * kLightDaysPerAu;
        g = sunB - sunV * tau - earthB;
        sh.sunGeo = sunB - earthB;
    } else {
        g = -sh.earthHelio();
        sh.sunGeo = g;
    }
    const double dist = glm::length(g);
    s.directionIcrs = aberrate(g / dist, f.earthVelocityIcrs, f.path, dist);
    s.heliocentricDistanceAu = 0;
    s.phaseAngleRad = 0;
    s.magnitude = magnitude::sun(dist);
    const glm::dvec3 tod = f.earth.celestialToTrueOfDate * s.directionIcrs;
    raDecFromDirection(tod, sh.sunRa, sh.sunDec);
    finish(s, sh, tod, dist);
    sh.sun = s;
    sh.haveSun = true;
}

void moonLibration(BodyState& s, const Shared& sh, const glm::dvec3& tod, double T, const MoonEcliptic& a) {
    // Meeus ch. 53. lambda, beta: apparent ecliptic coordinates of date (with nutation).
    const ObserverFrame& f = *sh.frame;
    const double eps = f.earth.trueObliquity, dpsi = f.earth.nutation.dpsi;
    const double ce = std::cos(eps), se = std::sin(eps);
    const glm::dvec3 ecl(tod.x, tod.y * ce + tod.z * se, -tod.y * se + tod.z * ce);
    const double lambda = std::atan2(ecl.y, ecl.x);
    const double beta = std::asin(std::clamp(ecl.z / glm::length(ecl), -1.0, 1.0));
    const double I = 1.54242 * kDeg;
    const double W = lambda - dpsi - a.ascendingNode;
    const double A = std::atan2(std::sin(W) * std::cos(beta) * std::cos(I) - std::sin(beta) * std::sin(I),
                                std::cos(W) * std::cos(beta));
    const double lOpt = wrapPi(A - a.argumentLatitude);
    const double bOpt = std::asin(std::clamp(-std::sin(W) * std::cos(beta) * std::sin(I) - std::sin(beta) * std::cos(I), -1.0, 1.0));
    // Physical libration (degrees), Meeus ch. 53.
    const double Mp = a.moonMeanAnomaly, M = a.sunMeanAnomaly, F = a.argumentLatitude, D = a.meanElongation;
    const double Om = a.ascendingNode, E = a.eccentricityFactor;
    const double K1 = (119.75 + 131.849 * T) * kDeg, K2 = (72.56 + 20.186 * T) * kDeg;
    using std::cos;
    using std::sin;
    const double rho = -0.02752 * cos(Mp) - 0.02245 * sin(F) + 0.00684 * cos(Mp - 2 * F) - 0.00293 * cos(2 * F) -
                       0.00085 * cos(2 * F - 2 * D) - 0.00054 * cos(Mp - 2 * D) - 0.00020 * sin(Mp + F) -
                       0.00020 * cos(Mp + 2 * F) - 0.00020 * cos(Mp - F) + 0.00014 * cos(Mp + 2 * F - 2 * D);
    const double sigma = -0.02816 * sin(Mp) + 0.02244 * cos(F) - 0.00682 * sin(Mp - 2 * F) - 0.00279 * sin(2 * F) -
                         0.00083 * sin(2 * F - 2 * D) + 0.00069 * sin(Mp - 2 * D) + 0.00040 * cos(Mp + F) -
                         0.00025 * sin(2 * Mp) - 0.00023 * sin(Mp + 2 * F) + 0.00020 * cos(Mp - F) +
                         0.00019 * sin(Mp - F) + 0.00013 * sin(Mp + 2 * F - 2 * D) - 0.00010 * cos(Mp - 3 * F);
    const double tau = 0.02520 * E * sin(M) + 0.00473 * sin(2 * Mp - 2 * F) - 0.00467 * sin(Mp) + 0.00396 * sin(K1) +
                       0.00276 * sin(2 * Mp - 2 * D) + 0.00196 * sin(Om) - 0.00183 * cos(Mp - F) +
                       0.00115 * sin(Mp - 2 * D) - 0.00096 * sin(Mp - D) + 0.00046 * sin(2 * F - 2 * D) -
                       0.00039 * sin(Mp - F) - 0.00032 * sin(Mp - M - D) + 0.00027 * sin(2 * Mp - M - 2 * D) +
                       0.00023 * sin(K2) - 0.00014 * sin(2 * D) + 0.00014 * cos(2 * Mp - 2 * F) -
                       0.00012 * sin(Mp - 2 * F) - 0.00012 * sin(2 * Mp) + 0.00011 * sin(2 * Mp - 2 * M - 2 * D);
    const double lPhys = (-tau + (rho * cos(A) + sigma * sin(A)) * std::tan(bOpt)) * kDeg;
    const double bPhys = (sigma * cos(A) - rho * sin(A)) * kDeg;
    s.librationLonRad = wrapPi(lOpt + lPhys);
    s.librationLatRad = bOpt + bPhys;
    // Position angle of the axis.
    const double V = Om + dpsi + sigma * kDeg / std::sin(I);
    const double Ir = I + rho * kDeg;
    const double X = std::sin(Ir) * std::sin(V);
    const double Y = std::sin(Ir) * std::cos(V) * ce - std::cos(Ir) * se;
    const double omega = std::atan2(X, Y);
    const double sinP = std::sqrt(X * X + Y * Y) * std::cos(s.raRad - omega) / std::cos(s.librationLatRad);
    s.axisAngleRad = wrapPi(std::asin(std::clamp(sinP, -1.0, 1.0)));
}

BodyState computeMoon(Shared& sh) {
    const ObserverFrame& f = *sh.frame;
    BodyState s;
    s.body = Body::Moon;
    const double T = f.time.centuriesTT();
    glm::dvec3 tod;
    double dist = 0;
    const MoonEcliptic m = sh.precise ? moonMeeus(T) : sh.moon(T);  // position (Fast) and the libration's arguments
    if (sh.precise) {
        double pv[2][3];
        eraMoon98(f.time.tt.day, f.time.tt.fraction, pv);  // GCRS, au, au/day, geometric
        glm::dvec3 p(pv[0][0], pv[0][1], pv[0][2]), v(pv[1][0], pv[1][1], pv[1][2]);
        const glm::dvec3 g = p - v * (glm::length(p) * kLightDaysPerAu);
        dist = glm::length(g);
        s.directionIcrs = g / dist;
        tod = f.earth.celestialToTrueOfDate * s.directionIcrs;
    } else {
        const double lam = m.longitude + f.earth.nutation.dpsi, beta = m.latitude, eps = f.earth.trueObliquity;
        const glm::dvec3 e(std::cos(beta) * std::cos(lam), std::cos(beta) * std::sin(lam), std::sin(beta));
        tod = glm::dvec3(e.x, e.y * std::cos(eps) - e.z * std::sin(eps), e.y * std::sin(eps) + e.z * std::cos(eps));
        dist = m.distanceKm * 1000.0 / kAstronomicalUnit;
        s.directionIcrs = glm::transpose(f.earth.celestialToTrueOfDate) * tod;
    }
    const glm::dvec3 g = s.directionIcrs * dist;
    const glm::dvec3 toSun = sh.sunGeo - g;
    s.heliocentricDistanceAu = glm::length(toSun);
    s.phaseAngleRad = angleBetween(toSun, -g);
    s.magnitude = magnitude::moon(s.heliocentricDistanceAu, dist, s.phaseAngleRad / kDeg);
    finish(s, sh, tod, dist);
    // Apparent size and magnitude from the topocentric distance (the Moon is 1.7% nearer at the zenith).
    s.magnitude = magnitude::moon(s.heliocentricDistanceAu, s.topo.distanceMeters / kAstronomicalUnit, s.phaseAngleRad / kDeg);
    moonLibration(s, sh, tod, T, m);
    return s;
}

BodyState computePlanet(Shared& sh, Body body) {
    const ObserverFrame& f = *sh.frame;
    BodyState s;
    s.body = body;
    const glm::dvec3 E = sh.earthHelio();
    const VsopBody& ser = series(vsopOf(body), sh.precise, sh.tMillennia);
    glm::dvec3 P, g;
    if (sh.precise) {
        // Light time iterated with the full series until it changes by < 1 ms.
        double tau = 0;
        for (int i = 0; i < 6; ++i) {
            P = vsopToEquatorialJ2000(evaluate(ser, sh.tMillennia - tau / 365250.0).lbr);
            g = P - E;
            const double next = glm::length(g) * kLightDaysPerAu;
            const bool done = std::fabs(next - tau) < 1e-8;
            tau = next;
            if (done) break;
        }
    } else {
        // One evaluation with rates; P(t - tau) = P(t) - V tau (the neglected curvature term is
        // < 0.01" even for Mercury); tau from two fixed-point steps.
        const VsopState st = sh.vsop(vsopOf(body), true);
        const glm::dvec3 P0 = vsopToEquatorialJ2000(st.lbr);
        const glm::dvec3 V = vsopRateToEquatorialJ2000(st.lbr, st.rate);
        double tau = glm::length(P0 - E) * kLightDaysPerAu;
        P = P0 - V * tau;
        tau = glm::length(P - E) * kLightDaysPerAu;
        P = P0 - V * tau;
        g = P - E;
    }
    const double dist = glm::length(g);
    s.directionIcrs = aberrate(g / dist, f.earthVelocityIcrs, f.path, glm::length(E));
    const glm::dvec3 tod = f.earth.celestialToTrueOfDate * s.directionIcrs;
    s.heliocentricDistanceAu = glm::length(P);
    s.phaseAngleRad = angleBetween(-P, -g);
    double subLatDeg = 0;
    if (body == Body::Saturn || body == Body::Uranus) {
        // IAU 2015 north poles (ICRS): Saturn (40.589, 83.537) deg, Uranus (257.311, -15.175) deg.
        const glm::dvec3 pole = body == Body::Saturn ? directionFromRaDec(40.589 * kDeg, 83.537 * kDeg)
                                                     : directionFromRaDec(257.311 * kDeg, -15.175 * kDeg);
        const double earthLat = std::asin(std::clamp(-glm::dot(pole, g / dist), -1.0, 1.0)) / kDeg;
        const double sunLat = std::asin(std::clamp(-glm::dot(pole, P / glm::length(P)), -1.0, 1.0)) / kDeg;
        if (body == Body::Saturn)
            subLatDeg = earthLat * sunLat > 0 ? std::sqrt(earthLat * sunLat) : 0.0;
        else
            subLatDeg = 0.5 * (std::fabs(earthLat) + std::fabs(sunLat));
    }
    const double year = 2000.0 + f.time.centuriesTT() * 100.0;
    s.magnitude = magnitude::planet(body, s.heliocentricDistanceAu, dist, s.phaseAngleRad / kDeg, subLatDeg, year);
    finish(s, sh, tod, dist);
    return s;
}

Shared makeShared(const ObserverFrame& frame) {
    checkValidity(frame);
    Shared sh;
    sh.frame = &frame;
    sh.precise = frame.path == Path::Precise;
    sh.tMillennia = julianMillenniaTT(frame.time.tt.day, frame.time.tt.fraction);
    return sh;
}

BodyState computeWith(Shared& sh, Body b) {
    if (!sh.haveSun) computeSun(sh);
    switch (b) {
        case Body::Sun: return sh.sun;
        case Body::Moon: return computeMoon(sh);
        default: return computePlanet(sh, b);
    }
}

}  // namespace

const char* bodyName(Body b) {
    static const char* names[] = {"sun", "moon", "mercury", "venus", "mars", "jupiter", "saturn", "uranus", "neptune"};
    return names[static_cast<int>(b)];
}

Body parseBody(std::string_view name) {
    std::string lower(name);
    for (char& c : lower) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    for (Body b : kAllBodies)
        if (lower == bodyName(b)) return b;
    throw Error("unknown body '" + std::string(name) + "' (expected sun, moon, mercury, venus, mars, jupiter, saturn, uranus, neptune)");
}

double bodyRadiusMeters(Body b) {
    switch (b) {
        case Body::Sun: return 695700e3;  // IAU 2015 nominal solar radius
        case Body::Moon: return 1737.4e3;
        case Body::Mercury: return 2440.53e3;
        case Body::Venus: return 6051.8e3;
        case Body::Mars: return 3396.19e3;
        case Body::Jupiter: return 71492e3;
        case Body::Saturn: return 60268e3;
        case Body::Uranus: return 25559e3;
        case Body::Neptune: return 24764e3;
    }
    return 1.0;
}

BodyState computeBody(Body body, const ObserverFrame& frame) {
    Shared sh = makeShared(frame);
    return computeWith(sh, body);
}

void Ephemeris::update(const ObserverFrame& frame) {
    Shared sh = makeShared(frame);
    sh.vsopCache = &vsop_;
    sh.moonCache = &moon_;
    for (Body b : kAllBodies) states_[static_cast<int>(b)] = computeWith(sh, b);
}

namespace magnitude {

double sun(double delta) { return -26.74 + 5.0 * std::log10(delta); }

double illuminanceLux(double m) { return std::pow(10.0, -0.4 * (m + 13.99)); }

namespace {
constexpr double kArcsec2Sr = (std::numbers::pi / (180.0 * 3600.0)) * (std::numbers::pi / (180.0 * 3600.0));  // 2.3504e-11 sr
}

double surfaceBrightnessCdM2(double m) {
    if (!std::isfinite(m)) throw Error("surfaceBrightnessCdM2(): magnitude not finite");
    return illuminanceLux(0.0) / kArcsec2Sr * std::pow(10.0, -0.4 * m);
}

double surfaceBrightnessMag(double cdM2) {
    if (!(cdM2 > 0.0)) throw Error("surfaceBrightnessMag(): luminance not > 0 cd/m^2");
    return -2.5 * std::log10(cdM2 * kArcsec2Sr / illuminanceLux(0.0));
}

double moon(double r, double delta, double a) {
    a = std::fabs(a);
    return 0.21 + 5.0 * std::log10(r * delta) + 0.026 * a + 4e-9 * a * a * a * a;
}

double planet(Body b, double r, double delta, double a, double subLat, double year) {
    const double dm = 5.0 * std::log10(r * delta);
    a = std::clamp(std::fabs(a), 0.0, 180.0);
    switch (b) {
        case Body::Mercury: {
            const double x = std::clamp(a, 0.0, 170.0);  // fitted over 2..170 deg
            return -0.613 + dm +
                   x * (6.3280e-02 + x * (-1.6336e-03 + x * (3.3644e-05 + x * (-3.4265e-07 + x * (1.6893e-09 - x * 3.0334e-12)))));
        }
        case Body::Venus:
            if (a < 163.7) return -4.384 + dm + a * (-1.044e-03 + a * (3.687e-04 + a * (-2.814e-06 + a * 8.938e-09)));
            return 236.05828 + dm - 2.81914 * a + 8.39034e-03 * a * a;
        case Body::Mars:
            if (a <= 50.0) return -1.601 + dm + 2.267e-02 * a - 1.302e-04 * a * a;
            return -0.367 + dm - 0.02573 * a + 0.0003445 * a * a;
        case Body::Jupiter: {
            if (a <= 12.0) return -9.395 + dm - 3.7e-04 * a + 6.16e-04 * a * a;
            const double x = a / 180.0;
            const double p = 1.0 - 1.507 * x - 0.363 * x * x - 0.062 * x * x * x + 2.809 * x * x * x * x - 1.876 * x * x * x * x * x;
            return -9.428 + dm - 2.5 * std::log10(std::max(p, 1e-6));
        }
        case Body::Saturn: {
            // Globe and rings (Mallama & Hilton eq. 10) inside the geocentric limits; the
            // globe-alone law (eq. 12) beyond them, where the rings' contribution is unmodelled.
            const double s = std::sin(std::fabs(subLat) * kDeg);
            if (a <= 6.5 && std::fabs(subLat) <= 27.0) return -8.914 + dm - 1.825 * s + 0.026 * a - 0.378 * s * std::exp(-2.25 * a);
            return -8.94 + dm + 2.446e-4 * a + 2.672e-4 * a * a - 1.506e-6 * a * a * a + 4.767e-9 * a * a * a * a;
        }
        case Body::Uranus: {
            double m = -7.110 + dm - 0.00084 * std::fabs(subLat);
            if (a > 3.1) m += 6.587e-3 * a + 1.045e-4 * a * a;
            return m;
        }
        case Body::Neptune: {
            double m = std::clamp(-6.89 - 0.0054 * (year - 1980.0), -7.00, -6.89) + dm;
            if (a > 1.9) m += 7.944e-3 * a + 9.617e-5 * a * a;
            return m;
        }
        default: return 0.0;
    }
}

}  // namespace magnitude

}  // namespace welkin::astro
