// The host example's frame: its own scene, camera and targets, with welkin as a guest.
//
//   auto ctx = welkin::gl::HeadlessContext::create({}, log);      // or a window
//   host::HostApp app({.assetsDir = "examples/host/assets"}, log);
//   app.render(welkin::UtcInstant::parse("2026-03-20T11:00:00Z"), host::FlyCamera{}, 640, 360);
//   app.present(0);                                               // tone map to the screen
//   welkin::Image hdr = app.readHdr();                            // cd/m^2, top row first
//
// One frame (render()):
//  1. welkin: time, the host's camera from its view and projection matrices
//     (Camera::fromViewProjection with enuFromYUp, reversed-Z, [0, 1] clip depth), update():
//     the generators that are due, the lighting (SkyLighting) among them;
//  2. the host: its HDR target (RGBA32F, cd/m^2) and depth texture (DEPTH_COMPONENT32F, reversed-Z:
//     cleared to 0, GL_GREATER, infinite far plane, glClipControl(GL_LOWER_LEFT, GL_ZERO_TO_ONE));
//     the scene's shadow map (the brighter of the Sun and the Moon), then the scene drawn by the
//     PBR renderer lit by the Sun, the Moon, the SH irradiance and the specular cube;
//  3. welkin: renderInto() (the sky where the depth is still the far plane), applyToScene()
//     (the clouds' shadows, then the aerial perspective, over the host's colour, from its depth).
// present(fb) tone-maps the HDR target with the eye's adaptation (toneMapInto(fb, hdrTexture)).
//
// The world: metres, Y-up (x east, y up, -z north: glTF's axes), its origin on the village floor
// at the observer's place (Site), so world = ENU rotated (enuFromYUp()).
#pragma once
#include <welkin_host/overlay.hpp>
#include <welkin_host/renderer.hpp>
#include <welkin_host/scene.hpp>

#include <welkin/image.hpp>
#include <welkin/log.hpp>
#include <welkin/processor.hpp>
#include <welkin/time.hpp>

#include <glm/glm.hpp>

#include <array>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace host {

/// Where the world's origin is on Earth: by default Malta, on the plain below Mdina
/// (35.9 N, 14.5 E, 50 m above the ellipsoid).
struct Site {
    double latitudeDeg = 35.9;
    double longitudeDeg = 14.5;
    double heightM = 50.0;
};

enum class CloudCover { None, Fair, Overcast };
/// "none", "fair", "overcast"; throws std::invalid_argument listing them.
CloudCover parseCloudCover(const std::string& name);

/// A game's fly camera in the Y-up world.
struct FlyCamera {
    glm::dvec3 position{0.0, 8.0, 0.0};  ///< metres, world
    double yawDeg = 270.0;               ///< heading, degrees from north (-z) through east (+x): 270 looks west
    double pitchDeg = -2.0;              ///< degrees above the horizontal, [-89, 89]
    double verticalFovDeg = 50.0;        ///< (0, 179)
    double nearM = 0.1;                  ///< near plane, metres (the far plane is at infinity)

    glm::dvec3 forward() const;
    glm::dvec3 right() const;
    glm::dmat4 view() const;
    /// Reversed-Z perspective with an infinite far plane for [0, 1] clip depth: window depth 1 at
    /// the near plane, 0 at infinity.
    glm::dmat4 projection(double aspect) const;
};

struct AppOptions {
    std::string assetsDir;  ///< where terrain.gltf, buildings.gltf and spheres.gltf are
    /// The glTF files of the scene; empty: those three in assetsDir (another demo passes its own).
    std::vector<std::string> sceneFiles;
    Site site;
    CloudCover clouds = CloudCover::None;
    /// Where the clouds' shadows and the aerial perspective come from. ApplyToScene (default):
    /// welkin's applyToScene() after the scene is drawn, from its colour and depth (the scene lit
    /// with the light at the observer, SkyLighting's). Shader: the host's own shader shades the
    /// clouds' shadow per light and normal (welkin_cloudShadow, the light above the clouds), and
    /// applyToScene() adds the aerial perspective only ({.surfaces = false}).
    enum class Effects { ApplyToScene, Shader } effects = Effects::ApplyToScene;
    /// A window's frames one after another (render.interactive): welkin spreads work over
    /// frames (the lighting's capture, time-sliced). false: every frame complete (headless).
    bool interactive = false;
    /// The scene's own shadows from the brighter of the Sun and the Moon (a shadow map).
    ShadowSettings shadows;
};

/// GPU time of the parts of a frame (timer queries, read a few frames later without stalling).
struct FrameTimes {
    double sceneMs = 0.0;    ///< the host's scene pass, GPU
    double welkinMs = 0.0;   ///< welkin's update() + renderInto() + applyToScene(), GPU (the tone map is not in it)
    double lightingMs = 0.0; ///< welkin's lighting outputs this frame, from its --stats ("lighting": CPU ms)
    double frameMs = 0.0;    ///< CPU, between two render() calls
};

class HostApp {
public:
    /// Needs a current GL 4.5 context. Loads the assets and sets up the sky. Throws
    /// std::runtime_error or welkin::Error with a one-line message.
    HostApp(const AppOptions& options, const welkin::Logger& log);
    ~HostApp();
    HostApp(const HostApp&) = delete;
    HostApp& operator=(const HostApp&) = delete;

    /// One frame into the HDR target at width x height (resized as needed).
    void render(const welkin::UtcInstant& time, const FlyCamera& camera, int width, int height);
    /// Tone-maps the HDR target into `framebuffer` (0: the default framebuffer).
    void present(unsigned framebuffer);
    /// The HDR frame: RGB, cd/m^2, top row first.
    welkin::Image readHdr() const;
    /// Renders the frame's tone-mapped image into an offscreen RGBA8 target and reads it back
    /// (RGB in [0, 1], sRGB-encoded, top row first).
    welkin::Image readToneMapped();

    welkin::SkyProcessor& sky() { return *sky_; }
    const Scene& scene() const { return scene_; }
    /// The last frame's lighting as the renderer saw it.
    const SceneLighting& lighting() const { return lighting_; }
    /// Host world -> clip of the last frame (projection x view).
    const glm::dmat4& viewProjection() const { return viewProjection_; }
    const glm::dmat4& worldToEnu() const { return worldToEnu_; }
    FrameTimes times() const { return times_; }
    /// Waits for the last frame's GPU timestamps (headless: one frame, read at once).
    void finishTimers() { readTimers(true); }
    int width() const { return width_; }
    int height() const { return height_; }

private:
    void resize(int width, int height);
    void updateLighting();
    void readTimers(bool wait);

    AppOptions options_;
    welkin::Logger log_;
    std::unique_ptr<welkin::SkyProcessor> sky_;
    bool cloudShadowMap_ = false;
    Scene scene_;
    std::unique_ptr<SceneRenderer> renderer_;
    SceneLighting lighting_;
    glm::dmat4 worldToEnu_{1.0}, viewProjection_{1.0};
    int width_ = 0, height_ = 0;
    GlName hdr_, depth_, fbo_, ldr_, ldrFbo_;
    static constexpr int kTimerFrames = 4;
    std::array<std::array<GlName, 4>, kTimerFrames> timers_;  // before/after update(), after the scene, after welkin's passes
    std::array<bool, kTimerFrames> timerPending_{};
    int frameIndex_ = 0;
    FrameTimes times_;
    std::optional<double> lastFrameClock_;
};

}  // namespace host
