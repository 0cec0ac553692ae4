// welkin's astronomy without GL: links welkin::astro only (CMake) or `pkg-config welkin-astro`,
// so it builds and runs where there is no GPU, no EGL and no window system.
//   example_astro_only [TIME [LAT_DEG LON_DEG]]
//   example_astro_only 2026-06-21T12:00:00+02:00 48.85 2.35
// Prints the Sun's apparent place (right ascension, declination) and where it stands in the sky
// (azimuth from north through east, refracted altitude) on both paths (Fast series, Precise ERFA).
// Defaults: 2026-06-21T12:00:00Z at Greenwich (51.4769 N, 0.0005 W). Exit status 0 when the two
// paths agree within 0.01 deg and the declination is within the obliquity (|dec| < 23.45 deg,
// true of any date within centuries of now), 1 if not, 2 for bad arguments.
#include <welkin/astro/bodies.hpp>
#include <welkin/error.hpp>
#include <welkin/time.hpp>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <numbers>
#include <string>

namespace {
constexpr double kDeg = std::numbers::pi / 180.0;

// A number of degrees in [lo, hi], else welkin::Error naming the argument and its range.
double parseDegrees(const char* text, const char* what, double lo, double hi) {
    char* end = nullptr;
    const double v = std::strtod(text, &end);
    if (end == text || *end != '\0' || !(v >= lo && v <= hi))
        throw welkin::Error(std::string(what) + " '" + text + "' is not a number of degrees in [" + std::to_string(int(lo)) +
                            ", " + std::to_string(int(hi)) + "]");
    return v;
}
}  // namespace

int main(int argc, char** argv) {
    using namespace welkin::astro;
    if (argc != 1 && argc != 2 && argc != 4) {
        std::fprintf(stderr, "usage: %s [TIME [LAT_DEG LON_DEG]]  (TIME: ISO 8601, e.g. 2026-06-21T12:00:00Z)\n", argv[0]);
        return 2;
    }
    BodyState sun[2];
    welkin::UtcInstant t;
    Site site{.latitudeRad = 51.4769 * kDeg, .longitudeRad = -0.0005 * kDeg};
    try {
        t = welkin::UtcInstant::parse(argc >= 2 ? argv[1] : "2026-06-21T12:00:00Z");
        if (argc == 4) {
            site.latitudeRad = parseDegrees(argv[2], "LAT_DEG", -90, 90) * kDeg;
            site.longitudeRad = parseDegrees(argv[3], "LON_DEG", -180, 180) * kDeg;
        }
        const TimeScales ts = timeScales(t);
        sun[0] = computeBody(Body::Sun, observerFrame(site, ts, Path::Fast));
        sun[1] = computeBody(Body::Sun, observerFrame(site, ts, Path::Precise));
    } catch (const welkin::Error& e) {
        std::fprintf(stderr, "example_astro_only: %s\n", e.what());
        return 2;
    }
    std::printf("Sun at %s, latitude %.4f deg, longitude %.4f deg:\n", t.toIso().c_str(), site.latitudeRad / kDeg,
                site.longitudeRad / kDeg);
    const char* names[2] = {"fast", "precise"};
    for (int i = 0; i < 2; ++i)
        std::printf("  %-7s  RA %9.5f h  Dec %+9.5f deg  azimuth %9.5f deg  altitude %+9.5f deg  distance %.6f au\n",
                    names[i], sun[i].raRad / kDeg / 15.0, sun[i].decRad / kDeg, sun[i].topo.azimuthRad / kDeg,
                    sun[i].topo.altitudeRad / kDeg, sun[i].distanceMeters / kAstronomicalUnit);
    // The Fast series follow the Precise path to arcseconds for the Sun (docs/astronomy-bodies.md):
    // 0.01 deg (36") is far above that and far below any error in the example's wiring.
    const double dAlt = std::abs(sun[0].topo.altitudeRad - sun[1].topo.altitudeRad) / kDeg;
    const double dDec = std::abs(sun[0].decRad - sun[1].decRad) / kDeg;
    if (dAlt > 0.01 || dDec > 0.01 || std::abs(sun[1].decRad) / kDeg > 23.45) {
        std::fprintf(stderr, "example_astro_only: the paths disagree (altitude %.4f deg, declination %.4f deg apart) "
                             "or the declination is beyond the obliquity\n", dAlt, dDec);
        return 1;
    }
    return 0;
}
