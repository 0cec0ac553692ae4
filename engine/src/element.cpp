#include <welkin/element.hpp>
#include <welkin/error.hpp>
#include <welkin/gl/objects.hpp>

#include <epoxy/gl.h>

#include <chrono>
#include <cmath>

namespace welkin {

namespace {
class Stopwatch {
public:
    explicit Stopwatch(bool finish) : finish_(finish) {
        if (finish_) glFinish();
        start_ = std::chrono::steady_clock::now();
    }
    double ms() const {
        if (finish_) glFinish();
        return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start_).count();
    }

private:
    bool finish_;
    std::chrono::steady_clock::time_point start_;
};
}  // namespace

void FrameContext::drawFullscreen() const {
    if (emptyVao) emptyVao->bind();
    glDrawArrays(GL_TRIANGLES, 0, 3);
}

// --- Generator ---------------------------------------------------------------------------------

uint64_t Generator::inputVersion(const SkyVars& vars, size_t i) const {
    if (slotsOf_ != vars.identity() || slots_.size() != inputs_.size()) {
        slots_.assign(inputs_.size(), nullptr);
        slotsOf_ = vars.identity();
    }
    if (!slots_[i]) slots_[i] = vars.versionSlot(inputs_[i].name);  // declared since: found now
    return slots_[i] ? *slots_[i] : 0;
}

bool Generator::isDue(const SkyVars& vars) const {
    if (invalidated_ || timing_.calls == 0 || seen_.size() != inputs_.size()) return true;
    for (size_t i = 0; i < inputs_.size(); ++i) {
        if (inputVersion(vars, i) == seen_[i]) continue;
        const double tol = inputOptions_[i].tolerance;
        if (tol <= 0.0) return true;
        std::vector<double> now = vars.numeric(inputs_[i].name);
        const std::vector<double>& then = seenValues_[i];
        if (now.size() != then.size()) return true;
        for (size_t k = 0; k < now.size(); ++k)
            if (!(std::abs(now[k] - then[k]) <= tol)) return true;
    }
    return false;
}

bool Generator::runIfDue(SkyVars& vars, const Logger& log, bool finish) {
    if (!isDue(vars)) return false;
    run(vars, log, finish);
    return true;
}

void Generator::run(SkyVars& vars, const Logger& log, bool finish) {
    Stopwatch sw(finish);
    again_ = false;
    doRun(vars, log);  // GL errors are checked by the caller (SkyProcessor), so CPU-only
                       // generators run without a context
    timing_.add(sw.ms());
    invalidated_ = again_;
    // Record the versions after running: a generator may itself update one of its inputs.
    seen_.resize(inputs_.size());
    seenValues_.resize(inputs_.size());
    for (size_t i = 0; i < inputs_.size(); ++i) {
        seen_[i] = inputVersion(vars, i);
        if (inputOptions_[i].tolerance > 0.0) seenValues_[i] = vars.numeric(inputs_[i].name);
    }
}

const char* toString(Layer layer) {
    switch (layer) {
        case Layer::Background: return "background";
        case Layer::Bodies: return "bodies";
        case Layer::Atmosphere: return "atmosphere";
        case Layer::Clouds: return "clouds";
        case Layer::Foreground: return "foreground";
        case Layer::Overlay: return "overlay";
    }
    return "?";
}

// --- SkyElement --------------------------------------------------------------------------------

void SkyElement::addGenerator(std::shared_ptr<Generator> g) {
    if (!g) throw Error(name_ + "::addGenerator(): null generator");
    for (auto& existing : generators_)
        if (existing == g) return;
    generators_.push_back(std::move(g));
}

void SkyElement::requireInitialized(const char* what) const {
    if (!initialized_) throw Error(name_ + "::" + what + "(): element not initialised (call init() first)");
}

void SkyElement::init(InitContext& ctx) {
    if (initialized_) throw Error(name_ + "::init(): already initialised");
    Stopwatch sw(timingEnabled_);
    doInit(ctx);
    if (validationEnabled_) gl::checkError(name_ + "::init()");
    initTiming_.add(sw.ms());
    initialized_ = true;
}

void SkyElement::update(const FrameContext& ctx) {
    requireInitialized("update");
    Stopwatch sw(timingEnabled_);
    doUpdate(ctx);
    if (validationEnabled_) gl::checkError(name_ + "::update()");
    updateTiming_.add(sw.ms());
}

void SkyElement::render(const FrameContext& ctx) {
    requireInitialized("render");
    Stopwatch sw(timingEnabled_);
    drewNothing_ = false;
    doRender(ctx);
    if (validationEnabled_) gl::checkError(name_ + "::render()");
    renderTiming_.add(sw.ms());
}

const char* toString(ScenePass pass) { return pass == ScenePass::Surfaces ? "surfaces" : "air"; }

void SkyElement::applyToScene(const FrameContext& ctx, ScenePass pass) {
    requireInitialized("applyToScene");
    if (!ctx.depth) throw Error(name_ + "::applyToScene(): FrameContext::depth is not set (the host's depth is required)");
    Stopwatch sw(timingEnabled_);
    doApplyToScene(ctx, pass);
    if (validationEnabled_) gl::checkError(name_ + "::applyToScene(" + toString(pass) + ")");
    sceneTiming_.add(sw.ms());
}

void SkyElement::resize(int width, int height) {
    if (width < 1 || height < 1)
        throw Error(name_ + "::resize(): " + std::to_string(width) + "x" + std::to_string(height) + " must be at least 1x1");
    if (!initialized_) return;
    doResize(width, height);
    if (validationEnabled_) gl::checkError(name_ + "::resize()");
}

void SkyElement::release() {
    if (!initialized_) return;
    doRelease();
    initialized_ = false;
}

}  // namespace welkin
