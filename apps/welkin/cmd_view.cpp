// welkin view: the same scene as `welkin render` in a GLFW window, with mouse-look, zoom, time
// controls, screenshots and a Dear ImGui panel (view_panel.hpp, docs/viewer.md).
#include "command.hpp"
#include "scene_options.hpp"
#include "view_panel.hpp"

#include <welkin/error.hpp>
#include <welkin/gl/context.hpp>
#include <welkin/image.hpp>
#include <welkin/keys.hpp>
#include <welkin/processor.hpp>

#include <epoxy/gl.h>
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <memory>
#include <numbers>

namespace welkin::cli {

namespace {

constexpr double kDeg = std::numbers::pi / 180;

struct ViewOptions {
    SceneOptions scene;
    int frames = 0;          // 0: until the window closes
    std::string screenshot;  // written after the last frame when --frames is given
    double speed = 60.0;     // simulated seconds per real second
    bool noPanel = false;    // start with the panel hidden (H or Tab shows it)
    bool expandPanel = false;  // open every section of the panel
};

// Input state shared with the GLFW callbacks.
struct ViewState {
    Camera camera;
    ViewClock clock;
    bool dragging = false;
    double lastX = 0, lastY = 0;
    bool screenshot = false;
    const Logger* log = nullptr;
    ViewPanel* panel = nullptr;  // the panel's wishes: when it has the mouse or keyboard, the view ignores them
};

ViewState& state(GLFWwindow* w) { return *static_cast<ViewState*>(glfwGetWindowUserPointer(w)); }

void onKey(GLFWwindow* w, int key, int, int action, int) {
    if (action != GLFW_PRESS && action != GLFW_REPEAT) return;
    ViewState& s = state(w);
    if (s.panel && s.panel->wantsKeyboard()) return;  // typing into the panel
    ViewClock& c = s.clock;
    switch (key) {
        case GLFW_KEY_ESCAPE: glfwSetWindowShouldClose(w, GLFW_TRUE); break;
        case GLFW_KEY_PERIOD: c.offsetSeconds += 10 * std::abs(c.speed); break;  // step forward
        case GLFW_KEY_COMMA: c.offsetSeconds -= 10 * std::abs(c.speed); break;   // step backward
        case GLFW_KEY_RIGHT_BRACKET: c.speed = std::clamp(c.speed * 10, -1e7, 1e7); break;
        case GLFW_KEY_LEFT_BRACKET: c.speed = c.speed / 10; break;
        case GLFW_KEY_R: c.speed = -c.speed; break;  // reverse
        case GLFW_KEY_SPACE: c.paused = !c.paused; break;
        case GLFW_KEY_H:
        case GLFW_KEY_TAB:
            if (s.panel) s.panel->visible = !s.panel->visible;
            break;
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
    s.dragging = action == GLFW_PRESS && !(s.panel && s.panel->wantsMouse());  // a press on the panel is the panel's
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
    if (s.panel && s.panel->wantsMouse()) return;
    s.camera.verticalFovRad = std::clamp(s.camera.verticalFovRad * std::pow(1.1, -dy), 0.5 * kDeg, 150 * kDeg);
}

// What the window shows (the sky and the panel over it), read from the back buffer before the
// swap: RGB in [0, 1] as displayed (sRGB-encoded), top row first.
Image readDisplayed(int width, int height) {
    std::vector<unsigned char> rgba(size_t(width) * size_t(height) * 4);
    GLint fbo = 0, readBuffer = 0, packAlign = 4;
    glGetIntegerv(GL_READ_FRAMEBUFFER_BINDING, &fbo);
    glGetIntegerv(GL_READ_BUFFER, &readBuffer);
    glGetIntegerv(GL_PACK_ALIGNMENT, &packAlign);
    glBindFramebuffer(GL_READ_FRAMEBUFFER, 0);
    glReadBuffer(GL_BACK);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glReadPixels(0, 0, width, height, GL_RGBA, GL_UNSIGNED_BYTE, rgba.data());
    glPixelStorei(GL_PACK_ALIGNMENT, packAlign);
    glBindFramebuffer(GL_READ_FRAMEBUFFER, GLuint(fbo));
    glReadBuffer(GLenum(readBuffer));
    Image img{width, height, 3, std::vector<float>(size_t(width) * size_t(height) * 3)};
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x)
            for (int c = 0; c < 3; ++c) img.at(x, height - 1 - y, c) = float(rgba[(size_t(y) * size_t(width) + size_t(x)) * 4 + size_t(c)]) / 255.0f;
    return img;
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
    s.clock.speed = o.speed;
    s.clock.start = o.scene.instant();
    s.log = &log;
    GLFWwindow* w = ctx->window();
    glfwSetWindowUserPointer(w, &s);
    glfwSetKeyCallback(w, onKey);
    glfwSetMouseButtonCallback(w, onMouseButton);
    glfwSetCursorPosCallback(w, onCursor);
    glfwSetScrollCallback(w, onScroll);
    ViewPanel panel(w);  // after the callbacks above: its GLFW backend chains them
    panel.visible = !o.noPanel;
    panel.expandAll = o.expandPanel;
    s.panel = &panel;

    // Timing brackets every element and generator call with glFinish: the panel's frame-time
    // readout. The view runs without it when started without the panel.
    SkyProcessor sky(SkyVars::earth(), log, ProcessorOptions{.timing = !o.noPanel});
    sky.vars().set(keys::interactive, true);  // before the --var values, which may override it
    o.scene.apply(sky);
    sky.setAnimationTime(std::nullopt);  // the window animates with the wall clock
    auto last = std::chrono::steady_clock::now();
    int frame = 0;
    std::string shownTitle;
    while (!ctx->shouldClose()) {
        ctx->pollEvents();
        auto now = std::chrono::steady_clock::now();
        double dt = std::chrono::duration<double>(now - last).count();
        last = now;
        ViewClock& c = s.clock;
        if (!c.paused) c.offsetSeconds += dt * c.speed;
        int fw = 0, fh = 0;
        ctx->framebufferSize(fw, fh);
        if (fw < 1 || fh < 1) continue;  // minimised
        s.camera.width = fw;
        s.camera.height = fh;
        sky.setCamera(s.camera);
        try {
            sky.setTime(c.start.plusSeconds(c.offsetSeconds));
        } catch (const Error& e) {  // ran past year 10000 or before -4000: stop there
            log.warn(e.what());
            c.offsetSeconds -= dt * c.speed;
            c.paused = true;
        }
        sky.renderFrame();
        sky.toneMapInto(0);
        if (frame == 0)  // the window's sRGB-capable framebuffer encodes the tone map's output (docs/eye.md)
            std::printf("welkin view: the window encodes sRGB on write: %s\n",
                        sky.stats()["tonemap_srgb_target"].get<bool>() ? "yes" : "no (the tone map encodes)");
        if (panel.visible) panel.draw(sky, c, s.camera, log);
        ++frame;
        bool done = o.frames > 0 && frame >= o.frames;
        if (s.screenshot || (done && !o.screenshot.empty())) {
            std::string path = !o.screenshot.empty() && done
                                   ? o.screenshot
                                   : "welkin-" + std::to_string(std::time(nullptr)) + "-" + std::to_string(frame) + ".png";
            // What is displayed, the panel included (docs/viewer.md): hide the panel (H) for the sky alone.
            writeImage(readDisplayed(fw, fh), path);
            std::printf("screenshot %s (%s)\n", path.c_str(), sky.time().toIso().c_str());
            s.screenshot = false;
        }
        char title[160];
        std::snprintf(title, sizeof title, "welkin view  %s  x%g%s  fov %.1f", sky.time().toIso().c_str(), c.speed,
                      c.paused ? " (paused)" : "", s.camera.verticalFovRad / kDeg);
        if (title != shownTitle) {  // X11 properties and a flush per call: only when it changes (a still view: once)
            glfwSetWindowTitle(w, title);
            shownTitle = title;
        }
        ctx->swapBuffers();
        if (done) break;
    }
    sky.release();
    return 0;
}

Registrar reg("view", "show the scene in a window with a settings panel: drag to look, scroll to zoom, ./, time, ]/[ speed, H panel, P screenshot",
              [](CLI::App& sub) {
                  auto o = std::make_shared<ViewOptions>();  // the action below owns it
                  o->scene.addTo(sub, false);
                  sub.add_option("--speed", o->speed, "simulated seconds per real second")->capture_default_str();
                  sub.add_option("--frames", o->frames, "exit after this many frames (0: run until closed)");
                  sub.add_option("--screenshot", o->screenshot, "with --frames: save the last frame as displayed, panel included, here (.png)");
                  sub.add_flag("--panel-expand", o->expandPanel, "open every section of the panel and every element's keys (screenshots)");
                  sub.add_flag("--no-panel", o->noPanel, "start with the panel hidden (H or Tab shows it) and without per-element timing");
                  return [o]() { return run(*o); };
              });

}  // namespace
}  // namespace welkin::cli
