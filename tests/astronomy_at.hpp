// The astronomy's SkyVars for an instant and a site, on the CPU (no GL): what the astronomy
// generator publishes each frame (sun.direction, moon.direction, the eclipse keys ...).
//
//   SkyVars v = welkin::test::astronomyAt("2026-08-12T18:29:00Z", 42.34, -3.70);
//   double f = v.get(welkin::keys::sunEclipseFraction);
#pragma once
#include <welkin/astro/astro_keys.hpp>
#include <welkin/keys.hpp>
#include <welkin/time.hpp>
#include <welkin/vars.hpp>

#include <numbers>

namespace welkin::test {

/// `iso`: ISO 8601 instant; latitude and longitude in degrees (east positive); height 0 m.
inline SkyVars astronomyAt(const char* iso, double latDeg, double lonDeg) {
    constexpr double deg = std::numbers::pi / 180.0;
    SkyVars v = SkyVars::earth();
    const JulianDate jd = UtcInstant::parse(iso).julianDate();
    v.set(keys::timeJdUtc, glm::dvec2(jd.day, jd.fraction));
    v.set(keys::observerLatitude, latDeg * deg);
    v.set(keys::observerLongitude, lonDeg * deg);
    v.set(keys::observerHeight, 0.0);
    astro::updateSkyVars(v);
    return v;
}

}  // namespace welkin::test
