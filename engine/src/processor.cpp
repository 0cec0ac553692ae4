#include <welkin/astro/astro_keys.hpp>
#include <welkin/check.hpp>
#include <welkin/error.hpp>
#include <welkin/gl/shader.hpp>
#include <welkin/keys.hpp>
#include <welkin/processor.hpp>

#include <epoxy/gl.h>

#include <nlohmann/json.hpp>

#include <cmath>
#include <algorithm>
#include <numbers>
#include <tuple>

namespace welkin {

namespace {
constexpr double kPi = std::numbers::pi;
constexpr int kLogLumSize = 128;  // log-luminance reduction resolution (power of two)

double msSince(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}
}  // namespace

void Observer::validate() const {
    const Shown deg{180 / kPi, " deg"};
    checkRange("Observer", "latitude", latitudeRad, -kPi / 2, kPi / 2, deg);
    checkRange("Observer", "longitude", longitudeRad, -kPi, kPi, deg);
    checkRange("Observer", "height", heightMeters, -1e4, 1e9, {1, " m"});
}

SkyProcessor::SkyProcessor(SkyVars vars, Logger log, ProcessorOptions options)
    : vars_(std::move(vars)), log_(std::move(log)), options_(options) {
    deriveVariables();
}

SkyProcessor::~SkyProcessor() { release(); }

void SkyProcessor::release() {
    for (auto& e : elements_) e->release();
    hdr_ = {};
    ldr_ = {};
    logLum_ = {};
    hdrFbo_ = {};
    ldrFbo_ = {};
    logLumFbo_ = {};
    toneMap_ = {};
    logLumProgram_ = {};
    emptyVao_ = {};
    cameraUbo_ = {};
    glReady_ = false;
}

SkyElement& SkyProcessor::add(std::unique_ptr<SkyElement> element) {
    if (!element) throw Error("SkyProcessor::add(): null element");
    if (find(element->name())) throw Error("SkyProcessor::add(): an element named '" + element->name() + "' is already registered");
    element->setTimingEnabled(options_.timing);
    elements_.push_back(std::move(element));
    return *elements_.back();
}

SkyElement* SkyProcessor::find(std::string_view name) const {
    for (auto& e : elements_)
        if (e->name() == name) return e.get();
    return nullptr;
}

void SkyProcessor::setTime(const UtcInstant& t) { time_ = t; }
void SkyProcessor::setObserver(const Observer& o) {
    o.validate();
    observer_ = o;
}
void SkyProcessor::setCamera(const Camera& c) {
    c.validate();
    bool resized = c.width != camera_.width || c.height != camera_.height;
    camera_ = c;
    if (resized && glReady_) {
        hdr_ = {};  // recreated at the new size by ensureTargets()
        ldr_ = {};
        logLumValid_ = false;
        for (auto& e : elements_) e->resize(c.width, c.height);
    }
}
void SkyProcessor::setExposure(const Exposure& e) {
    checkRange("SkyProcessor::setExposure()", "ev100", e.ev100, -20, 30);
    checkRange("SkyProcessor::setExposure()", "compensationEv", e.compensationEv, -10, 10);
    exposure_ = e;
    vars_.set(keys::exposureEv100, e.ev100);
    vars_.set(keys::exposureAuto, e.automatic);
}

double SkyProcessor::seconds() const {
    if (animationTime_) return *animationTime_;
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
}

void SkyProcessor::setAnimationTime(std::optional<double> s) {
    if (s && !std::isfinite(*s)) throw Error("SkyProcessor::setAnimationTime(): seconds must be finite");
    animationTime_ = s;
}

void SkyProcessor::deriveVariables() {
    const JulianDate jd = time_.julianDate();
    vars_.set(keys::timeJdUtc, glm::dvec2(jd.day, jd.fraction));
    vars_.set(keys::timeIso, time_.toIso());
    vars_.set(keys::observerLatitude, observer_.latitudeRad);
    vars_.set(keys::observerLongitude, observer_.longitudeRad);
    vars_.set(keys::observerHeight, observer_.heightMeters);
    if (options_.astronomy) astro::updateSkyVars(vars_);  // Sun, Moon, planets: directions and the astro keys (astro_keys.hpp)
}

void SkyProcessor::init() {
    if (!glReady_) {
        emptyVao_ = gl::VertexArray::create();
        cameraUbo_ = gl::Buffer(sizeof(CameraBlock));
        toneMap_ = gl::ProgramBuilder("SkyProcessor tone map")
                       .fullscreenVertex()
                       .fragment("engine/tonemap.frag.glsl", gl::engineShader("tonemap.frag.glsl"))
                       .build();
        logLumProgram_ = gl::ProgramBuilder("SkyProcessor log luminance")
                             .fullscreenVertex()
                             .fragment("engine/camera.glsl", gl::engineShader("camera.glsl"))
                             .fragment("engine/loglum.frag.glsl", gl::engineShader("loglum.frag.glsl"))
                             .build();
        int levels = int(std::log2(kLogLumSize)) + 1;
        logLum_ = gl::Texture2D(kLogLumSize, kLogLumSize, GL_RG32F, levels);
        logLumFbo_ = gl::Framebuffer::create();
        logLumFbo_.attach(GL_COLOR_ATTACHMENT0, logLum_);
        logLumFbo_.checkComplete("SkyProcessor log luminance");
        glReady_ = true;
    }
    InitContext ctx{vars_, log_};
    for (auto& e : elements_) {
        if (!e->initialized()) {
            e->init(ctx);
            e->resize(camera_.width, camera_.height);
        }
    }
    gl::checkError("SkyProcessor::init()");
}

void SkyProcessor::ensureTargets() {
    if (hdr_ && hdr_.width() == camera_.width && hdr_.height() == camera_.height) return;
    hdr_ = gl::Texture2D(camera_.width, camera_.height, GL_RGBA32F);
    hdr_.setFilter(GL_NEAREST);
    hdrFbo_ = gl::Framebuffer::create();
    hdrFbo_.attach(GL_COLOR_ATTACHMENT0, hdr_);
    hdrFbo_.checkComplete("SkyProcessor HDR target");
    ldr_ = gl::Texture2D(camera_.width, camera_.height, GL_RGBA8);
    ldrFbo_ = gl::Framebuffer::create();
    ldrFbo_.attach(GL_COLOR_ATTACHMENT0, ldr_);
    ldrFbo_.checkComplete("SkyProcessor LDR target");
}

FrameContext SkyProcessor::frameContext() { return FrameContext{vars_, log_, camera_, seconds(), &emptyVao_}; }

void SkyProcessor::runGenerators() {
    // Each generator once per frame, in element order (shared instances deduplicated).
    std::vector<Generator*> seen;
    auto t0 = std::chrono::steady_clock::now();
    for (auto& e : elements_) {
        for (auto& g : e->generators()) {
            if (std::find(seen.begin(), seen.end(), g.get()) != seen.end()) continue;
            seen.push_back(g.get());
            g->runIfDue(vars_, log_, options_.timing);
            gl::checkError(g->name() + "::run()");
        }
    }
    generatorsMs_ = msSince(t0);
}

void SkyProcessor::update() {
    init();
    deriveVariables();
    CameraBlock block = makeCameraBlock(camera_, seconds());
    cameraUbo_.update(&block, sizeof block);
    runGenerators();
    FrameContext ctx = frameContext();
    for (auto& e : elements_) e->update(ctx);
}

namespace {
// GL state that compositing changes, saved from and restored to the host (renderInto()).
struct SavedState {
    GLint framebuffer = 0, program = 0, vao = 0, ubo0 = 0, viewport[4] = {};
    GLint blendSrcRgb = 0, blendDstRgb = 0, blendSrcA = 0, blendDstA = 0, blendEqRgb = 0, blendEqA = 0, depthFunc = 0;
    GLboolean blend = 0, depthTest = 0, cull = 0, depthMask = 0;
    std::vector<GLenum> drawBuffers;

    void save() {
        glGetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &framebuffer);
        glGetIntegerv(GL_CURRENT_PROGRAM, &program);
        glGetIntegerv(GL_VERTEX_ARRAY_BINDING, &vao);
        glGetIntegeri_v(GL_UNIFORM_BUFFER_BINDING, 0, &ubo0);
        glGetIntegerv(GL_VIEWPORT, viewport);
        glGetIntegerv(GL_BLEND_SRC_RGB, &blendSrcRgb);
        glGetIntegerv(GL_BLEND_DST_RGB, &blendDstRgb);
        glGetIntegerv(GL_BLEND_SRC_ALPHA, &blendSrcA);
        glGetIntegerv(GL_BLEND_DST_ALPHA, &blendDstA);
        glGetIntegerv(GL_BLEND_EQUATION_RGB, &blendEqRgb);
        glGetIntegerv(GL_BLEND_EQUATION_ALPHA, &blendEqA);
        glGetIntegerv(GL_DEPTH_FUNC, &depthFunc);
        blend = glIsEnabled(GL_BLEND);
        depthTest = glIsEnabled(GL_DEPTH_TEST);
        cull = glIsEnabled(GL_CULL_FACE);
        glGetBooleanv(GL_DEPTH_WRITEMASK, &depthMask);
        if (framebuffer != 0) {
            GLint n = 0;
            glGetIntegerv(GL_MAX_DRAW_BUFFERS, &n);
            for (GLint i = 0; i < n; ++i) {
                GLint b = 0;
                glGetIntegerv(GL_DRAW_BUFFER0 + i, &b);
                drawBuffers.push_back(GLenum(b));
            }
        }
    }
    void restore() const {
        glBindFramebuffer(GL_FRAMEBUFFER, GLuint(framebuffer));
        if (!drawBuffers.empty()) glDrawBuffers(GLsizei(drawBuffers.size()), drawBuffers.data());
        // Names the host saw may have been deleted since (bindings can still report them):
        // restore only live objects.
        glUseProgram(program && glIsProgram(GLuint(program)) ? GLuint(program) : 0);
        glBindVertexArray(vao && glIsVertexArray(GLuint(vao)) ? GLuint(vao) : 0);
        glBindBufferBase(GL_UNIFORM_BUFFER, 0, ubo0 && glIsBuffer(GLuint(ubo0)) ? GLuint(ubo0) : 0);
        glViewport(viewport[0], viewport[1], viewport[2], viewport[3]);
        glBlendFuncSeparate(GLenum(blendSrcRgb), GLenum(blendDstRgb), GLenum(blendSrcA), GLenum(blendDstA));
        glBlendEquationSeparate(GLenum(blendEqRgb), GLenum(blendEqA));
        glDepthFunc(GLenum(depthFunc));
        (blend ? glEnable : glDisable)(GL_BLEND);
        (depthTest ? glEnable : glDisable)(GL_DEPTH_TEST);
        (cull ? glEnable : glDisable)(GL_CULL_FACE);
        glDepthMask(depthMask);
    }
};
}  // namespace

void SkyProcessor::composite(unsigned framebuffer, bool depthTest, bool clearedToBlack) {
    // The compositing state is applied before every element, so an element that binds its own
    // framebuffer or changes blending in doRender() cannot break the ones after it.
    auto apply = [&] {
        glBindFramebuffer(GL_FRAMEBUFFER, framebuffer);
        if (framebuffer != 0) glDrawBuffer(GL_COLOR_ATTACHMENT0);  // dual-source: one draw buffer
        glViewport(0, 0, camera_.width, camera_.height);
        cameraUbo_.bindBase(GL_UNIFORM_BUFFER, 0);
        emptyVao_.bind();
        glEnable(GL_BLEND);
        // dst.rgb = src0.rgb + dst.rgb * src1.rgb (radiance plus attenuated background); alpha kept.
        glBlendFuncSeparate(GL_ONE, GL_SRC1_COLOR, GL_ZERO, GL_ONE);
        glBlendEquation(GL_FUNC_ADD);
        if (depthTest) {
            glEnable(GL_DEPTH_TEST);
            glDepthFunc(GL_LEQUAL);
        } else {
            glDisable(GL_DEPTH_TEST);
        }
        glDepthMask(GL_FALSE);
        glDisable(GL_CULL_FACE);
    };
    FrameContext ctx = frameContext();
    // Over the processor's own HDR target (cleared to black) the first element has nothing
    // behind it; over a host's framebuffer there may be anything.
    ctx.nothingBehind = clearedToBlack;
    for (auto& e : elements_) {
        apply();
        e->render(ctx);
        ctx.nothingBehind = false;
    }
    glDisable(GL_BLEND);
    glDisable(GL_DEPTH_TEST);
    glDepthMask(GL_TRUE);
}

void SkyProcessor::renderFrame() {
    auto t0 = std::chrono::steady_clock::now();
    if (options_.timing) glFinish();
    update();
    ensureTargets();
    hdrFbo_.bind();
    const float black[4] = {0, 0, 0, 1};
    glClearBufferfv(GL_COLOR, 0, black);
    composite(hdrFbo_.id(), false, true);
    toneMapInto(ldrFbo_.id());
    if (options_.timing) glFinish();
    frameMs_ = msSince(t0);
    ++frames_;
    gl::checkError("SkyProcessor::renderFrame()");
}

void SkyProcessor::renderInto(const RenderTarget& target) {
    if (target.width != camera_.width || target.height != camera_.height)
        throw Error("SkyProcessor::renderInto(): target " + std::to_string(target.width) + "x" +
                    std::to_string(target.height) + " differs from the camera's " + std::to_string(camera_.width) + "x" +
                    std::to_string(camera_.height));
    auto t0 = std::chrono::steady_clock::now();
    SavedState saved;
    saved.save();
    try {
        update();
        composite(target.framebuffer, target.depthTest, false);
    } catch (...) {
        saved.restore();
        throw;
    }
    saved.restore();
    frameMs_ = msSince(t0);
    ++frames_;
    gl::checkError("SkyProcessor::renderInto()");
}

void SkyProcessor::toneMapInto(unsigned framebuffer) {
    if (!hdr_) throw Error("SkyProcessor::toneMapInto(): no HDR frame yet (call renderFrame() first)");
    auto t0 = std::chrono::steady_clock::now();
    if (options_.timing) glFinish();
    cameraUbo_.bindBase(GL_UNIFORM_BUFFER, 0);
    emptyVao_.bind();
    glDisable(GL_BLEND);
    glDisable(GL_DEPTH_TEST);
    if (exposure_.automatic) {
        logLumFbo_.bind();
        glViewport(0, 0, kLogLumSize, kLogLumSize);
        hdr_.bind(0);
        hdr_.setFilter(GL_LINEAR);
        logLumProgram_.use();
        glDrawArrays(GL_TRIANGLES, 0, 3);
        hdr_.setFilter(GL_NEAREST);
        logLum_.generateMipmaps();
        logLumValid_ = true;
    }
    glBindFramebuffer(GL_FRAMEBUFFER, framebuffer);
    glViewport(0, 0, camera_.width, camera_.height);
    hdr_.bind(0);
    logLum_.bind(1);
    toneMap_.use();
    toneMap_.set("u_ev100", float(exposure_.ev100));
    toneMap_.set("u_auto", exposure_.automatic ? 1 : 0);
    toneMap_.set("u_compensation", float(exposure_.compensationEv));
    toneMap_.set("u_logLumLevel", logLum_.levels() - 1);
    glDrawArrays(GL_TRIANGLES, 0, 3);
    if (options_.timing) glFinish();
    toneMapMs_ = msSince(t0);
    gl::checkError("SkyProcessor::toneMapInto()");
}

double SkyProcessor::lastEv100() const {
    if (!exposure_.automatic || !logLumValid_) return exposure_.ev100;
    std::vector<float> top = logLum_.readRgbaFloat(logLum_.levels() - 1);
    // Same arithmetic as welkin_autoEv100() in tonemap.frag.glsl.
    double logAvg = top[1] > 0 ? top[0] / top[1] : std::log(1e-7);
    double ev = std::clamp(std::log2(std::exp(logAvg) * 100.0 / 12.5), -20.0, 30.0);
    return ev - exposure_.compensationEv;
}

namespace {
Image readTexture(const gl::Texture2D& t) {
    std::vector<float> rgba = t.readRgbaFloat();
    Image img;
    img.width = t.width();
    img.height = t.height();
    img.channels = 3;
    img.pixels.resize(size_t(img.width) * img.height * 3);
    for (int y = 0; y < img.height; ++y) {
        const float* src = &rgba[size_t(img.height - 1 - y) * img.width * 4];  // GL rows are bottom-up
        for (int x = 0; x < img.width; ++x)
            for (int c = 0; c < 3; ++c) img.at(x, y, c) = src[x * 4 + c];
    }
    return img;
}
}  // namespace

Image SkyProcessor::readHdr() const {
    if (!hdr_) throw Error("SkyProcessor::readHdr(): no frame rendered yet");
    return readTexture(hdr_);
}

Image SkyProcessor::readToneMapped() const {
    if (!ldr_) throw Error("SkyProcessor::readToneMapped(): no frame rendered yet");
    return readTexture(ldr_);
}

nlohmann::json SkyProcessor::stats() const {
    using nlohmann::json;
    json j;
    j["time"] = time_.toIso();
    j["observer"] = {{"lat_deg", observer_.latitudeRad * 180 / kPi},
                     {"lon_deg", observer_.longitudeRad * 180 / kPi},
                     {"height_m", observer_.heightMeters}};
    j["camera"] = {{"projection", std::string(toString(camera_.projection))},
                   {"width", camera_.width},
                   {"height", camera_.height},
                   {"az_deg", camera_.azimuthRad * 180 / kPi},
                   {"alt_deg", camera_.altitudeRad * 180 / kPi},
                   {"fov_deg", camera_.verticalFovRad * 180 / kPi}};
    j["exposure"] = {{"automatic", exposure_.automatic}, {"ev100", lastEv100()}};
    if (vars_.has(astro::keys::sunAzimuth))
        for (auto [name, az, alt] : {std::tuple{"sun", &astro::keys::sunAzimuth, &astro::keys::sunAltitude},
                                     std::tuple{"moon", &astro::keys::moonAzimuth, &astro::keys::moonAltitude}})
            j[name] = {{"az_deg", vars_.get(*az) * 180 / kPi}, {"alt_deg", vars_.get(*alt) * 180 / kPi}};
    j["timing_includes_gpu"] = options_.timing;
    json el = json::array();
    for (auto& e : elements_) {
        json gens = json::array();
        for (auto& g : e->generators())
            gens.push_back({{"name", g->name()}, {"runs", g->runCount()}, {"last_ms", g->timing().lastMs}, {"total_ms", g->timing().totalMs}});
        el.push_back({{"name", e->name()},
                      {"init_ms", e->initTiming().lastMs},
                      {"update_ms", e->updateTiming().lastMs},
                      {"render_ms", e->renderTiming().lastMs},
                      {"generators", gens}});
    }
    j["elements"] = el;
    for (auto& e : elements_) e->stats(j);
    j["frame_ms"] = frameMs_;
    j["generators_ms"] = generatorsMs_;
    j["tonemap_ms"] = toneMapMs_;
    j["frames"] = frames_;
    return j;
}

}  // namespace welkin
