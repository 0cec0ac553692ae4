// welkin bench lighting: the cost of SkyLighting (welkin/lighting.hpp, issue 18 item 2) against a
// sky frame. The scene: the default elements (or --elements) at Malta, a 1280x720 perspective
// camera, the interactive path (render.interactive), time running at --speed x real time at
// --fps frames per second of the animation (3600x at 30 frames/s: 120 s of sky per frame, so
// every frame's keys change and the lighting refreshes continuously, --slices per frame). Rows:
// (1) the sky frame without lighting (processor instrumented with glFinish: frame_ms); (2) the
// lighting's own cost per frame (its stages' glFinish-bracketed time from --stats) while time
// runs, mean and maximum, as a ratio to (1)'s mean (target <= 0.3); (3) a jump of 6 h then the
// time-sliced refresh it starts: the worst frame's lighting cost over the refresh, as a ratio to
// a sky frame (target <= 1), both as the lighting's stages and as the difference between the two
// processors' frames (the elements' own work after a jump, e.g. the clouds' cache refill, lands
// in whichever draws first); (1)-(3) run in lockstep; (4) the offline path's whole refresh in one frame (welkin render),
// with each stage.
#include "bench_util.hpp"
#include "command.hpp"

#include <welkin/csv.hpp>
#include <welkin/elements/registry.hpp>
#include <welkin/error.hpp>
#include <welkin/gl/context.hpp>
#include <welkin/keys.hpp>
#include <welkin/lighting.hpp>
#include <welkin/processor.hpp>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <numeric>
#include <string>
#include <vector>

namespace welkin::cli {
namespace {

constexpr double kDeg = M_PI / 180;
constexpr int kWarmup = 12;  // frames before timing: more than one refresh at one slice per frame

struct LightingBenchOptions {
    int frames = 40;           // timed frames while time runs
    double speed = 3600;       // simulated seconds per real second
    double fps = 30;           // animation frames per real second
    int cubeSize = 32;
    int slices = 1;
    std::string elements = "default";
    std::string time = "2026-07-15T06:30:00+02:00";  // Malta, the Sun ~10 deg up and rising
    std::string csv = "bench_lighting.csv";
};

double mean(const std::vector<double>& v) { return v.empty() ? NAN : std::accumulate(v.begin(), v.end(), 0.0) / double(v.size()); }

int run(const LightingBenchOptions& o) {
    if (o.frames < 2 || o.frames > 10000) throw Error("--frames " + std::to_string(o.frames) + " not in [2, 10000]");
    if (!(o.speed >= 0 && o.speed <= 1e7)) throw Error("--speed " + std::to_string(o.speed) + " not in [0, 1e7]");
    if (!(o.fps >= 1 && o.fps <= 1000)) throw Error("--fps " + std::to_string(o.fps) + " not in [1, 1000]");
    LightingOptions lo{.cubeSize = o.cubeSize, .specularMips = 5, .slicesPerFrame = o.slices};
    lo.validate("welkin bench lighting");
    const std::vector<std::string> names = elements::expandElementList(o.elements);
    const UtcInstant t0 = UtcInstant::parse(o.time);
    checkOutputDirectory("--csv", o.csv);

    Logger log;
    auto ctx = gl::HeadlessContext::create({}, log);
    auto makeProcessor = [&] {
        auto p = std::make_unique<SkyProcessor>(SkyVars::earth(), log, ProcessorOptions{.timing = true});
        for (const std::string& n : names) p->add(elements::makeElement(n));
        p->setObserver({.latitudeRad = 35.9 * kDeg, .longitudeRad = 14.5 * kDeg, .heightMeters = 50});
        Camera cam;
        cam.projection = Projection::Perspective;
        cam.azimuthRad = 90 * kDeg;
        cam.altitudeRad = 20 * kDeg;
        cam.verticalFovRad = 60 * kDeg;
        cam.width = 1280;
        cam.height = 720;
        p->setCamera(cam);
        p->setExposure({.automatic = true});
        p->setAnimationTime(0.0);
        p->vars().set(keys::interactive, true);
        return p;
    };
    const double stepS = o.speed / o.fps;
    auto at = [&](int frame) { return t0.plusSeconds(frame * stepS); };
    auto lightingMs = [](const nlohmann::json& j) { return j["lighting"]["frame_ms"]["total"].get<double>(); };

    // (1)-(3) Two processors in lockstep (the same instants, frame after frame, so the machine's
    // load slows both alike): one without lighting (the sky frame), one with it.
    std::vector<double> sky, running, runningFrame, jump, jumpExtra;
    nlohmann::json last;
    int jumpFrames = 0;
    {
        auto base = makeProcessor();
        auto p = makeProcessor();
        p->setLighting(lo);
        for (int i = -kWarmup; i < o.frames; ++i) {  // warm-up: tables, programs (llvmpipe compiles at first use), caches, a whole refresh
            for (SkyProcessor* q : {base.get(), p.get()}) {
                q->setTime(at(i));
                q->setAnimationTime(i / o.fps);
                q->renderFrame();
            }
            if (i < 0) continue;
            const nlohmann::json j = p->stats();
            sky.push_back(base->stats()["frame_ms"].get<double>());
            running.push_back(lightingMs(j));
            runningFrame.push_back(j["frame_ms"].get<double>());
        }
        // Let the last refresh finish with time stopped, then jump both by 6 h. The jump costs
        // the elements themselves (the clouds refill their direction cache, the sky its tables):
        // when the capture draws first it pays part of that for the frame, so the lighting's
        // share of a jump frame is the difference of the two processors' frames.
        for (int k = 0; k < 64 && p->stats()["lighting"]["refreshing"].get<bool>(); ++k) p->renderFrame();
        const int jumpTo = o.frames + int(6 * 3600 / std::max(stepS, 1.0));
        for (SkyProcessor* q : {base.get(), p.get()}) q->setTime(at(jumpTo));
        for (int k = 0; k < 64; ++k) {
            base->renderFrame();
            p->renderFrame();
            const nlohmann::json j = p->stats();
            jump.push_back(lightingMs(j));
            jumpExtra.push_back(j["frame_ms"].get<double>() - base->stats()["frame_ms"].get<double>());
            ++jumpFrames;
            if (!j["lighting"]["refreshing"].get<bool>()) {
                last = j["lighting"];
                break;
            }
        }
    }
    const double skyMs = mean(sky);
    // (4) The offline path: the whole refresh in one frame.
    nlohmann::json offline;
    {
        auto p = makeProcessor();
        p->vars().set(keys::interactive, false);
        p->setLighting(lo);
        p->setTime(t0);
        p->renderFrame();
        p->setTime(at(1));
        p->renderFrame();
        offline = p->stats();
    }
    const double runMean = mean(running), runMax = *std::max_element(running.begin(), running.end());
    const double jumpMax = *std::max_element(jump.begin(), jump.end());
    const double jumpExtraMax = *std::max_element(jumpExtra.begin(), jumpExtra.end());
    std::printf("welkin bench lighting (%s)\n%d frames, time at %gx, %g frames/s (%g s of sky per frame), cube %d, %d slice(s) per frame, elements %s\n\n",
                ctx->description().c_str(), o.frames, o.speed, o.fps, stepS, o.cubeSize, o.slices, o.elements.c_str());
    std::printf("| what | ms | x sky frame |\n|---|---|---|\n");
    std::unique_ptr<CsvWriter> f;
    if (!o.csv.empty()) {
        f = std::make_unique<CsvWriter>(o.csv, std::vector<std::string>{"what", "ms", "ratio_sky_frame"});
        f->comment("welkin bench lighting, " + ctx->description() + ", cube " + std::to_string(o.cubeSize) + ", slices " + std::to_string(o.slices));
    }
    auto emit = [&](const std::string& what, double ms) {
        std::printf("| %s | %.2f | %.3f |\n", what.c_str(), ms, ms / skyMs);
        if (f) f->row(what, ms, ms / skyMs);
    };
    emit("sky frame 1280x720 without lighting (mean)", skyMs);
    emit("sky frame with lighting (mean)", mean(runningFrame));
    emit("lighting per frame while time runs (mean)", runMean);
    emit("lighting per frame while time runs (max)", runMax);
    emit("lighting's stages, worst frame of the refresh after a 6 h jump (" + std::to_string(jumpFrames) + " frames)", jumpMax);
    emit("frame with lighting - frame without, worst frame of that refresh", jumpExtraMax);
    const nlohmann::json& r = offline["lighting"]["refresh_ms"];
    emit("offline refresh in one frame: total", r["total"].get<double>());
    emit("offline refresh: capture (6 faces)", r["capture"].get<double>());
    emit("offline refresh: SH projection", r["sh"].get<double>());
    emit("offline refresh: light map + axis lights", r["light_map"].get<double>());
    emit("offline refresh: GGX prefilter (mips 1..4)", r["prefilter"].get<double>());
    std::printf("\ntarget: lighting while time runs <= 0.3x a sky frame: %s (%.3f)\n", runMean <= 0.3 * skyMs ? "met" : "NOT met", runMean / skyMs);
    std::printf("target: each frame of a time-sliced refresh <= 1 sky frame: %s (%.3f; the frames' difference)\n",
                jumpExtraMax <= skyMs ? "met" : "NOT met", jumpExtraMax / skyMs);
    if (f) {
        f->close();
        std::printf("wrote %s\n", o.csv.c_str());
    }
    return 0;
}

BenchRegistrar reg("lighting", "SkyLighting's cost per frame while time runs and after a jump, against a sky frame", [](CLI::App& sub) {
    auto o = std::make_shared<LightingBenchOptions>();  // the action below owns it
    sub.add_option("--frames", o->frames, "timed frames while time runs, [2, 10000]")->capture_default_str();
    sub.add_option("--speed", o->speed, "simulated seconds per real second, [0, 1e7]")->capture_default_str();
    sub.add_option("--fps", o->fps, "animation frames per real second, [1, 1000]")->capture_default_str();
    sub.add_option("--cube-size", o->cubeSize, "lighting.cube_size, power of two in [8, 1024]")->capture_default_str();
    sub.add_option("--slices", o->slices, "lighting.slices_per_frame, [1, 64]")->capture_default_str();
    sub.add_option("--elements", o->elements, "element list (as welkin render --elements)")->capture_default_str();
    sub.add_option("--time", o->time, "ISO 8601 start instant (Malta)")->capture_default_str();
    sub.add_option("--csv", o->csv, "write the rows as CSV (empty: none)")->capture_default_str();
    return [o]() { return run(*o); };
});

}  // namespace
}  // namespace welkin::cli
