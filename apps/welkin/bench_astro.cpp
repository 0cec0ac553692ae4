// `welkin bench astro`: cost of the astronomy paths and the Fast path's error against Precise.
//
//   welkin bench astro [--samples 2000] [--json]
//
// Cost: microseconds per evaluation of the Sun + Moon + seven planets (Ephemeris::update), with
// and without building the ObserverFrame (time scales, precession-nutation, sidereal time), and of
// the star rotation matrix (stars.hpp), for each path. Accuracy: for random instants 1900-2100
// and random sites, the angle between the Fast and the Precise topocentric (airless) directions
// per body: median, 95th percentile and maximum, in arcseconds. Timings: mean thread CPU time
// per call, best of 5 passes over the instants (the machine may be shared).
#include "command.hpp"

#include <welkin/astro/bodies.hpp>
#include <welkin/astro/stars.hpp>
#include <welkin/astro/vsop87.hpp>
#include <welkin/error.hpp>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <ctime>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <numbers>
#include <random>
#include <vector>

namespace {

using namespace welkin;
using namespace welkin::astro;

constexpr double kDeg = std::numbers::pi / 180.0;
constexpr double kArcsec = kDeg / 3600.0;

struct BenchOptions {
    int samples = 2000;
    double from = 1900, to = 2100;  // years of the random instants
    bool json = false;
};

struct Instant {
    Site site;
    TimeScales ts;
};

std::vector<Instant> randomInstants(int n, unsigned seed, double fromYear, double toYear) {
    std::mt19937_64 rng(seed);
    // Julian dates of 1 January of the two years (365.2425-day years: good to a day).
    std::uniform_real_distribution<double> jd(2451544.5 + (fromYear - 2000) * 365.2425, 2451544.5 + (toYear - 2000) * 365.2425);
    std::uniform_real_distribution<double> lat(-89.0, 89.0), lon(-180.0, 180.0), h(0.0, 3000.0);
    std::vector<Instant> out;
    out.reserve(n);
    for (int i = 0; i < n; ++i) {
        const double d = jd(rng);
        Instant in;
        in.site = Site{lat(rng) * kDeg, lon(rng) * kDeg, h(rng)};
        in.ts = timeScales(JulianDate{std::floor(d - 0.5) + 0.5, d - (std::floor(d - 0.5) + 0.5)});
        out.push_back(in);
    }
    return out;
}

// This thread's CPU time, microseconds (excludes the time other processes hold the core).
double threadCpuMicroseconds() {
    timespec ts{};
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return ts.tv_sec * 1e6 + ts.tv_nsec * 1e-3;
}

// Mean CPU time per call over the n instants, best of 5 passes: the machine may be shared, and
// CPU time (not wall time) with the least disturbed pass measures the code, not the load.
template <class F>
double microsecondsPer(int n, F&& f) {
    double best = 1e300;
    for (int pass = 0; pass < 5; ++pass) {
        const double t0 = threadCpuMicroseconds();
        for (int i = 0; i < n; ++i) f(i);
        best = std::min(best, (threadCpuMicroseconds() - t0) / n);
    }
    return best;
}

double percentile(std::vector<double> v, double p) {
    std::sort(v.begin(), v.end());
    const double x = p * (v.size() - 1);
    const size_t i = static_cast<size_t>(x);
    return i + 1 < v.size() ? v[i] + (x - i) * (v[i + 1] - v[i]) : v.back();
}

int run(const BenchOptions& o) {
    if (o.samples < 10 || o.samples > 1000000) throw welkin::Error("--samples " + std::to_string(o.samples) + " not in [10, 1000000]");
    if (!(o.from >= kEphemerisFirstYear && o.to <= kEphemerisLastYear && o.from < o.to))
        throw welkin::Error("--from/--to: need -2000 <= from < to <= 6000");
    const auto instants = randomInstants(o.samples, 20261122, o.from, o.to);
    vsop87Full(VsopPlanet::Earth);  // load the full series before timing
    for (int p = 0; p < 8; ++p) vsop87Full(static_cast<VsopPlanet>(p));

    nlohmann::json j;
    volatile double sink = 0;
    // --- Cost ---
    std::vector<ObserverFrame> fastFrames, preciseFrames;
    fastFrames.reserve(instants.size());
    preciseFrames.reserve(instants.size());
    for (const auto& in : instants) {
        fastFrames.push_back(observerFrame(in.site, in.ts, Path::Fast));
        preciseFrames.push_back(observerFrame(in.site, in.ts, Path::Precise));
    }
    const int n = static_cast<int>(instants.size());
    const int nPrecise = std::min(n, 100);
    Ephemeris eph;
    double fastBodies = microsecondsPer(n, [&](int i) { eph.update(fastFrames[i]); sink = sink + eph[Body::Moon].raRad; });
    double fastTotal = microsecondsPer(n, [&](int i) {
        ObserverFrame f = observerFrame(instants[i].site, instants[i].ts, Path::Fast);
        eph.update(f);
        sink = sink + eph[Body::Sun].raRad;
    });
    double preciseBodies = microsecondsPer(nPrecise, [&](int i) { eph.update(preciseFrames[i]); sink = sink + eph[Body::Moon].raRad; });
    double preciseTotal = microsecondsPer(nPrecise, [&](int i) {
        ObserverFrame f = observerFrame(instants[i].site, instants[i].ts, Path::Precise);
        eph.update(f);
        sink = sink + eph[Body::Sun].raRad;
    });
    double starFast = microsecondsPer(n, [&](int i) { sink = sink + starMatrix(instants[i].site, instants[i].ts, Path::Fast)[0][0]; });
    double starPrecise = microsecondsPer(nPrecise, [&](int i) { sink = sink + starMatrix(instants[i].site, instants[i].ts, Path::Precise)[0][0]; });
    j["cost_us"] = {{"fast_bodies", fastBodies},     {"fast_bodies_with_frame", fastTotal}, {"precise_bodies", preciseBodies},
                    {"precise_bodies_with_frame", preciseTotal}, {"star_matrix_fast", starFast},     {"star_matrix_precise", starPrecise}};

    // --- Accuracy: Fast vs Precise, topocentric airless directions ---
    std::array<std::vector<double>, kBodyCount> err;
    std::array<std::vector<double>, kBodyCount> distErr, geoErr;
    Ephemeris fastEph, preciseEph;
    for (int i = 0; i < n; ++i) {
        fastEph.update(fastFrames[i]);
        preciseEph.update(preciseFrames[i]);
        for (Body b : kAllBodies) {
            const auto& a = fastEph[b].topo.enuGeometric;
            const auto& c = preciseEph[b].topo.enuGeometric;
            err[static_cast<int>(b)].push_back(std::atan2(glm::length(glm::cross(a, c)), glm::dot(a, c)) / kArcsec);
            const glm::dvec3 ga = directionFromRaDec(fastEph[b].raRad, fastEph[b].decRad);
            const glm::dvec3 gc = directionFromRaDec(preciseEph[b].raRad, preciseEph[b].decRad);
            geoErr[static_cast<int>(b)].push_back(std::atan2(glm::length(glm::cross(ga, gc)), glm::dot(ga, gc)) / kArcsec);
            distErr[static_cast<int>(b)].push_back(std::fabs(fastEph[b].distanceMeters / preciseEph[b].distanceMeters - 1.0));
        }
    }
    nlohmann::json acc;
    for (Body b : kAllBodies) {
        const auto& e = err[static_cast<int>(b)];
        acc[bodyName(b)] = {{"median_arcsec", percentile(e, 0.5)},
                            {"p95_arcsec", percentile(e, 0.95)},
                            {"max_arcsec", percentile(e, 1.0)},
                            {"geocentric_max_arcsec", percentile(geoErr[static_cast<int>(b)], 1.0)},
                            {"max_relative_distance_error", percentile(distErr[static_cast<int>(b)], 1.0)}};
    }
    j["fast_vs_precise"] = acc;
    j["samples"] = n;
    j["years"] = {o.from, o.to};
    j["sites"] = "random, |lat| < 89 deg, 0-3000 m";

    if (o.json) {
        std::cout << j.dump(2) << '\n';
        return 0;
    }
    std::printf("welkin bench astro: %d random instants %g-%g (precise timings over %d); thread CPU time, best of 5\n\n", n, o.from,
                o.to, nPrecise);
    std::printf("cost, microseconds per evaluation          fast      precise\n");
    std::printf("  Sun+Moon+7 planets (Ephemeris::update) %8.2f   %10.2f\n", fastBodies, preciseBodies);
    std::printf("  ... including ObserverFrame            %8.2f   %10.2f\n", fastTotal, preciseTotal);
    std::printf("  star rotation matrix                   %8.2f   %10.2f\n\n", starFast, starPrecise);
    std::printf("fast vs precise (arcsec)   topocentric: median      p95      max   geocentric max   max rel. dist. err\n");
    for (Body b : kAllBodies) {
        const auto& a = acc[bodyName(b)];
        std::printf("  %-8s                           %8.3f %8.3f %8.3f   %14.3f   %.2e\n", bodyName(b), a["median_arcsec"].get<double>(),
                    a["p95_arcsec"].get<double>(), a["max_arcsec"].get<double>(), a["geocentric_max_arcsec"].get<double>(),
                    a["max_relative_distance_error"].get<double>());
    }
    return sink == 12345.678 ? 2 : 0;
}

welkin::cli::BenchRegistrar bench("astro", "astronomy cost per evaluation and Fast-vs-Precise error per body, 1900-2100",
                                  [](CLI::App& sub) -> welkin::cli::Action {
                                      static BenchOptions o;
                                      sub.add_option("--samples", o.samples, "random instants (default 2000)");
                                      sub.add_option("--from", o.from, "first year of the random instants (default 1900)");
                                      sub.add_option("--to", o.to, "last year of the random instants (default 2100)");
                                      sub.add_flag("--json", o.json, "print one JSON object");
                                      return [] { return run(o); };
                                  });

}  // namespace
