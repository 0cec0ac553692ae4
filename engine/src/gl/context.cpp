#include <welkin/error.hpp>
#include <welkin/gl/context.hpp>

#include <epoxy/gl.h>
// epoxy/gl.h must come before the EGL and GLFW headers.
#include <EGL/egl.h>
#include <EGL/eglext.h>
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

#include <cstdio>
#include <cstring>
#include <mutex>
#include <string>
#include <vector>

#if defined(__SANITIZE_ADDRESS__)
#include <dlfcn.h>
#include <link.h>
#endif

namespace welkin::gl {

std::string Context::description() const {
    const char* v = reinterpret_cast<const char*>(glGetString(GL_VERSION));
    const char* r = reinterpret_cast<const char*>(glGetString(GL_RENDERER));
    return std::string(v ? v : "?") + " | " + (r ? r : "?");
}

namespace {
void GLAPIENTRY debugCallback(GLenum, GLenum type, GLuint id, GLenum severity, GLsizei length, const GLchar* message,
                              const void* user) {
    const Logger* log = static_cast<const Logger*>(user);
    LogLevel level = LogLevel::Debug;
    if (severity == GL_DEBUG_SEVERITY_HIGH || type == GL_DEBUG_TYPE_ERROR)
        level = LogLevel::Error;
    else if (severity == GL_DEBUG_SEVERITY_MEDIUM && type != GL_DEBUG_TYPE_PERFORMANCE)
        level = LogLevel::Warning;
    else if (type == GL_DEBUG_TYPE_PERFORMANCE)  // hints (NVIDIA's buffer-placement notes): not warnings
        level = LogLevel::Info;
    else if (severity == GL_DEBUG_SEVERITY_LOW)
        level = LogLevel::Info;
    std::string m = "GL[" + std::to_string(id) + "] " + std::string(message, size_t(length < 0 ? 0 : length));
    log->log(level, m);
}
}  // namespace

void Context::setupDebugOutput(bool debug, const Logger& log) {
    if (!debug) return;
    log_ = log;
    glEnable(GL_DEBUG_OUTPUT);
    glEnable(GL_DEBUG_OUTPUT_SYNCHRONOUS);
    glDebugMessageCallback(debugCallback, &log_);
    glDebugMessageControl(GL_DONT_CARE, GL_DONT_CARE, GL_DONT_CARE, 0, nullptr, GL_TRUE);
}

// --- Headless (EGL surfaceless) ------------------------------------------------------------------

namespace {
const char* eglErrorName(EGLint e) {
    switch (e) {
        case EGL_SUCCESS: return "EGL_SUCCESS";
        case EGL_NOT_INITIALIZED: return "EGL_NOT_INITIALIZED";
        case EGL_BAD_ALLOC: return "EGL_BAD_ALLOC";
        case EGL_BAD_CONFIG: return "EGL_BAD_CONFIG";
        case EGL_BAD_CONTEXT: return "EGL_BAD_CONTEXT";
        case EGL_BAD_DISPLAY: return "EGL_BAD_DISPLAY";
        case EGL_BAD_MATCH: return "EGL_BAD_MATCH";
        case EGL_BAD_PARAMETER: return "EGL_BAD_PARAMETER";
        case EGL_BAD_ATTRIBUTE: return "EGL_BAD_ATTRIBUTE";
        default: return "EGL error";
    }
}
}  // namespace

namespace {
// The first GPU through EGL_EXT_platform_device (NVIDIA's headless path, where the surfaceless
// platform may be missing); EGL_NO_DISPLAY when the extension or a device is absent.
EGLDisplay deviceDisplay() {
    const char* ext = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
    if (!ext || !std::strstr(ext, "EGL_EXT_platform_device")) return EGL_NO_DISPLAY;
    auto query = reinterpret_cast<PFNEGLQUERYDEVICESEXTPROC>(eglGetProcAddress("eglQueryDevicesEXT"));
    if (!query) return EGL_NO_DISPLAY;
    EGLDeviceEXT devices[8];
    EGLint n = 0;
    if (!query(8, devices, &n) || n < 1) return EGL_NO_DISPLAY;
    for (EGLint i = 0; i < n; ++i) {
        EGLDisplay d = eglGetPlatformDisplay(EGL_PLATFORM_DEVICE_EXT, devices[i], nullptr);
        EGLint major = 0, minor = 0;
        if (d != EGL_NO_DISPLAY && eglInitialize(d, &major, &minor)) return d;
    }
    return EGL_NO_DISPLAY;
}
}  // namespace

std::unique_ptr<HeadlessContext> HeadlessContext::create(const ContextOptions& options, const Logger& log) {
    // Mesa's surfaceless platform first (llvmpipe or a Mesa GPU driver), then an EGL device.
    EGLDisplay dpy = eglGetPlatformDisplay(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
    EGLint major = 0, minor = 0;
    EGLint surfacelessError = EGL_SUCCESS;
    if (dpy == EGL_NO_DISPLAY || !eglInitialize(dpy, &major, &minor)) {
        surfacelessError = eglGetError();
        dpy = deviceDisplay();
    }
    if (dpy == EGL_NO_DISPLAY)
        throw Error(std::string("HeadlessContext: no EGL surfaceless display (") + eglErrorName(surfacelessError) +
                    ") and no EGL device; install Mesa's libegl-mesa0 and libgl1-mesa-dri");
    if (!eglBindAPI(EGL_OPENGL_API)) {
        eglTerminate(dpy);
        throw Error("HeadlessContext: EGL cannot bind the desktop OpenGL API");
    }
    const EGLint attribs[] = {EGL_CONTEXT_MAJOR_VERSION, 4, EGL_CONTEXT_MINOR_VERSION, 5,
                              EGL_CONTEXT_OPENGL_PROFILE_MASK, EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT,
                              EGL_CONTEXT_OPENGL_DEBUG, options.debug ? EGL_TRUE : EGL_FALSE, EGL_NONE};
    EGLContext ctx = eglCreateContext(dpy, EGL_NO_CONFIG_KHR, EGL_NO_CONTEXT, attribs);
    if (ctx == EGL_NO_CONTEXT) {
        EGLint err = eglGetError();
        eglTerminate(dpy);
        throw Error(std::string("HeadlessContext: OpenGL 4.5 core context not available (") + eglErrorName(err) + ")");
    }
    std::unique_ptr<HeadlessContext> c(new HeadlessContext());
    c->display_ = dpy;
    c->context_ = ctx;
    c->makeCurrent();
    if (epoxy_gl_version() < 45) throw Error("HeadlessContext: OpenGL 4.5 core required, got " + c->description());
    c->setupDebugOutput(options.debug, log);
    return c;
}

HeadlessContext::~HeadlessContext() {
    if (display_) {
        // Release this context only if it is the current one: another context may be in use.
        if (eglGetCurrentContext() == context_) eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
        if (context_) eglDestroyContext(display_, context_);
        // The display is shared by every context in the process (EGL returns the same handle),
        // so it is not terminated here: another context may still be alive.
    }
}

void HeadlessContext::makeCurrent() {
    if (!eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, context_))
        throw Error(std::string("HeadlessContext: eglMakeCurrent failed (") + eglErrorName(eglGetError()) + ")");
}

// --- Window (GLFW) -----------------------------------------------------------------------------

namespace {
std::mutex gGlfwMutex;
int gGlfwUsers = 0;  // windows alive; GLFW is a process-wide library by design

// Sanitizer builds only (the nightly run's LeakSanitizer): Mesa's GLX loader unloads its DRI driver
// (swrast_dri.so) when the window's display closes, and the driver's state that its own globals
// still pointed to is then reported as leaked ("<unknown module>" frames, 240 bytes per `welkin
// view`; measured 2026-11-27: none with the driver kept loaded). The driver is marked not to be
// unloaded (RTLD_NODELETE), so LeakSanitizer sees that state reachable as the EGL path's is and its
// suppressions (scripts/lsan.supp) name the module. Release builds do nothing here.
void keepGlDriversLoaded() {
#if defined(__SANITIZE_ADDRESS__)
    std::vector<std::string> drivers;
    dl_iterate_phdr(
        [](dl_phdr_info* info, size_t, void* out) -> int {
            if (info->dlpi_name && std::strstr(info->dlpi_name, "_dri.so"))
                static_cast<std::vector<std::string>*>(out)->push_back(info->dlpi_name);
            return 0;
        },
        &drivers);
    for (const std::string& d : drivers) dlopen(d.c_str(), RTLD_NOW | RTLD_NOLOAD | RTLD_NODELETE);  // a reference never closed
#endif
}
}  // namespace

std::unique_ptr<WindowContext> WindowContext::create(const ContextOptions& o, const Logger& log) {
    if (o.width < 1 || o.width > 16384 || o.height < 1 || o.height > 16384)
        throw Error("WindowContext: size " + std::to_string(o.width) + "x" + std::to_string(o.height) +
                    " not in [1, 16384]");
    {
        std::lock_guard lock(gGlfwMutex);
        if (gGlfwUsers == 0 && !glfwInit()) {
            const char* d = nullptr;
            glfwGetError(&d);
            throw Error(std::string("WindowContext: GLFW cannot start (") + (d ? d : "no display") +
                        "); use a headless render or xvfb-run");
        }
        ++gGlfwUsers;
    }
    glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 4);
    glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 5);
    glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
    glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
    glfwWindowHint(GLFW_OPENGL_DEBUG_CONTEXT, o.debug ? GLFW_TRUE : GLFW_FALSE);
    glfwWindowHint(GLFW_VISIBLE, o.visible ? GLFW_TRUE : GLFW_FALSE);
    // sRGB-capable: the tone map then lets the framebuffer encode on write (docs/eye.md).
    glfwWindowHint(GLFW_SRGB_CAPABLE, GLFW_TRUE);
    GLFWwindow* w = glfwCreateWindow(o.width, o.height, o.title.c_str(), nullptr, nullptr);
    if (!w) {
        const char* d = nullptr;
        glfwGetError(&d);
        std::lock_guard lock(gGlfwMutex);
        if (--gGlfwUsers == 0) glfwTerminate();
        throw Error(std::string("WindowContext: cannot open a GL 4.5 core window (") + (d ? d : "unknown") + ")");
    }
    std::unique_ptr<WindowContext> c(new WindowContext());
    c->window_ = w;
    c->makeCurrent();
    keepGlDriversLoaded();
    glfwSwapInterval(o.vsync ? 1 : 0);
    c->setupDebugOutput(o.debug, log);
    return c;
}

WindowContext::~WindowContext() {
    if (window_) glfwDestroyWindow(window_);
    std::lock_guard lock(gGlfwMutex);
    if (--gGlfwUsers == 0) glfwTerminate();
}
void WindowContext::makeCurrent() { glfwMakeContextCurrent(window_); }
bool WindowContext::shouldClose() const { return glfwWindowShouldClose(window_); }
void WindowContext::swapBuffers() { glfwSwapBuffers(window_); }
void WindowContext::pollEvents() { glfwPollEvents(); }
void WindowContext::framebufferSize(int& w, int& h) const { glfwGetFramebufferSize(window_, &w, &h); }

}  // namespace welkin::gl
