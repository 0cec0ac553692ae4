// SkyElement: the plugin contract, and Generator: a pass that runs only when its inputs changed.
//
//   class Halo final : public welkin::SkyElement {
//   public:
//       Halo() : SkyElement("halo") { reads(welkin::keys::sunDirection); }
//   private:
//       void doInit(welkin::InitContext& ctx) override {
//           tableUnit_ = textureUnit("HALO_TABLE");  // a private unit: WELKIN_BINDING_HALO_TABLE
//           program_ = /* ProgramBuilder(...).bindings(bindings()) ... */;
//       }
//       void doRender(const welkin::FrameContext& ctx) override {
//           program_.use(); glBindTextureUnit(tableUnit_, table_.id()); ctx.drawFullscreen();
//       }
//       void doRelease() override { program_ = {}; }
//       welkin::gl::Program program_;
//       welkin::gl::Texture2D table_;
//       int tableUnit_ = 0;
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
#include <welkin/gl/private_bindings.hpp>
#include <welkin/host_depth.hpp>
#include <welkin/log.hpp>
#include <welkin/vars.hpp>

#include <nlohmann/json_fwd.hpp>

#include <functional>
#include <memory>
#include <string>
#include <string_view>
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
    /// True when an element composited after this one attenuates what is behind it (declared
    /// with SkyElement::attenuatesBehind(), e.g. the Sky): light drawn now will be reddened and
    /// dimmed by it, so this element must not apply the atmosphere's extinction itself.
    bool attenuatedLater = false;
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

/// The passes of SkyProcessor::applyToScene() over the host's own scene (its colour and depth), in
/// this order: first what changes the light on the host's surfaces (the clouds' shadows), then
/// what the air in front of them does (aerial perspective). An element that takes part overrides
/// SkyElement::doApplyToScene(); FrameContext::depth is then always set.
enum class ScenePass {
    Surfaces,  ///< light on the host's surfaces (cloud shadows): dst = dst * T
    Air,       ///< the air between the eye and the surfaces: dst = inscatter + dst * T
};
const char* toString(ScenePass pass);
/// Which passes SkyProcessor::applyToScene() runs: a host that shades the clouds' shadows in its
/// own shaders (welkin_cloudShadow) asks for the air only, so the shadows are not applied twice.
struct ScenePasses {
    bool surfaces = true;  ///< ScenePass::Surfaces (the clouds' shadows)
    bool air = true;       ///< ScenePass::Air (the aerial perspective)
};

/// How a generator depends on one of its inputs.
struct InputOptions {
    /// A change smaller than this (largest absolute difference of any component since the
    /// generator's last run) does not make the generator due: the tables are kept while the Sun
    /// creeps. 0 = any change. Numeric keys only.
    double tolerance = 0.0;
    /// The generator copes with the key being undeclared (reads it with getOr); otherwise a read
    /// of a key that nobody declares and no generator writes is an error at init.
    bool optional = false;
};

/// A pass that runs only when one of its declared inputs changed. The processor orders all
/// generators by their inputs and outputs (a generator that reads another's output runs after
/// it), whatever the order of the elements that use them.
class Generator {
public:
    virtual ~Generator() = default;
    Generator(const Generator&) = delete;
    Generator& operator=(const Generator&) = delete;

    const std::string& name() const { return name_; }
    const std::vector<KeyInfo>& inputs() const { return inputs_; }
    /// Options of inputs()[i].
    const InputOptions& inputOptions(size_t i) const { return inputOptions_.at(i); }
    const std::vector<KeyInfo>& outputs() const { return outputs_; }

    /// True if it never ran, was invalidated, or an input changed (beyond its tolerance) since its
    /// last run.
    bool isDue(const SkyVars& vars) const;
    /// Runs if due; returns whether it ran.
    bool runIfDue(SkyVars& vars, const Logger& log, bool finish = false);
    /// Runs unconditionally and records the input versions (and values, for tolerances).
    void run(SkyVars& vars, const Logger& log, bool finish = false);
    /// Makes the next isDue() true (after release(), or when its outputs were lost).
    void invalidate() { invalidated_ = true; }
    /// Frees GL resources (context current) and invalidates: the next run recreates them.
    void release() {
        doRelease();
        invalidate();
    }
    int runCount() const { return timing_.calls; }
    const Timing& timing() const { return timing_; }
    /// Adds the generator's own physical quantities to the --stats JSON.
    void stats(nlohmann::json& root) const { doStats(root); }
    /// Declares the keys the generator needs that nobody else may declare (with defaults), so a
    /// host can set them before the first frame. SkyProcessor calls it, named as the declarer,
    /// when the generator is registered.
    void declareKeys(SkyVars& vars) { doDeclare(vars); }

protected:
    explicit Generator(std::string name) : name_(std::move(name)) {}
    template <class T>
    void input(const Key<T>& key, InputOptions options = {}) {
        inputs_.push_back(key.info());
        inputOptions_.push_back(options);
    }
    template <class T>
    void output(const Key<T>& key) { outputs_.push_back(key.info()); }
    /// From doRun(): the generator has more work pending (a table built over several frames) and
    /// is due again at the next run whatever its inputs.
    void runAgain() { again_ = true; }
    /// The version of inputs()[i] in `vars` (0 if undeclared), read through a pointer kept per
    /// SkyVars: for a generator that fingerprints its inputs every run without a lookup by name.
    uint64_t inputVersion(const SkyVars& vars, size_t i) const;

private:
    virtual void doRun(SkyVars& vars, const Logger& log) = 0;
    virtual void doRelease() {}
    virtual void doStats(nlohmann::json&) const {}
    virtual void doDeclare(SkyVars&) {}
    std::string name_;
    std::vector<KeyInfo> inputs_, outputs_;
    std::vector<InputOptions> inputOptions_;
    std::vector<uint64_t> seen_;
    std::vector<std::vector<double>> seenValues_;  // for inputs with a tolerance
    /// Where each input's version lives in the SkyVars last asked (SkyVars::versionSlot(); nullptr:
    /// undeclared then, looked up by name) and that SkyVars' identity: no hashed lookup per input
    /// per frame.
    mutable std::vector<const uint64_t*> slots_;
    mutable uint64_t slotsOf_ = 0;
    bool invalidated_ = false;
    bool again_ = false;
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
    /// Applies the element's effect on the host's scene (SkyProcessor::applyToScene()): drawn
    /// with the same dual-source compositing as render() into the host's framebuffer, with
    /// ctx.depth set. Elements without one do nothing.
    void applyToScene(const FrameContext& ctx, ScenePass pass);
    /// The output size changed (pixels, >= 1).
    void resize(int width, int height);
    /// Frees GL resources; the element can be initialised again.
    void release();

    /// True if the last render() drew nothing into the target (the element said so with
    /// reportNothingDrawn(), e.g. the night sky by day, no star above the limit, no planet in
    /// view): the processor then keeps FrameContext::nothingBehind for the next element.
    bool drewNothing() const { return drewNothing_; }
    /// True if the element's transmittance output attenuates what is behind it by the
    /// atmosphere's extinction (the Sky): elements before it then leave extinction to it
    /// (FrameContext::attenuatedLater).
    bool attenuatesBehind() const { return attenuatesBehind_; }
    /// True (the default) if the element is part of the environment that lights a host's scene:
    /// SkyLighting (welkin/lighting.hpp) captures it into its cube map. False for what is not
    /// diffuse light from the sky: the Sun's and Moon's disks (they are SkyLighting's directional
    /// lights, from the lights.* keys) and overlays (grids, labels). Set in the constructor with
    /// setContributesToLighting().
    bool contributesToLighting() const { return contributesToLighting_; }
    const std::vector<KeyInfo>& readKeys() const { return reads_; }
    const std::vector<KeyInfo>& writeKeys() const { return writes_; }
    /// The element's options: keys it declares with defaults (settable by the host, by
    /// `welkin render --var KEY=VALUE` and listed by `welkin vars`).
    const std::vector<KeyInfo>& optionKeys() const { return optionKeys_; }
    /// Checks the option values in `vars` together (beyond each key's own range), throwing one
    /// line naming the key and what it accepts. Needs no GL: tools call it before rendering.
    void validateOptions(const SkyVars& vars) const { doValidateOptions(vars); }
    /// Declares the option keys with their defaults in `vars` (SkyProcessor::add() does it, with
    /// the element named as the declarer; a key already declared keeps its value unless the
    /// element was constructed with explicit options). Once per SkyVars: a second call for the
    /// same SkyVars does nothing, so values set since (a host, --var) are kept.
    void declareOptions(SkyVars& vars) {
        if (optionsDeclaredIn_ == &vars) return;
        for (auto& d : optionDeclarers_) d(vars);
        optionsDeclaredIn_ = &vars;
    }
    const std::vector<std::shared_ptr<Generator>>& generators() const { return generators_; }
    /// The element's own texture units and buffer bindings, assigned by name (textureUnit(), ...):
    /// give them to its programs with gl::ProgramBuilder::bindings(bindings()).
    const gl::PrivateBindings& bindings() const { return bindings_; }

    /// Adds the element's physical quantities to the --stats JSON (e.g. root["sky"][...]).
    void stats(nlohmann::json& root) const { doStats(root); }

    /// When enabled, each call is bracketed by glFinish so timings include GPU work.
    void setTimingEnabled(bool enabled) { timingEnabled_ = enabled; }
    /// When enabled (ProcessorOptions::validation), each call is followed by glGetError and an
    /// error is thrown naming the element and the call; otherwise no per-call glGetError (it can
    /// stall a threaded driver).
    void setValidationEnabled(bool enabled) { validationEnabled_ = enabled; }
    const Timing& initTiming() const { return initTiming_; }
    const Timing& updateTiming() const { return updateTiming_; }
    const Timing& renderTiming() const { return renderTiming_; }
    const Timing& sceneTiming() const { return sceneTiming_; }

protected:
    explicit SkyElement(std::string name) : name_(std::move(name)), bindings_("element '" + name_ + "'") {}
    template <class T>
    void reads(const Key<T>& key) { reads_.push_back(key.info()); }
    template <class T>
    void writes(const Key<T>& key) { writes_.push_back(key.info()); }
    /// Declares (in the constructor) that the element attenuates what is behind it by the
    /// atmosphere's extinction; see FrameContext::attenuatedLater.
    void setAttenuatesBehind(bool on) { attenuatesBehind_ = on; }
    /// Declares (in the constructor) whether SkyLighting's environment capture draws the element;
    /// see contributesToLighting(). Elements of Layer::Bodies and Layer::Overlay say false.
    void setContributesToLighting(bool on) { contributesToLighting_ = on; }
    /// Declares an option: a key with a default, read by the element (also counts as reads()).
    /// Call in the constructor; read the value in doUpdate()/doRender() with ctx.vars.get(key).
    /// `force`: the value is set even if the key already has one (a constructor given explicit
    /// options means them); otherwise a value already there (shared, or set by the host) wins.
    template <class T>
    void option(const Key<T>& key, T defaultValue, bool force = false) {
        optionKeys_.push_back(key.info());
        reads_.push_back(key.info());
        optionDeclarers_.push_back([key, defaultValue, force](SkyVars& v) {
            v.declare(key, defaultValue);
            if (force) v.set(key, defaultValue);
        });
    }
    /// Declares an option without a default (listed by `welkin vars` as unset): the element
    /// supplies a value in doInit() when nobody set one (SkyVars::has()), e.g. from a preset.
    /// An enumerated option, its default given by value (stored as its name).
    template <class E>
    void option(const EnumKey<E>& key, E defaultValue, bool force = false) {
        option(static_cast<const Key<std::string>&>(key), key.nameOf(defaultValue), force);
    }
    template <class T>
    void optionUnset(const Key<T>& key) {
        optionKeys_.push_back(key.info());
        reads_.push_back(key.info());
        optionDeclarers_.push_back([key](SkyVars& v) { v.declareUnset(key); });
    }
    /// Adds a generator this element depends on (shared instances are run once per frame).
    void addGenerator(std::shared_ptr<Generator> g);
    /// The element's own GL bindings, asked for by name (in the constructor or doInit(), before
    /// building the programs that use them; welkin/gl/private_bindings.hpp): the framework
    /// assigns consecutive values from the private ranges of welkin/gl/bindings.hpp (texture
    /// units from binding::kPrivateTextureUnitFirst, ...), the same value for the same name, and
    /// its programs see `WELKIN_BINDING_<NAME>` through ProgramBuilder::bindings(bindings()).
    /// Throws welkin::Error naming the element, the name and the range when the range is full.
    /// Called in doRender() when this frame's render() left the target untouched (no draw call
    /// that writes it): the next element may then be told it has nothing behind it. Reset
    /// before every render(); an element that never calls it is taken to have drawn.
    void reportNothingDrawn() { drewNothing_ = true; }
    int textureUnit(std::string_view name) { return bindings_.textureUnit(name); }
    int imageUnit(std::string_view name) { return bindings_.imageUnit(name); }
    int uniformBuffer(std::string_view name) { return bindings_.uniformBuffer(name); }
    int storageBuffer(std::string_view name) { return bindings_.storageBuffer(name); }

private:
    virtual void doInit(InitContext& ctx) = 0;
    virtual void doUpdate(const FrameContext&) {}
    virtual void doRender(const FrameContext& ctx) = 0;
    virtual void doResize(int, int) {}
    virtual void doApplyToScene(const FrameContext&, ScenePass) {}
    virtual void doRelease() = 0;
    virtual void doStats(nlohmann::json&) const {}
    virtual void doValidateOptions(const SkyVars&) const {}

    void requireInitialized(const char* what) const;

    std::string name_;
    gl::PrivateBindings bindings_;  // after name_: built from it
    std::vector<KeyInfo> reads_, writes_, optionKeys_;
    std::vector<std::function<void(SkyVars&)>> optionDeclarers_;
    const SkyVars* optionsDeclaredIn_ = nullptr;
    bool attenuatesBehind_ = false;
    bool contributesToLighting_ = true;
    bool drewNothing_ = false;
    std::vector<std::shared_ptr<Generator>> generators_;
    bool initialized_ = false;
    bool timingEnabled_ = false;
    bool validationEnabled_ = false;
    Timing initTiming_, updateTiming_, renderTiming_, sceneTiming_;
};

}  // namespace welkin

namespace welkin {

/// Where an element goes in the default compositing order (farthest first).
enum class Layer {
    Background,  ///< stars, the Milky Way, airglow: behind everything
    Bodies,      ///< the Sun's and Moon's disks, planets
    Atmosphere,  ///< the sky's scattering (attenuates what is behind it)
    Clouds,      ///< cloud layers
    Foreground,  ///< rainbows, halos, fog in front of the clouds
    Overlay,     ///< grids, labels, constellation lines: drawn last, not physical
};
const char* toString(Layer layer);

/// What an element folder says about itself; the registry (skyelements/, generated at build time
/// from the folders) lists one per folder. Declare it in the element's .cpp with
/// WELKIN_ELEMENT_DESCRIPTOR(folder) { static const ElementDescriptor d{...}; return d; }.
struct ElementDescriptor {
    std::string name;         ///< as used by --elements; equals SkyElement::name() and the folder name
    std::string description;  ///< one line
    Layer layer = Layer::Foreground;
    bool inDefaultSet = false;  ///< rendered when no --elements list is given
    std::function<std::unique_ptr<SkyElement>()> make;
};

}  // namespace welkin

/// Defines the descriptor function of the element in `skyelements/<folder>/` (the build generates
/// the registry from these: adding a folder is all it takes).
#define WELKIN_ELEMENT_DESCRIPTOR(folder) const ::welkin::ElementDescriptor& welkin_element_descriptor_##folder()
