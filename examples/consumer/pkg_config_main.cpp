// Uses an installed welkin through pkg-config (tested in CI, scripts/test.sh):
//   c++ -std=c++20 pkg_config_main.cpp $(pkg-config --cflags --libs welkin) -o welkin_pkg_config
// CPU parts only, so it runs anywhere; it touches the three libraries (engine, generators, the
// element registry) and the precise astronomy path (ERFA), so a library or a dependency missing
// from welkin.pc fails the link.
#include <welkin/astro/bodies.hpp>
#include <welkin/elements/registry.hpp>
#include <welkin/generators/atmosphere.hpp>
#include <welkin/time.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>

int main() {
    using namespace welkin::astro;
    // On the June solstice at the Tropic of Cancer, the Sun culminates at the zenith near 12:00 UTC
    // at longitude 0 (the equation of time moves it by under 2 minutes: about 0.5 deg).
    const double deg = std::numbers::pi / 180.0;
    const Site site{.latitudeRad = 23.44 * deg, .longitudeRad = 0.0};
    const auto t = welkin::UtcInstant::parse("2026-06-21T12:00:00Z");
    const BodyState sun = computeBody(Body::Sun, observerFrame(site, timeScales(t), Path::Precise));
    const double altitudeDeg = sun.topo.altitudeRad / deg;

    welkin::atmosphere::Atmosphere::earthClear().validate();  // generators (throws if out of range)
    const auto known = welkin::elements::knownElements();       // sky elements
    const bool hasSky = std::find(known.begin(), known.end(), "sky") != known.end();

    std::printf("welkin pkg-config consumer: Sun at %.2f deg at %s, %zu elements known\n", altitudeDeg,
                t.toIso().c_str(), known.size());
    if (altitudeDeg < 88.0 || !hasSky) {
        std::fprintf(stderr, "welkin pkg-config consumer: expected the Sun above 88 deg and a 'sky' element\n");
        return 1;
    }
    return 0;
}
