// SkyProcessor: the scene. Holds the SkyVars and the ordered elements; per frame it derives the
// time and observer variables, runs the generators that are due, composites the elements in
// registration order into an HDR target and tone-maps into the caller's framebuffer or an image.
//
//   auto ctx = welkin::gl::HeadlessContext::create({}, log);
//   welkin::SkyProcessor sky;                                  // SkyVars::earth(), own logger
//   sky.add(std::make_unique<welkin::elements::Grid>());
//   sky.setObserver({.latitudeRad = 0.6227, .longitudeRad = 0.2517, .heightMeters = 30});
//   sky.setTime(welkin::UtcInstant::parse("2026-07-15T21:30:00+02:00"));
//   sky.setCamera(camera);
//   sky.setExposure({.automatic = true});
//   sky.renderFrame();                                         // HDR composite + the eye's meter
//   welkin::Image hdr = sky.readHdr();                         // cd/m^2, top row first
//
// Embedding in a game loop (docs/embedding.md, examples/host):
//
//   sky.setCamera(welkin::Camera::fromViewProjection(view, proj, welkin::enuFromYUp(), w, h,
//                                                    {.reversedZ = true, .zeroToOne = true}));
//   welkin::RenderTarget t{.framebuffer = hdrFbo, .width = w, .height = h,
//                          .depth = welkin::HostDepth{.depthTexture = depthTex}};
//   // ... draw the host's scene into hdrFbo (cd/m^2), lit by sky.lighting() ...
//   sky.renderInto(t);                 // the sky at the far plane, behind the host's geometry
//   sky.applyToScene(t);               // cloud shadows and aerial perspective over the scene
//   sky.toneMapInto(0, hdrTexture);    // the eye's adaptation and display curve, to the screen
//
// Elements are drawn at the far plane with GL_LEQUAL (standard depth) or GL_GEQUAL (the camera's
// DepthMode::reversedZ), whatever the host's glClipControl, so the host's geometry hides the sky.
// Or call renderFrame() and toneMapInto(0) to present welkin's own frame.
//
// GL errors: an error the host left pending is drained when welkin is entered and reported as
// the host's (a warning in the log, never thrown as welkin's); welkin checks its own once per
// public call, and after every element and generator call only with ProcessorOptions::validation
// (which also routes KHR_debug messages to the log while welkin runs).
//
// A guest in the host's GL: init(), update(), renderFrame(), renderInto() and toneMapInto()
// leave the host's OpenGL state as they found it (bindings of framebuffers, program, vertex
// array, textures and samplers on units 0..15, uniform and storage buffers 0..7, image units
// 0..7; viewport, blend, depth, cull, scissor, colour mask, pixel store ...; the full list is in
// docs/architecture.md), also when they throw. No global state: two processors in one process are independent
// (each needs its context current when called, including when it is destroyed: GL names belong
// to the context that created them).
//
// HDR format: RGBA32F. Starlight (~1e-5 cd/m^2) and the solar disk (~1.6e9 cd/m^2) both keep
// 24-bit relative precision; fp16 would clip at 65504 cd/m^2 without pre-exposure. Cost and
// memory are measured by `welkin bench` (docs/architecture.md).
#pragma once
#include <welkin/camera.hpp>
#include <welkin/element.hpp>
#include <welkin/gl/objects.hpp>
#include <welkin/host_depth.hpp>
#include <welkin/image.hpp>
#include <welkin/lighting.hpp>
#include <welkin/log.hpp>
#include <welkin/time.hpp>
#include <welkin/vars.hpp>

#include <nlohmann/json_fwd.hpp>

#include <chrono>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace welkin {

class GeneratorGraph;
class ToneMapper;
class LightingEngine;

/// Where the observer stands. Geodetic on WGS84.
struct Observer {
    double latitudeRad = 0.0;   ///< [-pi/2, pi/2], north positive
    double longitudeRad = 0.0;  ///< [-pi, pi], east positive
    double heightMeters = 0.0;  ///< above the ellipsoid, [-1e4, 1e9]
    /// Throws welkin::Error naming the member and range.
    void validate() const;
};

/// Tone-mapping exposure; written into the keys exposure.auto, exposure.ev100,
/// exposure.compensation_ev (the keys are what the tone map reads; the eye's own parameters are
/// the eye.* keys, welkin/eye.hpp and docs/eye.md).
struct Exposure {
    bool automatic = false;       ///< adapt to the frame: the eye's model (eye.adaptation) or a camera's log-average
    double ev100 = 15.0;          ///< manual exposure value at ISO 100, [-20, 30]
    double compensationEv = 0.0;  ///< added brightness for automatic exposure, EV, [-10, 10]
};

/// A caller-provided framebuffer to composite into (game-loop embedding).
struct RenderTarget {
    unsigned framebuffer = 0;  ///< GL framebuffer name (0 = default framebuffer)
    int width = 0;             ///< pixels; must equal the camera's size
    int height = 0;
    bool depthTest = true;     ///< test against the target's depth buffer (sky at the far plane)
    /// The host's depth as a texture, for elements that need the distance to the host's
    /// geometry (FrameContext::depth); none by default. Validated by renderInto(): ranges, and a
    /// live texture of the camera's size.
    std::optional<HostDepth> depth;
};

/// A SkyVars the caller owns and keeps, for a processor that renders with it (tests, tools).
struct BorrowedVars {
    SkyVars& vars;
};

struct ProcessorOptions {
    bool timing = false;     ///< bracket every element and generator call with glFinish (for --stats)
    bool astronomy = true;   ///< register the astronomy generator (Sun, Moon, planets, star frame from
                             ///< time and place, astro_keys.hpp); false leaves sun.direction,
                             ///< moon.direction ... to the host
    bool timeAndPlace = true;  ///< write time.* and observer.* from setTime()/setObserver() every
                               ///< frame; false: the host writes those keys into the SkyVars itself
    bool validation = false;   ///< glGetError after every element and generator call, and the driver's
                               ///< KHR_debug messages in the log while welkin runs (debugging; costs a
                               ///< pipeline sync per call on threaded drivers)
};

class SkyProcessor {
public:
    explicit SkyProcessor(SkyVars vars = SkyVars::earth(), Logger log = Logger(), ProcessorOptions options = {});
    /// Renders with the caller's SkyVars (which must outlive the processor).
    explicit SkyProcessor(BorrowedVars vars, Logger log = Logger(), ProcessorOptions options = {});
    ~SkyProcessor();
    SkyProcessor(const SkyProcessor&) = delete;
    SkyProcessor& operator=(const SkyProcessor&) = delete;

    SkyVars& vars() { return *vars_; }
    const SkyVars& vars() const { return *vars_; }
    /// Sets an input key from text, as `welkin render --var KEY=VALUE` does (parsed by the key's
    /// type, checked against its range: SkyVars::setFromString()), and refuses the keys that are
    /// outputs, not inputs: the ones derived from setTime() and setObserver() (time.*,
    /// observer.*) and every generator's output (the astronomy's sun.direction,
    /// stars.frame_icrs_to_enu ...), which the next frame would overwrite. Throws welkin::Error
    /// naming what sets the key. A key written by a generator an element attaches at init() is
    /// refused then: init() throws if a key set here is one of its outputs.
    void setOption(std::string_view name, std::string_view text);
    Logger& logger() { return log_; }

    /// Appends an element (composited after the ones already added). Initialised lazily on the
    /// next frame, or now if init() was already called. Names must be unique.
    SkyElement& add(std::unique_ptr<SkyElement> element);
    template <class E, class... Args>
    E& emplace(Args&&... args) {
        return static_cast<E&>(add(std::make_unique<E>(std::forward<Args>(args)...)));
    }
    const std::vector<std::unique_ptr<SkyElement>>& elements() const { return elements_; }
    /// The element with this name, or nullptr.
    SkyElement* find(std::string_view name) const;
    /// Takes the element named `name` out of the scene (its GL resources stay: re-add it, or
    /// release() it with the context current); nullptr if there is none.
    std::unique_ptr<SkyElement> remove(std::string_view name);
    /// Registers a processor-level generator (world state any element may read: the astronomy,
    /// a host's own weather...). Its keys are declared now (SkyVars::DeclarerScope = its name).
    void addGenerator(std::shared_ptr<Generator> generator);
    /// Every generator in the order they run: sorted by their inputs and outputs (a generator
    /// that reads another's output runs after it), otherwise in registration order (processor
    /// generators, then each element's). Valid after init().
    const std::vector<Generator*>& generatorOrder() const;

    void setTime(const UtcInstant& t);
    const UtcInstant& time() const { return time_; }
    void setObserver(const Observer& o);
    const Observer& observer() const { return observer_; }
    void setCamera(const Camera& c);
    const Camera& camera() const { return camera_; }
    void setExposure(const Exposure& e);
    const Exposure& exposure() const { return exposure_; }

    /// Initialises every element not yet initialised (needs a current GL 4.5 context) and orders
    /// the generators. Throws welkin::Error if two generators write one key, a generator reads a
    /// key nobody declares or writes, or the generators' dependencies form a cycle.
    void init();
    /// Derives time/observer variables, runs the due generators and every element's update().
    void update();
    /// update(), then composites all elements into the processor's HDR target and advances the
    /// eye's adaptation (the automatic exposure's meter). The tone map's per-pixel pass into the
    /// processor's LDR target is drawn when readToneMapped() first asks for it, so a viewer that
    /// shows the frame with toneMapInto() pays for one tone map, not two.
    void renderFrame();
    /// update(), then composites into a caller's framebuffer (its current contents are the
    /// background; blending is additive-attenuating). Does not tone-map. Only colour attachment 0
    /// is drawn to. Elements see target.depth in render() (FrameContext::depth).
    void renderInto(const RenderTarget& target);
    /// Over the host's scene in target.framebuffer (its colour, cd/m^2) with its depth
    /// (target.depth, required): every element's effect on it, in two passes (ScenePass): the
    /// clouds' shadows on the host's surfaces, then the aerial perspective of the air in front of
    /// them (the Sky; it builds its aerial-perspective volume from the first call on). Call after
    /// renderInto() in the same frame (it draws with that frame's state; depthTest is ignored).
    /// `passes`: which of the two (a host that shades the clouds' shadows itself asks for the air only).
    void applyToScene(const RenderTarget& target, ScenePasses passes = {});
    /// Tone-maps the last HDR frame into `framebuffer` (0 = default) at the camera's size.
    void toneMapInto(unsigned framebuffer);
    /// Tone-maps the host's HDR texture (`hostHdrTexture`: a GL_TEXTURE_2D of the camera's size,
    /// RGBA16F or RGBA32F, linear radiance in cd/m^2, e.g. the target of renderInto() and
    /// applyToScene()) into `framebuffer`, with the eye's adaptation: each call is a new frame
    /// that advances the adaptation by the animation time since the previous one. The texture's
    /// parameters are not changed.
    void toneMapInto(unsigned framebuffer, unsigned hostHdrTexture);

    /// The HDR composite of the last renderFrame() (RGBA32F, cd/m^2).
    const gl::Texture2D& hdrTexture() const { return hdr_; }
    /// Reads the HDR frame back: RGB float, cd/m^2, top row first.
    Image readHdr() const;
    /// Reads the tone-mapped frame back: RGB float in [0, 1] (sRGB-encoded), top row first. The
    /// first call after a renderFrame() draws the tone map into the processor's LDR target (with
    /// that frame's settings and adaptation); later calls read it again.
    Image readToneMapped() const;
    /// EV100 used by the last tone map (automatic: the adapted exposure, welkin/eye.hpp).
    double lastEv100() const;
    /// The eye's adaptation luminances after the last automatic tone map: (cones, cd/m^2; rods,
    /// scotopic cd/m^2). Each renderFrame() advances them by the animation time since the
    /// previous one (seconds(); none passed: the steady state, as a still render).
    glm::dvec2 adaptationLuminance() const;
    /// Forgets the adaptation: the next frame starts in the steady state (a cut in an animation).
    void resetAdaptation();

    /// Turns SkyLighting on with these options (writes the lighting.* keys; welkin/lighting.hpp),
    /// or off with std::nullopt. Off by default: a scene pays only for what it uses. Throws one
    /// line naming the member out of range ("SkyProcessor::setLighting(): cubeSize 3 not in [8, 1024]").
    void setLighting(std::optional<LightingOptions> options);
    /// The host's lighting, updated at the end of each update() (a capture only when a key
    /// changed; time-sliced when render.interactive); ev100 is the last tone map's.
    const SkyLighting& lighting() const;

    /// Animation time passed to elements: seconds since construction, or the fixed value given
    /// to setAnimationTime() (offline renders use 0 so that output is deterministic).
    double seconds() const;
    /// Fixes the animation time (seconds, finite), or, with std::nullopt, follows the wall clock.
    void setAnimationTime(std::optional<double> seconds);
    /// While paused, update() runs no generator: the tables stay as they are (a tool looks at a
    /// state without advancing it).
    void setGeneratorsPaused(bool paused) { generatorsPaused_ = paused; }
    /// CPU time of the last frame's generators, ms (with glFinish when timing is enabled).
    double lastGeneratorsMs() const { return generatorsMs_; }
    /// Stats of the last frame: inputs, per element and generator CPU-timed cost (ms).
    nlohmann::json stats() const;
    /// Frees every GL resource of the processor, its elements and generators (also done by the
    /// destructor; needs the context current). init() (or the next frame) makes them again.
    void release();

private:
    void ensureTargets();
    void deriveVariables();
    void publishPreviousExposure();  ///< keys::exposurePrevious, before the elements' update
    void runGenerators();
    /// `clearedToBlack`: the target was just cleared to black (the first element has nothing behind it).
    /// `depth`: the host's depth for the elements (FrameContext::depth), or nullptr.
    void composite(unsigned framebuffer, bool depthTest, bool clearedToBlack, const HostDepth* depth);
    /// The compositing state (framebuffer, viewport, camera block, dual-source blending, depth
    /// test in the camera's DepthMode), set before every element's pass.
    void applyCompositeState(unsigned framebuffer, bool depthTest);
    void applyCompositeState(unsigned framebuffer, bool depthTest, const Camera& camera, const gl::Buffer& ubo);
    void checkDepthTexture(const HostDepth& depth) const;
    void declareToneMapKeys();
    /// `newFrame`: the frame renderFrame() just composited (advances the eye's adaptation).
    /// `draw` false: only the meter and the adaptation step (renderFrame(); the display pass into
    /// the LDR target waits for readToneMapped()).
    void toneMap(unsigned framebuffer, bool newFrame, unsigned hdrTexture, bool draw = true);
    FrameContext frameContext();
    /// Writes the camera block (with the host depth's planes for cameras not made from matrices).
    void uploadCamera(const HostDepth* depth);
    /// update() with the host's depth in the camera block (renderInto()).
    void update(const HostDepth* depth);
    // SkyLighting (engine/src/lighting.cpp): keys, the step at the end of update(), stats, and the
    // environment's compositing (the elements that contribute to lighting, for a capture camera).
    friend class LightingEngine;
    void declareLightingKeys();
    void updateLighting();
    void releaseLighting();
    void lightingStats(nlohmann::json& root) const;
    void compositeEnvironment(const Camera& camera, const gl::Buffer& cameraUbo, unsigned framebuffer);

    SkyVars ownVars_;
    SkyVars* vars_ = &ownVars_;
    Logger log_;
    ProcessorOptions options_;
    std::vector<std::unique_ptr<SkyElement>> elements_;
    std::unique_ptr<GeneratorGraph> graph_;  // the generators and their order: engine/src/generator_graph.hpp
    std::vector<std::string> optionsSet_;  // keys setOption() set, checked against the generators' outputs at init()
    bool generatorsPaused_ = false;
    UtcInstant time_ = UtcInstant::parse("2000-01-01T12:00:00Z");
    Observer observer_{};
    Camera camera_{};
    Exposure exposure_{};
    bool glReady_ = false;
    mutable int hostGuardDepth_ = 0;  // nesting of public calls that save and restore the host's GL state
    std::optional<double> animationTime_;
    std::optional<double> lastFrameSeconds_;  // seconds() at the last renderFrame()'s tone map
    std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();

    gl::Texture2D hdr_, ldr_;
    gl::Framebuffer hdrFbo_, ldrFbo_;
    mutable bool ldrPending_ = false;  // the last renderFrame()'s display pass into ldr_ is not drawn yet
    std::unique_ptr<ToneMapper> toneMapper_;  // engine/src/tone_mapper.hpp
    std::unique_ptr<LightingEngine> lighting_;  // engine/src/lighting_engine.hpp
    gl::VertexArray emptyVao_;
    gl::Buffer cameraUbo_;
    double frameMs_ = 0.0, toneMapMs_ = 0.0, generatorsMs_ = 0.0, sceneMs_ = 0.0;
    int frames_ = 0;
};

}  // namespace welkin
