// The astronomy step inside SkyProcessor: sun/moon directions and stats follow time and place.
#include <welkin/astro/astro_keys.hpp>
#include <welkin/processor.hpp>

#include <epoxy/gl.h>

#include "gl_test_context.hpp"

#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>

#include <cmath>
#include <numbers>

using namespace welkin;

TEST_CASE("SkyProcessor writes the Sun and Moon from time and observer", "[gl][astro][bodies]") {
    test::glContext();
    SkyProcessor p;
    Camera cam;
    cam.width = 8;
    cam.height = 8;
    p.setCamera(cam);
    const double d = std::numbers::pi / 180.0;
    p.setObserver({.latitudeRad = 52.52 * d, .longitudeRad = 13.405 * d, .heightMeters = 34.0});
    const UtcInstant t = UtcInstant::parse("2026-06-21T11:00:00Z");
    p.setTime(t);
    p.update();
    // Reference: the library directly (Fast path, standard refraction) for the same site.
    astro::Site site{52.52 * d, 13.405 * d, 34.0};
    astro::Ephemeris eph;
    eph.update(astro::observerFrame(site, astro::timeScales(t), astro::Path::Fast));
    const glm::dvec3 sun = p.vars().get(keys::sunDirection);
    CHECK(glm::length(sun - eph[astro::Body::Sun].topo.enu) < 1e-12);
    CHECK(glm::length(p.vars().get(keys::moonDirection) - eph[astro::Body::Moon].topo.enu) < 1e-12);
    // Near local noon at midsummer in Berlin: the Sun is ~61 deg high, due south.
    nlohmann::json j = p.stats();
    CHECK(j["sun"]["alt_deg"].get<double>() == Approx(eph[astro::Body::Sun].topo.altitudeRad / d).margin(1e-9));
    CHECK(j["sun"]["alt_deg"].get<double>() == Approx(60.9).margin(0.5));
    CHECK(j["sun"]["az_deg"].get<double>() == Approx(180.0).margin(10.0));
    CHECK(j["moon"]["az_deg"].get<double>() == Approx(eph[astro::Body::Moon].topo.azimuthRad / d).margin(1e-9));
    // Switching the path through the SkyVars key changes the Moon by less than an arcsecond.
    p.vars().set(astro::keys::precise, true);
    p.update();
    CHECK(glm::length(p.vars().get(keys::moonDirection) - eph[astro::Body::Moon].topo.enu) < 5e-6);
    CHECK(p.vars().get(keys::moonDirection) != eph[astro::Body::Moon].topo.enu);
}
