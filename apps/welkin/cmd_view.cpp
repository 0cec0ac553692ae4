// welkin view: the same scene as `welkin render` in a GLFW window, with mouse-look, zoom, time
// controls and screenshots.
#include "command.hpp"
#include "scene_options.hpp"

#include <welkin/error.hpp>
#include <welkin/gl/context.hpp>
#include <welkin/image.hpp>
#include <welkin/keys.hpp>
#include <welkin/processor.hpp>

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <numbers>

namespace welkin::cli {

namespace {

constexpr double kDeg = std::numbers::pi / 180;

struct ViewOptions {
    SceneOptions scene;
    int frames = 0;          // 0: until the window closes
    std::string screenshot;  // written after the last frame when --frames is given
    double speed = 60.0;     // simulated seconds per real second
};

// Input state shared with the GLFW callbacks.
struct ViewState {
    Camera camera;
    double speed = 60.0;  // simulated seconds per real second
    bool paused = false;
    double timeOffset = 0.0;  // simulated seconds since the start time
    bool dragging = false;
    double lastX = 0, lastY = 0;
    bool screenshot = false;
    const Logger* log = nullptr;
};

ViewState& state(GLFWwindow* w) { return *static_cast<ViewState*>(glfwGetWindowUserPointer(w)); }

void onKey(GLFWwindow* w, int key, int, int action, int) {
    if (action != GLFW_PRESS && action != GLFW_REPEAT) return;
    ViewState& s = state(w);
    switch (key) {
        case GLFW_KEY_ESCAPE: glfwSetWindowShouldClose(w, GLFW_TRUE); break;
        case GLFW_KEY_PERIOD: s.timeOffset += 10 * std::abs(s.speed); break;  // step forward
        case GLFW_KEY_COMMA: s.timeOffset -= 10 * std::abs(s.speed); break;   // step backward
        case GLFW_KEY_RIGHT_BRACKET: s.speed = std::clamp(s.speed * 10, -1e7, 1e7); break;
        case GLFW_KEY_LEFT_BRACKET: s.speed = s.speed / 10; break;
        case GLFW_KEY_R: s.speed = -s.speed; break;  // reverse
        case GLFW_KEY_SPACE: s.paused = !s.paused; break;
        case GLFW_KEY_P: s.screenshot = true; break;
        case GLFW_KEY_F:
            s.camera.projection = s.camera.projection == Projection::Fisheye ? Projection::Perspective : Projection::Fisheye;
            break;
        default: break;
    }
}

void onMouseButton(GLFWwindow* w, int button, int action, int) {
    ViewState& s = state(w);
    if (button != GLFW_MOUSE_BUTTON_LEFT) return;
    s.dragging = action == GLFW_PRESS;
    glfwGetCursorPos(w, &s.lastX, &s.lastY);
}

void onCursor(GLFWwindow* w, double x, double y) {
    ViewState& s = state(w);
    if (!s.dragging) return;
    int ww = 1, wh = 1;
    glfwGetWindowSize(w, &ww, &wh);
    // Drag the sky: one window height = one vertical field of view.
    double perPixel = s.camera.verticalFovRad / std::max(1, wh);
    s.camera.azimuthRad = std::fmod(s.camera.azimuthRad - (x - s.lastX) * perPixel + 4 * std::numbers::pi, 2 * std::numbers::pi);
    s.camera.altitudeRad = std::clamp(s.camera.altitudeRad + (y - s.lastY) * perPixel, -89.9 * kDeg, 89.9 * kDeg);
    s.lastX = x;
    s.lastY = y;
}

void onScroll(GLFWwindow* w, double, double dy) {
    ViewState& s = state(w);
    s.camera.verticalFovRad = std::clamp(s.camera.verticalFovRad * std::pow(1.1, -dy), 0.5 * kDeg, 150 * kDeg);
}

int run(const ViewOptions& o) {
    o.scene.validate();
    if (o.frames < 0) throw Error("--frames " + std::to_string(o.frames) + " must be >= 0");
    if (!(std::abs(o.speed) <= 1e7)) {
        char buf[96];
        std::snprintf(buf, sizeof buf, "--speed %g not in [-1e7, 1e7]", o.speed);
        throw Error(buf);
    }
    if (!o.screenshot.empty()) checkWritable(o.screenshot);
    Logger log;
    Camera cam = o.scene.camera();
    auto ctx = gl::WindowContext::create({.title = "welkin view", .width = cam.width, .height = cam.height}, log);
    ViewState s;
    s.camera = cam;
    s.speed = o.speed;
    s.log = &log;
    GLFWwindow* w = ctx->window();
    glfwSetWindowUserPointer(w, &s);
    glfwSetKeyCallback(w, onKey);
    glfwSetMouseButtonCallback(w, onMouseButton);
    glfwSetCursorPosCallback(w, onCursor);
    glfwSetScrollCallback(w, onScroll);

    SkyProcessor sky(SkyVars::earth(), log);
    sky.vars().set(keys::interactive, true);  // before the --var values, which may override it
    o.scene.apply(sky);
    sky.setAnimationTime(std::nullopt);  // the window animates with the wall clock
    const UtcInstant start = o.scene.instant();
    auto last = std::chrono::steady_clock::now();
    int frame = 0;
    while (!ctx->shouldClose()) {
        ctx->pollEvents();
        auto now = std::chrono::steady_clock::now();
        double dt = std::chrono::duration<double>(now - last).count();
        last = now;
        if (!s.paused) s.timeOffset += dt * s.speed;
        int fw = 0, fh = 0;
        ctx->framebufferSize(fw, fh);
        if (fw < 1 || fh < 1) continue;  // minimised
        s.camera.width = fw;
        s.camera.height = fh;
        sky.setCamera(s.camera);
        try {
            sky.setTime(start.plusSeconds(s.timeOffset));
        } catch (const Error& e) {  // ran past year 10000 or before -4000: stop there
            log.warn(e.what());
            s.timeOffset -= dt * s.speed;
            s.paused = true;
        }
        sky.renderFrame();
        sky.toneMapInto(0);
        ++frame;
        bool done = o.frames > 0 && frame >= o.frames;
        if (s.screenshot || (done && !o.screenshot.empty())) {
            std::string path = !o.screenshot.empty() && done
                                   ? o.screenshot
                                   : "welkin-" + std::to_string(std::time(nullptr)) + "-" + std::to_string(frame) + ".png";
            writeImage(sky.readToneMapped(), path);
            std::printf("screenshot %s (%s)\n", path.c_str(), sky.time().toIso().c_str());
            s.screenshot = false;
        }
        char title[160];
        std::snprintf(title, sizeof title, "welkin view  %s  x%g%s  fov %.1f", sky.time().toIso().c_str(), s.speed,
                      s.paused ? " (paused)" : "", s.camera.verticalFovRad / kDeg);
        glfwSetWindowTitle(w, title);
        ctx->swapBuffers();
        if (done) break;
    }
    sky.release();
    return 0;
}

Registrar reg("view", "show the scene in a window: drag to look, scroll to zoom, ./, time, ]/[ speed, P screenshot",
              [](CLI::App& sub) {
                  auto* o = new ViewOptions();  // lives for the whole process
                  o->scene.addTo(sub, false);
                  sub.add_option("--speed", o->speed, "simulated seconds per real second")->capture_default_str();
                  sub.add_option("--frames", o->frames, "exit after this many frames (0: run until closed)");
                  sub.add_option("--screenshot", o->screenshot, "with --frames: save the last frame here (.png)");
                  return [o]() { return run(*o); };
              });

}  // namespace
}  // namespace welkin::cli
