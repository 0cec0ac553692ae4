// welkin bench sky: the measured speed/accuracy trade of the real-time sky (issue 4 item 8).
// For each quality preset and Sun altitude: LUT build time, per-frame time at two sizes
// (CPU-timed with glFinish) beside a trivial fullscreen pass of the same size in the same run,
// and the error against the brute-force reference integrator (RGB mode: the same model and
// channels as the real-time path, all scattering orders) over the upper hemisphere outside the
// solar disk. Writes a CSV, and from it a PNG plot of error against frame time drawn by
// scripts/plots/plot_bench_sky.py (matplotlib; see plot.hpp). `--wavelengths 3,15` also
// runs the spectral mode (sky_spectral.hpp) and `--reference spectral` compares with the
// reference integrator's spectral mode (the atmosphere's 47 wavelengths through the CIE observer).
#include "bench_util.hpp"
#include "plot.hpp"

#include <CLI/CLI.hpp>
#include <welkin/bench.hpp>
#include <welkin/color.hpp>
#include <welkin/csv.hpp>
#include <welkin/elements/sky.hpp>
#include <welkin/elements/sky_offline.hpp>
#include <welkin/error.hpp>
#include <welkin/generators/atmosphere.hpp>
#include <welkin/generators/reference_sky.hpp>
#include <welkin/generators/sky_luts.hpp>
#include <welkin/gl/context.hpp>
#include <welkin/gl/shader.hpp>
#include <welkin/image.hpp>
#include <welkin/keys.hpp>
#include <welkin/astro/bodies.hpp>
#include <welkin/astro/events.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <functional>
#include <memory>
#include <vector>

namespace welkin::cli {
namespace {

constexpr double kDeg = M_PI / 180;

struct SkyBenchOptions {
    std::string csv = "bench_sky.csv";
    std::string plot = "bench_sky.png";
    std::string presets = "0,1,2,3";
    int repeats = 3;
    bool full = false;  // also time `reference` at 1280x720 (minutes on llvmpipe)
    bool timingOnly = false;  // skip the reference integrator (no error columns)
    std::string projection = "fisheye";  // of the 1280x720 frame
    std::string wavelengths = "0";       // comma list: 0 = the preset's, 3 = RGB, 6..24 = spectral
    std::string reference = "rgb";       // reference integrator mode: rgb | spectral
    bool noPrefill = false;  // --animate: grid tables along the Sun's path instead of at its first move
    bool breakdown = false;  // print each generator's share of a full LUT rebuild
    bool behind = false;     // time the sky as if something (stars) were behind it
    // --animate: time running (bench_sky_animate below)
    bool animate = false;
    int frames = 600;
    double stepS = 60;          // simulated seconds per frame
    int sampleEvery = 20;       // error against the reference at every n-th frame
    double keyframeStepDeg = 0; // 0: the preset's
    double keyframeCoarseStepDeg = 0; // 0: the preset's
    int keyframeChunks = 0;     // 0: the preset's
};

double Y(const glm::dvec3& c) { return 0.2126 * c.r + 0.7152 * c.g + 0.0722 * c.b; }

using Trivial = TrivialElement;

struct Row {
    int preset;
    int wavelengths;
    double sunAlt;
    double allLutsMs, sunLutsMs, frameBig, frameSmall, trivialBig, trivialSmall;
    double ratioBig = NAN, ratioSmall = NAN;  // median of per-pair frame / trivial
    double rms = NAN, maxErr = NAN, dxy = NAN;
};

// Luminance error of `img` (probe camera) against the reference with the Sun at `sun`: RMS and
// max relative error over the upper hemisphere (above 2 deg) outside 2 deg from the Sun.
// Also the mean chromaticity distance (CIE 1931 xy) in `dxy`.
struct ProbeError {
    double rms = 0, max = 0, dxy = 0;
};
ProbeError probeErrors(const atmosphere::ReferenceSky& ref, const Image& img, const Camera& probe, const glm::dvec3& sun) {
    double s2 = 0, mx = 0, sxy = 0;
    int n = 0;
    for (int y = 0; y < probe.height / 2; ++y)
        for (int x = 0; x < probe.width; x += 2) {
            auto d = probe.directionAt({x + 0.5, y + 0.5});
            if (!d || d->z < std::sin(2 * kDeg) || glm::dot(*d, sun) > std::cos(2 * kDeg)) continue;
            glm::dvec3 g(img.at(x, y, 0), img.at(x, y, 1), img.at(x, y, 2));
            glm::dvec3 rf = ref.radiance(0.0, *d, sun);
            double e = (Y(g) - Y(rf)) / std::max(Y(rf), 1e-30);
            s2 += e * e;
            mx = std::max(mx, std::abs(e));
            sxy += glm::length(color::chromaticity(color::linearSrgbToXyz(g)) - color::chromaticity(color::linearSrgbToXyz(rf)));
            ++n;
        }
    return {std::sqrt(s2 / std::max(n, 1)), mx, sxy / std::max(n, 1)};
}
std::pair<double, double> probeError(const atmosphere::ReferenceSky& ref, const Image& img, const Camera& probe, const glm::dvec3& sun) {
    const ProbeError e = probeErrors(ref, img, probe, sun);
    return {e.rms, e.max};
}

// welkin bench sky --animate: a game loop's sky. Time advances `stepS` per frame from 2 h before
// sunset (lat 45 N, lon 0, 2026-06-21) and turns back at 2 h after it (and again at 2 h before),
// `frames` frames at 1280x720. Per frame: the generators' time (what the moving Sun costs) and
// the draw's (what a static frame costs), both with glFinish. Every `sampleEvery` frames: the
// animated frame's error against the reference integrator at that instant (so the tables'
// staleness and interpolation count), beside the error of a second Sky built fresh at that
// instant (the static figure).
int runAnimate(const SkyBenchOptions& o, const std::vector<int>& presets) {
    Logger log;
    auto ctx = gl::HeadlessContext::create({}, log);
    const atmosphere::Atmosphere atm = atmosphere::Atmosphere::earthClear();
    atmosphere::ReferenceOptions ro;
    ro.mode = atmosphere::SpectralMode::Rgb;
    ro.threads = 2;
    std::unique_ptr<atmosphere::ReferenceSky> ref;
    if (!o.timingOnly) ref = std::make_unique<atmosphere::ReferenceSky>(atm, ro);
    const astro::Site site{45 * kDeg, 0.0, 0.0};
    const UtcInstant day = UtcInstant::parse("2026-06-21T00:00:00Z");
    const astro::DayEvents ev = astro::findDayEvents(site, day, astro::Path::Fast);
    if (!ev.sunset) throw Error("bench sky --animate: no sunset found");
    const UtcInstant t0 = ev.sunset->plusSeconds(-7200.0);
    auto sunAt = [&](double s) {
        return astro::computeBody(astro::Body::Sun, astro::observerFrame(site, astro::timeScales(t0.plusSeconds(s)), astro::Path::Fast)).topo.enu;
    };
    Camera big, probe;
    big.width = 1280, big.height = 720, big.projection = parseProjection(o.projection);
    probe.width = 64, probe.height = 32, probe.projection = Projection::Equirect;
    std::ofstream csv(o.csv);
    if (!csv) throw Error("--csv: cannot write '" + o.csv + "'");
    csv << "preset,frame,time_s,sun_alt_deg,generators_ms,draw_ms,rms_rel,max_rel,static_rms_rel,static_max_rel\n";
    struct Summary {
        int preset;
        double meanAnim, p95Anim, meanStatic, rmsAnim = NAN, rmsStatic = NAN, maxDiff = NAN, prefillMs = 0;
        int samples = 0;
    };
    std::vector<Summary> sums;
    for (int preset : presets) {
        SkyVars vars = SkyVars::earth();
        vars.set(keys::observerHeight, 0.0);
        vars.set(keys::moonDirection, glm::dvec3(0, 0, -1));
        SkyVars fresh = SkyVars::earth();  // the static figure: a second sky built at each sampled instant
        fresh.set(keys::observerHeight, 0.0);
        fresh.set(keys::moonDirection, glm::dvec3(0, 0, -1));
        elements::OfflineRenderer r(vars, log), rf(fresh, log);
        elements::Sky sky(elements::SkyOptions{.quality = preset, .moon = false, .wavelengths = 3});
        elements::Sky skyFresh(elements::SkyOptions{.quality = preset, .moon = false, .wavelengths = 3});
        generators::SkyQuality q = generators::SkyQuality::preset(preset);
        if (o.keyframeStepDeg > 0) q.keyframeStepRad = o.keyframeStepDeg * kDeg;
        if (o.keyframeCoarseStepDeg > 0) q.keyframeCoarseStepRad = o.keyframeCoarseStepDeg * kDeg;
        if (o.keyframeChunks > 0) q.keyframeChunks = o.keyframeChunks;
        if (o.noPrefill) q.keyframePrefill = false;
        generators::SkyLuts luts = generators::SkyLuts::obtain(vars);
        for (generators::SkyGenerator* g : {static_cast<generators::SkyGenerator*>(luts.sunView.get()),
                                            static_cast<generators::SkyGenerator*>(luts.moonView.get()),
                                            static_cast<generators::SkyGenerator*>(luts.aerial.get())})
            g->setFixedQuality(q);
        // Warm-up at the first instant: every program compiled, every LUT built.
        double s = 0, dir = 1;
        vars.set(keys::sunDirection, sunAt(s));
        Camera probeBig = big;
        probeBig.width = 64, probeBig.height = 36;
        r.draw(sky, probe, true);
        r.draw(sky, probeBig, true);
        r.draw(sky, big, true);
        // The first moving frame: with SkyQuality::keyframePrefill every grid table is built
        // then, once (reported apart: a load-time cost, like a precomputed table's).
        vars.set(keys::sunDirection, sunAt(o.stepS));
        r.draw(sky, big, true);
        const double prefillMs = r.generatorsMs();
        vars.set(keys::sunDirection, sunAt(s));
        r.draw(sky, big, true);
        std::vector<double> anim, stat;
        double e2a = 0, e2s = 0, maxDiff = 0;
        int ns = 0;
        for (int f = 0; f < o.frames; ++f) {
            // Bounce between 2 h before and 2 h after sunset.
            if (s + dir * o.stepS > 4 * 3600.0 + 1e-6 || s + dir * o.stepS < -1e-6) dir = -dir;
            s += dir * o.stepS;
            const glm::dvec3 sun = sunAt(s);
            vars.set(keys::sunDirection, sun);
            r.draw(sky, big, true);
            const double genMs = r.generatorsMs(), drawMs = r.drawMs();
            anim.push_back(genMs + drawMs);
            stat.push_back(drawMs);
            double rms = NAN, mx = NAN, srms = NAN, smx = NAN;
            if (ref && f % o.sampleEvery == o.sampleEvery - 1) {
                r.runGenerators = false;  // look without advancing the schedule
                Image img = r.render(sky, probe);
                r.runGenerators = true;
                std::tie(rms, mx) = probeError(*ref, img, probe, sun);
                fresh.set(keys::sunDirection, sun);
                generators::SkyLuts lf = generators::SkyLuts::obtain(fresh);
                lf.sunView->resetKeyframes();  // a table at exactly this instant
                lf.aerial->resetKeyframes();
                Image imgF = rf.render(skyFresh, probe);
                std::tie(srms, smx) = probeError(*ref, imgF, probe, sun);
                const double alt = std::asin(std::clamp(sun.z, -1.0, 1.0)) / kDeg;
                if (alt >= -10) {  // the static table's own figures are meaningless deeper (skyelements/sky/README.md)
                    e2a += rms * rms;
                    e2s += srms * srms;
                    maxDiff = std::max(maxDiff, std::abs(rms - srms));
                    ++ns;
                }
            }
            csv << preset << ',' << f << ',' << s << ',' << std::asin(std::clamp(sun.z, -1.0, 1.0)) / kDeg << ',' << genMs << ',' << drawMs << ',' << rms << ',' << mx << ',' << srms << ',' << smx << '\n';
        }
        Summary sm{preset, 0, 0, 0};
        for (size_t i = 0; i < anim.size(); ++i) sm.meanAnim += anim[i] / anim.size(), sm.meanStatic += stat[i] / stat.size();
        std::vector<double> sorted = anim;
        std::sort(sorted.begin(), sorted.end());
        sm.p95Anim = sorted[size_t(0.95 * (sorted.size() - 1))];
        if (ns > 0) sm.rmsAnim = std::sqrt(e2a / ns), sm.rmsStatic = std::sqrt(e2s / ns), sm.maxDiff = maxDiff;
        sm.samples = ns;
        sm.prefillMs = prefillMs;
        sums.push_back(sm);
        int builds = luts.sunView->runCount();
        std::printf("preset %d: first moving frame (keyframe prefill: %d grid tables) %.0f ms\n", preset, luts.sunView->keyframes().gridTables(), prefillMs);
        if (o.breakdown) {  // where the generators' time went over the whole run (glFinish around each)
            std::printf("preset %d generators over %d frames:", preset, o.frames);
            for (Generator* g : std::initializer_list<Generator*>{luts.transmittance.get(), luts.multiScattering.get(), luts.sh.get(),
                                                                  luts.sunView.get(), luts.moonView.get(), luts.aerial.get(),
                                                                  luts.irradiance.get(), luts.lightZenith.get()})
                if (g) std::printf(" %s %.1f ms/frame (%d runs)", g->name().c_str(), g->timing().totalMs / o.frames, g->runCount());
            std::printf("\n");
        }
        std::printf("preset %d: %d frames, %g s per frame: frame %.1f ms mean, %.1f ms p95 (static %.1f ms): x%.2f mean, x%.2f p95; "
                    "sky-view runs %d; error RMS %.2f%% animated, %.2f%% static (Sun >= -10 deg, %d samples), worst sample difference %.2f points\n",
                    preset, o.frames, o.stepS, sm.meanAnim, sm.p95Anim, sm.meanStatic, sm.meanAnim / sm.meanStatic, sm.p95Anim / sm.meanStatic,
                    builds, 100 * sm.rmsAnim, 100 * sm.rmsStatic, ns, 100 * sm.maxDiff);
        std::fflush(stdout);
        sky.release();
        skyFresh.release();
        r.release();
        rf.release();
    }
    std::printf("\n| preset | mean frame ms (× static) | 95th pct ms (× static) | static frame ms | RMS error animated | RMS error static | first moving frame (prefill) |\n|---|---|---|---|---|---|---|\n");
    static const char* names[] = {"low", "medium", "high", "reference"};
    for (auto& sm : sums)
        std::printf("| %s | %.1f (×%.2f) | %.1f (×%.2f) | %.1f | %.2f %% | %.2f %% | %.2f s |\n", names[sm.preset], sm.meanAnim, sm.meanAnim / sm.meanStatic,
                    sm.p95Anim, sm.p95Anim / sm.meanStatic, sm.meanStatic, 100 * sm.rmsAnim, 100 * sm.rmsStatic, sm.prefillMs / 1000.0);
    std::printf("wrote %s\n", o.csv.c_str());
    return 0;
}

int run(const SkyBenchOptions& o) {
    std::vector<int> presets;
    for (char c : o.presets)
        if (c >= '0' && c <= '3') presets.push_back(c - '0');
        else if (c != ',') throw Error("--presets '" + o.presets + "': a comma list of 0..3");
    if (o.repeats < 1 || o.repeats > 100) throw Error("--repeats " + std::to_string(o.repeats) + " not in [1, 100]");
    std::vector<int> wavelengths;
    {
        std::string cur;
        for (char c : o.wavelengths + ",") {
            if (c == ',') {
                if (cur.empty()) continue;
                int n = 0;
                try {
                    n = std::stoi(cur);
                } catch (...) {
                    throw Error("--wavelengths '" + o.wavelengths + "': a comma list of 0, 3 or 6..24 (multiples of 3)");
                }
                generators::validateWavelengthCount(n, "--wavelengths");
                wavelengths.push_back(n);
                cur.clear();
            } else {
                cur += c;
            }
        }
        if (wavelengths.empty()) throw Error("--wavelengths: empty list");
    }
    if (o.animate) {
        if (o.frames < 1 || o.frames > 100000) throw Error("--frames " + std::to_string(o.frames) + " not in [1, 100000]");
        if (!(o.stepS > 0 && o.stepS <= 3600)) throw Error("--step " + std::to_string(o.stepS) + " s not in (0, 3600]");
        if (o.sampleEvery < 1) throw Error("--sample-every " + std::to_string(o.sampleEvery) + " must be >= 1");
        return runAnimate(o, presets);
    }
    if (o.reference != "rgb" && o.reference != "spectral")
        throw Error("--reference '" + o.reference + "' unknown (accepted: rgb, spectral)");
    // Output directories checked before minutes of measurement, not after.
    checkOutputDirectory("--csv", o.csv);
    checkOutputDirectory("--plot", o.plot);
    Logger log;
    auto ctx = gl::HeadlessContext::create({}, log);
    const atmosphere::Atmosphere atm = atmosphere::Atmosphere::earthClear();
    atmosphere::ReferenceOptions ro;
    ro.mode = o.reference == "rgb" ? atmosphere::SpectralMode::Rgb : atmosphere::SpectralMode::Spectral;
    // Spectral: on the atmosphere's own wavelengths (47 for the Earth), so that the reference has
    // no spectral interpolation error of its own (its default 16 samples over 365-825 nm are off
    // by ~2 % in luminance at Sun -4 deg, more than the effect measured).
    ro.spectralSamples = std::min(int(atm.size()), 64);
    ro.threads = 2;
    auto t0 = std::chrono::steady_clock::now();
    std::unique_ptr<atmosphere::ReferenceSky> refPtr;
    if (!o.timingOnly) refPtr = std::make_unique<atmosphere::ReferenceSky>(atm, ro);
    std::printf("reference integrator (%s, all orders) precomputed in %.1f s\n", o.reference.c_str(),
                std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
    const double sunAlts[] = {60, 20, 5, 0, -4, -10, -18};
    const double sunAz = 3.0;
    Camera big, small, probe;
    big.width = 1280, big.height = 720, big.projection = parseProjection(o.projection);
    small.width = 512, small.height = 256, small.projection = Projection::Equirect;
    probe.width = 64, probe.height = 32, probe.projection = Projection::Equirect;
    std::vector<Row> rows;
    for (int preset : presets)
    for (int nWl : wavelengths) {
        SkyVars vars = SkyVars::earth();
        vars.set(keys::observerHeight, 0.0);
        vars.set(keys::moonDirection, glm::dvec3(0, 0, -1));
        elements::OfflineRenderer r(vars, log);
        r.nothingBehind = !o.behind;
        elements::Sky sky(elements::SkyOptions{.quality = preset, .moon = false, .wavelengths = nWl});
        Trivial trivial;
        double allLuts = NAN;
        const int repeats = preset == 3 ? 1 : o.repeats;
        // Warm-up: compiles every program the timed frames use (not part of a LUT rebuild nor of
        // a frame): the programs are per projection, so both the probe's (equirect, also the
        // 512x256 frame's) and the 1280x720 frame's.
        vars.set(keys::sunDirection, directionFromAzAlt(sunAz, 0.5));
        Camera probeBig = big;
        probeBig.width = 64, probeBig.height = 36;
        for (const Camera* c : {&probe, &probeBig}) {
            r.draw(sky, *c, true);
            r.draw(trivial, *c, true);
        }
        for (double alt : sunAlts) {
            Row row{};
            row.preset = preset;
            row.wavelengths = generators::effectiveWavelengths(nWl, generators::SkyQuality::preset(preset));
            row.sunAlt = alt;
            glm::dvec3 sun = directionFromAzAlt(sunAz, alt * kDeg);
            vars.set(keys::sunDirection, sun);
            // All LUTs (a new atmosphere pointer makes every generator due): measured once per
            // preset, the Sun-independent part does not change with the Sun.
            if (alt == sunAlts[0]) {
                // Median of `repeats` rebuilds (the first one also allocates the textures).
                std::vector<double> t;
                for (int i = 0; i < repeats; ++i) {
                    vars.set(atmosphere::kAtmosphere, std::make_shared<const atmosphere::Atmosphere>(atm));
                    r.draw(sky, small, true);
                    t.push_back(r.generatorsMs());
                }
                std::sort(t.begin(), t.end());
                allLuts = t[t.size() / 2];
                if (o.breakdown) {
                    // The same rebuild again, each generator bracketed by glFinish.
                    vars.set(atmosphere::kAtmosphere, std::make_shared<const atmosphere::Atmosphere>(atm));
                    std::printf("preset %d, all LUTs rebuilt, per generator:", preset);
                    for (auto& g : sky.generators()) {
                        g->runIfDue(vars, log, true);
                        std::printf(" %s %.1f ms;", g->name().c_str(), g->timing().lastMs);
                    }
                    std::printf("\n");
                }
            }
            row.allLutsMs = allLuts;
            // Sun-dependent LUTs only (sky view, aerial perspective, irradiance).
            // (Their tables forgotten and rebuilt at this elevation: what a jump of the Sun costs.)
            {
                generators::SkyLuts l = generators::SkyLuts::obtain(vars);
                l.sunView->resetKeyframes();
                l.moonView->resetKeyframes();
                l.aerial->resetKeyframes();
                for (Generator* g : {static_cast<Generator*>(l.sunView.get()), static_cast<Generator*>(l.moonView.get()),
                                     static_cast<Generator*>(l.aerial.get()), static_cast<Generator*>(l.irradiance.get())})
                    g->invalidate();
            }
            r.draw(sky, small, true);
            row.sunLutsMs = r.generatorsMs();
            // The sky frame and the trivial pass are timed alternately and the ratio is the median
            // of the per-pair ratios: other jobs on the machine then slow both alike.
            auto pairs = [&](const Camera& cam, int n, double& frame, double& triv) {
                std::vector<double> f, t, q;
                for (int i = 0; i < n; ++i) {
                    // The element's own update + render (glFinish around each), as drawn by the
                    // processor: the clear, the tone map and the read-back are the same for both.
                    r.draw(trivial, cam, true);
                    t.push_back(r.drawMs());
                    r.draw(sky, cam, true);
                    f.push_back(r.drawMs());
                    q.push_back(f.back() / t.back());
                }
                auto med = [](std::vector<double> v) {
                    std::sort(v.begin(), v.end());
                    return v[v.size() / 2];
                };
                frame = med(f);
                triv = med(t);
                return med(q);
            };
            row.ratioSmall = pairs(small, repeats, row.frameSmall, row.trivialSmall);
            if (preset == 3 && !o.full) {
                std::vector<double> tb;
                for (int i = 0; i < o.repeats; ++i) {
                    r.draw(trivial, big, true);
                    tb.push_back(r.drawMs());
                }
                std::sort(tb.begin(), tb.end());
                row.trivialBig = tb[tb.size() / 2];
                row.frameBig = row.ratioBig = NAN;
            } else {
                row.ratioBig = pairs(big, repeats, row.frameBig, row.trivialBig);
            }
            if (refPtr) {
            const atmosphere::ReferenceSky& ref = *refPtr;
            // Error over the upper hemisphere (probe pixels above 2 deg altitude), outside 2 deg
            // from the Sun's centre (the disk and the aureole's steepest part).
            Image img = r.render(sky, probe);
            const ProbeError pe = probeErrors(ref, img, probe, sun);
            row.rms = pe.rms;
            row.maxErr = pe.max;
            row.dxy = pe.dxy;
            }
            std::printf("preset %d wl %2d sun %5.1f: LUTs %8.1f ms (sun-dependent %7.1f), frame 1280x720 %8.1f ms (trivial %6.1f, x%.1f), "
                        "512x256 %7.1f ms (trivial %5.1f, x%.1f)",
                        preset, row.wavelengths, alt, row.allLutsMs, row.sunLutsMs, row.frameBig, row.trivialBig, row.ratioBig,
                        row.frameSmall, row.trivialSmall, row.ratioSmall);
            if (o.timingOnly)
                std::printf("\n");  // no comparison with the reference integrator
            else
                std::printf(", error RMS %.2f%% max %.2f%% dxy %.4f\n", 100 * row.rms, 100 * row.maxErr, row.dxy);
            std::fflush(stdout);
            rows.push_back(row);
        }
        if (std::getenv("WELKIN_BENCH_DEBUG")) {
            for (int i = 0; i < 3; ++i) {
                r.draw(sky, big, true);
                double gs = r.generatorsMs(), ds = r.drawMs();
                r.draw(trivial, big, true);
                std::printf("  sky: generators %.2f ms, update+render %.2f ms; trivial: %.2f, %.2f\n", gs, ds, r.generatorsMs(), r.drawMs());
            }
        }
        if (std::getenv("WELKIN_BENCH_DEBUG"))
            for (auto& g : sky.generators()) std::printf("  %s: %d runs\n", g->name().c_str(), g->runCount());
        sky.release();
        trivial.release();
        r.release();
    }
    CsvWriter csv(o.csv, {"preset", "wavelengths", "sun_alt_deg", "all_luts_ms", "sun_luts_ms", "frame_1280x720_ms",
                          "trivial_1280x720_ms", "frame_512x256_ms", "trivial_512x256_ms", "ratio_1280x720", "ratio_512x256",
                          "rms_rel", "max_rel", "mean_dxy"});
    csv.comment("welkin bench sky, reference integrator " + (o.timingOnly ? std::string("not run (--timing-only)") : o.reference) +
                ", 1280x720 projection " + o.projection + ", " + ctx->description());
    for (auto& r : rows)
        csv.row(r.preset, r.wavelengths, r.sunAlt, r.allLutsMs, r.sunLutsMs, r.frameBig, r.trivialBig, r.frameSmall, r.trivialSmall,
                r.ratioBig, r.ratioSmall, r.rms, r.maxErr, r.dxy);
    csv.close();
    std::printf("wrote %s\n", o.csv.c_str());
    if (!o.plot.empty()) std::printf("%s\n", drawPlot("plot_bench_sky.py", o.csv, o.plot).message.c_str());
    return 0;
}

static bench::CommandBenchRegistrar reg({"sky", "real-time sky: LUT build and frame cost per quality preset, error against the reference integrator",
                          [](CLI::App& sub) -> std::function<int()> {
                              static SkyBenchOptions o;
                              sub.add_option("--csv", o.csv, "CSV output path");
                              sub.add_option("--plot", o.plot,
                                             "PNG plot of error against frame time, drawn from the CSV by scripts/plots/plot_bench_sky.py "
                                             "(python3 + matplotlib); empty: CSV only");
                              sub.add_option("--presets", o.presets, "comma list of presets 0..3");
                              sub.add_option("--repeats", o.repeats, "timed repetitions per measurement (median)");
                              sub.add_flag("--full", o.full, "also time `reference` at 1280x720 (slow on llvmpipe)");
                              sub.add_flag("--timing-only", o.timingOnly, "skip the comparison with the reference integrator");
                              sub.add_option("--wavelengths", o.wavelengths,
                                             "comma list of sky wavelength counts: 0 = the preset's (reference: 15, else 3), 3 = RGB, 6..24 (multiple of 3) = spectral");
                              sub.add_option("--reference", o.reference,
                                             "reference integrator mode: rgb (same channels as RGB mode) | spectral (the atmosphere's 47 wavelengths, CIE 1931)");
                              sub.add_flag("--behind", o.behind,
                                           "time the sky as if something (stars) were behind it: with its transmittance output");
                              sub.add_flag("--animate", o.animate,
                                           "time running: --frames at 1280x720, --step s per frame around sunset; frame cost and error against the reference at sampled frames");
                              sub.add_option("--frames", o.frames, "--animate: frames to render");
                              sub.add_option("--step", o.stepS, "--animate: simulated seconds per frame");
                              sub.add_option("--sample-every", o.sampleEvery, "--animate: error against the reference every n-th frame");
                              sub.add_option("--keyframe-step", o.keyframeStepDeg, "--animate: keyframe step in elevation, deg (0: the preset's)");
                              sub.add_option("--keyframe-coarse-step", o.keyframeCoarseStepDeg, "--animate: keyframe step above 4 deg of elevation, deg (0: the preset's)");
                              sub.add_flag("--no-prefill", o.noPrefill, "--animate: build the grid tables along the Sun's path, not all when it first moves");
                              sub.add_option("--keyframe-chunks", o.keyframeChunks, "--animate: frames over which one keyframe is built (0: the preset's)");
                              sub.add_flag("--breakdown", o.breakdown, "print each generator's time in a full LUT rebuild (glFinish around each)");
                              sub.add_option("--projection", o.projection, "projection of the 1280x720 frame (perspective: az 0, alt 20 deg, fov 60 deg)");
                              return [] { return run(o); };
                          },
                          // The tables `welkin bench all` writes into docs/BENCHMARKS.md from this bench.
                          {{.element = "sky",
                            .title = "Sky: each quality preset against the reference integrator",
                            .what = "Every scattering order integrated along each view ray in double precision (`atmosphere::ReferenceSky`, "
                                    "RGB mode: the same three channels), against the real-time sky of each preset (0 low, 1 medium, "
                                    "2 high, 3 reference quality) at seven Sun altitudes: RMS and largest relative luminance error over the "
                                    "upper hemisphere above 2 deg outside 2 deg from the Sun (64x32 probe), mean CIE xy distance; the "
                                    "LUTs' full rebuild and the Sun-dependent part in ms; the frame as a multiple of a trivial pass timed "
                                    "alternately with it. Errors at -18 deg are relative to a sky of ~1e-3 cd/m2.",
                            .args = {"--presets", "0,1,2,3", "--repeats", "3", "--plot", ""},
                            .quickArgs = {"--presets", "0,1", "--repeats", "1", "--plot", ""},
                            .columns = {"preset", "sun_alt_deg:Sun altitude deg", "all_luts_ms:all LUTs ms", "sun_luts_ms:Sun-dependent LUTs ms",
                                        "ratio_512x256:512x256 x trivial", "ratio_1280x720:1280x720 x trivial", "rms_rel*100:RMS error %",
                                        "max_rel*100:largest error %", "mean_dxy:mean xy distance"}},
                           {.element = "sky",
                            .title = "Sky: wavelengths as work",
                            .what = "The medium preset with its LUTs computed on 3 (RGB), 6, 12 and 24 wavelengths: build cost, frame cost "
                                    "and error against the reference integrator (RGB mode, as above).",
                            .args = {"--presets", "1", "--wavelengths", "3,6,12,24", "--repeats", "3", "--plot", ""},
                            .quickArgs = {"--presets", "1", "--wavelengths", "3,12", "--repeats", "1", "--plot", ""},
                            .columns = {"wavelengths", "sun_alt_deg:Sun altitude deg", "all_luts_ms:all LUTs ms", "sun_luts_ms:Sun-dependent LUTs ms",
                                        "ratio_512x256:512x256 x trivial", "rms_rel*100:RMS error %", "max_rel*100:largest error %"}}}});

}  // namespace
}  // namespace welkin::cli
