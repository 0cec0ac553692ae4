// welkin bench framework: a fixed scene for counting the framework's CPU instructions per frame
// with callgrind (welkin bench all runs it so):
//
//   LP_NUM_THREADS=0 valgrind --tool=none welkin bench framework --frames 30   # fills Mesa's shader cache
//   LP_NUM_THREADS=0 valgrind --tool=callgrind --instr-atstart=no welkin bench framework --frames 30
//
// (LP_NUM_THREADS=0: llvmpipe rasterises on the calling thread.) Under valgrind, llvmpipe's LLVM
// compiles of every shader variant take most of the run; the first run leaves them in Mesa's
// on-disk cache, which llvmpipe reads back in the second. The first runs under valgrind too:
// llvmpipe keys its cached code on the CPU features it detects, and valgrind's virtual CPU has
// fewer than the machine (no AVX-512), so a native run's entries are not found under valgrind.
//
// The default elements at Malta, 2026-06-21 08:00 UTC, looking east, at a tiny size (the driver's
// per-pixel work is not what is measured), time running at 600x real time at 30 frames/s. The
// warm-up frames (programs compiled, tables built) run uninstrumented; callgrind's
// instrumentation is switched on (CALLGRIND_START_INSTRUMENTATION) for the --frames measured
// frames only, and off after them. Without valgrind the client requests do nothing and the
// command prints the wall time per frame.
#include "command.hpp"

#include <memory>
#include <welkin/elements/registry.hpp>
#include <welkin/error.hpp>
#include <welkin/gl/context.hpp>
#include <welkin/keys.hpp>
#include <welkin/processor.hpp>

#include <epoxy/gl.h>
#include <nlohmann/json.hpp>
#include <valgrind/callgrind.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <string>

namespace welkin::cli {
namespace {

constexpr double kDeg = M_PI / 180;

struct FrameworkOptions {
    int frames = 30;                     // measured frames, [1, 10000]
    int warmup = 8;                      // uninstrumented frames before them, [1, 1000]
    std::string size = "64x36";          // frame size WIDTHxHEIGHT
    std::string elements = "default";    // --elements list
    std::string json;                    // write {elements, size, frames, warmup, ms_per_frame} here
};

int run(const FrameworkOptions& o) {
    if (o.frames < 1 || o.frames > 10000) throw Error("--frames " + std::to_string(o.frames) + " not in [1, 10000]");
    if (o.warmup < 1 || o.warmup > 1000) throw Error("--warmup " + std::to_string(o.warmup) + " not in [1, 1000]");
    int w = 0, h = 0;
    char tail = 0;
    if (std::sscanf(o.size.c_str(), "%dx%d%c", &w, &h, &tail) != 2 || w < 1 || h < 1 || w > 8192 || h > 8192)
        throw Error("--size '" + o.size + "' not WIDTHxHEIGHT in [1, 8192]");
    const std::vector<std::string> names = elements::expandElementList(o.elements);
    Logger log;
    auto ctx = gl::HeadlessContext::create({}, log);
    SkyProcessor p(SkyVars::earth(), log);
    for (const std::string& n : names) p.add(elements::makeElement(n));
    p.setObserver({.latitudeRad = 35.9 * kDeg, .longitudeRad = 14.5 * kDeg, .heightMeters = 50});
    Camera cam;
    cam.projection = Projection::Perspective;
    cam.azimuthRad = 90 * kDeg;
    cam.altitudeRad = 20 * kDeg;
    cam.verticalFovRad = 60 * kDeg;
    cam.width = w;
    cam.height = h;
    p.setCamera(cam);
    p.setExposure({.automatic = true});
    p.vars().set(keys::interactive, true);
    const UtcInstant t0 = UtcInstant::parse("2026-06-21T08:00:00Z");
    constexpr double kStepS = 600.0 / 30.0;  // 600x at 30 frames/s
    auto frame = [&](int i) {
        p.setTime(t0.plusSeconds(i * kStepS));
        p.setAnimationTime(i / 30.0);
        p.renderFrame();
    };
    for (int i = 0; i < o.warmup; ++i) frame(i);
    glFinish();
    const auto start = std::chrono::steady_clock::now();
    CALLGRIND_START_INSTRUMENTATION;
    for (int i = 0; i < o.frames; ++i) frame(o.warmup + i);
    CALLGRIND_STOP_INSTRUMENTATION;
    glFinish();
    const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count() / o.frames;
    std::string list;
    for (const std::string& n : names) list += (list.empty() ? "" : ", ") + n;
    std::printf("welkin bench framework: %d frames of %s at %s, %.2f ms per frame (wall)\n", o.frames, list.c_str(), o.size.c_str(), ms);
    if (!o.json.empty()) {
        std::ofstream f(o.json);
        f << nlohmann::json{{"elements", list}, {"size", o.size}, {"frames", o.frames}, {"warmup", o.warmup}, {"ms_per_frame", ms}}.dump() << "\n";
        if (!f) throw Error("--json '" + o.json + "': cannot write");
    }
    return 0;
}

BenchRegistrar reg("framework", "a fixed scene for counting the framework's instructions per frame under callgrind", [](CLI::App& sub) {
    auto o = std::make_shared<FrameworkOptions>();  // owned by the action returned below (LeakSanitizer)
    sub.add_option("--frames", o->frames, "measured frames (instrumented under callgrind), in [1, 10000]")->capture_default_str();
    sub.add_option("--warmup", o->warmup, "uninstrumented frames before them, in [1, 1000]")->capture_default_str();
    sub.add_option("--size", o->size, "frame size WIDTHxHEIGHT")->capture_default_str();
    sub.add_option("--elements", o->elements, "elements drawn (as welkin render --elements)")->capture_default_str();
    sub.add_option("--json", o->json, "also write the run's description as JSON");
    return [o]() { return run(*o); };
});

}  // namespace
}  // namespace welkin::cli
