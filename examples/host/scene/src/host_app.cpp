#include <welkin_host/host_app.hpp>

#include <welkin/camera.hpp>
#include <welkin/elements/registry.hpp>
#include <welkin/generators/cloud_shadow.hpp>
#include <welkin/keys.hpp>
#include <welkin/lighting.hpp>

#include <nlohmann/json.hpp>

#include <epoxy/gl.h>

#include <glm/gtc/matrix_transform.hpp>

#include <chrono>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>

namespace host {

namespace {
constexpr double kDeg = std::numbers::pi / 180.0;

double clockMs() {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now().time_since_epoch()).count();
}
}  // namespace

CloudCover parseCloudCover(const std::string& name) {
    if (name == "none") return CloudCover::None;
    if (name == "fair") return CloudCover::Fair;
    if (name == "overcast") return CloudCover::Overcast;
    throw std::invalid_argument("--clouds '" + name + "' is not one of none, fair, overcast");
}

// ------------------------------------------------------------------ FlyCamera

glm::dvec3 FlyCamera::forward() const {
    const double yaw = yawDeg * kDeg, pitch = pitchDeg * kDeg;
    // ENU (sin yaw cos pitch, cos yaw cos pitch, sin pitch) in the Y-up world (x east, y up, -z north).
    return {std::sin(yaw) * std::cos(pitch), std::sin(pitch), -std::cos(yaw) * std::cos(pitch)};
}

glm::dvec3 FlyCamera::right() const {
    const double yaw = yawDeg * kDeg;
    return {std::cos(yaw), 0.0, std::sin(yaw)};
}

glm::dmat4 FlyCamera::view() const { return glm::lookAt(position, position + forward(), glm::dvec3(0.0, 1.0, 0.0)); }

glm::dmat4 FlyCamera::projection(double aspect) const {
    const double f = 1.0 / std::tan(0.5 * verticalFovDeg * kDeg);
    glm::dmat4 p(0.0);
    p[0][0] = f / aspect;
    p[1][1] = f;
    p[2][3] = -1.0;   // w_clip = -z_view
    p[3][2] = nearM;  // z_clip = near: z_ndc = near / -z_view, 1 at the near plane, 0 at infinity
    return p;
}

// ------------------------------------------------------------------ HostApp

HostApp::HostApp(const AppOptions& options, const welkin::Logger& log) : options_(options), log_(log) {
    std::vector<std::string> files = options_.sceneFiles;
    if (files.empty())
        for (const char* file : {"terrain.gltf", "buildings.gltf", "spheres.gltf"}) files.push_back(options_.assetsDir + "/" + file);
    for (const auto& file : files) scene_.load(file);
    renderer_ = std::make_unique<SceneRenderer>(options_.shadows);

    sky_ = std::make_unique<welkin::SkyProcessor>(welkin::SkyVars::earth(), log_);
    const bool clouds = options_.clouds != CloudCover::None;
    for (const auto& name : welkin::elements::expandElementList(clouds ? "default,clouds" : "default"))
        sky_->add(welkin::elements::makeElement(name));
    if (clouds) {
        sky_->vars().setFromString("clouds.preset", options_.clouds == CloudCover::Fair ? "fair" : "overcast");
        // The clouds' shadow on the host's ground: the shadow map generator, run with the others.
        sky_->addGenerator(welkin::generators::CloudShadowMap::obtain(sky_->vars()));
        cloudShadowMap_ = true;
    }
    const Site& s = options_.site;
    sky_->setObserver({.latitudeRad = s.latitudeDeg * kDeg, .longitudeRad = s.longitudeDeg * kDeg, .heightMeters = s.heightM});
    sky_->setExposure({.automatic = true});
    sky_->vars().set(welkin::keys::interactive, options_.interactive);
    sky_->setLighting(welkin::LightingOptions{});
    // The world's origin is the observer: ENU = the Y-up world rotated, 1 m per unit.
    worldToEnu_ = welkin::enuFromYUp(1.0, glm::dvec3(0.0));
    for (auto& frame : timers_)
        for (auto& q : frame) q = GlName::query(GL_TIMESTAMP);
}

HostApp::~HostApp() = default;

void HostApp::resize(int width, int height) {
    if (width == width_ && height == height_) return;
    if (width < 1 || height < 1 || width > 16384 || height > 16384)
        throw std::invalid_argument("frame size " + std::to_string(width) + "x" + std::to_string(height) + " not in [1, 16384]");
    width_ = width, height_ = height;
    hdr_ = GlName::texture(GL_TEXTURE_2D);
    glTextureStorage2D(hdr_.id(), 1, GL_RGBA32F, width, height);
    depth_ = GlName::texture(GL_TEXTURE_2D);
    glTextureStorage2D(depth_.id(), 1, GL_DEPTH_COMPONENT32F, width, height);
    for (GLuint t : {hdr_.id(), depth_.id()}) {
        glTextureParameteri(t, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
        glTextureParameteri(t, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
        glTextureParameteri(t, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
        glTextureParameteri(t, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    }
    fbo_ = GlName::framebuffer();
    glNamedFramebufferTexture(fbo_.id(), GL_COLOR_ATTACHMENT0, hdr_.id(), 0);
    glNamedFramebufferTexture(fbo_.id(), GL_DEPTH_ATTACHMENT, depth_.id(), 0);
    if (glCheckNamedFramebufferStatus(fbo_.id(), GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
        throw std::runtime_error("HostApp: the HDR framebuffer is incomplete");
    ldr_ = {};
    ldrFbo_ = {};
}

void HostApp::updateLighting() {
    const welkin::SkyLighting& L = sky_->lighting();
    const welkin::SkyVars& vars = sky_->vars();
    const glm::dmat3 toEnu = glm::dmat3(worldToEnu_);
    const glm::dmat3 toWorld = glm::inverse(toEnu);
    auto worldDir = [&](const glm::dvec3& enu) { return glm::vec3(glm::normalize(toWorld * enu)); };
    lighting_.sun.directionWorld = worldDir(L.sun.directionEnu);
    lighting_.moon.directionWorld = worldDir(L.moon.directionEnu);
    lighting_.sun.illuminanceRgb = glm::vec3(L.sun.illuminanceRgb);
    lighting_.moon.illuminanceRgb = glm::vec3(L.moon.illuminanceRgb);
    lighting_.sky = &L;  // SH irradiance and specular cube: welkin::bindLighting() in the renderer
    lighting_.enuFromWorld = glm::dmat3(glm::normalize(toEnu[0]), glm::normalize(toEnu[1]), glm::normalize(toEnu[2]));
    lighting_.worldToEnuPoint = worldToEnu_;
    lighting_.sun.cloudShadow = lighting_.moon.cloudShadow = false;
    lighting_.cloudShadowGlsl.clear();
    lighting_.bindCloudShadow = nullptr;
    if (options_.effects == AppOptions::Effects::Shader && cloudShadowMap_ && vars.has(welkin::generators::cloudkeys::shadowMap)) {
        // The shadow map is made for the Sun, or the Moon at night. SkyLighting's illuminance is
        // the light at the observer, after the clouds over the observer; the shader needs the
        // light above the clouds (the same product without the clouds' transmittance,
        // docs/lighting.md) and shadows it per fragment with welkin_cloudShadow().
        const glm::dvec3 shadowLight = welkin::generators::CloudShadowMap::lightDirection(vars);
        const bool onSun = glm::dot(shadowLight, L.sun.directionEnu) > glm::dot(shadowLight, L.moon.directionEnu);
        if (onSun) {
            lighting_.sun.illuminanceRgb = glm::vec3(vars.get(welkin::keys::sunIlluminance) * vars.get(welkin::keys::sunTransmittance) *
                                                     vars.getOr(welkin::keys::sunEclipseFraction, 1.0));
            lighting_.sun.cloudShadow = true;
        } else {
            lighting_.moon.illuminanceRgb = glm::vec3(vars.get(welkin::keys::moonIlluminance) * vars.get(welkin::keys::moonTransmittance));
            lighting_.moon.cloudShadow = true;
        }
        lighting_.cloudShadowGlsl = std::string(welkin::generators::CloudShadowMap::hostGlsl());
        const welkin::SkyVars* v = &vars;
        lighting_.bindCloudShadow = [v](unsigned program) { welkin::generators::CloudShadowMap::bindForHost(*v, program); };
    }
}

void HostApp::render(const welkin::UtcInstant& time, const FlyCamera& camera, int width, int height) {
    const double now = clockMs();
    if (lastFrameClock_) times_.frameMs = now - *lastFrameClock_;
    lastFrameClock_ = now;
    resize(width, height);
    readTimers(false);
    auto& q = timers_[size_t(frameIndex_ % kTimerFrames)];

    const glm::dmat4 view = camera.view();
    const glm::dmat4 proj = camera.projection(double(width) / double(height));
    viewProjection_ = proj * view;
    sky_->setTime(time);
    sky_->setCamera(welkin::Camera::fromViewProjection(view, proj, worldToEnu_, width, height,
                                                       welkin::DepthMode{.reversedZ = true, .zeroToOne = true}));
    glQueryCounter(q[0].id(), GL_TIMESTAMP);
    // The generators that are due, the lighting among them: this frame's scene is lit by this
    // frame's sky (renderInto() below finds nothing left to do).
    sky_->update();
    glQueryCounter(q[1].id(), GL_TIMESTAMP);
    // The lighting's own cost this frame (welkin's --stats: CPU ms, with glFinish only when the
    // processor times with ProcessorOptions::timing).
    const nlohmann::json stats = sky_->stats();
    times_.lightingMs = stats.contains("lighting") && stats["lighting"].contains("frame_ms")
                            ? stats["lighting"]["frame_ms"].value("total", 0.0)
                            : 0.0;
    updateLighting();

    // The scene's shadow map, over the ground in front of the camera.
    glm::dvec3 ahead = camera.forward();
    ahead.y = 0.0;
    ahead = glm::length(ahead) > 1e-6 ? glm::normalize(ahead) : glm::dvec3(0.0);
    renderer_->renderShadows(scene_, lighting_, glm::vec3(camera.position + ahead * (0.6 * options_.shadows.halfExtentM)));

    // The host's scene pass: reversed-Z, [0, 1] clip depth, infinite far plane.
    glBindFramebuffer(GL_FRAMEBUFFER, fbo_.id());
    glViewport(0, 0, width, height);
    glClipControl(GL_LOWER_LEFT, GL_ZERO_TO_ONE);
    glDisable(GL_BLEND);
    glDisable(GL_SCISSOR_TEST);
    glEnable(GL_DEPTH_TEST);
    glDepthMask(GL_TRUE);
    glDepthFunc(GL_GREATER);
    glEnable(GL_CULL_FACE);
    glCullFace(GL_BACK);
    glFrontFace(GL_CCW);
    const float black[4] = {0, 0, 0, 0};
    const float farDepth = 0.0f;
    glClearNamedFramebufferfv(fbo_.id(), GL_COLOR, 0, black);
    glClearNamedFramebufferfv(fbo_.id(), GL_DEPTH, 0, &farDepth);
    renderer_->draw(scene_, {.view = glm::mat4(view), .projection = glm::mat4(proj), .eyeWorld = glm::vec3(camera.position)}, lighting_);
    glDisable(GL_CULL_FACE);
    glQueryCounter(q[2].id(), GL_TIMESTAMP);

    // welkin: the sky behind the scene, then the air between the eye and the scene.
    const welkin::RenderTarget target{.framebuffer = fbo_.id(),
                                      .width = width,
                                      .height = height,
                                      .depthTest = true,
                                      .depth = welkin::HostDepth{.depthTexture = depth_.id(),
                                                                 .nearM = camera.nearM,
                                                                 .farM = std::numeric_limits<double>::infinity(),
                                                                 .metresPerUnit = 1.0}};
    sky_->renderInto(target);
    // --effects shader: the scene's shader shades the clouds' shadows itself; welkin adds the air only.
    sky_->applyToScene(target, {.surfaces = options_.effects == AppOptions::Effects::ApplyToScene, .air = true});
    glQueryCounter(q[3].id(), GL_TIMESTAMP);
    timerPending_[size_t(frameIndex_ % kTimerFrames)] = true;
    ++frameIndex_;
    // The host's own state for what follows (the overlay, the window's default framebuffer).
    glClipControl(GL_LOWER_LEFT, GL_NEGATIVE_ONE_TO_ONE);
    glDepthFunc(GL_LESS);
    glDisable(GL_DEPTH_TEST);
}

void HostApp::readTimers(bool wait) {
    // The oldest frame's timestamps, if the GPU is done with them (a window never stalls).
    for (int k = 0; k < kTimerFrames; ++k) {
        const size_t i = size_t((frameIndex_ + k) % kTimerFrames);
        if (!timerPending_[i]) continue;
        GLint available = 0;
        glGetQueryObjectiv(timers_[i][3].id(), GL_QUERY_RESULT_AVAILABLE, &available);
        if (!available && !wait) continue;
        GLuint64 t[4];
        for (int j = 0; j < 4; ++j) glGetQueryObjectui64v(timers_[i][size_t(j)].id(), GL_QUERY_RESULT, &t[j]);
        times_.sceneMs = double(t[2] - t[1]) * 1e-6;
        times_.welkinMs = double((t[1] - t[0]) + (t[3] - t[2])) * 1e-6;
        timerPending_[i] = false;
    }
}

void HostApp::present(unsigned framebuffer) { sky_->toneMapInto(framebuffer, hdr_.id()); }

welkin::Image HostApp::readHdr() const {
    std::vector<float> px(size_t(width_) * size_t(height_) * 4);
    glGetTextureImage(hdr_.id(), 0, GL_RGBA, GL_FLOAT, GLsizei(px.size() * sizeof(float)), px.data());
    welkin::Image img{width_, height_, 3, std::vector<float>(size_t(width_) * size_t(height_) * 3)};
    for (int y = 0; y < height_; ++y)
        for (int x = 0; x < width_; ++x)
            for (int c = 0; c < 3; ++c) img.at(x, y, c) = px[(size_t(height_ - 1 - y) * size_t(width_) + size_t(x)) * 4 + size_t(c)];
    return img;
}

welkin::Image HostApp::readToneMapped() {
    if (!ldr_) {
        ldr_ = GlName::texture(GL_TEXTURE_2D);
        glTextureStorage2D(ldr_.id(), 1, GL_RGBA8, width_, height_);
        ldrFbo_ = GlName::framebuffer();
        glNamedFramebufferTexture(ldrFbo_.id(), GL_COLOR_ATTACHMENT0, ldr_.id(), 0);
    }
    present(ldrFbo_.id());
    std::vector<unsigned char> px(size_t(width_) * size_t(height_) * 4);
    glGetTextureImage(ldr_.id(), 0, GL_RGBA, GL_UNSIGNED_BYTE, GLsizei(px.size()), px.data());
    welkin::Image img{width_, height_, 3, std::vector<float>(size_t(width_) * size_t(height_) * 3)};
    for (int y = 0; y < height_; ++y)
        for (int x = 0; x < width_; ++x)
            for (int c = 0; c < 3; ++c) img.at(x, y, c) = px[(size_t(height_ - 1 - y) * size_t(width_) + size_t(x)) * 4 + size_t(c)] / 255.0f;
    return img;
}

}  // namespace host
