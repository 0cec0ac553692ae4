#include "scene_options.hpp"

#include <welkin/astro/bodies.hpp>
#include <welkin/check.hpp>
#include <welkin/elements/registry.hpp>
#include <welkin/error.hpp>
#include <welkin/keys.hpp>
#include <welkin/point_source.hpp>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <numbers>
#include <unistd.h>

namespace welkin::cli {

namespace {
constexpr double kDeg = std::numbers::pi / 180.0;

// The one range check (welkin/check.hpp); an option names itself: "--lat 100 not in [-90, 90]".
void checkRange(const char* option, double v, double lo, double hi) { welkin::checkRange("", option, v, lo, hi); }
}  // namespace

void parseSize(const std::string& text, const char* option, int& width, int& height) {
    int w = 0, h = 0;
    char extra = 0;
    if (std::sscanf(text.c_str(), "%dx%d%c", &w, &h, &extra) != 2)
        throw Error(std::string(option) + " '" + text + "' is not WIDTHxHEIGHT (e.g. 1280x720)");
    if (w < 1 || w > 16384 || h < 1 || h > 16384)
        throw Error(std::string(option) + " " + text + ": width and height must be in [1, 16384]");
    width = w;
    height = h;
}

void SceneOptions::addTo(CLI::App& app, bool required) {
    auto* t = app.add_option("--time", time, "instant, ISO 8601 (e.g. 2026-06-21T12:00:00Z or +02:00 offset)");
    auto* la = app.add_option("--lat", latDeg, "geodetic latitude, degrees [-90, 90], north positive");
    auto* lo = app.add_option("--lon", lonDeg, "longitude, degrees [-180, 180], east positive");
    if (required) {
        t->required();
        la->required();
        lo->required();
    } else {
        time = "2026-06-21T12:00:00Z";
    }
    app.add_option("--height", heightM, "observer height above the ellipsoid, metres [-10000, 1e9]")->capture_default_str();
    std::string known;
    for (auto& k : elements::knownElements()) known += (known.empty() ? "" : ",") + k;
    app.add_option("--elements", elements, "comma list of elements, composited in this order; 'default' stands for the default set (known: " + known + ")")
        ->each([this](const std::string&) { elementsGiven = true; });
    app.add_option("--projection", projection, "perspective | fisheye | equirect | cube")->capture_default_str();
    app.add_option("--az", azDeg, "view azimuth, degrees from north through east (perspective)")->capture_default_str();
    app.add_option("--alt", altDeg, "view altitude, degrees [-90, 90] (perspective)")->capture_default_str();
    app.add_option("--fov", fovDeg, "vertical field of view, degrees (0, 180) (perspective)")->capture_default_str();
    app.add_option("--face", cubeFace, "cube face 0..5 (+X,-X,+Y,-Y,+Z,-Z; x east, y up, z south) for --projection cube")
        ->capture_default_str();
    app.add_option("--size", size, "image size WIDTHxHEIGHT, each in [1, 16384]")->capture_default_str();
    app.add_option("--exposure", exposure,
                   "EV100 in [-20, 30], or auto (the eye's adaptation to the scene, docs/eye.md; eye.* and exposure.* keys "
                   "tune it)")->capture_default_str();
    app.add_option("--quality", quality, "low | medium | high | reference")->capture_default_str();
    app.add_option("--var", vars,
                   "KEY=VALUE: set any SkyVars key (an element's option, the atmosphere's, the astronomy's), checked against "
                   "its type and range; repeatable; `welkin vars` lists the keys (e.g. --var sky.wavelengths=15 "
                   "--var grid.altitude_step_rad=15deg)")
        ->allow_extra_args(false);
}

void checkAstronomyYear(const UtcInstant& t, const char* option) {
    // The astronomy (VSOP87, ELP) answers for civil years [-2000, 6000] only and would throw from
    // the first frame, after the GL context is made, without naming the option: refuse here.
    const int year = t.utc().year;
    if (year < int(astro::kEphemerisFirstYear) || year > int(astro::kEphemerisLastYear))
        throw Error(std::string(option) + " " + t.toIso() + ": year " + std::to_string(year) + " not in [" +
                    std::to_string(int(astro::kEphemerisFirstYear)) + ", " + std::to_string(int(astro::kEphemerisLastYear)) +
                    "] (the span of the ephemerides)");
}

UtcInstant SceneOptions::instant() const {
    UtcInstant t;
    try {
        t = UtcInstant::parse(time);
    } catch (const Error& e) {
        throw Error(std::string("--time ") + e.what());
    }
    checkAstronomyYear(t, "--time");
    return t;
}

Observer SceneOptions::observer() const {
    checkRange("--lat", latDeg, -90, 90);
    checkRange("--lon", lonDeg, -180, 180);
    checkRange("--height", heightM, -1e4, 1e9);
    return Observer{latDeg * kDeg, lonDeg * kDeg, heightM};
}

Camera SceneOptions::camera() const {
    Camera c;
    try {
        c.projection = parseProjection(projection);
    } catch (const Error& e) {
        throw Error(std::string("--projection: ") + e.what());
    }
    checkRange("--az", azDeg, -360, 360);
    checkRange("--alt", altDeg, -90, 90);
    welkin::checkOpenRange("", "--fov", fovDeg, 0, 180);
    checkRange("--face", cubeFace, 0, 5);
    c.azimuthRad = azDeg * kDeg;
    c.altitudeRad = altDeg * kDeg;
    c.verticalFovRad = fovDeg * kDeg;
    c.cubeFace = cubeFace;
    parseSize(size, "--size", c.width, c.height);
    return c;
}

Exposure SceneOptions::exposureSetting() const {
    Exposure e;
    if (exposure == "auto") {
        e.automatic = true;
        return e;
    }
    char* end = nullptr;
    double v = std::strtod(exposure.c_str(), &end);
    if (end == exposure.c_str() || *end != '\0') throw Error("--exposure '" + exposure + "' is neither an EV100 number nor auto");
    checkRange("--exposure", v, -20, 30);
    e.ev100 = v;
    return e;
}

int SceneOptions::qualityLevel() const {
    if (quality == "low") return 0;
    if (quality == "medium") return 1;
    if (quality == "high") return 2;
    if (quality == "reference") return 3;
    throw Error("--quality '" + quality + "' unknown (accepted: low, medium, high, reference)");
}

std::vector<std::string> SceneOptions::elementNames() const {
    std::vector<std::string> names = elementsGiven ? elements::expandElementList(elements) : elements::defaultElements();
    for (auto& n : names) elements::makeElement(n);  // throws for an unknown name, listing the known ones
    return names;
}

void SceneOptions::validate() const {
    instant();
    observer();
    camera();
    exposureSetting();
    qualityLevel();
    elementNames();
    // The --var values against the keys the elements and the processor declare (no GL needed).
    SkyProcessor probe;
    for (auto& n : elementNames()) probe.add(elements::makeElement(n));
    probe.vars().set(keys::pointSources, pointSources);
    applyVars(probe);
    pointSourceMode(probe.vars());  // render.point_sources: physical | perceptual
    for (auto& e : probe.elements()) e->validateOptions(probe.vars());
}

void SceneOptions::applyVars(SkyProcessor& p) const {
    for (const std::string& kv : vars) {
        const size_t eq = kv.find('=');
        if (eq == std::string::npos || eq == 0) throw Error("--var '" + kv + "' is not KEY=VALUE");
        try {
            p.setOption(kv.substr(0, eq), kv.substr(eq + 1));
        } catch (const Error& e) {
            throw Error("--var " + kv + ": " + e.what());
        }
    }
}

void SceneOptions::apply(SkyProcessor& p) const {
    p.setAnimationTime(0.0);  // deterministic: animated elements show their state at t = 0
    p.vars().set(keys::quality, qualityLevel());
    p.setTime(instant());
    p.setObserver(observer());
    p.setCamera(camera());
    p.setExposure(exposureSetting());
    for (auto& n : elementNames()) p.add(elements::makeElement(n));
    p.vars().set(keys::pointSources, pointSources);
    applyVars(p);
}

}  // namespace welkin::cli
