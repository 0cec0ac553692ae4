// OpenGL 4.5 core contexts: headless (EGL surfaceless, for tests, CI and offline renders) and
// windowed (GLFW, for the viewer and game loops), behind one small interface.
//
//   welkin::Logger log;
//   auto ctx = welkin::gl::HeadlessContext::create({.debug = true}, log);   // throws if no EGL/GL 4.5
//   ctx->makeCurrent();
//   ... create welkin::gl objects, run a SkyProcessor ...
//
//   auto win = welkin::gl::WindowContext::create({.title = "sky", .width = 1280, .height = 720}, log);
//   while (!win->shouldClose()) { win->pollEvents(); ...; win->swapBuffers(); }
#pragma once
#include <welkin/log.hpp>

#include <memory>
#include <string>

struct GLFWwindow;

namespace welkin::gl {

struct ContextOptions {
    bool debug = false;            ///< create a debug context and route GL debug output to the logger
    std::string title = "welkin";  ///< window title (windowed only)
    int width = 1280;              ///< window size in screen pixels (windowed only), [1, 16384]
    int height = 720;
    bool vsync = true;             ///< windowed only
    bool visible = true;           ///< windowed only
};

/// A current-able GL 4.5 core context. Destroying it destroys the context: destroy every GL
/// object first, with this context current (GL names belong to the context that made them).
class Context {
public:
    virtual ~Context() = default;
    Context(const Context&) = delete;
    Context& operator=(const Context&) = delete;

    virtual void makeCurrent() = 0;
    /// "4.5 (Core Profile) Mesa ... | llvmpipe ..." for logs and --stats.
    std::string description() const;

protected:
    Context() = default;
    /// Installs the debug-output callback (if requested) once the context is current. The
    /// context keeps its own copy of `log`, so the caller's logger may go out of scope.
    void setupDebugOutput(bool debug, const Logger& log);

private:
    Logger log_;
};

class HeadlessContext final : public Context {
public:
    /// Creates a surfaceless EGL context (Mesa EGL_PLATFORM_SURFACELESS_MESA). Throws
    /// welkin::Error with a one-line reason if EGL or GL 4.5 core is not available.
    static std::unique_ptr<HeadlessContext> create(const ContextOptions& options, const Logger& log);
    ~HeadlessContext() override;
    void makeCurrent() override;

private:
    HeadlessContext() = default;
    void* display_ = nullptr;
    void* context_ = nullptr;
};

class WindowContext final : public Context {
public:
    /// Opens a GLFW window with a GL 4.5 core context. Throws welkin::Error if no display.
    static std::unique_ptr<WindowContext> create(const ContextOptions& options, const Logger& log);
    ~WindowContext() override;
    void makeCurrent() override;

    GLFWwindow* window() const { return window_; }
    bool shouldClose() const;
    void swapBuffers();
    void pollEvents();
    /// Framebuffer size in pixels.
    void framebufferSize(int& width, int& height) const;

private:
    WindowContext() = default;
    GLFWwindow* window_ = nullptr;
};

}  // namespace welkin::gl
