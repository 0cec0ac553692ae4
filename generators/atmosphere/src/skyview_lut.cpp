// Sky-view LUT generator, one instance per light (GPU pass skyview_lut.glsl; CPU twin
// cpu::skyViewTexel).
#include <welkin/cache.hpp>
#include <welkin/embedded/atmosphere_shaders.hpp>
#include <welkin/error.hpp>
#include <welkin/generators/sky_luts.hpp>
#include <welkin/gl/shader.hpp>
#include <welkin/keys.hpp>

#include <epoxy/gl.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <memory>
#include <functional>
#include <thread>

#include <unistd.h>

namespace welkin::generators {

namespace {
// FNV-1a, 64 bits: the disk cache's key over everything a keyframe table depends on.
struct Fnv {
    uint64_t h = 1469598103934665603ull;
    void bytes(const void* p, size_t n) {
        const auto* b = static_cast<const unsigned char*>(p);
        for (size_t i = 0; i < n; ++i) h = (h ^ b[i]) * 1099511628211ull;
    }
    void d(double v) { bytes(&v, sizeof v); }
    void i(int64_t v) { bytes(&v, sizeof v); }
    void v3(const glm::dvec3& v) { d(v.x), d(v.y), d(v.z); }
    void s(const std::string& t) { i(int64_t(t.size())), bytes(t.data(), t.size()); }
    void profile(const DensityProfile& p) {
        for (const DensityLayer& l : p.layers) d(l.width), d(l.expTerm), d(l.expScale), d(l.linearTerm), d(l.constantTerm);
    }
};
constexpr uint32_t kCacheMagic = 0x314b5653u;  // "SVK1": bump with the file's layout
constexpr double kMoonAngularRadius = 0.0045;  // rad, the Moon's mean apparent radius in the march
// The grid tables cached and built at load: from 3 grid steps below the prefill's low end (-20
// deg), so that the cubic around a light just above it (which needs one table below and, moving,
// looks two ahead) finds them all (without them a light at -18 deg built the -20.05 deg table a
// part a frame after a jump).
constexpr int kCacheStepsBelow = 3;
double cacheLowRad(const LightKeyframes& kf) { return kf.options().prefillLowRad - kCacheStepsBelow * kf.options().stepRad; }
}  // namespace

std::string SkyViewLut::cacheFolder(const SkyVars& vars) const {
    // The Sun's (the Moon's in an interactive session only), RGB mode (a spectral
    // table is built whole), the presets that prefill the grid.
    // The Moon's grid is built at load only in an interactive session (gridAtLoad), in a folder of
    // its own (its angular radius in the march).
    if (spectral_ || !q_.keyframePrefill || !vars.getOr(skykeys::keyframeCache, true)) return {};
    if (light_ == Light::Moon && !vars.getOr(keys::interactive, false)) return {};
    Fnv f;
    f.i(kCacheMagic);
    if (light_ == Light::Moon) f.i(1), f.d(kMoonAngularRadius);  // (nothing added for the Sun: its folders stay valid)
    for (const char* sh : {"atmosphere.glsl", "skyview_lut.glsl", "light_blend.glsl", "transmittance_lut.glsl", "multiscattering_lut.glsl", "sh_lut.glsl"})
        f.s(std::string(embedded::atmosphere_shaders(sh)));
    for (GLenum e : {GL_VENDOR, GL_RENDERER, GL_VERSION}) {
        const GLubyte* t = glGetString(e);
        f.s(t ? reinterpret_cast<const char*>(t) : "");
    }
    const SkyModel& m = model_;
    f.d(m.bottomRadius), f.d(m.topRadius), f.v3(m.rayleighScattering), f.profile(m.rayleighDensity), f.v3(m.mieScattering);
    f.v3(m.mieExtinction), f.profile(m.mieDensity), f.d(m.mieG), f.i(m.miePhase), f.v3(m.absorptionExtinction);
    f.profile(m.absorptionDensity), f.v3(m.groundAlbedo), f.v3(m.solarIlluminance), f.d(m.sunAngularRadius);
    const SkyQuality& q = q_;
    for (int v : {q.transmittanceW, q.transmittanceH, q.transmittanceSteps, q.multiScatteringMuS, q.multiScatteringSize,
                  q.multiScatteringDirections, q.multiScatteringSteps, int(q.directionalMs), q.shBands, q.shDirections, q.shIterations,
                  q.shIterationDirections, q.shIterationSteps, q.skyViewW, q.skyViewH, q.skyViewSteps, int(q.halfFloat), int(q.bakedMiePhase),
                  q.keyframeChunks})
        f.i(v);
    f.d(q.keyframeStepRad), f.d(q.keyframeCoarseStepRad), f.d(h_), f.d(kLutScale);
    char name[48];
    std::snprintf(name, sizeof name, "sky-keyframes-%016llx", static_cast<unsigned long long>(f.h));
    return (cacheDirectory() / name).string();
}

void SkyViewLut::preloadFromCache(const Logger& log) {
    // Every grid table of the prefill's range found in the folder, into a slot of its own (kept
    // out of the schedule until the light needs it: LightKeyframes::preload).
    if (cacheFolder_.empty()) return;
    std::error_code ec;
    if (!std::filesystem::is_directory(cacheFolder_, ec)) return;
    const auto t0 = std::chrono::steady_clock::now();
    const int before = cacheReads_;
    const std::vector<double>& grid = keyframes_.grid();
    const size_t texels = size_t(q_.skyViewW) * size_t(q_.skyViewH) * 4;
    std::vector<uint32_t> data(texels);
    for (int k = 0; k < int(grid.size()); ++k) {
        if (grid[size_t(k)] < cacheLowRad(keyframes_) - 1e-9) continue;
        char file[16];
        std::snprintf(file, sizeof file, "%03d.bin", k);
        std::ifstream in(std::filesystem::path(cacheFolder_) / file, std::ios::binary);
        if (!in) continue;
        uint32_t hdr[4] = {};
        in.read(reinterpret_cast<char*>(hdr), sizeof hdr);
        if (!in || hdr[0] != kCacheMagic || hdr[1] != uint32_t(q_.skyViewW) || hdr[2] != uint32_t(q_.skyViewH) || hdr[3] != uint32_t(k)) continue;
        in.read(reinterpret_cast<char*>(data.data()), std::streamsize(texels * sizeof(uint32_t)));
        if (!in || in.peek() != std::char_traits<char>::eof()) continue;
        const int s = keyframes_.preload(k);
        if (s < 0) break;  // no slot left
        while (int(slots_.size()) < keyframes_.slotCount()) {
            Slot& sl = slots_.emplace_back();
            sl.packed = gl::Texture2D(q_.skyViewW, q_.skyViewH, GL_RGBA32UI);
            sl.packed.setFilter(GL_NEAREST);
            sl.packed.setWrap(GL_CLAMP_TO_EDGE);
        }
        glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
        glTextureSubImage2D(slots_[size_t(s)].packed.id(), 0, 0, 0, q_.skyViewW, q_.skyViewH, GL_RGBA_INTEGER, GL_UNSIGNED_INT, data.data());
        ++cacheReads_;
    }
    glFinish();  // the uploads done: the time below is theirs (once per processor)
    char buf[200];
    std::snprintf(buf, sizeof buf, "%s: %d keyframe tables read from the disk cache (%.1f MB) in %.1f ms", name().c_str(), cacheReads_ - before,
                  double(cacheReads_ - before) * double(texels * sizeof(uint32_t)) / 1e6,
                  std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
    log.debug(buf);
}

void SkyViewLut::writeToCache(int slot) {
    // A grid table just completed (built, not read): written once, atomically (a temporary name
    // renamed over the final one), so concurrent processes see a whole file or none.
    const int k = keyframes_.slotGrid(slot);
    if (cacheFolder_.empty() || k < 0 || keyframes_.grid()[size_t(k)] < cacheLowRad(keyframes_) - 1e-9) return;
    char file[16];
    std::snprintf(file, sizeof file, "%03d.bin", k);
    const std::filesystem::path path = std::filesystem::path(cacheFolder_) / file;
    std::error_code ec;
    if (std::filesystem::exists(path, ec)) return;
    std::filesystem::create_directories(cacheFolder_, ec);
    const size_t texels = size_t(q_.skyViewW) * size_t(q_.skyViewH) * 4;
    // Not zero-filled (the read overwrites every texel): a vector's zeroing of these 0.3-1.3 MB was
    // the largest CPU cost of a frame that completes a grid table (docs/hardening.md).
    std::unique_ptr<uint32_t[]> data(new uint32_t[texels]);
    glPixelStorei(GL_PACK_ALIGNMENT, 4);
    glGetTextureImage(slots_[size_t(slot)].packed.id(), 0, GL_RGBA_INTEGER, GL_UNSIGNED_INT, GLsizei(texels * sizeof(uint32_t)), data.get());
    const std::string tmp = path.string() + ".tmp" + std::to_string(::getpid()) + "-" +
                            std::to_string(std::hash<std::thread::id>{}(std::this_thread::get_id()));
    {
        std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
        if (!out) return;
        const uint32_t hdr[4] = {kCacheMagic, uint32_t(q_.skyViewW), uint32_t(q_.skyViewH), uint32_t(k)};
        out.write(reinterpret_cast<const char*>(hdr), sizeof hdr);
        out.write(reinterpret_cast<const char*>(data.get()), std::streamsize(texels * sizeof(uint32_t)));
        if (!out) {
            out.close();
            std::filesystem::remove(tmp, ec);
            return;
        }
    }
    std::filesystem::rename(tmp, path, ec);
    if (ec) std::filesystem::remove(tmp, ec);
    else ++cacheWrites_;
}

SkyViewLut::SkyViewLut(Light light) : SkyGenerator(light == Light::Sun ? "sky.sun_view" : "sky.moon_view"), light_(light) {
    input(skykeys::transmittanceLuts);
    input(skykeys::multiScatteringLuts);
    input(skykeys::shLuts);
    input(skykeys::keyframeBudget, {.optional = true});  // the background prefill's parts per frame
    input(skykeys::keyframeCache, {.optional = true});   // the grid tables in the disk cache
    input(keys::interactive, {.optional = true});        // the whole grid at load, jumps through it, the mix in halves
    input(keys::observerHeight);
    if (light == Light::Sun) {
        // The light's elevation only: the table is parameterised by the azimuth from the light.
        input(skykeys::sunCosZenith, {.tolerance = kCosZenithTolerance});
        output(skykeys::sunViewLut);
        output(skykeys::sunViewMieLut);
        output(skykeys::sunViewTotalLut);
        output(skykeys::viewTransmittanceLut);
    } else {
        input(skykeys::moonCosZenith, {.tolerance = kCosZenithTolerance});
        input(skykeys::moonLit);
        output(skykeys::moonViewLut);
        output(skykeys::moonViewMieLut);
        output(skykeys::moonViewTotalLut);
    }
}

void SkyViewLut::releaseGl() {
    smooth_ = {};
    mie_ = {};
    total_ = {};
    viewT_ = {};
    viewTProg_ = {};
    smoothK_ = {};
    mieK_ = {};
    totalK_ = {};
    fboK_ = {};
    prog_ = {};
    slots_.clear();
    darkShown_ = false;
    chunkScratch_ = {};
    wholeScratch_ = {};
    showFbo_ = {};
    shownOnce_ = false;
    shownBlack_ = false;
    blendProg_ = {};
    toLogProg_ = {};
    keyframes_.reset();
    preloadDue_ = true;
    loadFilled_ = false;
    staleHalf_ = -1;
    viewTH_ = -1.0;
    releaseCommon();
}

int SkyViewLut::interactiveChunks(const SkyQuality& q) {
    const long work = long(std::max(1, q.skyViewW)) * std::max(1, q.skyViewH) * std::max(1, q.skyViewSteps);
    const long byWork = (work + kInteractivePartWork - 1) / kInteractivePartWork;
    // At most one texel a part.
    return int(std::min<long>(long(std::max(1, q.skyViewW)) * std::max(1, q.skyViewH),
                              std::max<long>(long(std::max(1, q.keyframeChunks)) * kInteractiveChunkFactor, byWork)));
}

void SkyViewLut::doRun(SkyVars& vars, const Logger& log) {
    prepare(vars);
    // Even heights: the two halves (sky, ground) then have the same rows and the pixel shaders'
    // mapping stays inside its half without a clamp.
    if (q_.skyViewH % 2 != 0 || q_.skyViewH < 4)
        throw Error("SkyViewLut: height " + std::to_string(q_.skyViewH) + " texels must be even and >= 4");
    const GLenum fmt = q_.halfFloat ? GL_RGBA16F : GL_RGBA32F;
    auto make = [&](gl::Texture2D& t) {
        t = gl::Texture2D(q_.skyViewW, q_.skyViewH, fmt);
        t.setFilter(GL_LINEAR);
        t.setWrap(GL_CLAMP_TO_EDGE);
    };
    auto attach3 = [](gl::Framebuffer& fb, gl::Texture2D& a, gl::Texture2D& b, gl::Texture2D& c, const char* what) {
        fb = gl::Framebuffer::create();
        fb.attach(GL_COLOR_ATTACHMENT0, a);
        fb.attach(GL_COLOR_ATTACHMENT1, b);
        fb.attach(GL_COLOR_ATTACHMENT2, c);
        fb.checkComplete(what);
    };
    // Keyframes (light_keyframes.hpp): tables at given elevations, each built over several runs
    // while the light moves; the shown table is blended from two of them (or is one of them).
    // In spectral mode a table is built whole in one run (each triple's pass is combined into it
    // over the whole texture).
    // Interactive (welkin view, a game loop) with the Sun's prefill presets: the whole grid is
    // there from the first run (read from the disk cache, the rest built at load), a jump is
    // shown through it, and a moving light's mix is done a half table per run (skyelements/sky/README.md,
    // "While time runs").
    const bool interactive = vars.getOr(keys::interactive, false);
    const bool gridAtLoad = interactive && !spectral_ && q_.keyframePrefill;
    // (Interactive: a table in many more parts (interactiveChunks); what is built over frames is
    // then only the exact table of a resting light (the grid is whole from the first run), a part
    // a frame within the 3-still-frame target at 512x256: ~0.2 ms at medium, quiet.)
    const int chunks = spectral_ ? 1 : gridAtLoad ? interactiveChunks(q_) : std::max(1, q_.keyframeChunks);
    // Interactive, the Moon's exact table waits for the Sun's: after a jump both lights come to
    // rest in the same frame, and their exact tables were built a part each in the same frames
    // (6.5 still frames in welkin bench all's jump column, issue 22 item 5); the Moon's rest rule
    // counts the Sun's parts more, so no frame builds a part of both.
    const int stillRuns = kKeyframeStillRuns + (light_ == Light::Moon && gridAtLoad ? chunks : 0);
    LightKeyframes::Options ko{.stepRad = q_.keyframeStepRad, .coarseStepRad = q_.keyframeCoarseStepRad, .chunks = chunks,
                               .slots = keyframeSlots(q_, &keyframes_) + (gridAtLoad ? kCacheStepsBelow : 0), .stillMuS = kCosZenithTolerance, .stillRuns = stillRuns,
                               .prefill = q_.keyframePrefill,
                               .prefillChunksPerRun = q_.keyframePrefill ? vars.getOr(skykeys::keyframeBudget, kKeyframeBudgetDefault) : 0,
                               .adoptOnJump = gridAtLoad};
    keyframes_.setOptions(ko);
    const bool resized = !smooth_ || smooth_.width() != q_.skyViewW || smooth_.height() != q_.skyViewH || smooth_.internalFormat() != fmt;
    if (resized) {
        make(smooth_);
        make(mie_);
        make(total_);
        attach3(showFbo_, smooth_, mie_, total_, "SkyViewLut");
        slots_.clear();
        keyframes_.reset();
    }
    if (!prog_ || progBands_ != q_.shBands) {
        progBands_ = q_.shBands;
        prog_ = gl::ProgramBuilder(name())
                    .define("ATM_USE_TRANSMITTANCE")
                    .define("ATM_USE_MULTISCATTERING")
                    .define("ATM_MS_DIRECTIONAL")
                    .define("ATM_SH_BANDS", q_.shBands)
                    .fullscreenVertex()
                    .fragment("generators/atmosphere.glsl", embedded::atmosphere_shaders("atmosphere.glsl"))
                    .fragment("generators/skyview_lut.glsl", embedded::atmosphere_shaders("skyview_lut.glsl"))
                    .build();
    }
    if (!blendProg_)
        blendProg_ = gl::ProgramBuilder(name() + " blend")
                         .define("SKY_VIEW_BLEND")
                         .fullscreenVertex()
                         .fragment("generators/atmosphere.glsl", embedded::atmosphere_shaders("atmosphere.glsl"))
                         .fragment("generators/light_blend.glsl", embedded::atmosphere_shaders("light_blend.glsl"))
                         .build();
    const double Ht = model_.topRadius - model_.bottomRadius;
    h_ = std::clamp(vars.getOr(keys::observerHeight, 0.0), 0.0, Ht);
    muS_ = std::clamp(vars.get(light_ == Light::Sun ? skykeys::sunCosZenith : skykeys::moonCosZenith), -1.0, 1.0);
    // The tables hold for one observer height, atmosphere and quality: any other change of input
    // (not the light's elevation) forgets them.
    {
        std::vector<uint64_t> v;
        for (size_t i = 0; i < inputs().size(); ++i) {
            const std::string& name = inputs()[i].name;
            if (name != skykeys::sunCosZenith.name() && name != skykeys::moonCosZenith.name() && name != keys::interactive.name())
                v.push_back(inputVersion(vars, i));
        }
        v.push_back(uint64_t(q_.skyViewSteps));
        v.push_back(uint64_t(std::llround(q_.keyframeStepRad * 1e9)));
        v.push_back(uint64_t(std::llround(q_.keyframeCoarseStepRad * 1e9)));
        if (v != validFor_ || resized) keyframes_.reset(), preloadDue_ = true;
        validFor_ = std::move(v);
    }
    // Spectral mode: each triple's pass goes to the scratch textures, then is added to the RGB
    // ones through the triple's matrix (combine()).
    if (spectral_ && (!smoothK_ || smoothK_.width() != smooth_.width() || smoothK_.height() != smooth_.height() ||
                      smoothK_.internalFormat() != fmt)) {
        make(smoothK_);
        make(mieK_);
        make(totalK_);
        attach3(fboK_, smoothK_, mieK_, totalK_, "SkyViewLut (triple)");
    }
    const GLenum bufs[3] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1, GL_COLOR_ATTACHMENT2};
    auto allocateSlots = [&] {
        // A packed texture for each slot the schedule uses (allocated as it grows).
        while (int(slots_.size()) < keyframes_.slotCount()) {
            Slot& sl = slots_.emplace_back();
            sl.packed = gl::Texture2D(q_.skyViewW, q_.skyViewH, GL_RGBA32UI);
            sl.packed.setFilter(GL_NEAREST);
            sl.packed.setWrap(GL_CLAMP_TO_EDGE);
        }
    };
    auto scratch = [&](Scratch& sc) -> Scratch& {
        if (!sc.smooth || sc.smooth.width() != q_.skyViewW || sc.smooth.height() != q_.skyViewH) {
            for (gl::Texture2D* t : {&sc.smooth, &sc.mie}) {
                *t = gl::Texture2D(q_.skyViewW, q_.skyViewH, GL_RGBA32F);
                t->setFilter(GL_NEAREST);
                t->setWrap(GL_CLAMP_TO_EDGE);
            }
            sc.fbo = gl::Framebuffer::create();
            sc.fbo.attach(GL_COLOR_ATTACHMENT0, sc.smooth);
            sc.fbo.attach(GL_COLOR_ATTACHMENT1, sc.mie);
            sc.fbo.checkComplete("SkyViewLut keyframe");
        }
        return sc;
    };
    // Texels [t0, t1) (row order, rows from the bottom) of slot `s`'s table at cos zenith `muS`,
    // into the scratch of its kind (whole: built in this run), drawn through at most three
    // scissor rectangles (a partial first row, whole rows, a partial last row); `complete`: the
    // table is whole now, packed into the slot.
    auto buildRows = [&](int s, double muS, long t0, long t1, bool complete, bool whole) {
        const long W = q_.skyViewW;
        std::array<glm::ivec4, 3> rects{};  // x, y, width, height
        int nRects = 0;
        if (t1 > t0) {
            const long ya = t0 / W, xa = t0 % W, yb = t1 / W, xb = t1 % W;  // [ya, xa] .. [yb, xb) exclusive
            if (ya == yb) {
                rects[size_t(nRects++)] = glm::ivec4(xa, ya, xb - xa, 1);
            } else {
                long yFull = ya;
                if (xa > 0) rects[size_t(nRects++)] = glm::ivec4(xa, ya, W - xa, 1), ++yFull;
                if (yb > yFull) rects[size_t(nRects++)] = glm::ivec4(0, yFull, W, yb - yFull);
                if (xb > 0) rects[size_t(nRects++)] = glm::ivec4(0, yb, xb, 1);
            }
        }
        const skykeys::TextureList T = vars.get(skykeys::transmittanceLuts), MS = vars.get(skykeys::multiScatteringLuts),
                                   SH = vars.get(skykeys::shLuts);
        const int K = triples();
        if (int(T->size()) != K || int(MS->size()) != K || int(SH->size()) != K)
            throw Error("SkyViewLut: input LUTs for " + std::to_string(T->size()) + " triples, expected " + std::to_string(K));
        Scratch& sc = scratch(whole ? wholeScratch_ : chunkScratch_);
        glEnable(GL_SCISSOR_TEST);
        for (int k = 0; k < K; ++k) {
            const gl::Framebuffer& fb = spectral_ ? fboK_ : sc.fbo;
            useTriple(k);
            fb.bind();
            glViewport(0, 0, q_.skyViewW, q_.skyViewH);
            const GLenum slotBufs[3] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1, GL_NONE};
            glNamedFramebufferDrawBuffers(fb.id(), 3, spectral_ ? bufs : slotBufs);
            glBindTextureUnit(gl::binding::kTransmittanceLut, (*T)[size_t(k)].id);
            glBindTextureUnit(gl::binding::kMultiScatteringLut, (*MS)[size_t(k)].id);
            glBindTextureUnit(gl::binding::kShLut, (*SH)[size_t(k)].id);
            prog_.use();
            prog_.set("u_h", float(h_));
            prog_.set("u_muS", float(muS));
            prog_.set("u_steps", q_.skyViewSteps);
            prog_.set("u_size", glm::ivec2(q_.skyViewW, q_.skyViewH));
            prog_.set("u_scale", float(kLutScale));
            prog_.set("u_angular", float(light_ == Light::Sun ? model_.sunAngularRadius : kMoonAngularRadius));
            for (int r = 0; r < nRects; ++r) {
                const glm::ivec4& R = rects[size_t(r)];
                glScissor(R.x, R.y, R.z, R.w);
                fullscreen();
            }
            if (spectral_) {
                glDisable(GL_SCISSOR_TEST);
                combine(smoothK_, sc.smooth, k);
                combine(mieK_, sc.mie, k);
                glEnable(GL_SCISSOR_TEST);
            }
        }
        glDisable(GL_SCISSOR_TEST);
        if (complete) {
            // Complete: log radiance packed into the slot, for the blend.
            if (!toLogProg_)
                toLogProg_ = gl::ProgramBuilder(name() + " keyframe pack")
                                 .define("KEYFRAME_PACK")
                                 .compute("generators/light_blend.glsl", embedded::atmosphere_shaders("light_blend.glsl"))
                                 .build();
            glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT | GL_FRAMEBUFFER_BARRIER_BIT | GL_TEXTURE_FETCH_BARRIER_BIT);
            toLogProg_.use();
            glUniform2i(glGetUniformLocation(toLogProg_.id(), "u_size"), q_.skyViewW, q_.skyViewH);
            glBindTextureUnit(gl::binding::kBlendA, sc.smooth.id());
            glBindTextureUnit(gl::binding::kBlendAMie, sc.mie.id());
            glBindImageTexture(gl::binding::kLutImage, slots_[size_t(s)].packed.id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA32UI);
            glDispatchCompute(GLuint((q_.skyViewW + 7) / 8), GLuint((q_.skyViewH + 7) / 8), 1);
            glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
        }
    };
    // Interactive: the whole grid from the first run on (gridAtLoad), whatever the light does
    // later: the tables the disk cache holds are read, the others built whole now and written to
    // it, all kept as preloaded tables (LightKeyframes::preload) that the schedule adopts where the
    // light is (a jump too). A load-time cost, once per processor: 54 tables, ~2.3 s at medium on
    // llvmpipe the first time on a machine, the cache's read (~50-80 ms) after. Done at the first
    // run even at night (the Sun below -20 deg), so that dawn with time running finds the grid.
    if (gridAtLoad && !loadFilled_) {
        loadFilled_ = true;
        if (preloadDue_) {
            preloadDue_ = false;
            cacheFolder_ = cacheFolder(vars);
            preloadFromCache(log);
        }
        const std::vector<double>& grid = keyframes_.grid();
        for (int k = 0; k < int(grid.size()); ++k) {
            if (grid[size_t(k)] < cacheLowRad(keyframes_) - 1e-9 || keyframes_.hasGrid(k)) continue;
            const int s = keyframes_.preload(k);
            if (s < 0) break;  // no slot left
            allocateSlots();
            buildRows(s, std::sin(grid[size_t(k)]), 0, long(q_.skyViewW) * q_.skyViewH, true, true);
            writeToCache(s);
            ++loadBuilt_;
        }
    }
    // A light's LUT is skipped (left black) while it is far below the horizon (< -20 deg: past
    // astronomical twilight its scattered light is below the natural night sky's 2e-4 cd/m^2 by
    // orders of magnitude), and the Moon's while it gives no light. Black once, then nothing to
    // do but publish until the light comes back. The Sun's grid tables are kept for its return (the Moon's
    // are forgotten: it comes back at another phase).
    const bool dark = muS_ < kDarkBelowCosZenith || (light_ == Light::Moon && !vars.get(skykeys::moonLit));
    if (resized) darkShown_ = false, shownBlack_ = false;
    if (dark) {
        if (!darkShown_) {
            const float zero[4] = {0, 0, 0, 1};
            glClearNamedFramebufferfv(showFbo_.id(), GL_COLOR, 0, zero);
            glClearNamedFramebufferfv(showFbo_.id(), GL_COLOR, 1, zero);
            glClearNamedFramebufferfv(showFbo_.id(), GL_COLOR, 2, zero);
        }
        darkShown_ = true;
        shownBlack_ = true;
        // The next lit run starts from a table at its exact elevation (interactive: the grid built
        // at load is kept for the Moon's return, as the Sun's).
        if (light_ == Light::Moon && !gridAtLoad) keyframes_.reset();
        plan_ = {};
        shownOnce_ = false;
        staleHalf_ = -1;
    } else {
        darkShown_ = false;
        if (preloadDue_) {
            // The grid tables this atmosphere, quality and height had on disk (sky.keyframe_cache).
            preloadDue_ = false;
            cacheFolder_ = cacheFolder(vars);
            preloadFromCache(log);
        }
        plan_ = keyframes_.plan(muS_);
        allocateSlots();
        if (plan_.build >= 0) {
            // This run's texels of the table (scissored), chunk c of n: texels [c W H / n, (c + 1) W H / n)
            // in row order (whole rows [c H / n, (c + 1) H / n) when n divides H).
            const int n = ko.chunks;
            const long WH = long(q_.skyViewW) * q_.skyViewH;
            buildRows(plan_.build, plan_.buildMuS, plan_.chunkBegin * WH / n, plan_.chunkEnd * WH / n, plan_.chunkEnd == n,
                      plan_.chunkBegin == 0 && plan_.chunkEnd == n);
            if (plan_.chunkEnd == n) writeToCache(plan_.build);
        }
        // Prefill (SkyQuality::keyframePrefill) with sky.keyframe_budget 0: the grid tables
        // queued when the light first moved, each built whole now (else plan() spreads them).
        for (LightKeyframes::Prefill pf = keyframes_.nextPrefill(); pf.slot >= 0; pf = keyframes_.nextPrefill()) {
            allocateSlots();
            buildRows(pf.slot, pf.muS, 0, long(q_.skyViewW) * q_.skyViewH, true, true);
            writeToCache(pf.slot);
        }
        // The shown table: the plan's slots mixed with its weights (the Mie phase applied at the
        // current elevation). Only complete slots are ever read here; unused inputs repeat the
        // first slot with weight 0. Unchanged since the last mix (a run that only counts the
        // light's rest): kept as it is, not republished.
        // Interactive, a moving light shown through the same kind of mix as the last run and
        // within kHalfMixRad of it: only one half of the table (the sky rows, then the ground
        // rows: the seam is the horizon, where the table has its own discontinuity) is mixed
        // this run; the other keeps the last run's mix, one run behind the light. The stale half
        // is mixed at the next run whatever it brings (an unchanged plan included), so a light
        // that stops is shown whole one run later. Halves the mix's per-frame cost (the whole of
        // what a running frame adds at small frame sizes); the lag is measured in skyelements/sky/README.md.
        const int H = q_.skyViewH;
        int y0 = 0, y1 = H;
        // Interactive, the Moon while the Sun is above the horizon: the Moon's sky is then below
        // ~1e-4 of the Sun's (a full Moon's sky ~0.01-0.05 cd/m^2 against >= 100s of cd/m^2 at
        // sunrise), so its mix is paced, not skipped: one half of the table every
        // kMoonDaylightMixEvery runs, alternately, a jump included (each half at most
        // 2 x kMoonDaylightMixEvery runs behind its light; a still Moon is shown whole after the
        // next two). Keeps the Moon's mix out of most running frames and out of a jump's frame
        // (issue 22 items 4-5).
        // (Paced too when the Moon comes up or becomes lit, from the black table it showed.)
        const bool moonPaced = light_ == Light::Moon && interactive && !spectral_ && (shownOnce_ || shownBlack_) &&
                               vars.getOr(skykeys::sunCosZenith, -1.0) > 0.0;
        if (!moonPaced) pacedGen_[0] = pacedGen_[1] = planGen_ = 0, pacedRuns_ = 0;
        if (moonPaced) {
            if (!plan_.unchanged) ++planGen_;
            if (staleHalf_ >= 0) pacedGen_[staleHalf_] = planGen_ + 1;  // a half left behind before pacing began
            staleHalf_ = -1;
            const bool owed = pacedGen_[0] != planGen_ || pacedGen_[1] != planGen_;
            if (!owed || ++pacedRuns_ < kMoonDaylightMixEvery) {
                if (owed || keyframes_.pending()) runAgain();
                return;
            }
            pacedRuns_ = 0;
            const int half = pacedGen_[nextHalf_] != planGen_ ? nextHalf_ : nextHalf_ ^ 1;
            nextHalf_ = half ^ 1;
            pacedGen_[half] = planGen_;
            y0 = half * (H / 2), y1 = y0 + H / 2;
            ++halfMixes_;
        } else if (plan_.unchanged && shownOnce_) {
            if (staleHalf_ < 0) {
                if (keyframes_.pending()) runAgain();
                return;
            }
            y0 = staleHalf_ * (H / 2), y1 = y0 + H / 2;
            staleHalf_ = -1;
        } else if (interactive && !spectral_ && shownOnce_ && plan_.build < 0 && !plan_.exact && plan_.count > 1 &&
                   std::abs(std::asin(muS_) - std::asin(lastMixMuS_)) <= kHalfMixRad) {
            // The half left behind by the last run (else the next in turn): each half is at
            // most one run behind the light.
            const int half = staleHalf_ >= 0 ? staleHalf_ : nextHalf_;
            nextHalf_ = half ^ 1;
            y0 = half * (H / 2), y1 = y0 + H / 2;
            staleHalf_ = half ^ 1;
            ++halfMixes_;
        } else {
            staleHalf_ = -1;
        }
        lastMixMuS_ = muS_;
        shownOnce_ = true;
        if (spectral_) useTriple(0);
        showFbo_.bind();
        glViewport(0, 0, q_.skyViewW, q_.skyViewH);
        glNamedFramebufferDrawBuffers(showFbo_.id(), 3, bufs);
        const int units[4] = {gl::binding::kBlendA, gl::binding::kBlendB, gl::binding::kBlendC, gl::binding::kBlendD};
        glm::vec4 w(0.0f);
        for (int i = 0; i < 4; ++i) {
            const Slot& S = slots_[size_t(i < plan_.count ? plan_.slot[size_t(i)] : plan_.slot[0])];
            glBindTextureUnit(GLuint(units[i]), S.packed.id());
            w[i] = i < plan_.count ? float(plan_.weight[size_t(i)]) : 0.0f;
        }
        blendProg_.use();
        blendProg_.set("u_w", w);
        blendProg_.set("u_muS", float(muS_));
        blendProg_.set("u_h", float(h_));
        blendProg_.set("u_size", glm::ivec2(q_.skyViewW, q_.skyViewH));
        const bool part = y0 > 0 || y1 < H;
        if (part) glEnable(GL_SCISSOR_TEST), glScissor(0, y0, q_.skyViewW, y1 - y0);
        fullscreen();
        if (part) glDisable(GL_SCISSOR_TEST);
        if (keyframes_.pending() || staleHalf_ >= 0 || (moonPaced && (pacedGen_[0] != planGen_ || pacedGen_[1] != planGen_))) runAgain();
    }
    if (light_ == Light::Sun) {
        // The view-transmittance row (view_transmittance.glsl), from the RGB (or, in spectral
        // mode, solar-weighted combined) transmittance LUT; the geometry is every triple's. It
        // does not depend on the Sun: rebuilt only with the height or the transmittance.
        const int nT = 4 * q_.skyViewH;
        const uint64_t tv = vars.version(skykeys::transmittanceLut);
        if (!viewT_ || viewT_.width() != nT || viewTH_ != h_ || viewTVersion_ != tv) {
            viewTH_ = h_;
            viewTVersion_ = tv;
            if (!viewT_ || viewT_.width() != nT) {
                viewT_ = gl::Texture1D(nT, GL_RGBA32F);
                viewT_.setFilter(GL_LINEAR);
                viewT_.setWrap(GL_CLAMP_TO_EDGE);
            }
            if (!viewTProg_)
                viewTProg_ = gl::ProgramBuilder("SkyViewLut transmittance row")
                                 .define("ATM_USE_TRANSMITTANCE")
                                 .compute("generators/atmosphere.glsl", embedded::atmosphere_shaders("atmosphere.glsl"))
                                 .compute("generators/view_transmittance.glsl", embedded::atmosphere_shaders("view_transmittance.glsl"))
                                 .build();
            if (spectral_) useTriple(0);
            glBindTextureUnit(gl::binding::kTransmittanceLut, vars.get(skykeys::transmittanceLut).id);
            glBindImageTexture(gl::binding::kLutImage, viewT_.id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA32F);
            viewTProg_.use();
            viewTProg_.set("u_h", float(h_));
            viewTProg_.set("u_size", nT);
            viewTProg_.set("u_skyViewH", q_.skyViewH);
            glDispatchCompute(GLuint((nT + 63) / 64), 1, 1);
            glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
            vars.publish(skykeys::viewTransmittanceLut, viewT_.ref());
        }
        vars.publish(skykeys::sunViewLut, smooth_.ref());
        vars.publish(skykeys::sunViewMieLut, mie_.ref());
        vars.publish(skykeys::sunViewTotalLut, total_.ref());
    } else {
        vars.publish(skykeys::moonViewLut, smooth_.ref());
        vars.publish(skykeys::moonViewMieLut, mie_.ref());
        vars.publish(skykeys::moonViewTotalLut, total_.ref());
    }
}

}  // namespace welkin::generators
