// Eclipse search: sampled separations, the maximum by golden section, contacts by bisection; the
// Earth's shadow as the Moon's light sees it.
#include <welkin/astro/eclipses.hpp>
#include <welkin/astro/events.hpp>
#include <welkin/astro/lunar_limb.hpp>
#include <welkin/color.hpp>
#include <welkin/error.hpp>
#include <welkin/glsl_cpp.hpp>

#include <algorithm>
#include <cmath>
#include <functional>
#include <numbers>

// The disks' overlap: the shaders' text (the Planet's eclipsed Sun), compiled here in double.
namespace welkin::glsl::dp::disk_overlap_shared {
const real WELKIN_PI = std::numbers::pi;  // (the GPU's: camera_projection.shared.glsl)
#include "../../shaders/disk_overlap.shared.glsl"
}  // namespace welkin::glsl::dp::disk_overlap_shared

namespace welkin::astro {

namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kDeg = kPi / 180.0;
// The Moon's radius in Earth equatorial radii (the Canon's values): C1/C4 and C2/C3.
constexpr double kMoonKOuter = 0.2725076, kMoonKInner = 0.272281;
// The upper limb on the horizon with the standard 34' refraction: geometric altitude of the
// centre + semi-diameter > -34'.
constexpr double kHorizonRefraction = -34.0 / 60.0 * kDeg;

double angleBetween(const glm::dvec3& a, const glm::dvec3& b) {
    return std::atan2(glm::length(glm::cross(a, b)), glm::dot(a, b));
}

UtcInstant instantAt(const JulianDate& jd0, double seconds) {
    return UtcInstant::fromJulianDate(jd0.plusDays(std::round(seconds) / 86400.0));
}

/// Golden-section minimum of f on [a, b], to `tol`.
double minimise(const std::function<double(double)>& f, double a, double b, double tol) {
    const double g = 0.5 * (std::sqrt(5.0) - 1.0);
    double c = b - g * (b - a), d = a + g * (b - a), fc = f(c), fd = f(d);
    while (b - a > tol) {
        if (fc < fd) {
            b = d; d = c; fd = fc; c = b - g * (b - a); fc = f(c);
        } else {
            a = c; c = d; fc = fd; d = a + g * (b - a); fd = f(d);
        }
    }
    return 0.5 * (a + b);
}

/// The zero of f between `inside` (f < 0) and the first sample `step` apart going in `dir` where
/// f >= 0 (at most `maxSteps` steps), refined by bisection to 0.05 s. nullopt if none.
std::optional<double> contact(const std::function<double(double)>& f, double inside, double dir, double step, int maxSteps) {
    double a = inside, b = inside;
    bool found = false;
    for (int i = 0; i < maxSteps; ++i) {
        b = a + dir * step;
        if (f(b) >= 0.0) { found = true; break; }
        a = b;
    }
    if (!found) return std::nullopt;
    while (std::abs(b - a) > 0.05) {
        const double m = 0.5 * (a + b);
        if (f(m) < 0.0) a = m; else b = m;
    }
    return 0.5 * (a + b);
}

struct SolarGeom {
    double sep = 0, sunRad = 0, moonOuterRad = 0, moonInnerRad = 0, sunAlt = 0;
    double sunPaRad = 0;   // the Sun's centre seen from the Moon's, from the Moon's north pole through east
    double moonDistM = 0;  // topocentric
};

SolarGeom solarAt(const Site& site, const JulianDate& jd0, Path path, double t) {
    const ObserverFrame f = observerFrame(site, timeScales(jd0.plusDays(t / 86400.0)), path);
    const BodyState sun = computeBody(Body::Sun, f), moon = computeBody(Body::Moon, f);
    SolarGeom g;
    g.sep = angleBetween(sun.topo.enuGeometric, moon.topo.enuGeometric);
    g.sunRad = 0.5 * sun.angularDiameterRad;
    g.moonOuterRad = std::asin(kMoonKOuter * kEarthEquatorialRadiusMeters / moon.topo.distanceMeters);
    g.moonInnerRad = std::asin(kMoonKInner * kEarthEquatorialRadiusMeters / moon.topo.distanceMeters);
    g.sunAlt = sun.topo.altitudeGeometricRad;
    g.moonDistM = moon.topo.distanceMeters;
    // Position angle on the sky at the Moon's centre c: north towards the celestial pole (ENU
    // (0, cos lat, sin lat): the pole of date within the precession since J2000, < 0.5 deg),
    // east = pole x c; then from the Moon's own north pole (its axis' position angle P).
    const glm::dvec3 c = glm::normalize(moon.topo.enuGeometric), s = glm::normalize(sun.topo.enuGeometric);
    const glm::dvec3 pole(0.0, std::cos(site.latitudeRad), std::sin(site.latitudeRad));
    const glm::dvec3 east = glm::normalize(glm::cross(pole, c)), north = glm::cross(c, east);
    g.sunPaRad = std::atan2(glm::dot(s, east), glm::dot(s, north)) - moon.axisAngleRad;
    return g;
}

LimbGeometry limbGeometry(const SolarGeom& g, bool profile) {
    return {.separationRad = g.sep, .sunPaRad = g.sunPaRad, .sunRadiusRad = g.sunRad, .moonDistanceM = g.moonDistM, .profile = profile};
}

struct LunarGeom {
    double sep = 0, moonRad = 0, umbraRad = 0, penumbraRad = 0, moonAlt = 0, moonTopoRad = 0;
};

LunarGeom lunarAt(const Site& site, const JulianDate& jd0, Path path, double t) {
    const ObserverFrame f = observerFrame(site, timeScales(jd0.plusDays(t / 86400.0)), path);
    const BodyState sun = computeBody(Body::Sun, f), moon = computeBody(Body::Moon, f);
    LunarGeom g;
    g.sep = angleBetween(moon.directionIcrs, -sun.directionIcrs);
    const double piM = std::asin(kEarthEquatorialRadiusMeters / moon.distanceMeters);
    const double piS = std::asin(kEarthEquatorialRadiusMeters / sun.distanceMeters);
    const double sS = std::asin(bodyRadiusMeters(Body::Sun) / sun.distanceMeters);
    g.moonRad = std::asin(bodyRadiusMeters(Body::Moon) / moon.distanceMeters);
    g.umbraRad = kEarthShadowFactor * piM - sS + piS;
    g.penumbraRad = kEarthShadowFactor * piM + sS + piS;
    g.moonAlt = moon.topo.altitudeGeometricRad;
    g.moonTopoRad = 0.5 * moon.angularDiameterRad;
    return g;
}

void checkWindow(const UtcInstant& from, const UtcInstant& to, const char* who) {
    const double days = daysBetween(from.julianDate(), to.julianDate());
    if (!(days >= 0.0 && days <= 20.0 * 366.0))
        throw Error(std::string(who) + ": the window from " + from.toIso() + " to " + to.toIso() + " must be 0 to 20 years long");
}

/// Every instant of the given Moon quarter in [from - 1 d, to + 1 d].
std::vector<UtcInstant> quarters(const UtcInstant& from, const UtcInstant& to, MoonQuarter q, Path path) {
    std::vector<UtcInstant> out;
    UtcInstant t = from.plusSeconds(-86400.0);
    const double endDays = daysBetween(from.julianDate(), to.julianDate()) + 1.0;
    for (;;) {
        const UtcInstant n = nextMoonQuarter(t, q, path);
        if (daysBetween(from.julianDate(), n.julianDate()) > endDays) break;
        out.push_back(n);
        t = n.plusSeconds(86400.0);
    }
    return out;
}

bool within(const UtcInstant& t, const UtcInstant& from, const UtcInstant& to) {
    return daysBetween(from.julianDate(), t.julianDate()) >= 0.0 && daysBetween(t.julianDate(), to.julianDate()) >= 0.0;
}

}  // namespace

const char* toString(SolarEclipseType t) {
    switch (t) {
        case SolarEclipseType::Annular: return "annular";
        case SolarEclipseType::Total: return "total";
        default: return "partial";
    }
}

const char* toString(LunarEclipseType t) {
    switch (t) {
        case LunarEclipseType::Partial: return "partial";
        case LunarEclipseType::Total: return "total";
        default: return "penumbral";
    }
}

std::vector<SolarEclipseLocal> findSolarEclipses(const Site& site, const UtcInstant& from, const UtcInstant& to, Path path) {
    validate(site);
    checkWindow(from, to, "findSolarEclipses()");
    std::vector<SolarEclipseLocal> out;
    for (const UtcInstant& newMoon : quarters(from, to, MoonQuarter::New, path)) {
        const JulianDate jd0 = newMoon.julianDate();
        auto geom = [&](double t) { return solarAt(site, jd0, path, t); };
        auto outer = [&](double t) { const SolarGeom g = geom(t); return g.sep - (g.sunRad + g.moonOuterRad); };
        // The topocentric maximum is within ~3 h of the geocentric conjunction in longitude
        // (parallax <= 1 deg at ~0.5 deg/h relative motion): sample +-7 h every 4 min.
        constexpr double kHalf = 7 * 3600.0, kStep = 240.0;
        double best = 0.0, bestSep = 1e9;
        for (double t = -kHalf; t <= kHalf; t += kStep) {
            const SolarGeom g = geom(t);
            const double s = g.sep - (g.sunRad + g.moonOuterRad);
            if (s < bestSep) { bestSep = s; best = t; }
        }
        if (bestSep > 0.2 * kDeg) continue;  // far from any contact: no eclipse this month
        const double tMax = minimise([&](double t) { return geom(t).sep; }, best - kStep, best + kStep, 0.05);
        const SolarGeom gm = geom(tMax);
        if (gm.sep >= gm.sunRad + gm.moonOuterRad) continue;
        const UtcInstant maxInstant = instantAt(jd0, tMax);
        if (!within(maxInstant, from, to)) continue;

        SolarEclipseLocal e;
        e.maximum = {maxInstant, gm.sunAlt};
        const double rs = gm.sunRad, rm = gm.moonInnerRad, d = gm.sep;
        e.magnitude = std::max(0.0, (rs + rm - d) / (2.0 * rs));
        e.obscuration = 1.0 - lensVisibleFraction(rs, rm, d);
        e.moonSunRatio = rm / rs;
        const auto c1 = contact(outer, tMax, -1.0, kStep, 120), c4 = contact(outer, tMax, +1.0, kStep, 120);
        if (!c1 || !c4) throw Error("findSolarEclipses(): no first or last contact within 8 h of the maximum (internal error)");
        e.c1 = {instantAt(jd0, *c1), geom(*c1).sunAlt};
        e.c4 = {instantAt(jd0, *c4), geom(*c4).sunAlt};
        if (d < std::abs(rm - rs)) {
            e.type = rm > rs ? SolarEclipseType::Total : SolarEclipseType::Annular;
            auto inner = [&](double t) { const SolarGeom g = geom(t); return g.sep - std::abs(g.moonInnerRad - g.sunRad); };
            const auto c2 = contact(inner, tMax, -1.0, 30.0, 40), c3 = contact(inner, tMax, +1.0, 30.0, 40);
            if (c2 && c3) {
                e.c2 = EclipseContact{instantAt(jd0, *c2), geom(*c2).sunAlt};
                e.c3 = EclipseContact{instantAt(jd0, *c3), geom(*c3).sunAlt};
                e.durationSeconds = *c3 - *c2;
                // With the limb's profile, and with a smooth limb at the profile's mean radius
                // (the Canon's C2/C3 radius, k = 0.272281, is 0.74 km smaller: an allowance for
                // the valleys). The profiled contacts lie within the profile's extremes of the
                // mean-radius ones: a valley delays C2 by at most its depth over the rate at which
                // the Moon's limb advances over the Sun's.
                const bool total = e.type == SolarEclipseType::Total;
                auto margin = [&](double t, bool profile) {
                    const LimbGeometry lg = limbGeometry(geom(t), profile);
                    return total ? limbCoverMargin(lg) : limbInsideMargin(lg);
                };
                const auto m2 = contact([&](double t) { return margin(t, false); }, tMax, -1.0, 30.0, 40);
                const auto m3 = contact([&](double t) { return margin(t, false); }, tMax, +1.0, 30.0, 40);
                const auto l2 = contact([&](double t) { return margin(t, true); }, tMax, -1.0, 2.0, 600);
                const auto l3 = contact([&](double t) { return margin(t, true); }, tMax, +1.0, 2.0, 600);
                if (margin(tMax, true) < 0.0 && l2 && l3 && m2 && m3) {
                    e.c2Limb = EclipseContact{instantAt(jd0, *l2), geom(*l2).sunAlt};
                    e.c3Limb = EclipseContact{instantAt(jd0, *l3), geom(*l3).sunAlt};
                    e.c2LimbShiftSeconds = *l2 - *m2;
                    e.c3LimbShiftSeconds = *l3 - *m3;
                    e.c2MeanShiftSeconds = *m2 - *c2;
                    e.c3MeanShiftSeconds = *m3 - *c3;
                }
            }
        }
        // Visible: the upper limb above the horizon at some sampled instant from C1 to C4.
        for (double t = *c1;; t = std::min(t + kStep, *c4)) {
            const SolarGeom g = geom(t);
            if (g.sunAlt + g.sunRad > kHorizonRefraction) { e.visible = true; break; }
            if (t >= *c4) break;
        }
        out.push_back(e);
    }
    return out;
}

std::vector<LunarEclipse> findLunarEclipses(const Site& site, const UtcInstant& from, const UtcInstant& to, Path path) {
    validate(site);
    checkWindow(from, to, "findLunarEclipses()");
    std::vector<LunarEclipse> out;
    for (const UtcInstant& fullMoon : quarters(from, to, MoonQuarter::Full, path)) {
        const JulianDate jd0 = fullMoon.julianDate();
        auto geom = [&](double t) { return lunarAt(site, jd0, path, t); };
        // Greatest eclipse is within ~1 h of opposition in longitude; P1 up to ~3.5 h before.
        constexpr double kHalf = 5 * 3600.0, kStep = 360.0;
        double best = 0.0, bestSep = 1e9;
        for (double t = -kHalf; t <= kHalf; t += kStep) {
            const double s = geom(t).sep;
            if (s < bestSep) { bestSep = s; best = t; }
        }
        if (bestSep > 2.0 * kDeg) continue;  // the penumbra's radius + the Moon's is < 1.6 deg
        const double tMax = minimise([&](double t) { return geom(t).sep; }, best - kStep, best + kStep, 0.05);
        const LunarGeom gm = geom(tMax);
        if (gm.sep >= gm.penumbraRad + gm.moonRad) continue;
        const UtcInstant greatest = instantAt(jd0, tMax);
        if (!within(greatest, from, to)) continue;

        LunarEclipse e;
        e.greatest = {greatest, gm.moonAlt};
        e.umbralMagnitude = (gm.umbraRad + gm.moonRad - gm.sep) / (2.0 * gm.moonRad);
        e.penumbralMagnitude = (gm.penumbraRad + gm.moonRad - gm.sep) / (2.0 * gm.moonRad);
        auto edge = [&](double which) {
            return [&, which](double t) {
                const LunarGeom g = geom(t);
                // which: +1 penumbra outer, 0 umbra outer, -1 umbra inner (the Moon wholly inside)
                const double r = which > 0.5 ? g.penumbraRad + g.moonRad : which > -0.5 ? g.umbraRad + g.moonRad : g.umbraRad - g.moonRad;
                return g.sep - r;
            };
        };
        auto pair = [&](double which, int maxSteps) -> std::optional<std::pair<EclipseContact, EclipseContact>> {
            const auto f = edge(which);
            if (f(tMax) >= 0.0) return std::nullopt;
            const auto a = contact(f, tMax, -1.0, kStep, maxSteps), b = contact(f, tMax, +1.0, kStep, maxSteps);
            if (!a || !b) throw Error("findLunarEclipses(): a contact beyond 5 h of greatest eclipse (internal error)");
            return std::pair{EclipseContact{instantAt(jd0, *a), geom(*a).moonAlt}, EclipseContact{instantAt(jd0, *b), geom(*b).moonAlt}};
        };
        const auto pen = pair(1.0, 50);
        if (!pen) continue;
        e.p1 = pen->first;
        e.p4 = pen->second;
        if (const auto u = pair(0.0, 50)) {
            e.type = LunarEclipseType::Partial;
            e.u1 = u->first;
            e.u4 = u->second;
            if (const auto tot = pair(-1.0, 50)) {
                e.type = LunarEclipseType::Total;
                e.u2 = tot->first;
                e.u3 = tot->second;
            }
        }
        const double t1 = daysBetween(jd0, e.p1.time.julianDate()) * 86400.0, t4 = daysBetween(jd0, e.p4.time.julianDate()) * 86400.0;
        for (double t = t1;; t = std::min(t + kStep, t4)) {
            const LunarGeom g = geom(t);
            if (g.moonAlt + g.moonTopoRad > kHorizonRefraction) { e.visible = true; break; }
            if (t >= t4) break;
        }
        out.push_back(e);
    }
    return out;
}

// --- The shadow's light ---------------------------------------------------------------------------

glm::dvec3 umbraColour() {
    const glm::dvec3 c{1.0, 0.30, 0.08};  // linear sRGB before normalisation
    return c / color::luminance(c);
}

double lensVisibleFraction(double rs, double re, double d) {
    if (!(rs > 0.0)) return 1.0;
    return glsl::dp::disk_overlap_shared::welkin_diskVisibleFraction(rs, std::max(re, 0.0), std::abs(d));  // the shaders' text
}

ShadowLight earthShadowLight(const glm::dvec3& P, const glm::dvec3& sunFromEarth) {
    const glm::dvec3 S = sunFromEarth - P;
    const double dS = glm::length(S), dE = glm::length(P);
    const double rs = std::asin(std::min(bodyRadiusMeters(Body::Sun) / dS, 1.0));
    const double re = std::asin(std::min(kEarthShadowRadiusMeters / dE, 1.0));
    const double sep = angleBetween(S, -P);
    ShadowLight l;
    l.direct = lensVisibleFraction(rs, re, sep);
    if (l.direct < 1.0) {
        // Depth: 0 on the shadow's axis, 1 at the umbra's edge (and beyond, in the penumbra).
        const double depth = std::clamp(sep / std::max(re - rs, 1e-9), 0.0, 1.0);
        l.refracted = (1.0 - l.direct) * (kUmbraRefractedCentre + (kUmbraRefractedEdge - kUmbraRefractedCentre) * depth * depth);
    }
    return l;
}

ShadowLight moonShadowLight(const glm::dvec3& M, const glm::dvec3& sunFromEarth) {
    const double rMoon = bodyRadiusMeters(Body::Moon);
    // Quick reject: the Moon's centre farther from the shadow's axis than the penumbra's radius
    // there plus the Moon's radius (+1 %).
    const glm::dvec3 axis = -glm::normalize(sunFromEarth);
    const double along = glm::dot(M, axis);
    const double off = glm::length(M - along * axis);
    const double penumbra = kEarthShadowRadiusMeters + along * (bodyRadiusMeters(Body::Sun) + kEarthShadowRadiusMeters) / glm::length(sunFromEarth);
    if (along <= 0.0 || off > 1.01 * (penumbra + rMoon)) return {};
    // A 12 x 12 grid on the disk facing the Earth (points of the projected disk).
    const glm::dvec3 w = -glm::normalize(M);
    const glm::dvec3 u = glm::normalize(glm::cross(std::abs(w.z) < 0.9 ? glm::dvec3(0, 0, 1) : glm::dvec3(1, 0, 0), w));
    const glm::dvec3 v = glm::cross(w, u);
    constexpr int kN = 12;
    ShadowLight sum{0.0, 0.0};
    int count = 0;
    for (int i = 0; i < kN; ++i)
        for (int j = 0; j < kN; ++j) {
            const double x = (i + 0.5) / kN * 2.0 - 1.0, y = (j + 0.5) / kN * 2.0 - 1.0;
            if (x * x + y * y > 1.0) continue;
            const glm::dvec3 p = M + rMoon * (x * u + y * v + std::sqrt(1.0 - x * x - y * y) * w);
            const ShadowLight l = earthShadowLight(p, sunFromEarth);
            sum.direct += l.direct;
            sum.refracted += l.refracted;
            ++count;
        }
    return {sum.direct / count, sum.refracted / count};
}

}  // namespace welkin::astro
