// welkin bench halos: the cost and accuracy of the Halos element (issue 21 items 3-4).
// (1) The phase tables' trace time per quality (traced afresh, not read from the disk cache;
// threads: all cores). (2) The halo pass per frame at 800x450 and 1280x720 (perspective, 100 deg,
// towards the Sun 20 deg up; a crystal layer of optical depth 0.3, the common preset): the
// element's render time against a trivial element (constant radiance through the same composite
// contract) drawn before it in the same frames; "x trivial" is the median of per-frame ratios.
// Also with no crystals (the element skips its draw). Target: pass <= 1.5x trivial. (3) Accuracy:
// the tables' Monte-Carlo trace (one random Fresnel branch per face) against the brute-force
// trace (every branch followed with its weight) with 4x the rays, plate-oriented plates at 20 deg:
// the relative L1 difference of the two tables over the sky, and the sundog's and the 22 deg
// edge's positions in both.
#include "bench_util.hpp"

#include <CLI/CLI.hpp>
#include <welkin/bench.hpp>
#include <welkin/csv.hpp>
#include <welkin/elements/halos.hpp>
#include <welkin/error.hpp>
#include <welkin/gl/context.hpp>
#include <welkin/keys.hpp>
#include <welkin/processor.hpp>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

namespace welkin::cli {
namespace {

constexpr double kDeg = M_PI / 180;

struct HalosBenchOptions {
    int repeats = 10;
    std::string csv = "bench_halos.csv";
    std::string qualities = "low,default";
    long long accuracyRays = 2000000;
};

int run(const HalosBenchOptions& o) {
    if (o.repeats < 1 || o.repeats > 1000) throw Error("--repeats " + std::to_string(o.repeats) + " not in [1, 1000]");
    if (o.accuracyRays < 3000 || o.accuracyRays > 100000000)
        throw Error("--accuracy-rays " + std::to_string(o.accuracyRays) + " not in [3000, 100000000]");
    for (const std::string& q : splitList(o.qualities)) (void)elements::halos::HaloTables::quality(q);
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
    // (2) Per frame.
    bool met = true;
    for (auto [w, h] : {std::pair{800, 450}, std::pair{1280, 720}}) {
        for (int path = 0; path < 2; ++path) {
            SkyProcessor p(SkyVars::earth(), log, ProcessorOptions{.timing = true, .astronomy = false});
            Camera cam;
            cam.projection = Projection::Perspective;
            cam.azimuthRad = M_PI;
            cam.altitudeRad = 30 * kDeg;
            cam.verticalFovRad = 100 * kDeg;
            cam.width = w;
            cam.height = h;
            p.setCamera(cam);
            p.setExposure({.ev100 = 12});
            p.add(std::make_unique<TrivialElement>());
            auto e = std::make_unique<elements::Halos>();
            elements::Halos* halos = e.get();
            p.add(std::move(e));
            p.vars().set(keys::sunDirection, directionFromAzAlt(M_PI, 20 * kDeg));
            p.vars().set(elements::haloskeys::opticalDepth, path == 0 ? 0.3 : 0.0);
            p.vars().set(elements::haloskeys::tableQuality, std::string("low"));  // the pass's cost does not depend on it
            p.renderFrame();  // tables, programs
            std::vector<double> ms, tms, ratio;
            for (int i = 0; i < o.repeats; ++i) {
                p.renderFrame();
                const nlohmann::json j = p.stats();
                double renderMs = 0, t = NAN;
                for (const auto& el : j["elements"]) {
                    if (el["name"] == "halos") renderMs = el["render_ms"].get<double>();
                    if (el["name"] == "trivial") t = el["render_ms"].get<double>();
                }
                ms.push_back(renderMs);
                tms.push_back(t);
                ratio.push_back(renderMs / t);
            }
            const std::string size = std::to_string(w) + "x" + std::to_string(h);
            const double r = median(ratio);
            emit(path == 0 ? "halo pass, crystal layer tau 0.3, ms" : "halo pass, no crystals (skipped), ms",
                 size + (halos->drewLastFrame() ? "" : ", not drawn"), median(ms), median(tms), r);
            if (path == 0 && r > 1.5) met = false;
        }
    }
    // (3) Accuracy against the brute-force trace.
    using namespace elements::halos;
    const Population plates{Orientation::Plate, 0.2, 1.0 * kDeg};
    const uint64_t rays = uint64_t(o.accuracyRays);
    const Phase2D mc = traceOriented(plates, 20 * kDeg, 180, 360, rays, 21);
    const Phase2D ex = traceOrientedExact(plates, 20 * kDeg, 180, 360, 4 * rays, 22);
    double diff = 0, norm = 0;
    for (int ie = 0; ie < mc.ne; ++ie) {
        const double e = mc.elevationRad(ie), omega = 2 * (M_PI / mc.na) * (std::sin(e + 0.5 * M_PI / mc.ne) - std::sin(e - 0.5 * M_PI / mc.ne));
        for (int ia = 0; ia < mc.na; ++ia) {
            const double a = mc.azimuthRad(ia);
            if (std::cos(e) * std::cos(a) * std::cos(20 * kDeg) + std::sin(e) * std::sin(20 * kDeg) > std::cos(1 * kDeg)) continue;  // the forward beam
            diff += std::abs(mc.at(ie, ia).y - ex.at(ie, ia).y) * omega;
            norm += ex.at(ie, ia).y * omega;
        }
    }
    emit("accuracy: L1(tables - brute force) / L1(brute force), plates at 20 deg", std::to_string(rays) + " vs " + std::to_string(4 * rays) + " rays",
         diff / norm, NAN, NAN);
    auto sundog = [](const Phase2D& p) {
        const int ie = int((20.0 + 90.0) / 180.0 * p.ne);
        int best = 30;
        for (int ia = 30; ia < 120; ++ia)
            if (p.at(ie, ia).y > p.at(ie, best).y) best = ia;
        return p.azimuthRad(best) / kDeg;
    };
    emit("sundog crest azimuth, deg: tables", "formula " + std::to_string(parhelionAzimuthRad(iceRefractiveIndex(kChannelNm[1]), 20 * kDeg) / kDeg),
         sundog(mc), NAN, NAN);
    emit("sundog crest azimuth, deg: brute force", "", sundog(ex), NAN, NAN);
    emit("trace time, s: tables' trace", std::to_string(rays) + " rays", mc.stats.seconds, NAN, NAN);
    emit("trace time, s: brute force", std::to_string(4 * rays) + " rays", ex.stats.seconds, NAN, NAN);
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
                       sub.add_option("--accuracy-rays", o->accuracyRays, "rays of the tables' trace in the accuracy check (the brute force: 4x), [3000, 1e8]")
                           ->capture_default_str();
                       return [o]() { return run(*o); };
                   },
                   // The table `welkin bench all` writes into docs/BENCHMARKS.md from this bench (crystal table sizes as work).
                   {{.element = "halos",
                     .title = "Halos: crystal tables by quality, the pass, and accuracy",
                     .what = "The crystal populations' ray trace at each table quality (rays traced: the tables' size as work), the "
                             "halo pass against a trivial pass timed alternately with it, and the tables against a brute-force trace "
                             "with four times the rays.",
                     .args = {"--qualities", "low,default", "--repeats", "5"},
                     .quickArgs = {"--qualities", "low", "--repeats", "1", "--accuracy-rays", "200000"},
                     .columns = {"what", "quality_or_size:quality, size or rays", "value", "trivial_ms:trivial pass ms", "ratio_trivial:x trivial pass"}}}});

}  // namespace
}  // namespace welkin::cli
