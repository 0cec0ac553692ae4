// Event search: sampled altitude functions, sign changes refined by bisection.
#include <welkin/astro/events.hpp>
#include <welkin/error.hpp>

#include <cmath>
#include <numbers>
#include <vector>

namespace welkin::astro {

namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kDeg = kPi / 180.0;
constexpr double kSunriseAltitude = -0.8333 * kDeg;
constexpr double kMoonRefraction = -34.0 / 60.0 * kDeg;

JulianDate jdPlusSeconds(const JulianDate& jd, double s) { return jd.plusDays(s / 86400.0); }

UtcInstant instantRounded(const JulianDate& start, double seconds) {
    // Round to whole seconds for display; events are not known better than that anyway.
    return UtcInstant::fromJulianDate(jdPlusSeconds(start, std::round(seconds)));
}

/// Altitude function relative to a threshold at `seconds` after the start.
struct AltitudeFunction {
    Site site;
    JulianDate start;
    Path path;
    Body body;
    double threshold;
    bool moonLimb;
    double operator()(double seconds) const {
        TimeScales ts = timeScales(jdPlusSeconds(start, seconds));
        ObserverFrame f = observerFrame(site, ts, path);
        BodyState s = computeBody(body, f);
        double h = s.topo.altitudeGeometricRad - threshold;
        if (moonLimb) h += 0.5 * s.angularDiameterRad;
        return h;
    }
};

double bisect(const AltitudeFunction& fn, double a, double fa, double b) {
    for (int i = 0; i < 40 && b - a > 0.01; ++i) {
        const double m = 0.5 * (a + b);
        const double fm = fn(m);
        if ((fm > 0) == (fa > 0)) {
            a = m;
            fa = fm;
        } else {
            b = m;
        }
    }
    return 0.5 * (a + b);
}

/// Golden-section search for the extremum of fn in [a, b] (maximum if `maximum`).
double extremum(const AltitudeFunction& fn, double a, double b, bool maximum, double& value) {
    const double g = 0.5 * (std::sqrt(5.0) - 1.0);
    double c = b - g * (b - a), d = a + g * (b - a);
    double fc = fn(c), fd = fn(d);
    if (!maximum) fc = -fc, fd = -fd;
    while (b - a > 1.0) {
        if (fc > fd) {
            b = d, d = c, fd = fc;
            c = b - g * (b - a);
            fc = maximum ? fn(c) : -fn(c);
        } else {
            a = c, c = d, fc = fd;
            d = a + g * (b - a);
            fd = maximum ? fn(d) : -fn(d);
        }
    }
    const double x = 0.5 * (a + b);
    value = fn(x);
    return x;
}

struct Crossings {
    std::optional<double> rising, setting;  // seconds from start
    bool alwaysAbove = false, alwaysBelow = false;
};

Crossings scan(const AltitudeFunction& fn, double hours) {
    const double step = 600.0;
    const int n = static_cast<int>(std::ceil(hours * 3600.0 / step));
    std::vector<double> t(n + 1), v(n + 1);
    for (int i = 0; i <= n; ++i) {
        t[i] = std::min(i * step, hours * 3600.0);
        v[i] = fn(t[i]);
    }
    Crossings c;
    auto record = [&](double x, bool rising) {
        auto& slot = rising ? c.rising : c.setting;
        if (!slot || x < *slot) slot = x;
    };
    bool anyAbove = false, anyBelow = false;
    for (int i = 0; i < n; ++i) {
        (v[i] > 0 ? anyAbove : anyBelow) = true;
        if ((v[i] > 0) != (v[i + 1] > 0)) {
            record(bisect(fn, t[i], v[i], t[i + 1]), v[i + 1] > 0);
        } else if (i + 2 <= n && (v[i + 1] > 0) == (v[i + 2] > 0)) {
            // Grazing: a local extremum at sample i+1 within the altitude change of one step of
            // the threshold may hide two crossings between samples i and i+2.
            const bool isMax = v[i + 1] >= v[i] && v[i + 1] >= v[i + 2];
            const bool isMin = v[i + 1] <= v[i] && v[i + 1] <= v[i + 2];
            const double slope = std::max(std::fabs(v[i + 1] - v[i]), std::fabs(v[i + 2] - v[i + 1]));
            if ((isMax && v[i + 1] <= 0 && -v[i + 1] < 2 * slope) || (isMin && v[i + 1] > 0 && v[i + 1] < 2 * slope)) {
                double ve = 0;
                const double te = extremum(fn, t[i], t[i + 2], isMax, ve);
                if ((ve > 0) != (v[i + 1] > 0)) {
                    const double x1 = bisect(fn, t[i], v[i], te);
                    const double x2 = bisect(fn, te, ve, t[i + 2]);
                    record(x1, isMax);
                    record(x2, !isMax);
                }
            }
        }
    }
    (v[n] > 0 ? anyAbove : anyBelow) = true;
    c.alwaysAbove = !c.rising && !c.setting && anyAbove && !anyBelow;
    c.alwaysBelow = !c.rising && !c.setting && anyBelow && !anyAbove;
    return c;
}

}  // namespace

const char* toString(PolarState p) {
    switch (p) {
        case PolarState::Day: return "day";
        case PolarState::Night: return "night";
        default: return "none";
    }
}

const char* toString(MoonQuarter q) {
    static const char* names[] = {"new_moon", "first_quarter", "full_moon", "last_quarter"};
    return names[static_cast<int>(q)];
}

std::optional<UtcInstant> findCrossing(const Site& site, const UtcInstant& start, Path path, Body body, double thresholdRad,
                                       int direction, double hours, bool moonLimb) {
    validate(site);
    if (!(hours >= 1.0 && hours <= 48.0)) throw Error("findCrossing(): hours " + std::to_string(hours) + " not in [1, 48]");
    AltitudeFunction fn{site, start.julianDate(), path, body, thresholdRad, moonLimb};
    Crossings c = scan(fn, hours);
    const auto& x = direction > 0 ? c.rising : c.setting;
    if (!x) return std::nullopt;
    return instantRounded(start.julianDate(), *x);
}

DayEvents findDayEvents(const Site& site, const UtcInstant& start, Path path, double hours) {
    validate(site);
    if (!(hours >= 1.0 && hours <= 48.0)) throw Error("findDayEvents(): hours " + std::to_string(hours) + " not in [1, 48]");
    const JulianDate jd0 = start.julianDate();
    DayEvents ev;
    auto run = [&](Body body, double threshold, bool limb, std::optional<UtcInstant>& rise, std::optional<UtcInstant>& set) {
        AltitudeFunction fn{site, jd0, path, body, threshold, limb};
        Crossings c = scan(fn, hours);
        if (c.rising) rise = instantRounded(jd0, *c.rising);
        if (c.setting) set = instantRounded(jd0, *c.setting);
        return c;
    };
    Crossings sun = run(Body::Sun, kSunriseAltitude, false, ev.sunrise, ev.sunset);
    ev.polar = sun.alwaysAbove ? PolarState::Day : sun.alwaysBelow ? PolarState::Night : PolarState::None;
    run(Body::Sun, -6.0 * kDeg, false, ev.civilDawn, ev.civilDusk);
    run(Body::Sun, -12.0 * kDeg, false, ev.nauticalDawn, ev.nauticalDusk);
    run(Body::Sun, -18.0 * kDeg, false, ev.astronomicalDawn, ev.astronomicalDusk);
    run(Body::Moon, kMoonRefraction, true, ev.moonrise, ev.moonset);
    return ev;
}

UtcInstant nextMoonQuarter(const UtcInstant& start, MoonQuarter q, Path path) {
    const JulianDate jd0 = start.julianDate();
    const double target = static_cast<int>(q) * 0.5 * kPi;
    // Elongation in ecliptic longitude (Moon - Sun) minus the target, wrapped to (-pi, pi]: it
    // increases by ~12.2 deg/day, so it crosses zero upwards exactly once per synodic month.
    auto f = [&](double days) {
        TimeScales ts = timeScales(jd0.plusDays(days));
        ObserverFrame fr = observerFrame(Site{}, ts, path);
        BodyState sun = computeBody(Body::Sun, fr), moon = computeBody(Body::Moon, fr);
        const double eps = fr.earth.trueObliquity;
        auto lon = [&](const BodyState& s) {
            glm::dvec3 v = directionFromRaDec(s.raRad, s.decRad);
            return std::atan2(v.y * std::cos(eps) + v.z * std::sin(eps), v.x);
        };
        double d = std::remainder(lon(moon) - lon(sun) - target, 2 * kPi);
        return d;
    };
    double a = 0, fa = f(0);
    for (double b = 0.5; b <= 32.0; b += 0.5) {
        const double fb = f(b);
        if (fa <= 0 && fb > 0 && fb - fa < kPi) {
            for (int i = 0; i < 40 && b - a > 1e-6; ++i) {
                const double m = 0.5 * (a + b), fm = f(m);
                if (fm > 0) b = m; else a = m;
            }
            return UtcInstant::fromJulianDate(jd0.plusDays(std::round(0.5 * (a + b) * 86400.0) / 86400.0));
        }
        a = b;
        fa = fb;
    }
    throw Error("nextMoonQuarter(): no quarter found in 32 days (internal error)");
}

}  // namespace welkin::astro
