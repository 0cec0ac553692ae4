// welkin bench soak: many frames with time running (a day of sky time per --day-frames frames,
// fixed animation step per frame) through every registered element, headless at a small size;
// after a warm-up it watches the GL object counts, the driver's reported memory (where an
// extension gives it) and the process RSS, and reads every frame's HDR image back to check that
// each pixel is finite (docs/hardening.md).
//
//   welkin bench soak                                  # 10,000 frames at 64x32, a day per 600 frames
//   welkin bench soak --frames 300 --day-frames 100 --size 16x8
//
// Exit status: 0 when nothing grew after the warm-up and every pixel was finite; 2 with a
// "verdict: FAIL: ..." line giving the reason otherwise; 1 for a bad option (one line).
#include "command.hpp"
#include "scene_options.hpp"

#include <memory>
#include <welkin/astro/bodies.hpp>
#include <welkin/elements/registry.hpp>
#include <welkin/error.hpp>
#include <welkin/gl/context.hpp>
#include <welkin/keys.hpp>
#include <welkin/processor.hpp>

#include <epoxy/gl.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <numbers>
#include <optional>
#include <string>
#include <unistd.h>
#include <vector>

namespace welkin::cli {
namespace {

struct SoakOptions {
    SceneOptions scene;
    long frames = 10000;           // frames rendered, [1, 10'000'000]
    long dayFrames = 600;          // frames per simulated day (600 = a day per 10 s at 60 fps), [1, 1e7]
    double dtSeconds = 1.0 / 60;   // animation time per frame (clouds' wind, twinkling, the eye), s, (0, 3600]
    long warmup = -1;              // frames before the baseline; -1: two days (2 dayFrames), at most frames / 2
    long rows = 20;                // table rows after the warm-up, [1, 1000]
    double rssToleranceMiB = 8;    // allowed RSS growth after the warm-up, MiB, [0, 1e6]
    double driverToleranceMiB = 8; // allowed growth of the driver's used memory after the warm-up, MiB
    bool interactive = true;       // render.interactive: the game-loop path (caches, time slicing)
    bool injectLeak = false;       // hidden: leak a texture and 1 MiB of heap per frame (tests the verdict)
};

// --- what is measured ---------------------------------------------------------------------

// The GL object kinds counted by probing names with glIs*.
enum Kind { kTexture, kBuffer, kProgram, kShader, kFramebuffer, kRenderbuffer, kVertexArray, kSampler, kQuery, kKinds };
constexpr std::array<const char*, kKinds> kKindNames = {"textures", "buffers",      "programs", "shaders", "framebuffers",
                                                        "renderbuffers", "vertex arrays", "samplers", "queries"};
constexpr std::array<const char*, kKinds> kKindShort = {"tex", "buf", "prog", "shd", "fbo", "rbo", "vao", "smp", "qry"};

GLboolean isObject(Kind k, GLuint n) {
    switch (k) {
    case kTexture: return glIsTexture(n);
    case kBuffer: return glIsBuffer(n);
    case kProgram: return glIsProgram(n);
    case kShader: return glIsShader(n);
    case kFramebuffer: return glIsFramebuffer(n);
    case kRenderbuffer: return glIsRenderbuffer(n);
    case kVertexArray: return glIsVertexArray(n);
    case kSampler: return glIsSampler(n);
    case kQuery: return glIsQuery(n);
    default: return GL_FALSE;
    }
}

// A fresh name of kind `k` (made by glCreate*, so it is an object glIs* sees), deleted at once:
// the name the driver hands out next bounds the names in use when it allocates upwards, and is
// below the highest when it reuses freed names (Mesa's util_idalloc).
GLuint probeName(Kind k) {
    GLuint n = 0;
    switch (k) {
    case kTexture: glCreateTextures(GL_TEXTURE_2D, 1, &n); glDeleteTextures(1, &n); break;
    case kBuffer: glCreateBuffers(1, &n); glDeleteBuffers(1, &n); break;
    case kProgram: n = glCreateProgram(); glDeleteProgram(n); break;
    case kShader: n = glCreateShader(GL_FRAGMENT_SHADER); glDeleteShader(n); break;
    case kFramebuffer: glCreateFramebuffers(1, &n); glDeleteFramebuffers(1, &n); break;
    case kRenderbuffer: glCreateRenderbuffers(1, &n); glDeleteRenderbuffers(1, &n); break;
    case kVertexArray: glCreateVertexArrays(1, &n); glDeleteVertexArrays(1, &n); break;
    case kSampler: glCreateSamplers(1, &n); glDeleteSamplers(1, &n); break;
    case kQuery: glCreateQueries(GL_TIME_ELAPSED, 1, &n); glDeleteQueries(1, &n); break;
    default: break;
    }
    return n;
}

// Live GL objects of each kind: glIs* over the names 1 .. max(next name, highest live name seen
// so far) + kMargin. The margin covers names freed and handed out again below a live one.
class ObjectCounter {
public:
    std::array<long, kKinds> count() {
        std::array<long, kKinds> c{};
        for (int k = 0; k < kKinds; ++k) {
            const GLuint limit = std::max(probeName(Kind(k)), highest_[size_t(k)]) + kMargin;
            for (GLuint n = 1; n <= limit; ++n)
                if (isObject(Kind(k), n)) {
                    ++c[size_t(k)];
                    highest_[size_t(k)] = std::max(highest_[size_t(k)], n);
                }
        }
        return c;
    }

private:
    static constexpr GLuint kMargin = 4096;
    std::array<GLuint, kKinds> highest_{};
};

// Resident set size of this process, MiB (/proc/self/statm: the second field, in pages).
double rssMiB() {
    std::ifstream f("/proc/self/statm");
    long size = 0, resident = 0;
    if (!(f >> size >> resident)) throw Error("bench soak: cannot read /proc/self/statm");
    return double(resident) * double(::sysconf(_SC_PAGESIZE)) / (1024.0 * 1024.0);
}

bool hasExtension(const char* name) {
    GLint n = 0;
    glGetIntegerv(GL_NUM_EXTENSIONS, &n);
    for (GLint i = 0; i < n; ++i)
        if (std::strcmp(reinterpret_cast<const char*>(glGetStringi(GL_EXTENSIONS, GLuint(i))), name) == 0) return true;
    return false;
}

// The driver's reported memory use, MiB, where an extension gives one: NVX_gpu_memory_info
// (dedicated total - current available) or ATI_meminfo (the texture pool's free memory, reported
// as its negative: a leak makes it grow). Mesa's llvmpipe has neither: nullopt ("n/a").
class DriverMemory {
public:
    DriverMemory() : nvx_(hasExtension("GL_NVX_gpu_memory_info")), ati_(!nvx_ && hasExtension("GL_ATI_meminfo")) {}
    const char* source() const { return nvx_ ? "GL_NVX_gpu_memory_info (used = total - available)"
                                      : ati_ ? "GL_ATI_meminfo (minus the free texture memory)"
                                             : "none (no GL_NVX_gpu_memory_info or GL_ATI_meminfo): n/a"; }
    std::optional<double> usedMiB() const {
        if (nvx_) {
            GLint total = 0, available = 0;  // KiB
            glGetIntegerv(0x9047 /* GL_GPU_MEMORY_INFO_TOTAL_AVAILABLE_MEMORY_NVX */, &total);
            glGetIntegerv(0x9049 /* GL_GPU_MEMORY_INFO_CURRENT_AVAILABLE_VIDMEM_NVX */, &available);
            return double(total - available) / 1024.0;
        }
        if (ati_) {
            GLint free[4] = {};  // KiB: total free, largest block, auxiliary free, largest auxiliary
            glGetIntegerv(0x87FC /* GL_TEXTURE_FREE_MEMORY_ATI */, free);
            return -double(free[0]) / 1024.0;
        }
        return std::nullopt;
    }

private:
    bool nvx_, ati_;
};

struct Sample {
    long frame = 0;
    std::string time;
    double sunAltDeg = 0;
    std::array<long, kKinds> objects{};
    std::optional<double> driverMiB;
    double rssMiB = 0;
    double msPerFrame = 0;
};

void printRow(const Sample& s) {
    std::printf("| %ld | %s | %.1f |", s.frame, s.time.c_str(), s.sunAltDeg);
    for (long c : s.objects) std::printf(" %ld |", c);
    if (s.driverMiB) std::printf(" %.1f |", *s.driverMiB);
    else std::printf(" n/a |");
    std::printf(" %.1f | %.1f |\n", s.rssMiB, s.msPerFrame);
    std::fflush(stdout);
}

// --- the run --------------------------------------------------------------------------------

int run(SoakOptions o) {
    auto checkCount = [](const char* option, long v, long lo, long hi) {
        if (v < lo || v > hi)
            throw Error(std::string(option) + " " + std::to_string(v) + " not in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
    };
    checkCount("--frames", o.frames, 1, 10'000'000);
    checkCount("--day-frames", o.dayFrames, 1, 10'000'000);
    checkCount("--rows", o.rows, 1, 1000);
    // Two days: the first makes every table of day and night, the second the time-sliced
    // generators' second buffers (made on their first refill: measured, 133 -> 137 textures on
    // the second day, then flat).
    if (o.warmup < 0) o.warmup = std::min(2 * o.dayFrames, o.frames / 2);
    checkCount("--warmup", o.warmup, 0, o.frames - 1);
    auto number = [](double v) {
        char b[32];
        std::snprintf(b, sizeof b, "%g", v);
        return std::string(b);
    };
    if (!(o.dtSeconds > 0 && o.dtSeconds <= 3600)) throw Error("--dt " + number(o.dtSeconds) + " not in (0, 3600] s");
    if (!(o.rssToleranceMiB >= 0 && o.rssToleranceMiB <= 1e6))
        throw Error("--rss-tolerance " + number(o.rssToleranceMiB) + " not in [0, 1e6] MiB");
    if (!(o.driverToleranceMiB >= 0 && o.driverToleranceMiB <= 1e6))
        throw Error("--driver-tolerance " + number(o.driverToleranceMiB) + " not in [0, 1e6] MiB");
    // Every registered element unless --elements names some: a new element is soaked without
    // editing this file.
    if (!o.scene.elementsGiven) {
        std::string all;
        for (auto& n : elements::knownElements()) all += (all.empty() ? "" : ",") + n;
        o.scene.elements = all;
        o.scene.elementsGiven = true;
    }
    // Rain in the user's curtain and under the clouds, so the rainbow draws; before the user's
    // --var values, which may change them.
    const std::vector<std::string> names = o.scene.elementNames();
    auto has = [&](const char* n) { return std::find(names.begin(), names.end(), n) != names.end(); };
    if (has("clouds")) o.scene.vars.insert(o.scene.vars.begin(), "clouds.rain_density=0.5");
    if (has("rainbow")) o.scene.vars.insert(o.scene.vars.begin(), "rain.rate_mm_h=5");
    o.scene.validate();
    const UtcInstant start = o.scene.instant();
    const double skySecondsPerFrame = 86400.0 / double(o.dayFrames);
    // The whole run within the astronomy's years (the start is checked by instant()).
    UtcInstant end;
    try {
        end = start.plusSeconds(skySecondsPerFrame * double(o.frames));
        checkAstronomyYear(end, "end");
    } catch (const Error&) {
        throw Error("--time + --frames: the run ends after year " + std::to_string(int(astro::kEphemerisLastYear)) +
                    " (the span of the ephemerides ends there)");
    }

    Logger log;
    auto ctx = gl::HeadlessContext::create({}, log);
    SkyProcessor processor(SkyVars::earth(), log);
    o.scene.apply(processor);
    processor.vars().set(keys::interactive, o.interactive);
    const Camera cam = processor.camera();
    DriverMemory driver;
    ObjectCounter counter;

    std::printf("welkin bench soak: %ld frames at %dx%d, %s, elements %s\n", o.frames, cam.width, cam.height,
                ctx->description().c_str(), o.scene.elements.c_str());
    std::printf("sky time: %s + %.1f s a frame (a day per %ld frames); animation time %.6f s a frame; render.interactive %s\n",
                start.toIso().c_str(), skySecondsPerFrame, o.dayFrames, o.dtSeconds, o.interactive ? "on" : "off");
    std::printf("warm-up: %ld frames; then a row every ~%ld frames; tolerances after the warm-up: GL objects 0, RSS %.1f MiB, "
                "driver memory %.1f MiB\ndriver memory: %s\n\n",
                o.warmup, std::max(1L, (o.frames - o.warmup) / o.rows), o.rssToleranceMiB, o.driverToleranceMiB, driver.source());
    std::printf("| frame | sky time (UTC) | sun alt deg |");
    for (auto* k : kKindShort) std::printf(" %s |", k);
    std::printf(" driver MiB | RSS MiB | ms/frame |\n|---|---|---|");
    for (int k = 0; k < kKinds; ++k) std::printf("---|");
    std::printf("---|---|---|\n");

    // The frames at which a row is taken: the end of the warm-up (the baseline), then evenly to the last.
    std::vector<long> at{o.warmup};
    for (long r = 1; r <= o.rows; ++r) {
        const long f = o.warmup + (o.frames - o.warmup) * r / o.rows;
        if (f > at.back()) at.push_back(f);
    }
    size_t next = 0;
    std::vector<Sample> samples;
    std::vector<GLuint> leakedTextures;
    std::vector<std::vector<char>> leakedHeap;
    auto lastRow = std::chrono::steady_clock::now();
    long lastRowFrame = 0;
    for (long f = 0; f <= o.frames; ++f) {
        if (next < at.size() && f == at[next]) {
            ++next;
            glFinish();
            const auto now = std::chrono::steady_clock::now();
            Sample s;
            s.frame = f;
            s.time = processor.time().toIso();
            s.sunAltDeg = std::asin(std::clamp(processor.vars().get(keys::sunDirection).z, -1.0, 1.0)) * 180 / std::numbers::pi;
            s.objects = counter.count();
            s.driverMiB = driver.usedMiB();
            s.rssMiB = rssMiB();
            s.msPerFrame = f > lastRowFrame ? std::chrono::duration<double, std::milli>(now - lastRow).count() / double(f - lastRowFrame) : 0;
            printRow(s);
            samples.push_back(s);
            lastRow = std::chrono::steady_clock::now();  // the counting itself is not a frame's cost
            lastRowFrame = f;
        }
        if (f == o.frames) break;
        processor.setTime(start.plusSeconds(skySecondsPerFrame * double(f + 1)));
        processor.setAnimationTime(o.dtSeconds * double(f + 1));
        processor.renderFrame();
        const Image hdr = processor.readHdr();
        for (size_t i = 0; i < hdr.pixels.size(); ++i)
            if (!std::isfinite(hdr.pixels[i])) {
                const size_t px = i / size_t(hdr.channels);
                std::printf("\nverdict: FAIL: frame %ld (%s): HDR pixel (%zu, %zu) channel %zu is %g\n", f + 1,
                            processor.time().toIso().c_str(), px % size_t(hdr.width), px / size_t(hdr.width), i % size_t(hdr.channels),
                            double(hdr.pixels[i]));
                return 2;
            }
        if (o.injectLeak) {  // what the verdict must catch: a texture and 1 MiB of heap a frame, never freed
            GLuint t = 0;
            glCreateTextures(GL_TEXTURE_2D, 1, &t);
            glTextureStorage2D(t, 1, GL_RGBA8, 4, 4);
            leakedTextures.push_back(t);
            leakedHeap.emplace_back(size_t(1) << 20, char(1));
        }
    }

    // The verdict: nothing above its value at the end of the warm-up (the first row).
    std::vector<std::string> reasons;
    const Sample& base = samples.front();
    for (int k = 0; k < kKinds; ++k)
        for (const Sample& s : samples)
            if (s.objects[size_t(k)] > base.objects[size_t(k)]) {
                reasons.push_back(std::string(kKindNames[size_t(k)]) + " grew from " + std::to_string(base.objects[size_t(k)]) + " at frame " +
                                  std::to_string(base.frame) + " to " + std::to_string(s.objects[size_t(k)]) + " at frame " +
                                  std::to_string(s.frame) + " (tolerance 0)");
                break;
            }
    char buf[256];
    for (const Sample& s : samples)
        if (s.rssMiB - base.rssMiB > o.rssToleranceMiB) {
            std::snprintf(buf, sizeof buf, "RSS grew from %.1f MiB at frame %ld to %.1f MiB at frame %ld (tolerance %.1f MiB)", base.rssMiB,
                          base.frame, s.rssMiB, s.frame, o.rssToleranceMiB);
            reasons.push_back(buf);
            break;
        }
    for (const Sample& s : samples)
        if (s.driverMiB && base.driverMiB && *s.driverMiB - *base.driverMiB > o.driverToleranceMiB) {
            std::snprintf(buf, sizeof buf, "driver memory grew from %.1f MiB at frame %ld to %.1f MiB at frame %ld (tolerance %.1f MiB)",
                          *base.driverMiB, base.frame, *s.driverMiB, s.frame, o.driverToleranceMiB);
            reasons.push_back(buf);
            break;
        }
    for (GLuint t : leakedTextures) glDeleteTextures(1, &t);
    processor.release();
    if (!reasons.empty()) {
        std::string all;
        for (auto& r : reasons) all += (all.empty() ? "" : "; ") + r;
        std::printf("\nverdict: FAIL: %s\n", all.c_str());
        return 2;
    }
    std::printf("\nverdict: PASS: %ld frames, every HDR pixel finite; after the warm-up (frame %ld) no GL object count grew, RSS "
                "%+.1f MiB (tolerance %.1f), driver memory %s\n",
                o.frames, base.frame, samples.back().rssMiB - base.rssMiB, o.rssToleranceMiB,
                base.driverMiB ? (std::to_string(*samples.back().driverMiB - *base.driverMiB) + " MiB").c_str() : "n/a");
    return 0;
}

BenchRegistrar reg("soak", "many frames with time running through every element: GL objects, memory and finite pixels must hold",
                   [](CLI::App& sub) {
    auto o = std::make_shared<SoakOptions>();  // owned by the action returned below (LeakSanitizer)
    o->scene.size = "64x32";
    o->scene.time = "2026-03-20T00:00:00Z";
    o->scene.latDeg = 48.0;
    o->scene.lonDeg = 11.0;
    o->scene.projection = "equirect";  // the whole sphere at 2:1: every element's pixels in the frame
    o->scene.addTo(sub, false);
    o->scene.time = "2026-03-20T00:00:00Z";  // addTo() sets its own default when --time is optional
    sub.add_option("--frames", o->frames, "frames to render, [1, 1e7]")->capture_default_str();
    sub.add_option("--day-frames", o->dayFrames, "frames per simulated day (600: a day per 10 s at 60 fps), [1, 1e7]")->capture_default_str();
    sub.add_option("--dt", o->dtSeconds, "animation time per frame, s, (0, 3600]")->capture_default_str();
    sub.add_option("--warmup", o->warmup, "frames before the baseline row (default: two days, at most half the frames)");
    sub.add_option("--rows", o->rows, "table rows after the warm-up, [1, 1000]")->capture_default_str();
    sub.add_option("--rss-tolerance", o->rssToleranceMiB, "allowed RSS growth after the warm-up, MiB")->capture_default_str();
    sub.add_option("--driver-tolerance", o->driverToleranceMiB, "allowed growth of the driver's reported memory, MiB")->capture_default_str();
    sub.add_option("--interactive", o->interactive, "render.interactive (the game-loop path: caches, time slicing)")->capture_default_str();
    sub.add_flag("--inject-leak", o->injectLeak, "leak a texture and 1 MiB a frame (tests the verdict)")->group("");
    return [o]() { return run(*o); };
});

}  // namespace
}  // namespace welkin::cli
