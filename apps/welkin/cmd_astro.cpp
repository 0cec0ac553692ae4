// `welkin astro`: positions, sizes, brightness and phases of the Sun, Moon and planets for a
// place and time, optionally with the day's rise/set/twilight events.
//
//   welkin astro --time 2026-06-21T21:00:00Z --lat 52.5 --lon 13.4 --events --json
//   welkin astro --time 2026-08-01T00:00:00Z --lat 42.34 --lon -3.70 --events --to 2026-09-01T00:00:00Z
//
// --events adds the solar eclipses (local circumstances: contacts C1..C4, maximum, magnitude,
// obscuration, type seen from the site) and lunar eclipses (P1, U1..U4, P4, magnitudes) in the
// window --from .. --to (default: --time .. --time + 366 days); see welkin/astro/eclipses.hpp.
#include "command.hpp"

#include <welkin/astro/bodies.hpp>
#include <welkin/astro/eclipses.hpp>
#include <welkin/astro/events.hpp>
#include <welkin/error.hpp>

#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

namespace {

using namespace welkin;
using namespace welkin::astro;

constexpr double kDeg = std::numbers::pi / 180.0;

struct AstroOptions {
    std::string time;
    std::string lat, lon, height = "0";  // parsed by run(): bad numbers are one-line errors
    std::string bodies = "sun,moon,mercury,venus,mars,jupiter,saturn,uranus,neptune";
    bool precise = false;
    std::string refraction = "on";
    bool events = false;
    bool json = false;
    std::string pressure = "1013.25", temperature = "10";
    std::string from, to;  // eclipse window (with --events)
};

std::vector<Body> parseBodies(const std::string& list) {
    std::vector<Body> out;
    std::stringstream ss(list);
    std::string item;
    while (std::getline(ss, item, ',')) {
        if (item.empty()) continue;
        Body b = parseBody(item);
        bool seen = false;
        for (Body x : out) seen = seen || x == b;
        if (!seen) out.push_back(b);
    }
    if (out.empty()) throw Error("--bodies: empty list");
    return out;
}

double round6(double x) { return std::round(x * 1e6) / 1e6; }
double deg(double rad) { return round6(rad / kDeg); }

nlohmann::json bodyJson(const BodyState& s) {
    nlohmann::json j;
    j["ra_deg"] = deg(s.raRad);
    j["dec_deg"] = deg(s.decRad);
    j["az_deg"] = deg(s.topo.azimuthRad);
    j["alt_deg"] = deg(s.topo.altitudeRad);
    j["alt_geometric_deg"] = deg(s.topo.altitudeGeometricRad);
    j["distance_km"] = std::round(s.distanceMeters / 1e3 * 1e3) / 1e3;
    j["angular_diameter_deg"] = std::round(s.angularDiameterRad / kDeg * 1e8) / 1e8;
    j["magnitude"] = std::round(s.magnitude * 1e3) / 1e3;
    j["phase_angle_deg"] = deg(s.phaseAngleRad);
    j["illuminated_fraction"] = round6(s.illuminatedFraction);
    j["bright_limb_angle_deg"] = deg(s.brightLimbAngleRad);
    if (s.body == Body::Moon) {
        j["libration_lon_deg"] = deg(s.librationLonRad);
        j["libration_lat_deg"] = deg(s.librationLatRad);
        j["axis_angle_deg"] = deg(s.axisAngleRad);
    }
    return j;
}

nlohmann::json optIso(const std::optional<UtcInstant>& t) { return t ? nlohmann::json(t->toIso()) : nlohmann::json(nullptr); }

nlohmann::json contactJson(const EclipseContact& c, const char* altName) {
    nlohmann::json j;
    j["time"] = c.time.toIso();
    j[altName] = std::round(c.altitudeRad / kDeg * 1e3) / 1e3;
    return j;
}
nlohmann::json contactJson(const std::optional<EclipseContact>& c, const char* altName) {
    return c ? contactJson(*c, altName) : nlohmann::json(nullptr);
}

nlohmann::json solarJson(const SolarEclipseLocal& e) {
    nlohmann::json j;
    j["type"] = toString(e.type);
    j["visible"] = e.visible;
    j["magnitude"] = std::round(e.magnitude * 1e4) / 1e4;
    j["obscuration"] = std::round(e.obscuration * 1e4) / 1e4;
    j["duration_s"] = std::round(e.durationSeconds * 10) / 10;
    j["moon_sun_ratio"] = std::round(e.moonSunRatio * 1e5) / 1e5;
    const char* alt = "sun_alt_deg";
    j["c1"] = contactJson(e.c1, alt);
    j["c2"] = contactJson(e.c2, alt);
    j["maximum"] = contactJson(e.maximum, alt);
    j["c3"] = contactJson(e.c3, alt);
    j["c4"] = contactJson(e.c4, alt);
    // C2/C3 with the lunar limb's profile (the last bead vanishes / the first appears), and their
    // shifts: against a smooth limb at the mean radius, and that limb's against c2/c3 (the Canon's).
    j["c2_limb"] = contactJson(e.c2Limb, alt);
    j["c3_limb"] = contactJson(e.c3Limb, alt);
    if (e.c2Limb) {
        j["c2_limb_shift_s"] = std::round(e.c2LimbShiftSeconds * 10) / 10;
        j["c3_limb_shift_s"] = std::round(e.c3LimbShiftSeconds * 10) / 10;
        j["c2_mean_radius_shift_s"] = std::round(e.c2MeanShiftSeconds * 10) / 10;
        j["c3_mean_radius_shift_s"] = std::round(e.c3MeanShiftSeconds * 10) / 10;
    }
    return j;
}

nlohmann::json lunarJson(const LunarEclipse& e) {
    nlohmann::json j;
    j["type"] = toString(e.type);
    j["visible"] = e.visible;
    j["umbral_magnitude"] = std::round(e.umbralMagnitude * 1e4) / 1e4;
    j["penumbral_magnitude"] = std::round(e.penumbralMagnitude * 1e4) / 1e4;
    const char* alt = "moon_alt_deg";
    j["p1"] = contactJson(e.p1, alt);
    j["u1"] = contactJson(e.u1, alt);
    j["u2"] = contactJson(e.u2, alt);
    j["greatest"] = contactJson(e.greatest, alt);
    j["u3"] = contactJson(e.u3, alt);
    j["u4"] = contactJson(e.u4, alt);
    j["p4"] = contactJson(e.p4, alt);
    return j;
}

void printContact(const char* name, const std::optional<EclipseContact>& c, const char* body) {
    if (!c) return;
    std::printf("    %-8s %s  %s alt %7.2f deg%s\n", name, c->time.toIso().c_str(), body, c->altitudeRad / kDeg,
                c->altitudeRad < 0 ? "  (below the horizon)" : "");
}

/// A number from the command line within [lo, hi]; throws a one-line Error naming the option.
double number(const std::string& option, const std::string& text, double lo, double hi, const char* unit) {
    if (text.empty()) throw Error(option + " is required");
    char* end = nullptr;
    const double v = std::strtod(text.c_str(), &end);
    if (end == text.c_str() || *end != '\0' || !std::isfinite(v)) throw Error(option + " '" + text + "': not a number");
    if (v < lo || v > hi) {
        char buf[128];
        std::snprintf(buf, sizeof buf, " not in [%g, %g] %s", lo, hi, unit);
        throw Error(option + " " + text + buf);
    }
    return v;
}

int run(const AstroOptions& opt) {
    if (opt.time.empty()) throw Error("--time is required (ISO 8601, e.g. 2026-06-21T21:00:00Z)");
    struct {
        double lat, lon, height, pressure, temperature;
        const std::string& refraction;
        const std::string& bodies;
        bool precise, events, json;
    } o{number("--lat", opt.lat, -90, 90, "deg"),
        number("--lon", opt.lon, -180, 180, "deg"),
        number("--height", opt.height, -1e4, 1e8, "m"),
        number("--pressure", opt.pressure, 0, 2000, "hPa"),
        number("--temperature", opt.temperature, -100, 100, "C"),
        opt.refraction, opt.bodies, opt.precise, opt.events, opt.json};
    if (o.refraction != "on" && o.refraction != "off") throw Error("--refraction '" + o.refraction + "': expected on or off");
    const UtcInstant t = UtcInstant::parse(opt.time);
    const std::vector<Body> bodies = parseBodies(o.bodies);
    Site site{o.lat * kDeg, o.lon * kDeg, o.height, o.refraction == "on" ? o.pressure : 0.0, o.temperature};
    validate(site);
    const Path path = o.precise ? Path::Precise : Path::Fast;
    const TimeScales ts = timeScales(t);
    const ObserverFrame frame = observerFrame(site, ts, path);
    Ephemeris eph;
    eph.update(frame);
    std::optional<DayEvents> ev;
    if (!o.events && (!opt.from.empty() || !opt.to.empty())) throw Error("--from/--to: the eclipse window needs --events");
    const UtcInstant from = opt.from.empty() ? t : UtcInstant::parse(opt.from);
    const UtcInstant to = opt.to.empty() ? from.plusSeconds(366.0 * 86400.0) : UtcInstant::parse(opt.to);
    if (o.events) {
        const double days = daysBetween(from.julianDate(), to.julianDate());
        if (!(days >= 0.0 && days <= 20.0 * 366.0))
            throw Error("--to " + to.toIso() + ": must be 0 to 20 years after --from " + from.toIso());
    }
    std::vector<SolarEclipseLocal> solar;
    std::vector<LunarEclipse> lunar;
    if (o.events) {
        Site eventSite = site;
        eventSite.pressureHpa = 1013.25;  // events use the standard refraction in their definitions
        ev = findDayEvents(eventSite, t, path);
        solar = findSolarEclipses(eventSite, from, to, path);
        lunar = findLunarEclipses(eventSite, from, to, path);
    }

    if (o.json) {
        nlohmann::json j;
        j["time"] = t.toIso();
        j["path"] = o.precise ? "precise" : "fast";
        j["jd_ut"] = ts.ut1.day + ts.ut1.fraction;
        j["jd_tt"] = ts.tt.day + ts.tt.fraction;
        j["delta_t_s"] = std::round(ts.deltaTSeconds * 1e3) / 1e3;
        j["gmst_deg"] = deg(frame.earth.gmst);
        j["last_deg"] = deg(frame.lastRad);
        nlohmann::json jb = nlohmann::json::object();
        for (Body b : bodies) jb[bodyName(b)] = bodyJson(eph[b]);
        j["bodies"] = jb;
        if (ev) {
            nlohmann::json je;
            je["sunrise"] = optIso(ev->sunrise);
            je["sunset"] = optIso(ev->sunset);
            je["civil_dawn"] = optIso(ev->civilDawn);
            je["civil_dusk"] = optIso(ev->civilDusk);
            je["nautical_dawn"] = optIso(ev->nauticalDawn);
            je["nautical_dusk"] = optIso(ev->nauticalDusk);
            je["astronomical_dawn"] = optIso(ev->astronomicalDawn);
            je["astronomical_dusk"] = optIso(ev->astronomicalDusk);
            je["moonrise"] = optIso(ev->moonrise);
            je["moonset"] = optIso(ev->moonset);
            je["polar"] = ev->polar == PolarState::None ? nlohmann::json(nullptr) : nlohmann::json(toString(ev->polar));
            for (MoonQuarter q : {MoonQuarter::New, MoonQuarter::FirstQuarter, MoonQuarter::Full, MoonQuarter::LastQuarter})
                je[std::string("next_") + toString(q)] = nextMoonQuarter(t, q, path).toIso();
            j["events"] = je;
            nlohmann::json jc;
            jc["from"] = from.toIso();
            jc["to"] = to.toIso();
            jc["solar"] = nlohmann::json::array();
            for (const auto& e : solar) jc["solar"].push_back(solarJson(e));
            jc["lunar"] = nlohmann::json::array();
            for (const auto& e : lunar) jc["lunar"].push_back(lunarJson(e));
            j["eclipses"] = jc;
        }
        std::cout << j.dump(2) << '\n';
        return 0;
    }

    std::printf("time %s  (%s path)  JD(UT1) %.6f  JD(TT) %.6f  Delta T %.3f s\n", t.toIso().c_str(),
                o.precise ? "precise" : "fast", ts.ut1.day + ts.ut1.fraction, ts.tt.day + ts.tt.fraction, ts.deltaTSeconds);
    std::printf("site lat %.6f  lon %.6f  height %.1f m   GMST %.6f deg  LAST %.6f deg   refraction %s\n", o.lat, o.lon, o.height,
                frame.earth.gmst / kDeg, frame.lastRad / kDeg, o.refraction.c_str());
    std::printf("\n%-8s %11s %11s %11s %10s %10s %15s %10s %6s %7s %6s %7s\n", "body", "RA deg", "Dec deg", "az deg", "alt deg",
                "geom alt", "distance km", "diam deg", "mag", "phase", "illum", "limb");
    for (Body b : bodies) {
        const BodyState& s = eph[b];
        std::printf("%-8s %11.5f %11.5f %11.5f %10.5f %10.5f %15.1f %10.6f %6.2f %7.2f %6.3f %7.2f\n", bodyName(b), s.raRad / kDeg,
                    s.decRad / kDeg, s.topo.azimuthRad / kDeg, s.topo.altitudeRad / kDeg, s.topo.altitudeGeometricRad / kDeg,
                    s.distanceMeters / 1e3, s.angularDiameterRad / kDeg, s.magnitude, s.phaseAngleRad / kDeg, s.illuminatedFraction,
                    s.brightLimbAngleRad / kDeg);
        if (b == Body::Moon)
            std::printf("%-8s libration lon %.3f deg, lat %.3f deg; axis position angle %.3f deg\n", "", s.librationLonRad / kDeg,
                        s.librationLatRad / kDeg, s.axisAngleRad / kDeg);
    }
    if (ev) {
        auto show = [](const char* name, const std::optional<UtcInstant>& x) {
            std::printf("  %-18s %s\n", name, x ? x->toIso().c_str() : "-");
        };
        std::printf("\nevents in the 24 h from %s:\n", t.toIso().c_str());
        show("astronomical dawn", ev->astronomicalDawn);
        show("nautical dawn", ev->nauticalDawn);
        show("civil dawn", ev->civilDawn);
        show("sunrise", ev->sunrise);
        show("sunset", ev->sunset);
        show("civil dusk", ev->civilDusk);
        show("nautical dusk", ev->nauticalDusk);
        show("astronomical dusk", ev->astronomicalDusk);
        show("moonrise", ev->moonrise);
        show("moonset", ev->moonset);
        if (ev->polar != PolarState::None) std::printf("  %-18s %s\n", "polar", toString(ev->polar));
        for (MoonQuarter q : {MoonQuarter::New, MoonQuarter::FirstQuarter, MoonQuarter::Full, MoonQuarter::LastQuarter})
            std::printf("  next %-13s %s\n", toString(q), nextMoonQuarter(t, q, path).toIso().c_str());
        std::printf("\nsolar eclipses from %s to %s, seen from this site:%s\n", from.toIso().c_str(), to.toIso().c_str(),
                    solar.empty() ? " none" : "");
        for (const auto& e : solar) {
            std::printf("  %s %s%s: magnitude %.4f, obscuration %.4f", e.maximum.time.toIso().substr(0, 10).c_str(), toString(e.type),
                        e.visible ? "" : " (Sun below the horizon)", e.magnitude, e.obscuration);
            if (e.durationSeconds > 0) std::printf(", %s %dm %04.1fs", toString(e.type), int(e.durationSeconds / 60), std::fmod(e.durationSeconds, 60.0));
            std::printf("\n");
            printContact("C1", e.c1, "Sun");
            printContact("C2", e.c2, "Sun");
            printContact("maximum", e.maximum, "Sun");
            printContact("C3", e.c3, "Sun");
            printContact("C4", e.c4, "Sun");
            if (e.c2Limb && e.c3Limb)
                std::printf("    with the lunar limb's profile (Baily's beads; docs/eclipse.md): C2 %s, C3 %s\n"
                            "      (%+.1f s and %+.1f s against a smooth limb at the mean radius, itself %+.1f s and %+.1f s from C2 and C3)\n",
                            e.c2Limb->time.toIso().c_str(), e.c3Limb->time.toIso().c_str(), e.c2LimbShiftSeconds, e.c3LimbShiftSeconds,
                            e.c2MeanShiftSeconds, e.c3MeanShiftSeconds);
        }
        std::printf("\nlunar eclipses from %s to %s:%s\n", from.toIso().c_str(), to.toIso().c_str(), lunar.empty() ? " none" : "");
        for (const auto& e : lunar) {
            std::printf("  %s %s%s: umbral magnitude %.4f, penumbral magnitude %.4f\n", e.greatest.time.toIso().substr(0, 10).c_str(),
                        toString(e.type), e.visible ? "" : " (Moon below the horizon)", e.umbralMagnitude, e.penumbralMagnitude);
            printContact("P1", e.p1, "Moon");
            printContact("U1", e.u1, "Moon");
            printContact("U2", e.u2, "Moon");
            printContact("greatest", e.greatest, "Moon");
            printContact("U3", e.u3, "Moon");
            printContact("U4", e.u4, "Moon");
            printContact("P4", e.p4, "Moon");
        }
    }
    return 0;
}

welkin::cli::Registrar reg("astro", "positions, sizes, magnitudes and phases of the Sun, Moon and planets; rise/set events",
                           [](CLI::App& sub) -> welkin::cli::Action {
                               static AstroOptions o;
                               sub.add_option("--time", o.time, "instant, ISO 8601 (e.g. 2026-06-21T21:00:00Z)");
                               sub.add_option("--lat", o.lat, "geodetic latitude, degrees [-90, 90], north positive");
                               sub.add_option("--lon", o.lon, "longitude, degrees [-180, 180], east positive");
                               sub.add_option("--height", o.height, "height above the WGS84 ellipsoid, m");
                               sub.add_option("--bodies", o.bodies, "comma-separated: sun,moon,mercury,venus,mars,jupiter,saturn,uranus,neptune");
                               sub.add_flag("--precise", o.precise, "precise path (ERFA, full VSOP87) instead of the fast series");
                               sub.add_option("--refraction", o.refraction, "on|off: refract the altitudes (alt_deg)");
                               sub.add_option("--pressure", o.pressure, "pressure for refraction, hPa (default 1013.25)");
                               sub.add_option("--temperature", o.temperature, "temperature for refraction, deg C (default 10)");
                               sub.add_flag("--events", o.events, "add sunrise/sunset, twilights, moonrise/moonset, polar day/night, Moon quarters, solar and lunar eclipses");
                               sub.add_option("--from", o.from, "with --events: start of the eclipse window, ISO 8601 (default --time)");
                               sub.add_option("--to", o.to, "with --events: end of the eclipse window, ISO 8601 (default --from + 366 days, at most 20 years)");
                               sub.add_flag("--json", o.json, "print one JSON object");
                               return [] { return run(o); };
                           });

}  // namespace
