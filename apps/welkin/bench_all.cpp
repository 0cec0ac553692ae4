// welkin bench all: every element's benchmark in one run, written to docs/BENCHMARKS.md (tables
// with the date, the machine and the commit) and PNG plots (scripts/plots/plot_bench_all.py).
//
// Each element registers how it is measured from its own folder (welkin/bench.hpp,
// skyelements/<name>/bench/*.cpp); an element of the registry that registers nothing is measured
// in the default scene. Per element and frame size: the element's own cost per frame (its
// update, render and own generators, from the processor's glFinish-bracketed timing) with time
// stopped and with time running at 600x (30 frames/s of animation: 20 s of sky per frame), as a
// ratio to a trivial fullscreen pass timed alternately with it in the same frames (software
// rendering: ratios hold on a loaded machine where milliseconds do not); the first frame (tables
// and generators built); the generators' first build and rebuild cost; cost against work with a
// fitted growth exponent (pixels for every element, and each element's sweeps); the
// framework's CPU instructions per frame under callgrind (`welkin bench framework`); and the
// tables an element's own bench names for this file (`CommandBench::reports`: the accuracy of each
// quality preset against its reference, table build times against table size and wavelengths),
// each bench run as a child process and its CSV printed as a Markdown table.
#include "bench_util.hpp"
#include "command.hpp"
#include "plot.hpp"

#include <welkin/bench.hpp>
#include <welkin/csv.hpp>
#include <welkin/elements/registry.hpp>
#include <welkin/error.hpp>
#include <welkin/gl/context.hpp>
#include <welkin/keys.hpp>
#include <welkin/processor.hpp>

#include <epoxy/gl.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cctype>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include <unistd.h>

namespace welkin::cli {
namespace {

constexpr double kDeg = M_PI / 180;
constexpr double kSpeed = 600;  // time running: simulated seconds per real second
constexpr double kFastSpeed = 1440;  // a day in a minute: the second running measurement
constexpr double kFps = 30;     // animation frames per real second
/// Frames with time stopped after each jump of the time (the rest rule's exact tables of the Sky
/// start after 20 of them: they are counted too).
constexpr int kJumpFrames = 36;
/// Times the start and the jumps are measured, at the first size: each frame's cost is the median
/// over the repetitions at the same frame index, the figure the costliest of those medians. A
/// table built in the k-th frame after a start or a jump costs in the k-th frame of every
/// repetition; a scheduler's hiccup on a 2-core machine (a few ms, seen as 4.5 still frames of the
/// Rainbow's 0.66 ms at 512x256 in one of eight single runs) in one of them only.
constexpr int kStartRepeats = 3;
/// Costs below this fraction of the trivial pass are divided by it instead in the time-running
/// ratios: an element that draws nothing in its scene (the halos without an ice cloud) costs the
/// driver's per-call overhead, ~0.01 ms, and a ratio of two such figures is noise.
constexpr double kRatioFloor = 0.1;

struct AllOptions {
    bool quick = false;
    std::string out = "docs/BENCHMARKS.md";
    std::string plots = "docs/images/bench";  // empty: no plots
    std::string only;                         // comma-separated element names; empty: all
    std::string sizeOverride;                 // WIDTHxHEIGHT: one size instead of the three
    int frames = -1;                          // timed frames per measurement; -1: 3 (--quick) or 9
    int frameworkFrames = -1;                 // frames under callgrind; 0: skip; -1: 10 (--quick) or 30
    std::vector<std::string> vars;            // KEY=VALUE applied to every scene after its own settings
    bool list = false;                        // print the elements and their scenes, measure nothing
    bool noReports = false;                   // skip the command benches' report tables (accuracy, table costs)
};

struct Size {
    int w, h;
};

std::string sizeText(Size s) { return std::to_string(s.w) + "x" + std::to_string(s.h); }

std::string fmt(double v, int prec = 2) {
    if (!std::isfinite(v)) return "n/a";
    char b[64];
    std::snprintf(b, sizeof b, "%.*f", prec, v);
    return b;
}

std::string loadAverage() {
    std::ifstream f("/proc/loadavg");
    std::string one;
    f >> one;
    return one.empty() ? "unknown" : one;
}

std::string cpuModel() {
    std::ifstream f("/proc/cpuinfo");
    std::string line;
    int cores = 0;
    std::string model = "unknown CPU";
    while (std::getline(f, line))
        if (line.rfind("model name", 0) == 0) {
            ++cores;
            model = line.substr(line.find(':') + 2);
        }
    return model + ", " + std::to_string(cores) + " logical cores";
}

/// One element's measurement at one size.
struct SizeResult {
    Size size;
    double trivialMs = NAN;
    double stillMs = NAN, stillRatio = NAN, stillFrameRatio = NAN;
    double runMs = NAN, runRatio = NAN, runFrameRatio = NAN;
    double fastMs = NAN;  ///< median own cost at kFastSpeed, ms
    /// The costliest own cost of the first frames after time starts (the 600x run from still,
    /// untimed warm-up frames included), ms; only at the first size (later sizes find the
    /// light's tables already built).
    double startMaxMs = NAN;
    int startFrames = 0;
    /// The costliest own cost of the frames after the time jumps (+1 h, then +100 days), with
    /// time stopped after each (kJumpFrames frames each), ms; only at the first size.
    double jumpMaxMs = NAN;
    int jumpFrames = 0;
    /// The denominator of the time-running ratios: the still cost, or kRatioFloor trivial passes
    /// when above it.
    double ratioBase() const { return std::max(stillMs, kRatioFloor * trivialMs); }
};
struct SweepResult {
    std::string name, unit;
    std::vector<double> work, ratio;
    double exponent = NAN;
};
struct GenResult {
    std::string name, scene;  // the element whose scene built it
    double firstMs = NAN, perChangeMs = NAN;
    int changes = 0;
};
struct ElementResult {
    std::string name, description;
    bool registered = false;  // false: the default scene (the element registers no bench)
    double firstFrameMs = NAN, firstFrameRatio = NAN;
    std::vector<SizeResult> sizes;
    double pixelExponent = NAN;
    std::vector<SweepResult> sweeps;
};

/// The world state every element may attach (docs/architecture.md: the astronomy, which the
/// processor runs, and the Sun's and Moon's light): the frame's shared cost, like the astronomy,
/// not the own cost of whichever element attached it (the Halos, alone in their scene, were
/// charged the lights' run in every running frame).
bool worldState(const Generator& g) { return g.name() == "atmosphere.lights"; }

/// The element's own cost in the last frame: update + render + its own generators that ran.
struct OwnCost {
    const SkyElement* e;
    std::vector<int> runs;
    double take() {
        double ms = e->updateTiming().lastMs + e->renderTiming().lastMs;
        const auto& gens = e->generators();
        runs.resize(gens.size(), 0);
        for (size_t i = 0; i < gens.size(); ++i) {
            if (gens[i]->runCount() != runs[i] && !worldState(*gens[i])) ms += gens[i]->timing().lastMs;
            runs[i] = gens[i]->runCount();
        }
        return ms;
    }
};

class Measurer {
public:
    Measurer(const bench::ElementBench& b, const bench::VarList& extra, Logger& log) : b_(b), extra_(extra), log_(log) {}

    ElementResult run(const std::vector<Size>& sizes, int frames, std::vector<GenResult>& gens, const std::function<void(const std::string&)>& progress) {
        ElementResult r{.name = b_.element, .description = b_.description};
        const Scene0 s = scene();
        auto p = std::make_unique<SkyProcessor>(SkyVars::earth(), log_, ProcessorOptions{.timing = true});
        for (const std::string& n : b_.scene.with) p->add(elements::makeElement(n));
        SkyElement& e = p->add(elements::makeElement(b_.element));
        for (const auto& [k, v] : b_.scene.vars) p->vars().setFromString(k, v);
        // A generator's key (sky.keyframe_budget, clouds.shadow_slices) is declared at the first
        // frame: set after it (the first frame is a still frame, built whole either way).
        std::vector<std::pair<std::string, std::string>> later;
        for (const auto& [k, v] : extra_) {
            if (p->vars().contains(k)) p->vars().setFromString(k, v);
            else later.push_back({k, v});
        }
        p->setObserver({.latitudeRad = b_.scene.latitudeDeg * kDeg, .longitudeRad = b_.scene.longitudeDeg * kDeg, .heightMeters = 50});
        p->setExposure({.automatic = true});
        p->vars().set(keys::interactive, true);
        OwnCost own{&e, {}};
        auto setSize = [&](Size z) {
            Camera cam;
            cam.projection = Projection::Perspective;
            cam.azimuthRad = b_.scene.azimuthDeg * kDeg;
            cam.altitudeRad = b_.scene.altitudeDeg * kDeg;
            cam.verticalFovRad = b_.scene.fovDeg * kDeg;
            cam.width = z.w;
            cam.height = z.h;
            p->setCamera(cam);
        };
        setSize(sizes[0]);
        p->setTime(s.t0);
        p->setAnimationTime(0.0);
        // First frame: init, programs, tables, every generator's first build.
        {
            TrivialPass trivial(sizes[0].w, sizes[0].h);
            trivial.draw();
            const double tMs = medianMs(3, [&] { trivial.draw(); });
            progress(b_.element + ": first frame (tables, programs) at " + sizeText(sizes[0]));
            glFinish();
            const auto t0 = std::chrono::steady_clock::now();
            p->renderFrame();
            glFinish();
            r.firstFrameMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
            r.firstFrameRatio = r.firstFrameMs / tMs;
            own.take();
            for (const auto& [k, v] : later) p->vars().setFromString(k, v);  // unknown still: the one-line error
            const nlohmann::json st = p->stats();  // kept: a range-for over a temporary's member dangles
            for (const auto& g : st["generators"]) {
                const std::string name = g["name"].get<std::string>();
                if (std::none_of(gens.begin(), gens.end(), [&](const GenResult& x) { return x.name == name; }))
                    gens.push_back({.name = name, .scene = b_.element, .firstMs = g["last_ms"].get<double>()});
            }
        }
        std::map<std::string, std::pair<double, int>> genBefore;  // name -> (total ms, runs) before the running frames
        std::vector<double> px, pxMs;
        for (size_t zi = 0; zi < sizes.size(); ++zi) {
            const Size z = sizes[zi];
            setSize(z);
            TrivialPass trivial(z.w, z.h);
            SizeResult sr{.size = z};
            // Time stopped.
            progress(b_.element + ": " + sizeText(z) + ", time stopped");
            p->setTime(s.t0);
            for (int i = 0; i < 2; ++i) p->renderFrame(), own.take();
            std::vector<double> triv, el, fr;
            for (int i = 0; i < frames; ++i) timedPair(*p, trivial, own, triv, el, fr);
            sr.trivialMs = median(triv);
            sr.stillMs = median(el);
            sr.stillRatio = sr.stillMs / sr.trivialMs;
            sr.stillFrameRatio = median(fr) / sr.trivialMs;
            // Time running at 600x (the first two frames absorb the start).
            progress(b_.element + ": " + sizeText(z) + ", time running at 600x");
            const nlohmann::json before = p->stats();
            if (zi == 0)
                for (const auto& g : before["generators"])
                    genBefore[g["name"].get<std::string>()] = {g["total_ms"].get<double>(), g["runs"].get<int>()};
            triv.clear(), el.clear(), fr.clear();
            std::vector<std::vector<double>> startCosts(1);  // [repetition][frame]: own cost after time starts, ms
            for (int i = 0; i < frames + 2; ++i) {
                p->setTime(s.t0.plusSeconds((i + 1) * kSpeed / kFps));
                p->setAnimationTime((i + 1) / kFps);
                if (i < 2) {
                    glFinish();
                    p->renderFrame();
                    glFinish();
                    startCosts[0].push_back(own.take());
                    continue;
                }
                timedPair(*p, trivial, own, triv, el, fr);
                startCosts[0].push_back(el.back());
            }
            sr.runMs = median(el);
            sr.runRatio = sr.runMs / median(triv);
            sr.runFrameRatio = median(fr) / median(triv);
            const nlohmann::json after = p->stats();
            if (zi == 0)
                for (const auto& g : after["generators"]) {
                    const std::string name = g["name"].get<std::string>();
                    auto it = genBefore.find(name);
                    auto gr = std::find_if(gens.begin(), gens.end(), [&](const GenResult& x) { return x.name == name; });
                    if (it == genBefore.end() || gr == gens.end() || gr->scene != b_.element) continue;
                    const int n = g["runs"].get<int>() - it->second.second;
                    gr->changes = n;
                    if (n > 0) gr->perChangeMs = (g["total_ms"].get<double>() - it->second.first) / n;
                }
            // Then at 1440x (a day in a minute), on from there (two more warm-up frames).
            {
                progress(b_.element + ": " + sizeText(z) + ", time running at 1440x");
                const UtcInstant t1 = s.t0.plusSeconds((frames + 2) * kSpeed / kFps);
                std::vector<double> tv, ev, fv;
                for (int i = 0; i < frames + 2; ++i) {
                    p->setTime(t1.plusSeconds((i + 1) * kFastSpeed / kFps));
                    p->setAnimationTime((frames + 2 + i + 1) / kFps);
                    if (i < 2) {
                        p->renderFrame(), own.take();
                        continue;
                    }
                    timedPair(*p, trivial, own, tv, ev, fv);
                }
                sr.fastMs = median(ev);
                // Then the time jumps (a user sets another time, a game loads a save): +1 h, then
                // +100 days at the same hour, with time stopped after each; the costliest frame.
                if (zi == 0) {
                    progress(b_.element + ": " + sizeText(z) + ", time jumps");
                    const UtcInstant t2 = t1.plusSeconds((frames + 2) * kFastSpeed / kFps);
                    // Each repetition a week after the last at the same hour (so the light and the
                    // scene are alike: the Rainbow's Sun stays up): set there and rested for
                    // kJumpFrames frames, untimed, then +1 h and +100 days, timed.
                    std::vector<std::vector<double>> jumpCosts;  // [repetition][frame], ms
                    for (int rep = 0; rep < kStartRepeats; ++rep) {
                        UtcInstant t = t2.plusSeconds(rep * 7 * 86400.0);
                        if (rep > 0) {
                            p->setTime(t);
                            for (int i = 0; i < kJumpFrames; ++i) p->renderFrame(), own.take();
                        }
                        jumpCosts.emplace_back();
                        for (double dt : {3600.0, 100 * 86400.0}) {
                            t = t.plusSeconds(dt);
                            p->setTime(t);
                            for (int i = 0; i < kJumpFrames; ++i) {
                                glFinish();
                                p->renderFrame();
                                glFinish();
                                jumpCosts.back().push_back(own.take());
                            }
                        }
                    }
                    sr.jumpMaxMs = costliestMedianFrame(jumpCosts), sr.jumpFrames = 2 * kJumpFrames;
                    // The start again from a resting light a week and two after the first, at
                    // the same hour: time stopped for kJumpFrames frames (the rest rule's exact
                    // tables built), then running at 600x (each frame timed alone).
                    for (int rep = 1; rep < kStartRepeats; ++rep) {
                        const UtcInstant t = s.t0.plusSeconds(rep * 7 * 86400.0);
                        p->setTime(t);
                        for (int i = 0; i < kJumpFrames; ++i) p->renderFrame(), own.take();
                        startCosts.emplace_back();
                        for (int i = 0; i < frames + 2; ++i) {
                            p->setTime(t.plusSeconds((i + 1) * kSpeed / kFps));
                            p->setAnimationTime((i + 1) / kFps);
                            glFinish();
                            p->renderFrame();
                            glFinish();
                            startCosts.back().push_back(own.take());
                        }
                    }
                    sr.startMaxMs = costliestMedianFrame(startCosts), sr.startFrames = frames + 2;
                }
            }
            p->setAnimationTime(0.0);
            r.sizes.push_back(sr);
            px.push_back(double(z.w) * z.h);
            pxMs.push_back(sr.stillMs);
        }
        r.pixelExponent = bench::fitGrowthExponent(px, pxMs);
        // Cost against work, at the first size with time stopped.
        for (const bench::WorkSweep& ws : b_.sweeps) {
            SweepResult sw{.name = ws.name, .unit = ws.unit};
            setSize(sizes[0]);
            p->setTime(s.t0);
            TrivialPass trivial(sizes[0].w, sizes[0].h);
            for (size_t k = 0; k < ws.points.size(); ++k) {
                progress(b_.element + ": " + ws.name + ", point " + std::to_string(k + 1) + " of " + std::to_string(ws.points.size()));
                for (const auto& [key, v] : ws.points[k].vars) p->vars().setFromString(key, v);
                for (int i = 0; i < 2; ++i) p->renderFrame(), own.take();
                std::vector<double> triv, el, fr;
                for (int i = 0; i < frames; ++i) timedPair(*p, trivial, own, triv, el, fr);
                double work = ws.points[k].work;
                if (!ws.workStat.empty()) {
                    const nlohmann::json j = p->stats();
                    const nlohmann::json::json_pointer ptr(ws.workStat);
                    if (!j.contains(ptr)) throw Error("element bench " + b_.element + ": no statistic " + ws.workStat);
                    work = j.at(ptr).get<double>();
                }
                sw.work.push_back(work);
                sw.ratio.push_back(median(el) / median(triv));
            }
            sw.exponent = bench::fitGrowthExponent(sw.work, sw.ratio);
            r.sweeps.push_back(sw);
        }
        p->release();
        return r;
    }

private:
    struct Scene0 {
        UtcInstant t0;
    };
    Scene0 scene() const { return {UtcInstant::parse(b_.scene.time)}; }

    // One trivial pass and one frame, timed one after the other (each bracketed by glFinish).
    /// The costliest frame of a measurement repeated: for each frame index the median over the
    /// repetitions, then the largest of those (ms).
    static double costliestMedianFrame(const std::vector<std::vector<double>>& costs) {
        double worst = 0.0;
        for (size_t i = 0; i < costs.front().size(); ++i) {
            std::vector<double> at;
            for (const auto& rep : costs) at.push_back(rep[i]);
            worst = std::max(worst, median(at));
        }
        return worst;
    }

    static void timedPair(SkyProcessor& p, TrivialPass& trivial, OwnCost& own, std::vector<double>& triv, std::vector<double>& el,
                          std::vector<double>& fr) {
        triv.push_back(medianMs(1, [&] { trivial.draw(); }));
        // The frame as displayed: renderFrame() and the tone map into a display target (since
        // 2026-11-27 renderFrame() leaves that pass to toneMapInto() / readToneMapped()).
        fr.push_back(medianMs(1, [&] {
            p.renderFrame();
            p.toneMapInto(trivial.framebuffer());
        }));
        el.push_back(own.take());
    }

    const bench::ElementBench& b_;
    const bench::VarList& extra_;
    Logger& log_;
};

/// The framework's instructions per frame under callgrind (`welkin bench framework`), as the
/// Markdown section; a sentence saying why not when valgrind is missing.
std::string frameworkSection(int frames, const std::function<void(const std::string&)>& progress) {
    std::string md = "## Framework CPU overhead per frame (callgrind)\n\n";
    if (frames <= 0) return md + "Not measured in this run (`--framework-frames 0`).\n\n";
    if (shellOut("command -v valgrind").empty()) return md + "Not measured: valgrind is not installed.\n\n";
    const std::string self_exe = std::filesystem::canonical("/proc/self/exe").string();
    const std::filesystem::path tmp = std::filesystem::temp_directory_path() / ("welkin_bench_callgrind_" + std::to_string(::getpid()));
    std::filesystem::create_directories(tmp);
    const std::string outFile = (tmp / "callgrind.out").string();
    const std::string jsonFile = (tmp / "framework.json").string();
    std::string preload;
#ifdef WELKIN_VALGRIND_SHIM
    if (std::filesystem::exists(WELKIN_VALGRIND_SHIM)) preload = "LD_PRELOAD='" WELKIN_VALGRIND_SHIM "' ";
#endif
    // Under valgrind the driver's start-up is what takes long: llvmpipe compiles every shader
    // variant with LLVM, tens of times slower there. Its compiled code goes to Mesa's on-disk
    // cache (~/.cache/mesa_shader_cache), keyed on the CPU features llvmpipe detects; valgrind's
    // virtual CPU has fewer (no AVX-512) than the machine, so a native run's entries are not used
    // under valgrind (measured: the run under callgrind kept adding entries). So the same command
    // first runs under `valgrind --tool=none` (the same virtual CPU, no instrumentation): it fills
    // the cache once per machine and driver, and the counted run reads the variants back.
    // LP_NUM_THREADS=0: llvmpipe rasterises on the calling thread (valgrind runs one thread at a
    // time anyway; no thread hand-offs counted).
    const std::string env = "LP_NUM_THREADS=0 MESA_SHADER_CACHE_DISABLE=false ";
    const std::string args = "' bench framework --frames " + std::to_string(frames) + " --json " + jsonFile;
    progress("framework: a first run under valgrind --tool=none (fills Mesa's shader cache; long the first time on a machine)");
    const int warmRc = std::system((env + preload + "valgrind --tool=none '" + self_exe + args + " > " + (tmp / "warm.txt").string() + " 2>&1").c_str());
    const std::string cmd = env + preload + "valgrind --tool=callgrind --instr-atstart=no --callgrind-out-file=" + outFile + " '" + self_exe +
                            args + " > " + (tmp / "log.txt").string() + " 2>&1";
    progress("framework: " + std::to_string(frames) + " frames under callgrind (minutes)");
    const int rc = warmRc != 0 ? warmRc : std::system(cmd.c_str());
    std::ifstream jf(jsonFile);
    if (rc != 0 || !jf) {
        std::filesystem::remove_all(tmp);
        return md + "Not measured: `valgrind --tool=callgrind welkin bench framework` failed (exit " + std::to_string(rc) + ").\n\n";
    }
    nlohmann::json fj = nlohmann::json::parse(jf);
    std::ifstream cg(outFile);
    const bench::CallgrindCosts c = bench::parseCallgrind(cg, self_exe);
    std::filesystem::remove_all(tmp);
    const double n = frames;
    const double welkin = c.own + c.ownCalls;
    md += "`LP_NUM_THREADS=0 valgrind --tool=callgrind --instr-atstart=no welkin bench framework --frames " + std::to_string(frames) +
          "` (after the same command under `valgrind --tool=none`, which fills Mesa's shader cache for valgrind's virtual CPU): the default elements (" + fj.value("elements", std::string()) +
          ") at " + fj.value("size", std::string()) + ", Malta, time running at 600x; instrumentation is on for the " + std::to_string(frames) +
          " measured frames only (after " + std::to_string(fj.value("warmup", 0)) +
          " warm-up frames). **Counted as welkin's:** every instruction executed in the welkin executable (the processor, SkyVars, the "
          "generator graph, the state guard, the elements' and generators' CPU work, the std templates they instantiate), plus the "
          "C/C++ runtime functions welkin calls (malloc, memcpy, string code: the inclusive cost of those calls). **Not counted:** "
          "the GL driver (Mesa llvmpipe, its JIT code, LLVM, libepoxy) including the runtime code it calls. This counts the "
          "elements' per-frame CPU work with the framework's, so it is an upper bound on the framework's own cost.\n\n";
    md += "| where | instructions per frame |\n|---|---|\n";
    md += "| **welkin (counted)**: its own code + the runtime calls it makes | **" + fmt(welkin / n, 0) + "** |\n";
    md += "| of which the runtime calls (malloc, memcpy, string code) | " + fmt(c.ownCalls / n, 0) + " |\n";
    md += "| C/C++ runtime in all (called by welkin or by the driver) | " + fmt(c.runtime / n, 0) + " |\n";
    md += "| driver (Mesa llvmpipe, its JIT code, LLVM, libepoxy; not counted) | " + fmt((c.total - c.own - c.runtime) / n, 0) + " |\n\n";
    md += "Target: at most 200,000 instructions per frame for the framework (default scene, time running). Measured: " + fmt(welkin / n, 0) +
          (welkin / n <= 200000 ? ": within the target." : ": over the target.") +
          "\n\nThe welkin functions with the most instructions per frame (self cost + the runtime calls they make):\n\n"
          "| function | instructions per frame |\n|---|---|\n";
    std::vector<std::pair<double, std::string>> top;
    for (auto& [f, v] : c.byFunction) top.push_back({v, f});
    std::sort(top.rbegin(), top.rend());
    for (size_t k = 0; k < top.size() && k < 12; ++k) {
        std::string f = top[k].second;
        if (f.size() > 110) f = f.substr(0, 107) + "...";
        for (char& ch : f)
            if (ch == '|') ch = '/';
        md += "| `" + f + "` | " + fmt(top[k].first / n, 0) + " |\n";
    }
    return md + "\n";
}

/// A number from a CSV field for the Markdown: 4 significant digits, "n/a" for NaN or empty.
std::string cellNumber(std::string_view text, double scale) {
    double v = NAN;
    const std::string t(text);
    char* end = nullptr;
    if (!t.empty()) v = std::strtod(t.c_str(), &end);
    if (t.empty() || end == t.c_str() || *end != '\0') return t;  // not a number: the text as it is
    if (!std::isfinite(v)) return "n/a";
    v *= scale;
    char b[64];
    if (v != 0 && (std::abs(v) >= 1e6 || std::abs(v) < 1e-3)) std::snprintf(b, sizeof b, "%.3g", v);
    else std::snprintf(b, sizeof b, "%.4g", v);
    return b;
}

std::string shellQuote(const std::string& s) {
    std::string q = "'";
    for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
    return q + "'";
}

/// The command benches' report tables (bench.hpp ReportTable): each bench run as a child process
/// of this executable, its CSV printed as a Markdown table. A bench that fails is reported as such
/// (its exit status and last output line) and the run goes on.
std::string reportsSection(bool quick, const std::set<std::string>& only, const std::function<void(const std::string&)>& progress) {
    std::vector<std::pair<std::string, bench::ReportTable>> todo;  // (command, table)
    for (const bench::CommandBench& b : bench::commandBenches())
        for (const bench::ReportTable& t : b.reports)
            if (only.empty() || only.count(t.element)) todo.push_back({b.name, t});
    if (todo.empty()) return "";
    // By element; an element's tables keep the order it registered them in.
    std::stable_sort(todo.begin(), todo.end(), [](const auto& a, const auto& b) { return a.second.element < b.second.element; });
    const std::string self_exe = std::filesystem::canonical("/proc/self/exe").string();
    const std::filesystem::path tmp = std::filesystem::temp_directory_path() / ("welkin_bench_reports_" + std::to_string(::getpid()));
    std::filesystem::create_directories(tmp);
    std::string md = "## Accuracy and table costs, from the elements' own benches\n\n"
                     "Each element can name tables of its own bench (`welkin bench <name>`, registered from its folder with "
                     "`CommandBench::reports`, welkin/bench.hpp) for this file: the bench runs with the arguments shown and its CSV "
                     "is printed as it is. Costs in these tables are the bench's own (each states its reference pass); errors are "
                     "against the reference named.\n\n";
    size_t k = 0;
    for (const auto& [cmd, t] : todo) {
        ++k;
        const std::vector<std::string>& args = quick && !t.quickArgs.empty() ? t.quickArgs : t.args;
        std::string argText;
        for (const std::string& a : args) argText += " " + (a.find_first_of(" '\"$;&|<>*?") == std::string::npos && !a.empty() ? a : shellQuote(a));
        const std::string csv = (tmp / ("report_" + std::to_string(k) + ".csv")).string();
        const std::string log = (tmp / ("report_" + std::to_string(k) + ".log")).string();
        progress("report " + std::to_string(k) + " of " + std::to_string(todo.size()) + ": welkin bench " + cmd + argText);
        const auto t0 = std::chrono::steady_clock::now();
        const int rc = std::system((shellQuote(self_exe) + " bench " + cmd + argText + " --csv " + shellQuote(csv) + " > " + shellQuote(log) + " 2>&1").c_str());
        const double sec = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        md += "### " + t.title + "\n\n" + t.what + "\n\n";
        std::string body;
        try {
            if (rc != 0) throw Error("exit status " + std::to_string(rc));
            const CsvTable table = CsvTable::load(csv);
            struct Col {
                size_t index;
                double scale;
                std::string heading;
            };
            std::vector<Col> cols;
            if (t.columns.empty())
                for (size_t c = 0; c < table.header().size(); ++c) cols.push_back({c, 1.0, table.header()[c]});
            for (const std::string& spec : t.columns) {
                const size_t colon = spec.find(':');
                std::string name = spec.substr(0, colon), heading = colon == std::string::npos ? "" : spec.substr(colon + 1);
                double scale = 1.0;
                if (const size_t star = name.find('*'); star != std::string::npos) {
                    scale = std::stod(name.substr(star + 1));
                    name = name.substr(0, star);
                }
                cols.push_back({table.column(name), scale, heading.empty() ? name : heading});
            }
            body += "|";
            for (const Col& c : cols) body += " " + c.heading + " |";
            body += "\n|";
            for (size_t c = 0; c < cols.size(); ++c) body += "---|";
            body += "\n";
            for (const CsvRow& row : table) {
                body += "|";
                for (const Col& c : cols) {
                    std::string cell = cellNumber(row.text(c.index), c.scale);
                    for (char& ch : cell)
                        if (ch == '|') ch = '/';
                    body += " " + cell + " |";
                }
                body += "\n";
            }
            if (table.rowCount() == 0) throw Error("no rows in its CSV");
        } catch (const std::exception& e) {
            std::string last;
            std::ifstream lf(log);
            for (std::string line; std::getline(lf, line);)
                if (!line.empty()) last = line;
            body = std::string("Not measured: the bench failed (") + e.what() + ")" + (last.empty() ? "" : ": " + last) + "\n";
            std::fprintf(stderr, "welkin bench all: warning: welkin bench %s failed (%s)\n", cmd.c_str(), e.what());
        }
        md += body + "\n*`welkin bench " + cmd + argText + " --csv FILE` (" + fmt(sec, 0) + " s in this run)*\n\n";
    }
    std::filesystem::remove_all(tmp);
    return md;
}

void writeAtomically(const std::string& path, const std::string& text) {
    const std::filesystem::path target(path);
    const std::filesystem::path tmp = target.parent_path() / ("." + target.filename().string() + ".tmp");
    {
        std::ofstream f(tmp, std::ios::binary);
        f << text;
        f.close();
        if (!f) throw Error("--out '" + path + "': cannot write " + tmp.string());
    }
    std::filesystem::rename(tmp, target);
}

int run(const AllOptions& o) {
    const auto started = std::chrono::steady_clock::now();
    const std::string loadAtStart = loadAverage();
    const int frames = o.frames >= 0 ? o.frames : (o.quick ? 3 : 9);
    if (frames < 1 || frames > 1000) throw Error("--frames " + std::to_string(o.frames) + " not in [1, 1000]");
    const int fwFrames = o.frameworkFrames >= 0 ? o.frameworkFrames : (o.quick ? 10 : 30);
    if (fwFrames < 0 || fwFrames > 1000) throw Error("--framework-frames " + std::to_string(o.frameworkFrames) + " not in [0, 1000]");
    std::vector<Size> sizes = {{512, 256}, {1280, 720}, {1920, 1080}};
    if (!o.sizeOverride.empty()) {
        int w = 0, h = 0;
        char tail = 0;
        if (std::sscanf(o.sizeOverride.c_str(), "%dx%d%c", &w, &h, &tail) != 2 || w < 1 || h < 1 || w > 8192 || h > 8192)
            throw Error("--size-override '" + o.sizeOverride + "' not WIDTHxHEIGHT in [1, 8192]");
        sizes = {{w, h}};
    }
    if (o.out.empty()) throw Error("--out: a file name is needed");
    if (!o.list) checkOutputDirectory("--out", o.out);
    if (!o.list && !o.plots.empty() && !std::filesystem::is_directory(o.plots)) {
        // The plots' directory is made when its parent exists (docs/images/bench in a checkout).
        const std::filesystem::path parent = std::filesystem::absolute(o.plots).parent_path();
        if (!std::filesystem::is_directory(parent)) throw Error("--plots '" + o.plots + "': no such directory");
        std::filesystem::create_directory(o.plots);
    }

    bench::VarList extra;
    for (const std::string& v : o.vars) {
        const size_t eq = v.find('=');
        if (eq == std::string::npos || eq == 0) throw Error("--var '" + v + "' not KEY=VALUE");
        extra.push_back({v.substr(0, eq), v.substr(eq + 1)});
    }
    // Every element of the registry: its own bench where it registered one, else the default scene.
    std::map<std::string, bench::ElementBench> benches;
    for (const bench::ElementBench& b : bench::elementBenches()) {
        if (!elements::findDescriptor(b.element)) throw Error("element bench for unknown element '" + b.element + "'");
        benches[b.element] = b;
    }
    std::set<std::string> registered;
    for (auto& [n, b] : benches) registered.insert(n);
    for (const std::string& n : elements::knownElements())
        if (!benches.count(n)) benches[n] = {.element = n, .description = "default scene (the element registers no bench)"};
    std::vector<std::string> names;
    if (o.only.empty()) {
        for (auto& [n, b] : benches) names.push_back(n);
    } else {
        names = elements::parseElementList(o.only);
        for (const std::string& n : names)
            if (!benches.count(n)) throw Error("--only: unknown element '" + n + "'");
    }

    if (o.list) {
        for (const std::string& n : names)
            std::printf("%s: %s\n", n.c_str(), benches[n].description.c_str());
        return 0;
    }
    Logger log;
    auto ctx = gl::HeadlessContext::create({}, log);
    const std::string renderer = reinterpret_cast<const char*>(glGetString(GL_RENDERER));
    const size_t total = names.size();
    size_t index = 0;
    auto progress = [&](const std::string& what) {
        const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
        std::fprintf(stderr, "[bench all %3.0f s] [%zu/%zu] %s\n", s, index, total, what.c_str());
    };
    std::vector<ElementResult> results;
    std::vector<GenResult> gens;
    for (const std::string& n : names) {
        ++index;
        ElementResult r = Measurer(benches[n], extra, log).run(sizes, frames, gens, progress);
        r.registered = registered.count(n) > 0;
        for (const SizeResult& s : r.sizes)
            if (!(s.stillRatio > 0) || !std::isfinite(s.stillRatio) || !(s.runRatio > 0) || !std::isfinite(s.runRatio))
                std::fprintf(stderr, "welkin bench all: warning: %s at %s has no positive finite cost\n", n.c_str(), sizeText(s.size).c_str());
        results.push_back(std::move(r));
    }
    ctx.reset();
    const std::string fwSection = frameworkSection(fwFrames, progress);
    std::string reports;
    if (!o.noReports) {
        std::set<std::string> only;
        if (!o.only.empty()) only.insert(names.begin(), names.end());
        reports = reportsSection(o.quick, only, progress);
    }

    // The Markdown.
    char date[64];
    const std::time_t now = std::time(nullptr);
    std::strftime(date, sizeof date, "%Y-%m-%d %H:%M UTC", std::gmtime(&now));
    const std::string commit = sourceCommit(WELKIN_SOURCE_DIR);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
    std::string cmdline = std::string("welkin bench all") + (o.quick ? " --quick" : "") +
                          (o.sizeOverride.empty() ? "" : " --size-override " + o.sizeOverride) + (o.only.empty() ? "" : " --only " + o.only) +
                          (o.frames >= 0 ? " --frames " + std::to_string(o.frames) : "") +
                          (o.frameworkFrames >= 0 ? " --framework-frames " + std::to_string(o.frameworkFrames) : "") +
                          (o.noReports ? " --no-reports" : "");
    for (const std::string& v : o.vars) cmdline += " --var " + v;
    if (o.out != "docs/BENCHMARKS.md") cmdline += " --out " + o.out;
    if (o.plots != "docs/images/bench") cmdline += " --plots '" + o.plots + "'";
    // The plots as the Markdown file links them (relative to its directory).
    std::string plotRel = "images/bench";
    if (!o.plots.empty()) {
        std::error_code ec;
        const std::filesystem::path outDir = std::filesystem::absolute(std::filesystem::path(o.out)).parent_path();
        plotRel = std::filesystem::relative(std::filesystem::absolute(o.plots), outDir, ec).generic_string();
        if (ec || plotRel.empty()) plotRel = std::filesystem::absolute(o.plots).generic_string();
    }
    std::ostringstream md;
    md << "# Benchmarks\n\n"
       << "Generated by `" << cmdline;
    md << "` (apps/welkin/bench_all.cpp). Do not edit by hand.\n\n"
       << "- Date: " << date << "\n- Machine: " << cpuModel() << "; GL renderer: " << renderer << "; load average (1 min) " << loadAtStart << " at the start, " << loadAverage() << " at the end" << "\n- Commit: " << commit
       << "\n- Run: " << (o.quick ? "`--quick` (" : "full (") << frames << " timed frames per measurement, median), " << fmt(seconds, 0)
       << " s in all\n\n"
       << (renderer.find("llvmpipe") != std::string::npos
               ? "This machine renders in software (Mesa llvmpipe) and may be shared with other jobs, so milliseconds are noisy; every cost is "
                 "therefore given as a ratio to a trivial fullscreen pass (one constant-cost fragment per pixel into an RGBA32F target) "
                 "timed alternately with it in the same frames, at the same size. Expect ratios to move by 10-30 % between runs on a "
                 "busy machine.\n\n"
               : "Every cost is given as a ratio to a trivial fullscreen pass (one constant-cost fragment per pixel into an RGBA32F "
                 "target) timed alternately with it in the same frames, at the same size; the trivial pass's own milliseconds are in "
                 "the last column, so the ratios convert to absolute times on this GPU.\n\n")
       << "An element registers its bench from its own folder (`skyelements/<name>/bench/*.cpp`, `welkin/bench.hpp`); an element "
          "that registers none is measured in the default scene.\n\n";
    md << "## Cost per frame, as a ratio to a trivial pass\n\n"
       << "The element's own cost per frame: its update and render and its own generators that ran in the frame (the processor's "
          "glFinish-bracketed timing; the world state every element may attach, the Sun's and Moon's light `atmosphere.lights`, is "
          "the frame's shared cost like the astronomy, not the attaching element's). *Still*: time stopped. *600x*: time running at 600x real time at 30 frames/s (20 s of sky per "
          "frame). *Frame*: the whole `renderFrame()` and the tone map into a display target (element, shared generators, the "
          "eye's meter, the tone map's pass: `toneMapInto()`) with time stopped.\n\n"
       << "| element | scene |";
    for (Size z : sizes) md << " " << sizeText(z) << " still | " << sizeText(z) << " 600x | " << sizeText(z) << " frame |";
    md << " trivial pass ms |\n|---|---|";
    for (size_t k = 0; k < sizes.size(); ++k) md << "---|---|---|";
    md << "---|\n";
    for (const ElementResult& r : results) {
        md << "| " << r.name << " | " << r.description << " |";
        std::string triv;
        for (const SizeResult& s : r.sizes) {
            md << " " << fmt(s.stillRatio) << " | " << fmt(s.runRatio) << " | " << fmt(s.stillFrameRatio) << " |";
            triv += (triv.empty() ? "" : ", ") + fmt(s.trivialMs);
        }
        md << " " << triv << " |\n";
    }
    md << "\n![Cost per frame of each element](" << plotRel << "/bench_all_elements.png)\n\n*`" << cmdline << "` (this run; scripts/plots/plot_bench_all.py)*\n\n";
    md << "## Time running\n\nThe element's own cost with time running, as a multiple of its own cost with time stopped "
          "(targets: at most 1.5 at 600x and 1440x). *Time starts*: the costliest of the first frames after time starts at 600x "
          "(from time stopped; the light's tables are built then, or spread over frames: the Halos' grid table, the Rainbow's and "
          "the Clouds' direction caches, the clouds' shadow map and loss table), at "
       << sizeText(sizes[0]) << " (target: at most 3). *Time jumps*: the costliest of the frames after the time jumps by +1 h and then "
          "by +100 days, with time stopped after each for " << kJumpFrames << " frames (a user setting another time; the frames in which "
          "a resting light's exact tables are built are among them; the Clouds' and the Rainbow's direction caches and the Halos' grid table are "
          "refilled over frames after a jump), at " << sizeText(sizes[0]) << " (target: at most 3). The start and the jumps are each "
          "measured " << kStartRepeats << " times, a week apart at the same hour (each after " << kJumpFrames << " still frames): a frame's cost is the median over the repetitions at the same frame index, the figure the costliest of those, so a "
          "table built in a given frame counts and a scheduler's hiccup in one repetition does not. An element "
          "whose still cost is below " << fmt(kRatioFloor, 1) << " trivial pass (one that draws nothing in its scene: its cost is the "
          "driver's per-call overhead, ~0.01 ms, and the ratio of two such figures is noise) is divided by " << fmt(kRatioFloor, 1)
       << " trivial pass instead (marked *).\n\n| element |";
    for (Size z : sizes) md << " " << sizeText(z) << " still ms | 600x | 1440x |";
    md << " time starts (frames) | time jumps (frames) |\n|---|";
    for (size_t k = 0; k < sizes.size(); ++k) md << "---|---|---|";
    md << "---|---|\n";
    for (const ElementResult& r : results) {
        md << "| " << r.name << " |";
        for (const SizeResult& s : r.sizes)
            md << " " << fmt(s.stillMs, 2) << (s.ratioBase() > s.stillMs ? "*" : "") << " | " << fmt(s.runMs / s.ratioBase()) << " | "
               << fmt(s.fastMs / s.ratioBase()) << " |";
        const SizeResult& s0 = r.sizes.front();
        md << " " << fmt(s0.startMaxMs / s0.ratioBase()) << " (" << s0.startFrames << ") | " << fmt(s0.jumpMaxMs / s0.ratioBase()) << " ("
           << s0.jumpFrames << ") |\n";
    }
    md << "\n## First frame and generators\n\n"
       << "First frame: init, shader compilation (llvmpipe compiles at first use), tables and every generator's first build, at "
       << sizeText(sizes[0]) << ".\n\n| element | first frame ms | x trivial pass |\n|---|---|---|\n";
    for (const ElementResult& r : results) md << "| " << r.name << " | " << fmt(r.firstFrameMs, 1) << " | " << fmt(r.firstFrameRatio, 0) << " |\n";
    md << "\nGenerators (tables): the first build, and the mean cost of a rebuild while time runs at 600x (the frames at "
       << sizeText(sizes[0]) << " of the scene that first built it).\n\n| generator | scene | first build ms | rebuilds while running | ms per rebuild |\n|---|---|---|---|---|\n";
    for (const GenResult& g : gens)
        md << "| " << g.name << " | " << g.scene << " | " << fmt(g.firstMs, 2) << " | " << g.changes << " | " << fmt(g.perChangeMs, 2) << " |\n";
    md << "\n## Cost against work\n\n"
       << "Growth exponent: the least-squares slope of log(cost) against log(work) (1: linear).\n\n";
    if (sizes.size() > 1) {
        md << "| element | exponent against pixels (" << sizeText(sizes.front()) << " .. " << sizeText(sizes.back()) << ", time stopped, ms) |\n|---|---|\n";
        for (const ElementResult& r : results) md << "| " << r.name << " | " << fmt(r.pixelExponent) << " |\n";
        md << "\n";
    }
    md << "| element | work | points (work: x trivial pass) at " << sizeText(sizes[0]) << " | growth exponent |\n|---|---|---|---|\n";
    for (const ElementResult& r : results)
        for (const SweepResult& s : r.sweeps) {
            md << "| " << r.name << " | " << s.name << " (" << s.unit << ") | ";
            for (size_t k = 0; k < s.work.size(); ++k) md << (k ? ", " : "") << fmt(s.work[k], 0) << ": " << fmt(s.ratio[k]);
            md << " | " << fmt(s.exponent) << " |\n";
        }
    md << "\n![Cost against work](" << plotRel << "/bench_all_work.png)\n\n*`" << cmdline << "` (this run; scripts/plots/plot_bench_all.py)*\n\n";
    md << fwSection;
    md << (o.noReports ? std::string("## Accuracy and table costs\n\nNot measured in this run (`--no-reports`).\n\n") : reports);

    // Plots: CSV beside the PNGs, drawn by scripts/plots/plot_bench_all.py.
    std::string plotNotes;
    if (!o.plots.empty()) {
        const std::filesystem::path dir(o.plots);
        const std::string costCsv = (dir / "bench_all_elements.csv").string(), workCsv = (dir / "bench_all_work.csv").string();
        {
            std::ofstream f(costCsv);
            f << "element,size,pixels,still_ratio,running_ratio,still_ms,trivial_ms\n";
            for (const ElementResult& r : results)
                for (const SizeResult& s : r.sizes)
                    f << r.name << "," << sizeText(s.size) << "," << double(s.size.w) * s.size.h << "," << s.stillRatio << "," << s.runRatio << ","
                      << s.stillMs << "," << s.trivialMs << "\n";
        }
        {
            std::ofstream f(workCsv);
            f << "series,unit,work,cost,cost_unit,exponent\n";
            for (const ElementResult& r : results) {
                for (const SizeResult& s : r.sizes)
                    if (sizes.size() > 1) f << r.name << ",pixels," << double(s.size.w) * s.size.h << "," << s.stillMs << ",ms," << r.pixelExponent << "\n";
                for (const SweepResult& sw : r.sweeps)
                    for (size_t k = 0; k < sw.work.size(); ++k)
                        f << r.name << "," << sw.unit << "," << sw.work[k] << "," << sw.ratio[k] << ",x trivial pass," << sw.exponent << "\n";
            }
        }
        for (const auto& [csv, png] : {std::pair{costCsv, (dir / "bench_all_elements.png").string()}, std::pair{workCsv, (dir / "bench_all_work.png").string()}}) {
            const PlotResult pr = drawPlot("plot_bench_all.py", csv, png);
            std::fprintf(stderr, "welkin bench all: %s\n", pr.message.c_str());
            if (!pr.drawn) plotNotes += "\n(plot not drawn: " + pr.message + ")\n";
        }
    }
    md << plotNotes;
    {  // `welkin bench display`'s section (apps/welkin/bench_display.cpp) is kept: from its marker to the end
        std::ifstream old(o.out, std::ios::binary);
        const std::string text((std::istreambuf_iterator<char>(old)), std::istreambuf_iterator<char>());
        const size_t at = text.find("<!-- welkin bench display -->");
        if (at != std::string::npos) md << "\n" << text.substr(at);
    }
    writeAtomically(o.out, md.str());
    std::printf("welkin bench all: wrote %s (%zu elements, %.0f s)\n", o.out.c_str(), results.size(), seconds);
    return 0;
}

BenchRegistrar reg("all", "every element's benchmark in one run: docs/BENCHMARKS.md and its plots", [](CLI::App& sub) {
    auto o = std::make_shared<AllOptions>();  // owned by the action returned below (LeakSanitizer)
    sub.add_flag("--quick", o->quick, "fewer frames per measurement and under callgrind (a few minutes)");
    sub.add_option("--out", o->out, "the Markdown file written (atomically)")->capture_default_str();
    sub.add_option("--plots", o->plots, "existing directory for the PNG plots and their CSV (empty: no plots)")->capture_default_str();
    sub.add_option("--only", o->only, "comma-separated elements to measure (default: every registered element)");
    sub.add_option("--size-override", o->sizeOverride, "one frame size WIDTHxHEIGHT instead of 512x256, 1280x720 and 1920x1080");
    sub.add_option("--frames", o->frames, "timed frames per measurement, in [1, 1000] (default 3 with --quick, else 9)");
    sub.add_option("--framework-frames", o->frameworkFrames,
                   "frames counted under callgrind, in [0, 1000] (0: skip; default 10 with --quick, else 30)");
    sub.add_option("--var", o->vars, "KEY=VALUE set in every scene after its own settings (repeatable), e.g. rain.table_quality=low");
    sub.add_flag("--list", o->list, "print the elements measured and their scenes, and exit");
    sub.add_flag("--no-reports", o->noReports, "skip the elements' report tables (accuracy against references, table build costs)");
    return [o]() { return run(*o); };
});

}  // namespace
}  // namespace welkin::cli
