// SkyElement: the plugin contract, and Generator: a pass that runs only when its inputs changed.
//
//   class Halo final : public welkin::SkyElement {
//   public:
//       Halo() : SkyElement("halo") { reads(welkin::keys::sunDirection); }
//   private:
//       void doInit(welkin::InitContext& ctx) override { program_ = /* ProgramBuilder ... */; }
//       void doRender(const welkin::FrameContext& ctx) override { program_.use(); ctx.drawFullscreen(); }
//       void doRelease() override { program_ = {}; }
//       welkin::gl::Program program_;
//   };
//
// The public init/update/render/resize/release are non-virtual: they check the element's state,
// time the call (CPU clock; with glFinish when timing is enabled), check GL errors and then call
// the private virtual hooks. A fragment shader of an element writes two outputs (dual-source
// blending, engine/shaders/composite.glsl): emitted or in-scattered radiance in cd/m^2 and a
// per-channel transmittance of what lies behind; the processor composites
// dst = src.rgb + dst.rgb * T in registration order.
#pragma once
#include <welkin/camera.hpp>
#include <welkin/host_depth.hpp>
#include <welkin/log.hpp>
#include <welkin/vars.hpp>

#include <nlohmann/json_fwd.hpp>

#include <memory>
#include <string>
#include <vector>

namespace welkin {

namespace gl {
class VertexArray;
}

/// CPU time of the last calls, milliseconds (with glFinish around each call when the owning
/// processor has timing enabled, so GPU work is included).
struct Timing {
    double lastMs = 0.0;
    double totalMs = 0.0;
    int calls = 0;
    void add(double ms) {
        lastMs = ms;
        totalMs += ms;
        ++calls;
    }
};

/// What init() receives.
struct InitContext {
    SkyVars& vars;
    const Logger& log;
};

/// What update() and render() receive each frame.
struct FrameContext {
    SkyVars& vars;
    const Logger& log;
    const Camera& camera;
    double seconds;                     ///< seconds since the processor was created (animation)
    const gl::VertexArray* emptyVao;    ///< bound VAO with no attributes, for fullscreen passes
    /// True when nothing is behind this element: it is the first one composited over the
    /// processor's own target, cleared to black. Its transmittance output then multiplies black,
    /// so an element may skip computing it (the Sky does: one texture fetch less per pixel).
    bool nothingBehind = false;
    /// The host's depth buffer during render() when the host passed one to renderInto()
    /// (RenderTarget::depth); nullptr otherwise (always in update(), and in renderFrame(), which
    /// draws into the processor's own target). An element may sample it (it is a depth texture:
    /// bind it to a unit of its own, read window depth, 1 = nothing drawn) to know the distance to
    /// the host's geometry, e.g. to attenuate its light by the air in front of it; it must not
    /// write to it or keep the pointer past render().
    const HostDepth* depth = nullptr;
    /// Draws the fullscreen triangle (3 vertices, engine/shaders/fullscreen.vert.glsl).
    void drawFullscreen() const;
};

class Generator {
public:
    virtual ~Generator() = default;
    Generator(const Generator&) = delete;
    Generator& operator=(const Generator&) = delete;

    const std::string& name() const { return name_; }
    const std::vector<KeyInfo>& inputs() const { return inputs_; }
    const std::vector<KeyInfo>& outputs() const { return outputs_; }

    /// True if it never ran or an input's version changed since its last run.
    bool isDue(const SkyVars& vars) const;
    /// Runs if due; returns whether it ran.
    bool runIfDue(SkyVars& vars, const Logger& log, bool finish = false);
    /// Runs unconditionally and records the input versions.
    void run(SkyVars& vars, const Logger& log, bool finish = false);
    int runCount() const { return timing_.calls; }
    const Timing& timing() const { return timing_; }

protected:
    explicit Generator(std::string name) : name_(std::move(name)) {}
    template <class T>
    void input(const Key<T>& key) { inputs_.push_back(key.info()); }
    template <class T>
    void output(const Key<T>& key) { outputs_.push_back(key.info()); }

private:
    virtual void doRun(SkyVars& vars, const Logger& log) = 0;
    std::string name_;
    std::vector<KeyInfo> inputs_, outputs_;
    std::vector<uint64_t> seen_;
    Timing timing_;
};

class SkyElement {
public:
    virtual ~SkyElement() = default;
    SkyElement(const SkyElement&) = delete;
    SkyElement& operator=(const SkyElement&) = delete;

    const std::string& name() const { return name_; }
    bool initialized() const { return initialized_; }

    /// Declares keys, creates GL resources. Needs a current context. Throws if already initialised.
    void init(InitContext& ctx);
    /// Per-frame update (the processor has already run the generators that are due).
    void update(const FrameContext& ctx);
    /// Draws the element into the bound HDR target (blend state set by the processor).
    void render(const FrameContext& ctx);
    /// The output size changed (pixels, >= 1).
    void resize(int width, int height);
    /// Frees GL resources; the element can be initialised again.
    void release();

    const std::vector<KeyInfo>& readKeys() const { return reads_; }
    const std::vector<KeyInfo>& writeKeys() const { return writes_; }
    const std::vector<std::shared_ptr<Generator>>& generators() const { return generators_; }

    /// Adds the element's physical quantities to the --stats JSON (e.g. root["sky"][...]).
    void stats(nlohmann::json& root) const { doStats(root); }

    /// When enabled, each call is bracketed by glFinish so timings include GPU work.
    void setTimingEnabled(bool enabled) { timingEnabled_ = enabled; }
    const Timing& initTiming() const { return initTiming_; }
    const Timing& updateTiming() const { return updateTiming_; }
    const Timing& renderTiming() const { return renderTiming_; }

protected:
    explicit SkyElement(std::string name) : name_(std::move(name)) {}
    template <class T>
    void reads(const Key<T>& key) { reads_.push_back(key.info()); }
    template <class T>
    void writes(const Key<T>& key) { writes_.push_back(key.info()); }
    /// Adds a generator this element depends on (shared instances are run once per frame).
    void addGenerator(std::shared_ptr<Generator> g);

private:
    virtual void doInit(InitContext& ctx) = 0;
    virtual void doUpdate(const FrameContext&) {}
    virtual void doRender(const FrameContext& ctx) = 0;
    virtual void doResize(int, int) {}
    virtual void doRelease() = 0;
    virtual void doStats(nlohmann::json&) const {}

    void requireInitialized(const char* what) const;

    std::string name_;
    std::vector<KeyInfo> reads_, writes_;
    std::vector<std::shared_ptr<Generator>> generators_;
    bool initialized_ = false;
    bool timingEnabled_ = false;
    Timing initTiming_, updateTiming_, renderTiming_;
};

}  // namespace welkin
