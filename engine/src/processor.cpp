#include "generator_graph.hpp"
#include "gl/state_guard.hpp"
#include "lighting_engine.hpp"
#include "tone_mapper.hpp"

#include <welkin/astro/astro_keys.hpp>
#include <welkin/check.hpp>
#include <welkin/gl/bindings.hpp>
#include <welkin/error.hpp>
#include <welkin/eye.hpp>
#include <welkin/keys.hpp>
#include <welkin/point_source.hpp>
#include <welkin/processor.hpp>

#include <epoxy/gl.h>

#include <cmath>
#include <algorithm>
#include <numbers>
#include <tuple>
#include <optional>

namespace welkin {

namespace {
constexpr double kPi = std::numbers::pi;

double msSince(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

// The driver's KHR_debug messages (core in GL 4.3) during a call in validation mode, to the log;
// the host's own callback is saved and restored by HostStateScope.
void GLAPIENTRY debugToLog(GLenum, GLenum type, GLuint, GLenum severity, GLsizei, const GLchar* message, const void* user) {
    if (severity == GL_DEBUG_SEVERITY_NOTIFICATION) return;
    const Logger& log = *static_cast<const Logger*>(user);
    const std::string m = std::string("GL debug: ") + message;
    if (type == GL_DEBUG_TYPE_ERROR) log.error(m);
    else log.warn(m);
}

// The host's GL state is saved by the outermost public call that issues GL commands
// (renderInto() calls update(), ...) and restored when it returns or throws. On entry it drains
// the GL errors the host left pending (reported as the host's, in the log: they are not welkin's);
// in validation mode it routes KHR_debug messages to the log until it returns.
class HostStateScope {
public:
    HostStateScope(int& depth, const Logger& log, bool validation, const char* where, std::vector<unsigned> framebuffers = {})
        : depth_(depth) {
        if (depth_++ != 0) return;
        // At most a few errors are recorded at once (one flag per kind); bounded against a
        // driver that never returns GL_NO_ERROR without a context.
        std::string pending;
        for (int i = 0; i < 16; ++i) {
            const GLenum e = glGetError();
            if (e == GL_NO_ERROR) break;
            pending += (pending.empty() ? "" : ", ") + std::string(gl::errorName(e));
        }
        if (!pending.empty())
            log.warn(std::string(where) + ": the host left GL error(s) pending before calling welkin: " + pending +
                     " (not welkin's; cleared)");
        guard_.emplace(std::move(framebuffers));
        if (validation) {
            debugWasOn_ = glIsEnabled(GL_DEBUG_OUTPUT);
            syncWasOn_ = glIsEnabled(GL_DEBUG_OUTPUT_SYNCHRONOUS);
            glGetPointerv(GL_DEBUG_CALLBACK_FUNCTION, &hostCallback_);
            glGetPointerv(GL_DEBUG_CALLBACK_USER_PARAM, &hostUser_);
            glEnable(GL_DEBUG_OUTPUT);
            glEnable(GL_DEBUG_OUTPUT_SYNCHRONOUS);  // the message arrives inside the call that caused it
            glDebugMessageCallback(debugToLog, &log);
            debug_ = true;
        }
    }
    ~HostStateScope() {
        if (debug_) {
            glDebugMessageCallback(reinterpret_cast<GLDEBUGPROC>(hostCallback_), hostUser_);
            if (!debugWasOn_) glDisable(GL_DEBUG_OUTPUT);
            if (!syncWasOn_) glDisable(GL_DEBUG_OUTPUT_SYNCHRONOUS);
        }
        guard_.reset();
        --depth_;
    }
    HostStateScope(const HostStateScope&) = delete;
    HostStateScope& operator=(const HostStateScope&) = delete;
    /// True for the outermost scope (the one that checks welkin's own errors once on return).
    bool outermost() const { return guard_.has_value(); }

private:
    int& depth_;
    std::optional<gl::GlStateGuard> guard_;
    bool debug_ = false, debugWasOn_ = false, syncWasOn_ = false;
    void* hostCallback_ = nullptr;
    void* hostUser_ = nullptr;
};
}  // namespace

void Observer::validate() const {
    const Shown deg{180 / kPi, " deg"};
    checkRange("Observer", "latitude", latitudeRad, -kPi / 2, kPi / 2, deg);
    checkRange("Observer", "longitude", longitudeRad, -kPi, kPi, deg);
    checkRange("Observer", "height", heightMeters, -1e4, 1e9, {1, " m"});
}

SkyProcessor::SkyProcessor(SkyVars vars, Logger log, ProcessorOptions options)
    : ownVars_(std::move(vars)), log_(std::move(log)), options_(options), graph_(std::make_unique<GeneratorGraph>()),
      toneMapper_(std::make_unique<ToneMapper>()) {
    deriveVariables();
    declareToneMapKeys();
    declareLightingKeys();
    if (options_.astronomy) addGenerator(std::make_shared<astro::AstronomyGenerator>());
}

SkyProcessor::SkyProcessor(BorrowedVars vars, Logger log, ProcessorOptions options)
    : vars_(&vars.vars), log_(std::move(log)), options_(options), graph_(std::make_unique<GeneratorGraph>()),
      toneMapper_(std::make_unique<ToneMapper>()) {
    deriveVariables();
    declareToneMapKeys();
    declareLightingKeys();
    if (options_.astronomy) addGenerator(std::make_shared<astro::AstronomyGenerator>());
}

std::unique_ptr<SkyElement> SkyProcessor::remove(std::string_view name) {
    for (auto it = elements_.begin(); it != elements_.end(); ++it)
        if ((*it)->name() == name) {
            std::unique_ptr<SkyElement> e = std::move(*it);
            elements_.erase(it);
            graph_->forgetOrder();
            return e;
        }
    return nullptr;
}

void SkyProcessor::addGenerator(std::shared_ptr<Generator> g) { graph_->add(std::move(g), *vars_); }

const std::vector<Generator*>& SkyProcessor::generatorOrder() const { return graph_->ordered(); }

SkyProcessor::~SkyProcessor() { release(); }

void SkyProcessor::declareToneMapKeys() {
    SkyVars::DeclarerScope scope(*vars_, "tone map");
    eye::declareKeys(*vars_);
    declarePointSourceKeys(*vars_);
}

void SkyProcessor::release() {
    for (auto& e : elements_) e->release();
    graph_->release();  // the generators' GL resources (LUTs): made again by init() and the next frame
    hdr_ = {};
    ldr_ = {};
    hdrFbo_ = {};
    ldrFbo_ = {};
    toneMapper_->release();
    releaseLighting();
    emptyVao_ = {};
    cameraUbo_ = {};
    glReady_ = false;
}

SkyElement& SkyProcessor::add(std::unique_ptr<SkyElement> element) {
    if (!element) throw Error("SkyProcessor::add(): null element");
    if (find(element->name())) throw Error("SkyProcessor::add(): an element named '" + element->name() + "' is already registered");
    element->setTimingEnabled(options_.timing);
    element->setValidationEnabled(options_.validation);
    {
        SkyVars::DeclarerScope scope(*vars_, element->name());
        element->declareOptions(*vars_);
    }
    elements_.push_back(std::move(element));
    graph_->invalidate();
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
        toneMapper_->invalidateMeter();
        for (auto& e : elements_) e->resize(c.width, c.height);
    }
}
void SkyProcessor::setExposure(const Exposure& e) {
    checkRange("SkyProcessor::setExposure()", "ev100", e.ev100, -20, 30);
    checkRange("SkyProcessor::setExposure()", "compensationEv", e.compensationEv, -10, 10);
    exposure_ = e;
    vars_->set(keys::exposureEv100, e.ev100);
    vars_->set(keys::exposureAuto, e.automatic);
    vars_->set(eye::keys::compensation, e.compensationEv);
}

void SkyProcessor::resetAdaptation() {
    toneMapper_->resetAdaptation();
    lastFrameSeconds_.reset();
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
    if (!options_.timeAndPlace) return;
    const JulianDate jd = time_.julianDate();
    vars_->set(keys::timeJdUtc, glm::dvec2(jd.day, jd.fraction));
    vars_->set(keys::timeIso, time_.toIso());
    vars_->set(keys::observerLatitude, observer_.latitudeRad);
    vars_->set(keys::observerLongitude, observer_.longitudeRad);
    vars_->set(keys::observerHeight, observer_.heightMeters);
}

namespace {
// What sets a derived key, for setOption()'s message ("" if the processor does not derive it).
std::string derivedFrom(std::string_view name) {
    if (name == keys::timeJdUtc.name() || name == keys::timeIso.name()) return "SkyProcessor::setTime() (welkin: --time)";
    if (name == keys::observerLatitude.name()) return "SkyProcessor::setObserver() (welkin: --lat)";
    if (name == keys::observerLongitude.name()) return "SkyProcessor::setObserver() (welkin: --lon)";
    if (name == keys::observerHeight.name()) return "SkyProcessor::setObserver() (welkin: --height)";
    return "";
}
}  // namespace

void SkyProcessor::setOption(std::string_view name, std::string_view text) {
    if (options_.timeAndPlace) {
        const std::string from = derivedFrom(name);
        if (!from.empty()) throw Error(std::string(name) + " is derived from " + from + ", not an input");
    }
    graph_->checkNotAnOutput(name, elements_);
    vars_->setFromString(name, text);
    if (std::find(optionsSet_.begin(), optionsSet_.end(), name) == optionsSet_.end()) optionsSet_.emplace_back(name);
}

void SkyProcessor::init() {
    HostStateScope host(hostGuardDepth_, log_, options_.validation, "SkyProcessor::init()");
    if (!glReady_) {
        emptyVao_ = gl::VertexArray::create();
        cameraUbo_ = gl::Buffer(sizeof(CameraBlock));
        toneMapper_->init();
        glReady_ = true;
    }
    InitContext ctx{*vars_, log_};
    for (auto& e : elements_) {
        if (!e->initialized()) {
            SkyVars::DeclarerScope scope(*vars_, e->name());
            e->declareOptions(*vars_);
            e->init(ctx);
            e->resize(camera_.width, camera_.height);
            graph_->invalidate();
        }
    }
    if (!graph_->valid()) graph_->order(*vars_, elements_, optionsSet_);
    if (host.outermost() || options_.validation) gl::checkError("SkyProcessor::init()");
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

FrameContext SkyProcessor::frameContext() { return FrameContext{*vars_, log_, camera_, seconds(), &emptyVao_}; }

void SkyProcessor::runGenerators() {
    // Each generator once per frame, in dependency order (GeneratorGraph::order()).
    if (!graph_->valid()) graph_->order(*vars_, elements_, optionsSet_);
    auto t0 = std::chrono::steady_clock::now();
    if (!generatorsPaused_) graph_->run(*vars_, log_, options_.timing, options_.validation);
    generatorsMs_ = msSince(t0);
}

void SkyProcessor::uploadCamera(const HostDepth* depth) {
    CameraBlock block = makeCameraBlock(camera_, seconds(), depth ? *depth : HostDepth{});
    cameraUbo_.update(&block, sizeof block);
}

void SkyProcessor::publishPreviousExposure() {
    // keys::exposurePrevious: the exposure the previous frame was shown with, for elements that
    // skip what cannot show (docs/eye.md). Manual: this frame's own. Automatic: the eye's state
    // of the frame before, only while frames follow each other (0 < dt <= 1 s: the state then
    // moves by 1 - exp(-dt / eye.cone_time_s) of its log distance to the new frame's target, 22 %
    // at 0.1 s and the default 0.4 s), else 0 (unknown).
    // Only for displayed frames (render.interactive: welkin view, a game loop): an offline frame's
    // HDR image (an EXR, readHdr()) keeps every term.
    constexpr double kMaxDt = 1.0;
    double e = 0.0;
    if (!vars_->getOr(keys::interactive, false)) {
        e = 0.0;
    } else if (!vars_->getOr(keys::exposureAuto, false)) {
        e = eye::exposureFromEv100(vars_->getOr(keys::exposureEv100, 15.0));
    } else if (lastFrameSeconds_) {
        const double dt = seconds() - *lastFrameSeconds_;
        const std::optional<double> previous = toneMapper_->previousExposure();
        if (dt > 0.0 && dt <= kMaxDt && previous && std::isfinite(*previous) && *previous > 0.0) e = *previous;
    }
    vars_->set(keys::exposurePrevious, e);
}

void SkyProcessor::update() { update(nullptr); }

void SkyProcessor::update(const HostDepth* depth) {
    HostStateScope host(hostGuardDepth_, log_, options_.validation, "SkyProcessor::update()");
    init();
    deriveVariables();
    publishPreviousExposure();
    uploadCamera(depth);
    runGenerators();
    FrameContext ctx = frameContext();
    for (auto& e : elements_) e->update(ctx);
    updateLighting();
    if (host.outermost()) gl::checkError("SkyProcessor::update()");
}

void SkyProcessor::applyCompositeState(unsigned framebuffer, bool depthTest) { applyCompositeState(framebuffer, depthTest, camera_, cameraUbo_); }

void SkyProcessor::applyCompositeState(unsigned framebuffer, bool depthTest, const Camera& camera, const gl::Buffer& ubo) {
    glBindFramebuffer(GL_FRAMEBUFFER, framebuffer);
    if (framebuffer != 0) glDrawBuffer(GL_COLOR_ATTACHMENT0);  // dual-source: one draw buffer
    glViewport(0, 0, camera.width, camera.height);
    ubo.bindBase(GL_UNIFORM_BUFFER, gl::binding::kCameraUbo);
    emptyVao_.bind();
    glEnable(GL_BLEND);
    // dst.rgb = src0.rgb + dst.rgb * src1.rgb (radiance plus attenuated background); alpha kept.
    glBlendFuncSeparate(GL_ONE, GL_SRC1_COLOR, GL_ZERO, GL_ONE);
    glBlendEquation(GL_FUNC_ADD);
    if (depthTest) {
        // The sky is at NDC z = 1 (z = w); the depth range puts that at window depth 1, or at 0
        // for a reversed-Z host (glDepthRange(1, 0)), whatever the host's glClipControl depth
        // mode (NDC 1 is the far end of both). The guard restores the host's range.
        glEnable(GL_DEPTH_TEST);
        if (camera.depth.reversedZ) {
            glDepthRange(1.0, 0.0);
            glDepthFunc(GL_GEQUAL);
        } else {
            glDepthRange(0.0, 1.0);
            glDepthFunc(GL_LEQUAL);
        }
    } else {
        glDisable(GL_DEPTH_TEST);
    }
    glDepthMask(GL_FALSE);
    glDisable(GL_CULL_FACE);
    glColorMaski(0, GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
}

void SkyProcessor::composite(unsigned framebuffer, bool depthTest, bool clearedToBlack, const HostDepth* depth) {
    // The compositing state is applied before every element, so an element that binds its own
    // framebuffer or changes blending in doRender() cannot break the ones after it.
    auto apply = [&] { applyCompositeState(framebuffer, depthTest); };
    FrameContext ctx = frameContext();
    // Over the processor's own HDR target (cleared to black) the first element has nothing
    // behind it; over a host's framebuffer there may be anything.
    ctx.nothingBehind = clearedToBlack;
    ctx.depth = depth;
    for (size_t i = 0; i < elements_.size(); ++i) {
        ctx.attenuatedLater = false;
        for (size_t j = i + 1; j < elements_.size(); ++j) ctx.attenuatedLater = ctx.attenuatedLater || elements_[j]->attenuatesBehind();
        apply();
        elements_[i]->render(ctx);
        // An element that drew nothing (SkyElement::reportNothingDrawn(): the night sky by day,
        // no star or planet) leaves the black target as it was for the next one.
        if (!elements_[i]->drewNothing()) ctx.nothingBehind = false;
    }
    glDisable(GL_BLEND);
    glDisable(GL_DEPTH_TEST);
    glDepthMask(GL_TRUE);
}

void SkyProcessor::renderFrame() {
    HostStateScope host(hostGuardDepth_, log_, options_.validation, "SkyProcessor::renderFrame()");
    auto t0 = std::chrono::steady_clock::now();
    if (options_.timing) glFinish();
    update();
    ensureTargets();
    hdrFbo_.bind();
    const float black[4] = {0, 0, 0, 1};
    glClearBufferfv(GL_COLOR, 0, black);
    composite(hdrFbo_.id(), false, true, nullptr);
    // The eye's meter and adaptation step now; the display pass into the LDR target waits for
    // readToneMapped(): a viewer that tone-maps into its window (toneMapInto) pays it once.
    toneMap(0, true, 0, false);
    ldrPending_ = true;
    if (options_.timing) glFinish();
    frameMs_ = msSince(t0);
    ++frames_;
    if (host.outermost()) gl::checkError("SkyProcessor::renderFrame()");
}

void SkyProcessor::checkDepthTexture(const HostDepth& depth) const {
    const char* where = "SkyProcessor::renderInto()";
    if (!glIsTexture(depth.depthTexture))
        throw Error(std::string(where) + ": HostDepth depthTexture " + std::to_string(depth.depthTexture) + " is not a texture");
    GLint w = 0, h = 0;
    glGetTextureLevelParameteriv(depth.depthTexture, 0, GL_TEXTURE_WIDTH, &w);
    glGetTextureLevelParameteriv(depth.depthTexture, 0, GL_TEXTURE_HEIGHT, &h);
    if (w != camera_.width || h != camera_.height)
        throw Error(std::string(where) + ": HostDepth texture " + std::to_string(w) + "x" + std::to_string(h) +
                    " differs from the camera's " + std::to_string(camera_.width) + "x" + std::to_string(camera_.height));
}

void SkyProcessor::renderInto(const RenderTarget& target) {
    if (target.width != camera_.width || target.height != camera_.height)
        throw Error("SkyProcessor::renderInto(): target " + std::to_string(target.width) + "x" +
                    std::to_string(target.height) + " differs from the camera's " + std::to_string(camera_.width) + "x" +
                    std::to_string(camera_.height));
    if (target.depth) {
        target.depth->validate("SkyProcessor::renderInto()");
        checkDepthTexture(*target.depth);
    }
    auto t0 = std::chrono::steady_clock::now();
    {
        HostStateScope host(hostGuardDepth_, log_, options_.validation, "SkyProcessor::renderInto()", {target.framebuffer});
        update(target.depth ? &*target.depth : nullptr);
        composite(target.framebuffer, target.depthTest, false, target.depth ? &*target.depth : nullptr);
        if (host.outermost()) gl::checkError("SkyProcessor::renderInto()");
    }
    frameMs_ = msSince(t0);
    ++frames_;
}

void SkyProcessor::applyToScene(const RenderTarget& target, ScenePasses passes) {
    const char* where = "SkyProcessor::applyToScene()";
    if (!target.depth) throw Error(std::string(where) + ": RenderTarget::depth is required (the host's depth texture)");
    if (target.width != camera_.width || target.height != camera_.height)
        throw Error(std::string(where) + ": target " + std::to_string(target.width) + "x" + std::to_string(target.height) +
                    " differs from the camera's " + std::to_string(camera_.width) + "x" + std::to_string(camera_.height));
    target.depth->validate(where);
    if (!glReady_) throw Error(std::string(where) + ": no frame yet (call renderInto() first in the same frame)");
    auto t0 = std::chrono::steady_clock::now();
    {
        HostStateScope host(hostGuardDepth_, log_, options_.validation, where, {target.framebuffer});
        checkDepthTexture(*target.depth);
        // Elements build what a host scene needs (the Sky's aerial-perspective volume) only once
        // a host asks: from this call on (the generators that now have work run at once).
        if (!vars_->getOr(keys::hostScene, false)) {
            vars_->set(keys::hostScene, true);
            runGenerators();
        }
        uploadCamera(&*target.depth);
        FrameContext ctx = frameContext();
        ctx.depth = &*target.depth;
        for (ScenePass pass : {ScenePass::Surfaces, ScenePass::Air}) {
            if (pass == ScenePass::Surfaces ? !passes.surfaces : !passes.air) continue;
            for (auto& e : elements_) {
                applyCompositeState(target.framebuffer, false);
                e->applyToScene(ctx, pass);
            }
        }
        if (host.outermost()) gl::checkError(where);
    }
    sceneMs_ = msSince(t0);
}

void SkyProcessor::toneMapInto(unsigned framebuffer) {
    if (!hdr_) throw Error("SkyProcessor::toneMapInto(): no HDR frame yet (call renderFrame() first)");
    toneMap(framebuffer, false, 0);
}

void SkyProcessor::toneMapInto(unsigned framebuffer, unsigned hostHdrTexture) {
    const char* where = "SkyProcessor::toneMapInto()";
    if (hostHdrTexture == 0 || !glIsTexture(hostHdrTexture))
        throw Error(std::string(where) + ": hostHdrTexture " + std::to_string(hostHdrTexture) + " is not a texture");
    GLint w = 0, h = 0, target = 0;
    glGetTextureParameteriv(hostHdrTexture, GL_TEXTURE_TARGET, &target);
    if (target != GL_TEXTURE_2D) throw Error(std::string(where) + ": hostHdrTexture is not a GL_TEXTURE_2D");
    glGetTextureLevelParameteriv(hostHdrTexture, 0, GL_TEXTURE_WIDTH, &w);
    glGetTextureLevelParameteriv(hostHdrTexture, 0, GL_TEXTURE_HEIGHT, &h);
    if (w != camera_.width || h != camera_.height)
        throw Error(std::string(where) + ": hostHdrTexture " + std::to_string(w) + "x" + std::to_string(h) +
                    " differs from the camera's " + std::to_string(camera_.width) + "x" + std::to_string(camera_.height));
    if (!glReady_) init();
    toneMap(framebuffer, true, hostHdrTexture);
}

void SkyProcessor::toneMap(unsigned framebuffer, bool newFrame, unsigned hdrTexture, bool draw) {
    // The exposure.* and eye.* keys are the settings (setExposure() writes them; --var too).
    const ToneSettings settings = ToneSettings::fromVars(*vars_);
    exposure_ = {settings.automatic, settings.ev100, settings.compensationEv};
    // A new frame advances the eye's adaptation by the animation time since the last one; the
    // same instant again (a still render) is the steady state; a second tone map of a frame keeps it.
    std::optional<double> dt;
    if (newFrame) {
        const double now = seconds();
        dt = lastFrameSeconds_ ? now - *lastFrameSeconds_ : 0.0;
        lastFrameSeconds_ = now;
    }
    auto t0 = std::chrono::steady_clock::now();
    if (options_.timing) glFinish();
    {
        HostStateScope host(hostGuardDepth_, log_, options_.validation, "SkyProcessor::toneMapInto()", {framebuffer});
        GLint format = GL_RGBA32F;
        if (hdrTexture) glGetTextureLevelParameteriv(hdrTexture, 0, GL_TEXTURE_INTERNAL_FORMAT, &format);
        const HdrSource source = hdrTexture ? HdrSource{hdrTexture, camera_.width, camera_.height, format == GL_RGBA32F}
                                            : HdrSource{hdr_.id(), hdr_.width(), hdr_.height(), true};
        if (draw) toneMapper_->run(source, framebuffer, settings, cameraUbo_, emptyVao_, dt);
        else toneMapper_->advance(source, settings, cameraUbo_, emptyVao_, dt);
        if (host.outermost()) gl::checkError("SkyProcessor::toneMapInto()");
    }
    if (options_.timing) glFinish();
    toneMapMs_ = msSince(t0);
}

double SkyProcessor::lastEv100() const { return exposure_.automatic ? toneMapper_->lastEv100() : exposure_.ev100; }

glm::dvec2 SkyProcessor::adaptationLuminance() const {
    const eye::Adaptation& a = toneMapper_->adaptation();
    return {a.cone, a.rod};
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
    if (ldrPending_) {
        // The last renderFrame()'s display pass, drawn now with the settings and the eye's state
        // of that frame: the image renderFrame() used to draw at once. The LDR target is a cache
        // of the frame, so filling it is logically const.
        HostStateScope host(hostGuardDepth_, log_, options_.validation, "SkyProcessor::readToneMapped()");
        toneMapper_->display(HdrSource{hdr_.id(), hdr_.width(), hdr_.height(), true}, ldrFbo_.id(), toneMapper_->lastSettings(),
                             cameraUbo_, emptyVao_);
        if (host.outermost()) gl::checkError("SkyProcessor::readToneMapped()");
        ldrPending_ = false;
    }
    return readTexture(ldr_);
}

}  // namespace welkin
