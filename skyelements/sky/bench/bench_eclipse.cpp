// welkin bench eclipse: the solar eclipse's sky (issue 21, docs/eclipse.md). (1) Frame cost: the
// whole frame (astronomy, the sky's tables, the Sky pass; perspective towards the Sun) at
// mid-totality over Burgos (2026-08-12 18:29 UTC): a normal sky (astro.eclipses off), the eclipse
// with the clock at --seconds-per-frame (the table rebuilt in bands when the shadow has moved), and
// the eclipse with the clock jumping 60 s per frame (the whole table every frame); frames
// alternated so machine load hits all alike. Target: <= 1.5x. (2) Accuracy at mid-totality and
// at the 99 % and 90 % partial phases: the real-time model (CPU twin cpu::integrateEclipse with
// the multiple-scattering field, which the GPU table follows) against the reference integrator
// extended to the eclipse (atmosphere::eclipseReferenceRadiance), luminance per lux of the Sun.
#include "bench_util.hpp"

#include <CLI/CLI.hpp>
#include <welkin/bench.hpp>
#include <welkin/astro/astro_keys.hpp>
#include <welkin/elements/sky.hpp>
#include <welkin/error.hpp>
#include <welkin/generators/atmosphere.hpp>
#include <welkin/generators/eclipse_reference.hpp>
#include <welkin/generators/lights.hpp>
#include <welkin/generators/sky_luts.hpp>
#include <welkin/gl/context.hpp>
#include <welkin/keys.hpp>
#include <welkin/processor.hpp>
#include <welkin/time.hpp>

#include <epoxy/gl.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <ctime>
#include <cmath>
#include <functional>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

namespace welkin::cli {
namespace {

constexpr double kDeg = M_PI / 180;

struct EclipseBenchOptions {
    int repeats = 10;
    int width = 1280, height = 720;
    double secondsPerFrame = 1.0 / 60.0;  // the clock's step per frame (real time at 60 frames/s)
    bool accuracy = true;
    bool cost = true;     // false: skip the frame cost (accuracy only)
    bool coarse = false;  // the reference at the [eclipse] test's resolution (seconds) instead of its defaults (minutes)
    bool plainModel = false;
    bool hazy = false;
    bool ring = false;  // the accuracy part in the fit set's directions (a ring every 45 deg at 2, 15, 45 deg; as --dump)  // the accuracy part on Atmosphere::earthHazy()  // the accuracy part on SkyModel::earthClear() (the [eclipse] tests' CPU cases)
    int quality = -1;     // the sky quality of the accuracy part (-1: the processor's)
    int cycleFrames = 0;  // > 0: time every frame of this many at --seconds-per-frame, by kind
    std::string sweep;  // comma list of multiple-scattering kernel lengths L (km) to compare (model tuning)
    std::string dump;  // append one CSV row per phase and direction (model fitting: the model is linear in its weight)
    std::string dumpLengths;  // comma list of kernel lengths L (km) whose w = 1 model the dump also writes (fitting L)
    std::string place = "burgos";
    double startSeconds = 0.0;  // the timed frames start this far from the place's mid-totality (s)
    bool predict = true;        // the table built for where the shadow will be when shown  // burgos, reykjavik, luxor: the place and its mid-totality (docs/eclipse.md)
};

// The places of docs/eclipse.md and their mid-totality: latitude, longitude (deg), instant.
struct Place {
    double latDeg, lonDeg;
    const char* mid;
};
Place gPlace{42.34, -3.70, "2026-08-12T18:29:00Z"};

UtcInstant t0Cycle(const UtcInstant& t0, double secondsPerFrame, int frame) { return t0.plusSeconds(secondsPerFrame * frame); }

double Y(const glm::dvec3& c) { return 0.2126 * c.r + 0.7152 * c.g + 0.0722 * c.b; }

// The astronomy's keys at an instant over the place (--place; Burgos by default; CPU only).
SkyVars astronomyAt(const UtcInstant& t) {
    SkyVars v = SkyVars::earth();
    const JulianDate jd = t.julianDate();
    v.set(keys::timeJdUtc, glm::dvec2(jd.day, jd.fraction));
    v.set(keys::observerLatitude, gPlace.latDeg * kDeg);
    v.set(keys::observerLongitude, gPlace.lonDeg * kDeg);
    v.set(keys::observerHeight, 0.0);
    astro::updateSkyVars(v);
    return v;
}

int run(const EclipseBenchOptions& o) {
    if (o.repeats < 1 || o.repeats > 1000) throw Error("--repeats " + std::to_string(o.repeats) + " not in [1, 1000]");
    if (o.width < 16 || o.width > 8192 || o.height < 16 || o.height > 8192) throw Error("--width/--height not in [16, 8192]");
    if (!(o.secondsPerFrame >= 0.0 && o.secondsPerFrame <= 600.0)) throw Error("--seconds-per-frame not in [0, 600]");
    if (o.quality < -1 || o.quality > 3) throw Error("--quality " + std::to_string(o.quality) + " not in [0, 3] (or -1: the default)");
    if (o.cycleFrames < 0 || o.cycleFrames > 100000) throw Error("--cycle-frames " + std::to_string(o.cycleFrames) + " not in [0, 100000]");
    Logger log;
    auto ctx = gl::HeadlessContext::create({}, log);
    if (!o.cost && !o.accuracy) throw Error("--cost false and --accuracy false: nothing to measure");
    std::printf("welkin bench eclipse (%s)\n\n", ctx->description().c_str());
    if (o.place == "burgos") gPlace = {42.34, -3.70, "2026-08-12T18:29:00Z"};
    else if (o.place == "reykjavik") gPlace = {64.15, -21.94, "2026-08-12T17:48:36Z"};
    else if (o.place == "luxor") gPlace = {25.69, 32.64, "2027-08-02T10:05:13Z"};
    else throw Error("--place " + o.place + " not one of burgos, reykjavik, luxor");
    if (!(std::abs(o.startSeconds) <= 7200.0)) throw Error("--start-seconds not in [-7200, 7200]");
    const UtcInstant t0 = UtcInstant::parse(gPlace.mid).plusSeconds(o.startSeconds);
    auto makeProcessor = [&](bool eclipses) {
        auto p = std::make_unique<SkyProcessor>(SkyVars::earth(), log, ProcessorOptions{.timing = false});
        p->setObserver({.latitudeRad = gPlace.latDeg * kDeg, .longitudeRad = gPlace.lonDeg * kDeg, .heightMeters = 0});
        p->setTime(t0);
        p->vars().set(astro::keys::eclipses, eclipses);
        generators::SkyLuts::obtain(p->vars()).eclipse->setPredict(o.predict);
        Camera cam;
        cam.projection = Projection::Perspective;
        cam.width = o.width;
        cam.height = o.height;
        cam.verticalFovRad = 60 * kDeg;
        p->add(std::make_unique<elements::Sky>());
        p->renderFrame();
        const glm::dvec3 s = p->vars().get(keys::sunDirection);
        cam.azimuthRad = std::atan2(s.x, s.y);
        cam.altitudeRad = std::asin(s.z);
        p->setCamera(cam);
        for (int i = 0; i < 3; ++i) p->renderFrame();  // programs, tables
        return p;
    };
    // (1) Frame cost: the normal sky, the eclipse with the clock at --seconds-per-frame (the table
    // rebuilt in bands as the shadow moves), and the eclipse with the clock jumping 60 s per frame
    // (the whole table rebuilt every frame: the table's full cost).
    auto off = makeProcessor(false), on = makeProcessor(true), jump = makeProcessor(true);
    auto lutOf = [](SkyProcessor& p) { return generators::SkyLuts::obtain(p.vars()).eclipse; };
    const int rebuilds0 = lutOf(*on)->rebuilds();
    int frames[3] = {0, 0, 0};
    auto step = [&](SkyProcessor& p, int k, double dt) {
        p.setTime(t0.plusSeconds(dt * ++frames[k]));
        p.renderFrame();
    };
    const std::vector<double> ms = !o.cost ? std::vector<double>{1.0, 1.0, 1.0} : alternatedMedianMs(
        o.repeats, {[&] { step(*off, 0, o.secondsPerFrame); }, [&] { step(*on, 1, o.secondsPerFrame); }, [&] { step(*jump, 2, 60.0); }});
    const bool drew = on->vars().get(generators::skykeys::eclipseViewLut).id != 0;
    if (o.cost) {
    std::printf("| frame (%dx%d, perspective 60 deg towards the Sun) | ms | / normal |\n|---|---|---|\n", o.width, o.height);
    std::printf("| normal sky (astro.eclipses=false), clock %.4g s per frame | %.2f | 1 |\n", o.secondsPerFrame, ms[0]);
    std::printf("| eclipse sky (mid-totality%s), clock %.4g s per frame: %d table bands in %d frames | %.2f | %.2f |\n",
                drew ? "" : ", NOT DRAWN", o.secondsPerFrame, lutOf(*on)->rebuilds() - rebuilds0, frames[1], ms[1], ms[1] / ms[0]);
    std::printf("| eclipse sky, clock 60 s per frame (the whole table every frame) | %.2f | %.2f |\n", ms[2], ms[2] / ms[0]);
    std::printf("\nthe whole table's extra time: %.2f ms; target <= 1.5x: %s\n\n", ms[2] - ms[0], ms[1] / ms[0] <= 1.5 ? "met" : "NOT met");
    }
    if (o.cost && o.cycleFrames > 0) {
        // (1b) Every frame of a rebuild cycle: the clock at --seconds-per-frame for --cycle-frames
        // frames, each eclipse frame timed right after a normal one (paired: the load they see is
        // the same), classified by what the eclipse table did in it: nothing (the shadow moved <
        // kEclipseRebuildMeters), the first band of a rebuild (with the multiple-scattering
        // field's CPU table), a later band, or the swap (the new table shown, the frame after its
        // last band: the irradiance pass re-runs).
        auto a = makeProcessor(false), b = makeProcessor(true);
        // Besides the wall time, the process's CPU time (all threads: the renderer's llvmpipe
        // threads too) for each frame: the work done, which a load spike does not lengthen.
        struct Cat {
            const char* name;
            std::vector<double> normal, eclipse, ratio, cpuRatio;
        };
        auto cpuMs = [] {
            timespec ts{};
            clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
            return 1e3 * double(ts.tv_sec) + 1e-6 * double(ts.tv_nsec);
        };
        Cat cats[5] = {{"no band (the shadow moved < 2 km)"}, {"first band of a rebuild (+ the field's CPU table if in one piece)"}, {"later band"},
                       {"the swap (the new table shown; the irradiance pass)"}, {"a piece of the field's CPU table (no band)"}};
        int fa = 0, fb = 0;
        bool bandInBuild = false;
        std::vector<double> offsets;  // the shown table's distance from the frame's shadow, m
        struct Outlier {
            double cpuRatio;
            int frame, kind;
            double cpuA, cpuB, wallA, wallB;
        };
        std::vector<Outlier> outliers;
        for (int i = 0; i < o.cycleFrames; ++i) {
            glFinish();
            auto c0 = std::chrono::steady_clock::now();
            const double u0 = cpuMs();
            a->setTime(t0Cycle(t0, o.secondsPerFrame, ++fa));
            a->renderFrame();
            glFinish();
            auto t1 = std::chrono::steady_clock::now();
            const double u1 = cpuMs();
            const int r0 = lutOf(*b)->rebuilds(), p0 = lutOf(*b)->fieldRuns();
            const uint32_t id0 = b->vars().get(generators::skykeys::eclipseViewLut).id;
            b->setTime(t0Cycle(t0, o.secondsPerFrame, ++fb));
            b->renderFrame();
            glFinish();
            auto t2 = std::chrono::steady_clock::now();
            const double u2 = cpuMs();
            const bool band = lutOf(*b)->rebuilds() != r0, swapped = b->vars().get(generators::skykeys::eclipseViewLut).id != id0;
            const bool piece = lutOf(*b)->fieldRuns() != p0;
            const int k = swapped ? 3 : band ? (bandInBuild ? 2 : 1) : piece ? 4 : 0;
            if (band) bandInBuild = true;
            if (swapped) bandInBuild = false;
            offsets.push_back(lutOf(*b)->shownOffsetMeters());
            const double msA = std::chrono::duration<double, std::milli>(t1 - c0).count(), msB = std::chrono::duration<double, std::milli>(t2 - t1).count();
            cats[k].normal.push_back(msA);
            cats[k].eclipse.push_back(msB);
            cats[k].ratio.push_back(msB / msA);
            cats[k].cpuRatio.push_back((u2 - u1) / std::max(u1 - u0, 1e-3));
            outliers.push_back({(u2 - u1) / std::max(u1 - u0, 1e-3), i, k, u1 - u0, u2 - u1, msA, msB});
        }
        std::printf("every frame of %d at %.4g s per frame (%dx%d), each eclipse frame paired with the normal frame timed just before it:\n\n",
                    o.cycleFrames, o.secondsPerFrame, o.width, o.height);
        std::printf("| eclipse frame | frames | normal ms (median) | eclipse ms (median) | eclipse / normal, median | max | CPU time eclipse / normal, median | max |\n|---|---|---|---|---|---|---|---|\n");
        double worst = 0.0;
        for (const Cat& c : cats) {
            if (c.ratio.empty()) {
                std::printf("| %s | 0 | | | | | | |\n", c.name);
                continue;
            }
            const double mx = *std::max_element(c.ratio.begin(), c.ratio.end());
            worst = std::max(worst, median(c.ratio));
            const double cmx = *std::max_element(c.cpuRatio.begin(), c.cpuRatio.end());
            std::printf("| %s | %zu | %.2f | %.2f | %.2f | %.2f | %.2f | %.2f |\n", c.name, c.ratio.size(), median(c.normal), median(c.eclipse), median(c.ratio), mx,
                        median(c.cpuRatio), cmx);
        }
        std::printf("\nlargest median ratio of a kind of frame: %.2f; target <= 1.5x: %s\n", worst, worst <= 1.5 ? "met" : "NOT met");
        std::printf("bands per rebuild %d, the field's pieces %d; the table shown against the frame's shadow: median %.2f km, max %.2f km\n",
                    lutOf(*b)->bandsPerRebuild(), lutOf(*b)->fieldPiecesPerRebuild(), median(offsets) * 1e-3,
                    *std::max_element(offsets.begin(), offsets.end()) * 1e-3);
        // The pairs whose eclipse frame took the most CPU time against its normal frame.
        std::sort(outliers.begin(), outliers.end(), [](const Outlier& x, const Outlier& y) { return x.cpuRatio > y.cpuRatio; });
        std::printf("\n| largest CPU-time ratios: frame | kind | CPU ms normal / eclipse | wall ms normal / eclipse |\n|---|---|---|---|\n");
        for (std::size_t j = 0; j < std::min<std::size_t>(outliers.size(), 6); ++j)
            std::printf("| %d | %s | %.2f / %.2f | %.2f / %.2f |\n", outliers[j].frame, cats[outliers[j].kind].name, outliers[j].cpuA, outliers[j].cpuB,
                        outliers[j].wallA, outliers[j].wallB);
        // The multiple-scattering field's CPU table alone (built in the first band's frame).
        const SkyVars& vb = b->vars();
        const generators::cpu::EclipseGeometry gb{.moonPos = vb.get(astro::keys::moonPosition), .moonRadius = astro::keys::kMoonRadiusMeters,
                                      .sunPos = glm::normalize(vb.get(keys::sunDirection)) * vb.get(astro::keys::sunDistance),
                                      .sunRadius = generators::kSunRadiusMeters};
        const double fieldMs = medianMs(9, [&] { (void)generators::cpu::eclipseMsTable(gb, generators::cpu::eclipseMsLength(gb)); });
        std::printf("the field's CPU table (cpu::eclipseMsTable, 128 x 128): %.2f ms (median of 9)\n\n", fieldMs);
    }
    if (!o.accuracy) return 0;
    // (2) Accuracy: mid-totality and the partial phases where 10 %, 1 % and 0.5 % of the Sun is
    // left (90 %, 99 % and 99.5 % obscured; found by bisection before second contact).
    using namespace generators;
    SkyVars& v0 = on->vars();
    // The processor's atmosphere (the renderer's), or with --plain-model the CPU default with no
    // atmosphere key (SkyModel::earthClear(): what the [eclipse] tests' CPU cases integrate).
    // --hazy: the renderer's atmosphere with Atmosphere::earthHazy() (AOD 0.4, g 0.75) instead.
    if (o.hazy) v0.set(atmosphere::kAtmosphere, std::make_shared<const atmosphere::Atmosphere>(atmosphere::Atmosphere::earthHazy()));
    const SkyModel m = o.plainModel ? SkyModel::earthClear() : SkyModel::fromVars(v0);
    const int quality = o.quality >= 0 ? o.quality : effectiveQuality(v0);
    const SkyQuality q = SkyQuality::preset(quality);
    const Lut2D T = cpu::transmittanceLut(m, q);
    const cpu::MsField MS = cpu::msField(m, q, T);
    auto instantOf = [&](double fraction) {
        double a = -1800.0, b = 0.0;  // seconds from mid-totality: 30 min before (Burgos: fraction ~0.5) .. totality (0)
        for (int i = 0; i < 40; ++i) {
            const double c = 0.5 * (a + b);
            (astronomyAt(t0.plusSeconds(c)).get(keys::sunEclipseFraction) > fraction ? a : b) = c;
        }
        return t0.plusSeconds(0.5 * (a + b));
    };
    struct Phase {
        std::string name;
        UtcInstant t;
    };
    const std::vector<Phase> phases = {{"totality", t0}, {"99.5 %", instantOf(0.005)}, {"99 %", instantOf(0.01)}, {"90 %", instantOf(0.10)}};
    std::vector<double> lengths;
    for (size_t a = 0, b; a < o.sweep.size(); a = b + 1) {
        b = o.sweep.find(',', a);
        if (b == std::string::npos) b = o.sweep.size();
        lengths.push_back(std::stod(o.sweep.substr(a, b - a)) * 1e3);
    }
    std::printf("the aerosol's scattering at the ground (green) %.4g 1/m, Rayleigh's %.4g 1/m\n", m.scatteringMie(0.0).g, m.scatteringRayleigh(0.0).g);
    atmosphere::EclipseReferenceOptions refOptions;
    if (o.coarse) refOptions = {.viewSteps = 24, .gatherZenith = 8, .gatherAzimuth = 12, .gatherSteps = 16, .rings = 48};
    std::printf("reference: eclipseReferenceRadiance (%s); model: cpu::integrateEclipse, 256 steps, L = cpu::eclipseMsLength() (per phase); sky quality %d; %s\n\n",
                o.coarse ? "the [eclipse] test's resolution" : "defaults", quality,
                o.plainModel ? "SkyModel::earthClear()" : o.hazy ? "Atmosphere::earthHazy()" : "the renderer's atmosphere");
    std::printf("| phase (UTC, sun.eclipse_fraction, L km) | direction (az from the Sun, alt) | reference (cd/m^2 per lx) | model / ref. | "
                "ref., no eclipse | model / ref., no eclipse | eclipse / no eclipse (ref.) | ref. order 1 / 2 / >= 3 (share) | ref. clear >= 3 |");
    for (double L : lengths) std::printf(" L = %.0f km |", L / 1e3);
    std::printf("\n|---|---|---|---|---|---|---|---|---|");
    for (size_t i = 0; i < lengths.size(); ++i) std::printf("---|");
    std::printf("\n");
    double worst = 0.0, worstRatio = 1.0;
    std::FILE* dump = o.dump.empty() ? nullptr : std::fopen(o.dump.c_str(), "a");
    if (!o.dump.empty() && !dump) throw Error("--dump " + o.dump + ": cannot open for appending");
    const char* atmName = o.plainModel ? "hillaire" : o.hazy ? "hazy" : "renderer";
    std::vector<std::pair<std::string, std::vector<double>>> summary;  // per phase: |ln(model / reference)| of every direction
    for (const Phase& ph : phases) {
        std::vector<double>& phaseLn = summary.emplace_back(ph.name, std::vector<double>{}).second;
        const SkyVars v = astronomyAt(ph.t);
        const glm::dvec3 sun = glm::normalize(v.get(keys::sunDirection));
        cpu::EclipseGeometry g{.moonPos = v.get(astro::keys::moonPosition), .moonRadius = astro::keys::kMoonRadiusMeters,
                               .sunPos = sun * v.get(astro::keys::sunDistance), .sunRadius = kSunRadiusMeters};
        const cpu::EclipseMsTable field = cpu::eclipseMsTable(g, cpu::eclipseMsLength(g));
        cpu::EclipseGeometry gm = g;
        gm.ms = &field;
        const double sunAz = std::atan2(sun.x, sun.y);
        std::vector<std::pair<double, double>> dirs = {{0.0, 90.0}, {0.0, 45.0}, {90.0, 45.0}, {180.0, 45.0},
                                                       {0.0, 2.0}, {90.0, 2.0}, {180.0, 2.0}, {270.0, 2.0}};
        // The fit set: the eight directions above, a ring every 45 deg of azimuth at 2 deg (the
        // horizon), 15 and 45 deg, and 30 and 70 deg in a few azimuths (docs/eclipse.md, "The ring").
        if (dump || o.ring) {
            for (double alt : {2.0, 15.0, 45.0})
                for (double daz = 0.0; daz < 359.0; daz += 45.0)
                    if (std::find(dirs.begin(), dirs.end(), std::pair{daz, alt}) == dirs.end()) dirs.push_back({daz, alt});
            dirs.insert(dirs.end(), {{45.0, 30.0}, {135.0, 30.0}, {0.0, 70.0}, {180.0, 70.0}});
        }
        std::vector<double> dumpL;
        for (size_t a = 0, b; a < o.dumpLengths.size(); a = b + 1) {
            b = o.dumpLengths.find(',', a);
            if (b == std::string::npos) b = o.dumpLengths.size();
            dumpL.push_back(std::stod(o.dumpLengths.substr(a, b - a)) * 1e3);
        }
        std::vector<cpu::EclipseMsTable> dumpFields;
        for (double L : dumpL) dumpFields.push_back(cpu::eclipseMsTable(g, L));
        // The shadow's geometry at the observer: the umbra's radius on the plane perpendicular to the
        // axis through the observer (negative: antumbra) and the observer's distance from the axis.
        const glm::dvec3 axis = glm::normalize(g.sunPos - g.moonPos);
        const double zBehind = glm::dot(g.moonPos, axis);
        const double umbraR = g.moonRadius - zBehind * (g.sunRadius - g.moonRadius) / glm::length(g.sunPos - g.moonPos);
        const double axisDist = glm::length(g.moonPos - glm::dot(g.moonPos, axis) * axis);
        for (auto [daz, alt] : dirs) {
            const glm::dvec3 dir = directionFromAzAlt(sunAz + daz * kDeg, alt * kDeg);
            atmosphere::EclipseReferenceOptions ro = refOptions;
            const atmosphere::EclipseReferenceRadiance rr = atmosphere::eclipseReferenceRadiance(m, T, MS, 0.0, dir, sun, g, ro);
            const double ref = Y(rr.radiance);
            ro.eclipse = false;
            const atmosphere::EclipseReferenceRadiance rc = atmosphere::eclipseReferenceRadiance(m, T, MS, 0.0, dir, sun, g, ro);
            const double refClear = Y(rc.radiance);
            const double nu = glm::dot(dir, sun);
            const double model = Y(cpu::radiance(m, cpu::integrateEclipse(m, T, MS, 0.0, dir, sun, gm, 256, false, m.sunAngularRadius), nu));
            cpu::EclipseGeometry far = g;
            far.moonPos = -g.moonPos;  // the Moon on the far side: no shadow
            const double modelClear =
                Y(cpu::radiance(m, cpu::integrateEclipse(m, T, MS, 0.0, dir, sun, far, 256, false, m.sunAngularRadius), nu));
            std::printf("| %s (%s, %.4f, %.1f) | %+.0f, %.0f deg | %.3g | %.3f | %.3g | %.3f | %.2e |", ph.name.c_str(), ph.t.toIso().c_str(),
                        v.get(keys::sunEclipseFraction), cpu::eclipseMsLength(g) / 1e3, daz, alt, ref, model / ref, refClear, modelClear / refClear, ref / refClear);
            std::printf(" %.2f / %.2f / %.2f | %.3g |", Y(rr.single) / ref, Y(rr.second) / ref, Y(rr.higher) / ref, Y(rc.higher));
            for (double L : lengths) {
                const cpu::EclipseMsTable fl = cpu::eclipseMsTable(g, L);
                cpu::EclipseGeometry gl = g;
                gl.ms = &fl;
                const double ml = Y(cpu::radiance(m, cpu::integrateEclipse(m, T, MS, 0.0, dir, sun, gl, 256, false, m.sunAngularRadius), nu));
                std::printf(" %.3f |", ml / ref);
            }
            std::printf("\n");
            std::fflush(stdout);
            if (dump) {
                // The model's radiance at the weights 0 and 1 (it is linear in the weight), and the
                // distance along the view to the first point with 1 % of the Sun visible.
                cpu::EclipseGeometry g0 = gm, g1 = gm;
                g0.msWeightOverride = 0.0;
                g1.msWeightOverride = 1.0;
                const double a0 = Y(cpu::radiance(m, cpu::integrateEclipse(m, T, MS, 0.0, dir, sun, g0, 256, false, m.sunAngularRadius), nu));
                const double a1 = Y(cpu::radiance(m, cpu::integrateEclipse(m, T, MS, 0.0, dir, sun, g1, 256, false, m.sunAngularRadius), nu));
                double edge = -1.0;
                for (double t = 0.0; t < 2000e3; t += 500.0)
                    if (cpu::eclipseAt(g, t * dir).x > 0.01) { edge = t; break; }
                const double tEdge = Y(cpu::integrate(m, T, MS, 0.0, dir.z, sun.z, nu, edge < 0.0 ? 1e30 : std::max(edge, 1.0), 256, false,
                                                      m.sunAngularRadius).transmittance);
                std::fprintf(dump, "%s,%s,%s,%.6f,%.1f,%.1f,%.6g,%.6g,%.6g,%.6g,%.6g,%.6g,%.6f,%.6f,%.6g,%.6g,%.6g,%.6g,%.6g,%.6g,%.6g,%.6g,%.6g", o.place.c_str(), atmName,
                             ph.name.c_str(), v.get(keys::sunEclipseFraction), daz, alt, ref, a0, a1, model, refClear, modelClear, sun.z, nu,
                             edge, m.scatteringMie(0.0).g, m.scatteringRayleigh(0.0).g, Y(rr.second), Y(rr.higher), Y(rr.single), tEdge, umbraR, axisDist);
                // Then, per --dump-lengths L, the model at w = 1 with that kernel length.
                for (const cpu::EclipseMsTable& fl : dumpFields) {
                    cpu::EclipseGeometry gl = g;
                    gl.ms = &fl;
                    gl.msWeightOverride = 1.0;
                    std::fprintf(dump, ",%.6g", Y(cpu::radiance(m, cpu::integrateEclipse(m, T, MS, 0.0, dir, sun, gl, 256, false, m.sunAngularRadius), nu)));
                }
                std::fprintf(dump, "\n");
                std::fflush(dump);
            }
            const double r = model / ref;
            phaseLn.push_back(std::abs(std::log(r)));
            worst = std::max(worst, std::abs(std::log(r)));
            if (std::abs(std::log(r)) >= std::abs(std::log(worstRatio))) worstRatio = r;
        }
    }
    if (dump) std::fclose(dump);
    for (const auto& [name, ls] : summary) {
        std::vector<double> sorted = ls;
        std::sort(sorted.begin(), sorted.end());
        std::printf("%s: %zu directions, the factor (exp |ln(model / reference)|): worst %.2f, median %.2f\n", name.c_str(), sorted.size(),
                    std::exp(sorted.back()), std::exp(sorted[sorted.size() / 2]));
    }
    std::printf("\nlargest model / reference factor: %.3f (|ln| %.2f)\n", worstRatio, worst);
    return 0;
}

bench::CommandBenchRegistrar reg({"eclipse", "the solar eclipse's sky: frame cost against a normal sky, and its error against the reference", [](CLI::App& sub) {
    auto o = std::make_shared<EclipseBenchOptions>();  // owned by the action returned below (LeakSanitizer)
    sub.add_option("--repeats", o->repeats, "timed frames per configuration (median reported), [1, 1000]")->capture_default_str();
    sub.add_option("--width", o->width, "frame width, px, [16, 8192]")->capture_default_str();
    sub.add_option("--height", o->height, "frame height, px, [16, 8192]")->capture_default_str();
    sub.add_option("--seconds-per-frame", o->secondsPerFrame, "clock step per frame, s, [0, 600] (1/60: real time at 60 frames/s)")
        ->capture_default_str();
    sub.add_option("--cycle-frames", o->cycleFrames,
                   "also time every frame of this many at --seconds-per-frame, paired with a normal frame and classified by the "
                   "eclipse table's work in it (0: off; 300 covers a rebuild at real time), [0, 100000]")
        ->capture_default_str();
    sub.add_option("--dump", o->dump, "append a CSV row per phase and direction of the accuracy part (model fitting; more directions)");
    sub.add_option("--dump-lengths", o->dumpLengths, "with --dump: also the model at w = 1 for these kernel lengths L, km (comma list)");
    sub.add_option("--start-seconds", o->startSeconds, "the timed frames start this far from the place's mid-totality, s, [-7200, 7200] (Burgos' C2 is -46)")
        ->capture_default_str();
    sub.add_option("--predict", o->predict, "build each table for where the shadow will be when it is shown (false: where it was when the rebuild began)")
        ->capture_default_str();
    sub.add_option("--place", o->place, "burgos, reykjavik or luxor: the place and its mid-totality (docs/eclipse.md)")->capture_default_str();
    sub.add_option("--ring", o->ring, "the accuracy part in the fit set's 29 directions (a ring every 45 deg of azimuth at 2, 15 and 45 deg, the zenith, 30 and 70 deg), with the worst and median factor per phase")
        ->capture_default_str();
    sub.add_option("--hazy", o->hazy, "the accuracy part on Atmosphere::earthHazy() (AOD 0.4 at 550 nm, g 0.75)")->capture_default_str();
    sub.add_option("--plain-model", o->plainModel,
                   "the accuracy part on SkyModel::earthClear() (no atmosphere key: the [eclipse] tests' CPU cases) instead of the renderer's atmosphere")
        ->capture_default_str();
    sub.add_option("--quality", o->quality, "the sky quality of the accuracy part, [0, 3] (-1: the processor's default)")->capture_default_str();
    sub.add_option("--ms-length-sweep", o->sweep, "also the model / reference for these multiple-scattering kernel lengths L, km (comma list)");
    sub.add_option("--accuracy", o->accuracy, "also measure the error against the reference (minutes on the CPU)")->capture_default_str();
    sub.add_option("--cost", o->cost, "measure the frame cost (false: accuracy only)")->capture_default_str();
    sub.add_option("--coarse", o->coarse, "the reference at the [eclipse] test's resolution (seconds) instead of its defaults (minutes)")
        ->capture_default_str();
    return [o]() { return run(*o); };
}});

}  // namespace
}  // namespace welkin::cli
