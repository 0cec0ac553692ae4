// welkin_host: a game's renderer with welkin as its sky. Its own glTF scene (terrain, houses,
// spheres), its own Y-up fly camera with reversed-Z depth and an infinite far plane, its own PBR
// shading lit only by welkin's outputs (the Sun and the Moon, the SH irradiance, the specular
// cube, the clouds' shadow), welkin's sky behind it and welkin's air in front of it.
//
//   welkin_host                                         a window: a day runs in a minute
//   welkin_host --headless --time 2026-06-21T13:00:00+02:00 --size 1280x720 --out noon.png
//
// Options (every one also in --help):
//   --headless            render one frame without a window (EGL) and write --out
//   --out FILE            .png (tone-mapped, sRGB) or .exr (HDR radiance, cd/m^2); headless only
//   --time ISO            the instant (ISO 8601 with an offset); default 2026-06-21T13:00:00+02:00
//   --size WxH            pixels, each in [16, 8192]; default 1280x720
//   --clouds C            none, fair or overcast (welkin's volumetric clouds); default none
//   --lat D --lon D       the world origin's place, degrees; default Malta, 35.9 N 14.5 E
//   --pos X,Y,Z           the camera, metres in the Y-up world (x east, y up, -z north); default 0,8,0
//   --yaw D --pitch D     heading from north through east, and elevation, degrees; default 270, -2
//   --fov D               vertical field of view, degrees in [10, 120]; default 50
//   --speed S             simulated seconds per real second in the window, [0, 1e6]; default 1440
//   --effects E           welkin (default): applyToScene() puts the clouds' shadows and the aerial
//                         perspective over the drawn scene; shader: the host's shader shades the
//                         clouds' shadows itself (welkin_cloudShadow), applyToScene() the air only
//   --shadows on|off      the scene's own shadows (a shadow map of the brighter of the Sun and
//                         the Moon over 800 m in front of the camera); default on
//   --overlay             draw the frame-time overlay into the headless image too
//   --frames N            window: quit after N frames, printing the mean frame, scene, welkin and
//                         lighting times of all but the first 10 (a benchmark run), N in [1, 1e6]
//   --assets DIR          the glTF assets (default: the source tree's examples/host/assets)
//
// Window keys: mouse look (hold the right button), W/A/S/D move, Q/E down/up, Shift x10,
// space pauses time, ]/[ doubles/halves its speed, F1 hides the overlay, Esc quits.
#include <welkin_host/host_app.hpp>
#include <welkin_host/overlay.hpp>

#include <welkin/gl/context.hpp>
#include <welkin/image.hpp>
#include <welkin/lighting.hpp>

#include <epoxy/gl.h>
#include <GLFW/glfw3.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <vector>

#ifndef WELKIN_HOST_ASSETS
#define WELKIN_HOST_ASSETS "assets"
#endif

namespace {

struct Options {
    bool headless = false;
    std::string out;
    std::string time = "2026-06-21T13:00:00+02:00";
    int width = 1280, height = 720;
    host::AppOptions app{.assetsDir = WELKIN_HOST_ASSETS};
    host::FlyCamera camera;
    double speed = 1440.0;
    bool overlay = false;
    int frames = 0;  // window: quit after this many frames and print the mean times (0: run until closed)
};

// A bad option: one line naming it and what it accepts.
struct UsageError : std::runtime_error {
    using std::runtime_error::runtime_error;
};

double parseNumber(const std::string& opt, const std::string& text, double lo, double hi) {
    char* end = nullptr;
    const double v = std::strtod(text.c_str(), &end);
    if (text.empty() || *end != '\0' || !std::isfinite(v) || v < lo || v > hi) {
        char range[96];
        std::snprintf(range, sizeof range, "[%g, %g]", lo, hi);
        throw UsageError(opt + " '" + text + "' must be a number in " + range);
    }
    return v;
}

void usage() {
    std::printf(
        "usage: welkin_host [--headless --out FILE.png|.exr] [--time ISO] [--size WxH] [--clouds none|fair|overcast]\n"
        "                   [--lat DEG --lon DEG] [--pos X,Y,Z] [--yaw DEG] [--pitch DEG] [--fov DEG] [--speed S]\n"
        "                   [--effects welkin|shader] [--shadows on|off] [--overlay] [--frames N] [--assets DIR]\n"
        "A game's scene under welkin's sky. Default place: Malta (35.9 N, 14.5 E), camera 8 m up looking west.\n"
        "Window: right mouse look, WASD/QE move (Shift x10), space pause, ]/[ time speed, F1 overlay, Esc quit.\n");
}

Options parse(int argc, char** argv) {
    Options o;
    auto value = [&](int& i, const std::string& opt) -> std::string {
        if (i + 1 >= argc) throw UsageError(opt + " needs a value");
        return argv[++i];
    };
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        if (a == "--help" || a == "-h") {
            usage();
            std::exit(0);
        } else if (a == "--headless") {
            o.headless = true;
        } else if (a == "--out") {
            o.out = value(i, a);
        } else if (a == "--time") {
            o.time = value(i, a);
        } else if (a == "--size") {
            const std::string v = value(i, a);
            int w = 0, h = 0;
            char tail = 0;
            if (std::sscanf(v.c_str(), "%dx%d%c", &w, &h, &tail) != 2 || w < 16 || h < 16 || w > 8192 || h > 8192)
                throw UsageError("--size '" + v + "' must be WxH with W and H in [16, 8192]");
            o.width = w, o.height = h;
        } else if (a == "--clouds") {
            const std::string v = value(i, a);
            try {
                o.app.clouds = host::parseCloudCover(v);
            } catch (const std::invalid_argument& e) {
                throw UsageError(e.what());
            }
        } else if (a == "--lat") {
            o.app.site.latitudeDeg = parseNumber(a, value(i, a), -90, 90);
        } else if (a == "--lon") {
            o.app.site.longitudeDeg = parseNumber(a, value(i, a), -180, 180);
        } else if (a == "--pos") {
            const std::string v = value(i, a);
            double x, y, z;
            char tail = 0;
            if (std::sscanf(v.c_str(), "%lf,%lf,%lf%c", &x, &y, &z, &tail) != 3 || !std::isfinite(x) || !std::isfinite(y) ||
                !std::isfinite(z) || std::abs(x) > 1e5 || std::abs(z) > 1e5 || y < -1e3 || y > 1e5)
                throw UsageError("--pos '" + v + "' must be X,Y,Z in metres with |X|, |Z| <= 1e5 and Y in [-1e3, 1e5]");
            o.camera.position = {x, y, z};
        } else if (a == "--yaw") {
            o.camera.yawDeg = parseNumber(a, value(i, a), -360, 360);
        } else if (a == "--pitch") {
            o.camera.pitchDeg = parseNumber(a, value(i, a), -89, 89);
        } else if (a == "--fov") {
            o.camera.verticalFovDeg = parseNumber(a, value(i, a), 10, 120);
        } else if (a == "--speed") {
            o.speed = parseNumber(a, value(i, a), 0, 1e6);
        } else if (a == "--effects") {
            const std::string v = value(i, a);
            if (v == "welkin") o.app.effects = host::AppOptions::Effects::ApplyToScene;
            else if (v == "shader") o.app.effects = host::AppOptions::Effects::Shader;
            else throw UsageError("--effects '" + v + "' is not one of welkin, shader");
        } else if (a == "--shadows") {
            const std::string v = value(i, a);
            if (v != "on" && v != "off") throw UsageError("--shadows '" + v + "' is not one of on, off");
            o.app.shadows.enabled = v == "on";
        } else if (a == "--frames") {
            o.frames = int(parseNumber(a, value(i, a), 1, 1e6));
        } else if (a == "--overlay") {
            o.overlay = true;
        } else if (a == "--assets") {
            o.app.assetsDir = value(i, a);
        } else {
            throw UsageError("unknown option '" + a + "' (see --help)");
        }
    }
    if (o.headless && o.out.empty()) throw UsageError("--headless needs --out FILE.png or FILE.exr");
    if (!o.headless && !o.out.empty()) throw UsageError("--out is for --headless (the window saves nothing)");
    if (o.headless && o.frames > 0) throw UsageError("--frames is for the window (--headless renders one frame)");
    if (!o.out.empty()) {
        const auto dot = o.out.rfind('.');
        const std::string ext = dot == std::string::npos ? "" : o.out.substr(dot);
        if (ext != ".png" && ext != ".exr") throw UsageError("--out '" + o.out + "' must end in .png or .exr");
    }
    return o;
}

welkin::UtcInstant parseTime(const std::string& iso) {
    try {
        return welkin::UtcInstant::parse(iso);
    } catch (const std::exception& e) {
        throw UsageError(std::string("--time: ") + e.what());
    }
}

std::vector<std::string> overlayLines(host::HostApp& app, const welkin::UtcInstant& t, double speed, bool paused) {
    const host::FrameTimes ft = app.times();
    char line[256];
    std::vector<std::string> lines;
    std::snprintf(line, sizeof line, "frame %.1f ms (%.0f fps)   scene %.2f ms   welkin %.2f ms   lighting %.2f ms", ft.frameMs,
                  ft.frameMs > 0 ? 1000.0 / ft.frameMs : 0.0, ft.sceneMs, ft.welkinMs, ft.lightingMs);
    lines.emplace_back(line);
    const auto& L = app.sky().lighting();
    const double sunAlt = std::asin(std::clamp(L.sun.directionEnu.z, -1.0, 1.0)) * 180.0 / 3.14159265358979;
    std::snprintf(line, sizeof line, "%s   time x%.0f%s   Sun %.1f deg, %.0f lux   Moon %.3f lux   EV100 %.1f", t.toIso().c_str(), speed,
                  paused ? " (paused)" : "", sunAlt, L.sun.illuminanceLux, L.moon.illuminanceLux, app.sky().lastEv100());
    lines.emplace_back(line);
    lines.emplace_back("right mouse: look   WASD/QE: move (Shift x10)   space: pause   ] [: time speed   F1: overlay   Esc: quit");
    return lines;
}

// The assets folder must hold the three glTF files (checked before any GL work).
void checkAssets(const std::string& dir) {
    for (const char* f : {"terrain.gltf", "buildings.gltf", "spheres.gltf"})
        if (!std::filesystem::is_regular_file(std::filesystem::path(dir) / f))
            throw UsageError("--assets '" + dir + "' has no " + f + " (the folder examples/host/assets, or make_assets.py's output)");
}

int runHeadless(const Options& o) {
    try {
        welkin::checkWritable(o.out);
    } catch (const std::exception& e) {
        throw UsageError(std::string("--out: ") + e.what());
    }
    const welkin::UtcInstant t = parseTime(o.time);
    welkin::Logger log;
    auto context = welkin::gl::HeadlessContext::create({}, log);
    host::HostApp app(o.app, log);
    app.sky().setAnimationTime(0.0);  // deterministic: the same inputs give the same image
    app.render(t, o.camera, o.width, o.height);
    const bool exr = o.out.size() > 4 && o.out.compare(o.out.size() - 4, 4, ".exr") == 0;
    if (exr) {
        welkin::writeImage(app.readHdr(), o.out);
    } else if (o.overlay) {
        // The tone-mapped frame with the overlay on top, read back from an offscreen target.
        host::GlName tex = host::GlName::texture(GL_TEXTURE_2D), fbo = host::GlName::framebuffer();
        glTextureStorage2D(tex.id(), 1, GL_RGBA8, o.width, o.height);
        glNamedFramebufferTexture(fbo.id(), GL_COLOR_ATTACHMENT0, tex.id(), 0);
        app.present(fbo.id());
        app.finishTimers();
        host::TextOverlay overlay;
        glBindFramebuffer(GL_FRAMEBUFFER, fbo.id());
        glViewport(0, 0, o.width, o.height);
        overlay.draw(overlayLines(app, t, 0.0, true), o.width, o.height);
        glBindFramebuffer(GL_FRAMEBUFFER, 0);
        std::vector<unsigned char> px(size_t(o.width) * size_t(o.height) * 4);
        glGetTextureImage(tex.id(), 0, GL_RGBA, GL_UNSIGNED_BYTE, GLsizei(px.size()), px.data());
        welkin::Image img{o.width, o.height, 3, std::vector<float>(size_t(o.width) * size_t(o.height) * 3)};
        for (int y = 0; y < o.height; ++y)
            for (int x = 0; x < o.width; ++x)
                for (int c = 0; c < 3; ++c)
                    img.at(x, y, c) = px[(size_t(o.height - 1 - y) * size_t(o.width) + size_t(x)) * 4 + size_t(c)] / 255.0f;
        welkin::writeImage(img, o.out);
    } else {
        welkin::writeImage(app.readToneMapped(), o.out);
    }
    std::printf("%s: %s at %.4f N %.4f E, %dx%d, EV100 %.2f\n", o.out.c_str(), t.toIso().c_str(), o.app.site.latitudeDeg,
                o.app.site.longitudeDeg, o.width, o.height, app.sky().lastEv100());
    return 0;
}

int runWindow(const Options& o) {
    welkin::UtcInstant t = parseTime(o.time);
    welkin::Logger log;
    auto window = welkin::gl::WindowContext::create({.title = "welkin host example", .width = o.width, .height = o.height}, log);
    host::AppOptions appOptions = o.app;
    appOptions.interactive = true;  // welkin may spread its work over frames
    host::HostApp app(appOptions, log);
    host::TextOverlay overlay;
    host::FlyCamera camera = o.camera;
    GLFWwindow* win = window->window();
    double speed = o.speed;
    bool paused = false, showOverlay = true;
    bool prevSpace = false, prevF1 = false, prevUp = false, prevDown = false, looking = false;
    double lastX = 0, lastY = 0;
    auto last = std::chrono::steady_clock::now();
    int frame = 0, counted = 0;
    host::FrameTimes sum;
    const int warmUp = 10;  // the first frames build welkin's tables and compile programs
    while (!window->shouldClose() && (o.frames == 0 || frame < o.frames)) {
        window->pollEvents();
        const auto now = std::chrono::steady_clock::now();
        const double dt = std::chrono::duration<double>(now - last).count();
        last = now;
        if (glfwGetKey(win, GLFW_KEY_ESCAPE) == GLFW_PRESS) break;
        auto pressed = [&](int key, bool& prev) {
            const bool down = glfwGetKey(win, key) == GLFW_PRESS;
            const bool edge = down && !prev;
            prev = down;
            return edge;
        };
        if (pressed(GLFW_KEY_SPACE, prevSpace)) paused = !paused;
        if (pressed(GLFW_KEY_F1, prevF1)) showOverlay = !showOverlay;
        if (pressed(GLFW_KEY_RIGHT_BRACKET, prevUp)) speed = std::min(speed * 2.0, 1e6);
        if (pressed(GLFW_KEY_LEFT_BRACKET, prevDown)) speed = speed / 2.0;
        // Mouse look while the right button is held.
        double mx, my;
        glfwGetCursorPos(win, &mx, &my);
        const bool rmb = glfwGetMouseButton(win, GLFW_MOUSE_BUTTON_RIGHT) == GLFW_PRESS;
        if (rmb && looking) {
            camera.yawDeg = std::fmod(camera.yawDeg + 0.15 * (mx - lastX) + 360.0, 360.0);
            camera.pitchDeg = std::clamp(camera.pitchDeg - 0.15 * (my - lastY), -89.0, 89.0);
        }
        looking = rmb, lastX = mx, lastY = my;
        const double v = (glfwGetKey(win, GLFW_KEY_LEFT_SHIFT) == GLFW_PRESS ? 100.0 : 10.0) * dt;  // m/s
        auto key = [&](int k) { return glfwGetKey(win, k) == GLFW_PRESS ? 1.0 : 0.0; };
        camera.position += v * (key(GLFW_KEY_W) - key(GLFW_KEY_S)) * camera.forward();
        camera.position += v * (key(GLFW_KEY_D) - key(GLFW_KEY_A)) * camera.right();
        camera.position.y += v * (key(GLFW_KEY_E) - key(GLFW_KEY_Q));
        if (!paused) t = t.plusSeconds(dt * speed);

        int w = 0, h = 0;
        window->framebufferSize(w, h);
        if (w < 1 || h < 1) continue;  // minimised
        app.render(t, camera, w, h);
        app.present(0);
        if (showOverlay) {
            glBindFramebuffer(GL_FRAMEBUFFER, 0);
            glViewport(0, 0, w, h);
            overlay.draw(overlayLines(app, t, speed, paused), w, h);
        }
        window->swapBuffers();
        if (++frame > warmUp) {
            const host::FrameTimes ft = app.times();
            sum.frameMs += ft.frameMs, sum.sceneMs += ft.sceneMs, sum.welkinMs += ft.welkinMs, sum.lightingMs += ft.lightingMs;
            ++counted;
        }
    }
    if (o.frames > 0 && counted > 0)
        std::printf("%d frames at %dx%d (after %d warm-up), mean: frame %.2f ms, scene %.2f ms (GPU), welkin %.2f ms (GPU), "
                    "lighting %.2f ms (welkin's stats)\n",
                    counted, o.width, o.height, warmUp, sum.frameMs / counted, sum.sceneMs / counted, sum.welkinMs / counted,
                    sum.lightingMs / counted);
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    try {
        const Options o = parse(argc, argv);
        checkAssets(o.app.assetsDir);
        return o.headless ? runHeadless(o) : runWindow(o);
    } catch (const std::exception& e) {
        std::fprintf(stderr, "welkin_host: %s\n", e.what());
        return 1;
    }
}
