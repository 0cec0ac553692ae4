// welkin bench halos: the cost and accuracy of the Halos element (issue 21 items 3-4).
// (1) The phase tables' trace time per quality (traced afresh, not read from the disk cache;
// threads: all cores). (2) The halo pass per frame at 800x450 and 1280x720 (perspective, 100 deg,
// towards the Sun 20 deg up; a crystal layer of optical depth 0.3, the common preset): the
// element's render time against a trivial element (constant radiance through the same composite
// contract) drawn before it in the same frames; "x trivial" is the median of per-frame ratios.
// The default display (the adaptive cells, `--cell-tolerance`, their fetching pieces reading the
// fine table nearest-texel, `--fine-scale`), every cell fetching bilinearly (the display before
// 2026-11-28), no crystals (the element skips its draw) and the per-pixel path; also as the
// process's CPU work. Target: the pass as drawn by default <= 1.5x trivial (CPU work). `--sizes` sets the frames' sizes (800x450 and 1280x720 by
// default); `--floors true` also times what cheaper displays would cost at least (Halos::setDisplayProbe:
// bigger cells, a nearest-texel fetch, every piece from its corners; not image paths). (3) Accuracy of one quality's tables (default: `default`) against the slow
// exact path, the brute-force trace (every Fresnel branch followed with its weight) with 10x the
// rays, at the light elevation midway between two slices (below).
#include "bench_util.hpp"
#include "scene_options.hpp"

#include <CLI/CLI.hpp>
#include <welkin/bench.hpp>
#include <welkin/csv.hpp>
#include <welkin/elements/halos.hpp>
#include <welkin/error.hpp>
#include <welkin/gl/context.hpp>
#include <welkin/keys.hpp>
#include <welkin/processor.hpp>

#include <epoxy/gl.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <utility>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <functional>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

namespace welkin::cli {
namespace {

constexpr double kDeg = M_PI / 180;

// The halo pass's and the trivial pass's render times (ms) in the frame just rendered (NaN for
// a trivial pass not in the frame).
std::pair<double, double> passTimes(const SkyProcessor& p) {
    const nlohmann::json j = p.stats();
    double halos = 0, trivial = NAN;
    for (const auto& el : j["elements"]) {
        if (el["name"] == "halos") halos = el["render_ms"].get<double>();
        if (el["name"] == "trivial") trivial = el["render_ms"].get<double>();
    }
    return {halos, trivial};
}

// The bench's view: perspective, towards the south 30 deg up, a 100 deg vertical field, w x h.
Camera benchCamera(int w, int h) {
    Camera cam;
    cam.projection = Projection::Perspective;
    cam.azimuthRad = M_PI;
    cam.altitudeRad = 30 * kDeg;
    cam.verticalFovRad = 100 * kDeg;
    cam.width = w;
    cam.height = h;
    return cam;
}

struct HalosBenchOptions {
    int repeats = 10;
    std::string csv = "bench_halos.csv";
    std::string qualities = "low,default";
    std::string accuracyQuality = "default";
    std::string passQuality = "default";  // the tables the element draws by default (the adaptive cells depend on them)
    bool accuracy = true;
    double cellTolerance = elements::Halos::kCellTolerance;
    int fineScale = elements::Halos::kFineScale;
    int exactFactor = 10;
    std::string sizes = "800x450,1280x720";  // the timed frames' sizes, WxH each
    bool floors = false;                     // also what cheaper displays would cost at least (Halos::setDisplayProbe)
};

// The sizes of `--sizes` ("WxH,WxH"), each side in [16, 4096]; throws naming the option.
std::vector<std::pair<int, int>> benchSizes(const std::string& list) {
    std::vector<std::pair<int, int>> out;
    for (const std::string& item : splitList(list)) {
        int w = 0, h = 0;
        parseSize(item, "--sizes", w, h);
        if (w < 16 || h < 16 || w > 4096 || h > 4096) throw Error("--sizes " + item + ": each side not in [16, 4096]");
        out.emplace_back(w, h);
    }
    if (out.empty()) throw Error("--sizes '" + list + "': no size (WxH,WxH...)");
    return out;
}

std::string fmtDeg(double d) {
    char b[32];
    std::snprintf(b, sizeof b, "%.2f", d);
    return b;
}

int run(const HalosBenchOptions& o) {
    if (o.repeats < 1 || o.repeats > 1000) throw Error("--repeats " + std::to_string(o.repeats) + " not in [1, 1000]");
    if (!(o.cellTolerance > 0.0 && o.cellTolerance <= 1.0)) throw Error("--cell-tolerance " + std::to_string(o.cellTolerance) + " not in (0, 1]");
    if (o.fineScale < 0 || o.fineScale > 4) throw Error("--fine-scale " + std::to_string(o.fineScale) + " not in [0, 4]");
    if (o.exactFactor < 2 || o.exactFactor > 100) throw Error("--exact-factor " + std::to_string(o.exactFactor) + " not in [2, 100]");
    (void)elements::halos::HaloTables::quality(o.accuracyQuality);
    (void)elements::halos::HaloTables::quality(o.passQuality);
    for (const std::string& q : splitList(o.qualities)) (void)elements::halos::HaloTables::quality(q);
    const std::vector<std::pair<int, int>> sizes = benchSizes(o.sizes);
    checkOutputDirectory("--csv", o.csv);
    Logger log;
    auto ctx = gl::HeadlessContext::create({}, log);
    std::unique_ptr<CsvWriter> f;
    if (!o.csv.empty()) f = std::make_unique<CsvWriter>(o.csv, std::vector<std::string>{"what", "quality_or_size", "value", "trivial_ms", "ratio_trivial"});
    if (f) f->comment("welkin bench halos, median of " + std::to_string(o.repeats) + " frames, " + ctx->description());
    std::printf("welkin bench halos (%s)\n\n| what | quality / size | value | trivial ms | x trivial |\n|---|---|---|---|---|\n",
                ctx->description().c_str());
    auto emit = [&](const std::string& what, const std::string& q, double v, double triv, double ratio) {
        std::printf("| %s | %s | %.4g | %.3f | %.2f |\n", what.c_str(), q.c_str(), v, triv, ratio);
        if (f) f->row(what, q, v, triv, ratio);
    };
    // (1) Tables.
    for (const std::string& name : splitList(o.qualities)) {
        const auto q = elements::halos::HaloTables::quality(name);
        const auto t = elements::halos::HaloTables::build(q, 0.2, 2.0, 1.0 * kDeg);
        emit("phase tables trace, s", name + " (" + std::to_string(q.na) + "x" + std::to_string(q.ne) + " bins, " + std::to_string(q.slices) +
                                          " elevations, " + std::to_string(q.raysPerSlice) + " rays each)",
             t.buildSeconds, NAN, NAN);
    }
    // (2) Per frame, four processors rendered in turn, frame after frame (so the machine's load
    // falls on all alike): the real-time grid with its adaptive cells (off by default), the grid
    // fetching in every cell (the default), no crystals, the per-pixel path.
    bool met = true;
    for (auto [w, h] : sizes) {
        struct Path {
            const char* what;
            std::unique_ptr<SkyProcessor> p;
            elements::Halos* halos = nullptr;
            std::vector<double> ms, tms, ratio;
        };
        std::vector<Path> paths;
        for (int path = 0; path < 4; ++path) {
            Path P{path == 0   ? "halo pass, crystal layer tau 0.3 (the default: adaptive cells), ms"
                   : path == 1 ? "halo pass, crystal layer tau 0.3, every cell fetching bilinearly (the display before), ms"
                   : path == 2 ? "halo pass, no crystals (skipped), ms"
                               : "halo pass, per-pixel path (offline: fisheye, equirect, cirrus), ms",
                   std::make_unique<SkyProcessor>(SkyVars::earth(), log, ProcessorOptions{.timing = true, .astronomy = false})};
            SkyProcessor& p = *P.p;
            p.setCamera(benchCamera(w, h));
            p.setExposure({.ev100 = 12});
            p.add(std::make_unique<TrivialElement>());
            auto e = std::make_unique<elements::Halos>();
            P.halos = e.get();
            p.add(std::move(e));
            p.vars().set(keys::sunDirection, directionFromAzAlt(M_PI, 20 * kDeg));
            p.vars().set(elements::haloskeys::opticalDepth, path == 2 ? 0.0 : 0.3);
            P.halos->setAdaptiveCells(path != 1);
            P.halos->setCellTolerance(o.cellTolerance);
            P.halos->setFineScale(o.fineScale);
            P.halos->setForcePerPixel(path == 3);
            // The adaptive cells depend on the table (its grain is detail): `--pass-quality default`
            // for the tables the element draws by default (from the disk cache after the first run).
            p.vars().set(elements::haloskeys::tableQuality, o.passQuality);
            p.renderFrame();  // tables, programs, the cells' lists
            paths.push_back(std::move(P));
        }
        for (int i = 0; i < o.repeats; ++i)
            for (Path& P : paths) {
                P.p->renderFrame();
                const auto [renderMs, t] = passTimes(*P.p);
                P.ms.push_back(renderMs);
                P.tms.push_back(t);
                P.ratio.push_back(renderMs / t);
            }
        const std::string size = std::to_string(w) + "x" + std::to_string(h);
        for (std::size_t k = 0; k < paths.size(); ++k) {
            Path& P = paths[k];
            const double r = median(P.ratio);
            std::string note = P.halos->drewLastFrame() ? "" : ", not drawn";
            if (k == 0 && P.halos->gridLastFrame()) {
                const auto c = P.halos->readCellCounts(P.p->camera());
                char b[200];
                std::snprintf(b, sizeof b, ", %.1f %% of the drawn pixels fetch (%d pieces fetch, %d smooth)",
                              100.0 * double(c.fetchPixels) / double(std::max(c.fetchPixels + c.smoothPixels, 1L)), c.fetchLeaves, c.smoothLeaves);
                note += b;
            }
            emit(P.what, size + note, median(P.ms), median(P.tms), r);
        }
        // The cells' lists are made once for a view at rest; a moving camera (or light) draws
        // every cell fetching instead (Halos::setCellsAtRestOnly): the element with the camera
        // moving in each frame, as the same median ratio.
        {
            Path& P = paths[0];
            std::vector<double> ms, tms, ratio;
            for (int i = 0; i < o.repeats; ++i) {
                Camera cam = P.p->camera();
                cam.azimuthRad = M_PI + ((i % 2) ? 1e-4 : -1e-4);  // a camera that moves: new lists
                P.p->setCamera(cam);
                P.p->renderFrame();
                const auto [renderMs, t] = passTimes(*P.p);
                ms.push_back(renderMs);
                tms.push_back(t);
                ratio.push_back(renderMs / t);
            }
            emit("halo pass, adaptive cells, camera moving (every cell fetching while the view moves), ms", size, median(ms), median(tms), median(ratio));
        }
    }
    // (3) Accuracy of the tables of one quality (`--accuracy-quality`) against the slow exact
    // path: the brute-force trace (every Fresnel branch followed with its weight) with
    // `--exact-factor` times the rays, at the light elevation midway between two slices near 20
    // deg (the worst case of the tables' linear interpolation between slices), same bins. The
    // tables' value there is what the element draws: the mean of the two slices' traces. Also the
    // Monte-Carlo trace at that elevation itself (the noise alone, without the interpolation).
    // Relative L1 over the sky outside 1 deg of the light (green), and over the bins where the
    // exact table exceeds 10 % of its maximum (the halos themselves). The exact table has noise
    // of its own, 1/sqrt(factor) of the tables': the difference overstates the tables' error by
    // sqrt(1 + 1/factor) (5 % at 10).
    // (2b) The same as work: the process's CPU time per frame (all threads, llvmpipe's too), which
    // the other jobs on a loaded machine lengthen less than the wall time. Six processors, frames
    // alternated: Z (the element with no crystals: skipped), Y (Z + the trivial pass), A (the
    // trivial pass and the halo pass, adaptive cells, the fetching pieces at `--fine-scale`), B (A
    // with the fetching pieces reading the table bilinearly: fine scale 0, the default), C (every
    // cell fetching bilinearly: the display before), M (A with the camera moving: every cell
    // fetching while the view moves). The halo pass's work is A - Y (B - Y, C - Y, M - Y), the
    // trivial pass's Y - Z; medians over the frames. The target is judged on A.
    // A processor with the trivial pass or not and the halos at optical depth tau, the element
    // configured by `setup` before it is added; two frames rendered (tables, programs).
    auto makeWith = [&](int w, int h, bool trivial, double tau, const std::function<void(elements::Halos&)>& setup) {
        auto p = std::make_unique<SkyProcessor>(SkyVars::earth(), log, ProcessorOptions{.timing = false, .astronomy = false});
        p->setCamera(benchCamera(w, h));
        p->setExposure({.ev100 = 12});
        if (trivial) p->add(std::make_unique<TrivialElement>());
        auto e = std::make_unique<elements::Halos>();
        setup(*e);
        p->add(std::move(e));
        p->vars().set(keys::sunDirection, directionFromAzAlt(M_PI, 20 * kDeg));
        p->vars().set(elements::haloskeys::opticalDepth, tau);
        p->vars().set(elements::haloskeys::tableQuality, o.passQuality);
        p->renderFrame();
        p->renderFrame();
        return p;
    };
    for (auto [w, h] : sizes) {
        elements::Halos* last = nullptr;  // the element of the processor made last
        auto make = [&](bool trivial, double tau, bool adaptive, int fine) {
            return makeWith(w, h, trivial, tau, [&](elements::Halos& e) {
                last = &e;
                e.setAdaptiveCells(adaptive);
                e.setCellTolerance(o.cellTolerance);
                e.setFineScale(fine);
            });
        };
        auto Z = make(false, 0.0, true, o.fineScale), Y = make(true, 0.0, true, o.fineScale), A = make(true, 0.3, true, o.fineScale);
        elements::Halos* aHalos = last;
        auto B = make(true, 0.3, true, 0), C = make(true, 0.3, false, o.fineScale), Mv = make(true, 0.3, true, o.fineScale);
        auto cpuMs = [] {
            timespec ts{};
            clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
            return 1e3 * double(ts.tv_sec) + 1e-6 * double(ts.tv_nsec);
        };
        std::vector<double> z, y, a, b, c, m;
        for (int i = 0; i < 3 * o.repeats; ++i) {
            Camera cam = Mv->camera();
            cam.azimuthRad = M_PI + ((i % 2) ? 1e-4 : -1e-4);
            Mv->setCamera(cam);
            for (auto [proc, out] : {std::pair{Z.get(), &z}, std::pair{Y.get(), &y}, std::pair{A.get(), &a}, std::pair{B.get(), &b}, std::pair{C.get(), &c}, std::pair{Mv.get(), &m}}) {
                glFinish();
                const double t0 = cpuMs();
                proc->renderFrame();
                glFinish();
                out->push_back(cpuMs() - t0);
            }
        }
        const double triv = median(y) - median(z);
        const std::string size = std::to_string(w) + "x" + std::to_string(h);
        A->renderFrame();  // the last frame drawn by A's element: the counts read back are its
        const auto cells = aHalos->readCellCounts(A->camera());
        char share[120];
        std::snprintf(share, sizeof share, " (%.1f %% of the drawn pixels fetch)",
                      100.0 * double(cells.fetchPixels) / double(std::max(cells.fetchPixels + cells.smoothPixels, 1L)));
        emit(std::string("work: halo pass, adaptive cells, fine scale ") + std::to_string(o.fineScale) + (o.fineScale == elements::Halos::kFineScale ? " (the default)" : "") + share + ", CPU ms per frame", size, median(a) - median(y), triv,
             (median(a) - median(y)) / triv);
        if ((median(a) - median(y)) / triv > 1.5) met = false;
        emit("work: halo pass, adaptive cells, the fetching pieces bilinear (fine scale 0, the default), CPU ms per frame", size, median(b) - median(y), triv,
             (median(b) - median(y)) / triv);
        emit("work: halo pass, every cell fetching bilinearly (the display before), CPU ms per frame", size, median(c) - median(y), triv, (median(c) - median(y)) / triv);
        emit("work: halo pass, adaptive cells, camera moving (every cell fetching while it moves), CPU ms per frame", size, median(m) - median(y), triv, (median(m) - median(y)) / triv);
    }
    // (2c) What cheaper displays would cost at least (`--floors`; skyelements/halos/README.md,
    // "What any route costs at least"): the grid drawn by probes (Halos::setDisplayProbe) that are
    // not image paths: fetching per pixel in bigger pieces, nearest-texel, or every piece from its
    // corners (no fetch per pixel) in pieces of 64, 32 and 16 pixels. Work as in (2b): each
    // processor's CPU time per frame less Y's (the trivial pass and the element with no
    // crystals), over the trivial pass's work (Y - Z); frames alternated.
    if (o.floors)
        for (auto [w, h] : sizes) {
            using Probe = elements::Halos::DisplayProbe;
            struct Floor {
                const char* what;
                Probe probe;
                int cellPx;
            };
            const Floor floors[] = {{"every cell fetching (the display before; a moving view's), 64-pixel cells", Probe::Fetch, 64},
                                    {"fetching, 256-pixel cells", Probe::Fetch, 256},
                                    {"nearest-texel fetch, 64-pixel cells", Probe::Nearest, 64},
                                    {"the fine table (--fine-scale, else 2 x) nearest-texel, 64-pixel cells", Probe::Fine, 64},
                                    {"every piece from its corners (no fetch per pixel), 64-pixel pieces", Probe::Corners, 64},
                                    {"every piece from its corners, 32-pixel pieces", Probe::Corners, 32},
                                    {"every piece from its corners, 16-pixel pieces", Probe::Corners, 16}};
            auto make = [&](bool trivial, double tau, const Floor* fl) {
                return makeWith(w, h, trivial, tau, [&](elements::Halos& e) {
                    e.setAdaptiveCells(false);  // the probes draw the grid without the adaptive cells
                    e.setFineScale(o.fineScale > 0 ? o.fineScale : 2);  // the Fine probe's table: 2 x finer unless --fine-scale says
                    if (fl) e.setDisplayProbe(fl->probe, fl->cellPx);
                });
            };
            auto Z = make(false, 0.0, nullptr), Y = make(true, 0.0, nullptr);
            std::vector<std::unique_ptr<SkyProcessor>> P;
            for (const Floor& fl : floors) P.push_back(make(true, 0.3, &fl));
            auto cpuMs = [] {
                timespec ts{};
                clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
                return 1e3 * double(ts.tv_sec) + 1e-6 * double(ts.tv_nsec);
            };
            std::vector<double> z, y;
            std::vector<std::vector<double>> t(P.size());
            auto timeFrame = [&](SkyProcessor& proc, std::vector<double>& out) {
                glFinish();
                const double t0 = cpuMs();
                proc.renderFrame();
                glFinish();
                out.push_back(cpuMs() - t0);
            };
            for (int i = 0; i < 3 * o.repeats; ++i) {
                timeFrame(*Z, z);
                timeFrame(*Y, y);
                for (std::size_t k = 0; k < P.size(); ++k) timeFrame(*P[k], t[k]);
            }
            const double triv = median(y) - median(z);
            const std::string size = std::to_string(w) + "x" + std::to_string(h);
            for (std::size_t k = 0; k < P.size(); ++k)
                emit(std::string("floor: ") + floors[k].what + ", CPU ms per frame", size, median(t[k]) - median(y), triv, (median(t[k]) - median(y)) / triv);
        }
    if (!o.accuracy) {
        std::printf("\ntarget: halo pass <= 1.5x the trivial pass: %s\n", met ? "met" : "NOT met");
        return 0;
    }
    using namespace elements::halos;
    const HaloTables::Quality aq = HaloTables::quality(o.accuracyQuality);
    const double step = 90.0 / (aq.slices - 1);
    const double h0 = std::floor(20.0 / step) * step, h1 = h0 + step, hm = 0.5 * (h0 + h1);
    const uint64_t exactRays = uint64_t(o.exactFactor) * aq.raysPerSlice;
    auto l1 = [&](const Phase2D& a, const Phase2D& ex, double hDeg, bool features, bool aboveHorizon) {
        double mx = 0;
        for (const auto& v : ex.p) mx = std::max(mx, v.y);
        double diff = 0, norm = 0;
        for (int ie = 0; ie < ex.ne; ++ie) {
            const double e = ex.elevationRad(ie), omega = 2 * (M_PI / ex.na) * (std::sin(e + 0.5 * M_PI / ex.ne) - std::sin(e - 0.5 * M_PI / ex.ne));
            for (int ia = 0; ia < ex.na; ++ia) {
                const double az = ex.azimuthRad(ia);
                if (std::cos(e) * std::cos(az) * std::cos(hDeg * kDeg) + std::sin(e) * std::sin(hDeg * kDeg) > std::cos(1 * kDeg)) continue;  // the direct beam
                if (features && ex.at(ie, ia).y < 0.1 * mx) continue;
                if (aboveHorizon && e < 0.0) continue;
                diff += std::abs(a.at(ie, ia).y - ex.at(ie, ia).y) * omega;
                norm += ex.at(ie, ia).y * omega;
            }
        }
        return norm > 0 ? diff / norm : NAN;
    };
    auto sundog = [&](const Phase2D& p, double hDeg) {
        const int ie = std::clamp(int((hDeg + 90.0) / 180.0 * p.ne), 0, p.ne - 1);
        int best = p.na / 12;
        for (int ia = p.na / 12; ia < p.na / 3; ++ia)
            if (p.at(ie, ia).y > p.at(ie, best).y) best = ia;
        return p.azimuthRad(best) / kDeg;
    };
    // Each slice without the light within 1 deg of its own light (HaloTables::mix: it stays in
    // the direct beam).
    auto cutForward = [&](Phase2D& p, double hDeg) {
        for (int ie = 0; ie < p.ne; ++ie)
            for (int ia = 0; ia < p.na; ++ia) {
                const double e = p.elevationRad(ie), az = p.azimuthRad(ia);
                if (std::cos(e) * std::cos(az) * std::cos(hDeg * kDeg) + std::sin(e) * std::sin(hDeg * kDeg) > std::cos(1 * kDeg))
                    p.p[std::size_t(ie) * std::size_t(p.na) + std::size_t(ia)] = glm::dvec3(0.0);
            }
    };
    const std::string at = o.accuracyQuality + " tables, light " + fmtDeg(hm) + " deg (slices " + fmtDeg(h0) + ", " + fmtDeg(h1) + ")";
    const Population pops[2] = {{Orientation::Plate, 0.2, 1.0 * kDeg}, {Orientation::Column, 2.0, 1.0 * kDeg}};
    const char* popName[2] = {"plates", "columns"};
    for (int k = 0; k < 2; ++k) {
        // The slices as HaloTables::build makes them: traced, then denoised.
        Phase2D a0 = traceOriented(pops[k], h0 * kDeg, aq.ne, aq.na, aq.raysPerSlice, 31 + uint64_t(k));
        Phase2D a1 = traceOriented(pops[k], h1 * kDeg, aq.ne, aq.na, aq.raysPerSlice, 41 + uint64_t(k));
        denoise(a0, aq.raysPerSlice);
        denoise(a1, aq.raysPerSlice);
        Phase2D a0c = a0, a1c = a1;
        cutForward(a0c, h0);
        cutForward(a1c, h1);
        // The element's blend (halos.cpp, sliceBlend): each slice shifted in elevation by the
        // light's offset from it, then the two averaged (the light midway).
        Phase2D tab = a0c;
        const double rowsPerDeg = aq.ne / 180.0;
        auto rowAt = [&](const Phase2D& p, double row, int ia) {
            const double f = std::clamp(row, 0.0, double(p.ne - 1));
            const int e0 = int(f), e1 = std::min(e0 + 1, p.ne - 1);
            return p.at(e0, ia) * (1.0 - (f - e0)) + p.at(e1, ia) * (f - e0);
        };
        // Mirrored below the horizon, linear between -5 and 5 deg (halos.cpp, rowShift).
        // (plates only: columns shift everywhere).
        auto mirror = [&](int ie) { return k == 0 ? std::clamp(tab.elevationRad(ie) / (5 * kDeg), -1.0, 1.0) : 1.0; };
        for (int ie = 0; ie < tab.ne; ++ie)
            for (int ia = 0; ia < tab.na; ++ia)
                tab.p[std::size_t(ie) * std::size_t(tab.na) + std::size_t(ia)] =
                    0.5 * (rowAt(a0c, ie + mirror(ie) * (h0 - hm) * rowsPerDeg, ia) + rowAt(a1c, ie + mirror(ie) * (h1 - hm) * rowsPerDeg, ia));
        Phase2D mid = traceOriented(pops[k], hm * kDeg, aq.ne, aq.na, aq.raysPerSlice, 51 + uint64_t(k));
        Phase2D midDenoised = mid;
        denoise(midDenoised, aq.raysPerSlice);
        Phase2D ex = traceOrientedExact(pops[k], hm * kDeg, aq.ne, aq.na, exactRays, 61 + uint64_t(k));
        cutForward(mid, hm);
        cutForward(midDenoised, hm);
        cutForward(ex, hm);
        const std::string what = std::string("accuracy, ") + popName[k] + ": ";
        const std::string vs = at + " vs brute force " + std::to_string(exactRays) + " rays";
        emit(what + "L1(tables - exact) / L1(exact), whole sphere", vs, l1(tab, ex, hm, false, false), NAN, NAN);
        emit(what + "L1(tables - exact) / L1(exact), above the horizon", vs, l1(tab, ex, hm, false, true), NAN, NAN);
        emit(what + "L1(tables - exact) / L1(exact), the halos (> 10 % of max)", vs, l1(tab, ex, hm, true, false), NAN, NAN);
        emit(what + "L1(trace at that elevation - exact) / L1(exact), whole sphere (noise alone)", vs, l1(mid, ex, hm, false, false), NAN, NAN);
        emit(what + "L1(trace at that elevation - exact) / L1(exact), above the horizon (noise alone)", vs, l1(mid, ex, hm, false, true), NAN, NAN);
        emit(what + "L1(trace at that elevation, denoised - exact) / L1(exact), whole sphere", vs, l1(midDenoised, ex, hm, false, false), NAN, NAN);
        emit(what + "L1(trace at that elevation, denoised - exact) / L1(exact), above the horizon", vs, l1(midDenoised, ex, hm, false, true), NAN, NAN);
        emit(what + "L1(trace at that elevation, denoised - exact) / L1(exact), the halos (> 10 % of max)", vs, l1(midDenoised, ex, hm, true, false), NAN, NAN);
        emit(what + "L1(trace at that elevation - exact) / L1(exact), the halos (> 10 % of max) (noise alone)", vs, l1(mid, ex, hm, true, false), NAN, NAN);
        emit(what + "brute force trace time, s", std::to_string(exactRays) + " rays", ex.stats.seconds, NAN, NAN);
        if (k == 0) {
            emit("accuracy, plates: sundog crest azimuth, deg: tables", at + ", formula " + fmtDeg(parhelionAzimuthRad(iceRefractiveIndex(kChannelNm[1]), hm * kDeg) / kDeg),
                 sundog(tab, hm), NAN, NAN);
            emit("accuracy, plates: sundog crest azimuth, deg: brute force", "", sundog(ex, hm), NAN, NAN);
        }
    }
    {
        // The random population's 1-D table against the same trace with factor x the rays (no
        // branch-following variant for random crystals: the noise alone).
        // The table as HaloTables::build makes it (denoised), and the raw trace.
        const Phase1D raw = traceRandom({Orientation::Random, 2.0, 0.0}, aq.bins, aq.raysRandom, 7777);
        Phase1D a = raw;
        denoise(a, aq.raysRandom);
        const Phase1D ex = traceRandom({Orientation::Random, 2.0, 0.0}, aq.bins, uint64_t(o.exactFactor) * aq.raysRandom, 8888);
        auto l1r = [&](const Phase1D& t) {
            double diff = 0, norm = 0;
            for (std::size_t i = 0; i < t.p.size(); ++i) {
                const double th = (double(i) + 0.5) * t.binRad();
                if (th < 1 * kDeg) continue;
                const double omega = 2 * M_PI * std::sin(th) * t.binRad();
                diff += std::abs(t.p[i].y - ex.p[i].y) * omega;
                norm += ex.p[i].y * omega;
            }
            return diff / norm;
        };
        const std::string vs1 = o.accuracyQuality + " table " + std::to_string(aq.raysRandom) + " vs " + std::to_string(uint64_t(o.exactFactor) * aq.raysRandom) + " rays";
        emit("accuracy, random: L1(table, denoised - trace with more rays) / L1", vs1, l1r(a), NAN, NAN);
        emit("accuracy, random: L1(raw trace - trace with more rays) / L1", vs1, l1r(raw), NAN, NAN);
    }
    std::printf("\ntarget: halo pass <= 1.5x the trivial pass: %s\n", met ? "met" : "NOT met");
    if (f) {
        f->close();
        std::printf("wrote %s\n", o.csv.c_str());
    }
    return 0;
}

bench::CommandBenchRegistrar reg({"halos", "halo table trace times, the halo pass's cost against a trivial pass, accuracy against a brute-force trace",
                   [](CLI::App& sub) {
                       auto o = std::make_shared<HalosBenchOptions>();  // the action below owns it
                       sub.add_option("--repeats", o->repeats, "timed frames per row (median reported), [1, 1000]")->capture_default_str();
                       sub.add_option("--csv", o->csv, "write the rows as CSV (empty: none)")->capture_default_str();
                       sub.add_option("--qualities", o->qualities, "comma list of table qualities to trace: low, default, high")->capture_default_str();
                       sub.add_option("--accuracy-quality", o->accuracyQuality, "the table quality whose accuracy is measured: low, default, high")
                           ->capture_default_str();
                       sub.add_option("--pass-quality", o->passQuality, "the tables the timed pass draws: low, default, high (the adaptive cells depend on them)")->capture_default_str();
                       sub.add_option("--cell-tolerance", o->cellTolerance,
                                      "the adaptive cells' tolerance, a fraction of what the pixel shows, (0, 1] (Halos::kCellTolerance)")
                           ->capture_default_str();
                       sub.add_option("--fine-scale", o->fineScale,
                                      "the fetching pieces' fine table, texels per grid-table texel and axis, [1, 4], or 0: the table bilinearly (Halos::kFineScale)")
                           ->capture_default_str();
                       sub.add_option("--accuracy", o->accuracy, "measure the tables against the brute-force trace (minutes with default tables)")
                           ->capture_default_str();
                       sub.add_option("--sizes", o->sizes, "comma list of the timed frames' sizes, WxH (each side in [16, 4096])")->capture_default_str();
                       sub.add_option("--floors", o->floors,
                                      "also time what cheaper displays would cost at least: bigger cells, nearest-texel, every piece from its corners (not image paths)")
                           ->capture_default_str();
                       sub.add_option("--exact-factor", o->exactFactor, "the brute-force trace's rays over the tables' rays per slice, [2, 100]")
                           ->capture_default_str();
                       return [o]() { return run(*o); };
                   },
                   // The table `welkin bench all` writes into docs/BENCHMARKS.md from this bench (crystal table sizes as work).
                   {{.element = "halos",
                     .title = "Halos: crystal tables by quality, the pass, and accuracy",
                     .what = "The crystal populations' ray trace at each table quality (rays traced: the tables' size as work), the "
                             "halo pass against a trivial pass timed alternately with it (the default display: adaptive cells and a fine "
                             "table read nearest-texel; every cell fetching bilinearly, the display before; also as the process's CPU work), and the tables against a brute-force trace "
                             "with four times the rays.",
                     .args = {"--qualities", "low,default", "--repeats", "5"},
                     .quickArgs = {"--qualities", "low", "--repeats", "1", "--accuracy-quality", "low", "--exact-factor", "2", "--pass-quality", "low"},
                     .columns = {"what", "quality_or_size:quality, size or rays", "value", "trivial_ms:trivial pass ms", "ratio_trivial:x trivial pass"}}}});

}  // namespace
}  // namespace welkin::cli
