// GL tier: headless context, RAII wrappers, shader errors, compositing math, projections on the
// GPU, depth-tested embedding, automatic exposure, independent processors.
#include <catch2/catch.hpp>

#include "gl_test_context.hpp"

#include <epoxy/gl.h>

#include <welkin/embedded/engine_shaders.hpp>
#include <welkin/error.hpp>
#include <welkin/gl/objects.hpp>
#include <welkin/gl/projection_programs.hpp>
#include <welkin/gl/shader.hpp>
#include <welkin/eye.hpp>
#include <welkin/keys.hpp>
#include <welkin/processor.hpp>

#include <cmath>

using namespace welkin;

static_assert(!std::is_copy_constructible_v<gl::Texture2D>);
static_assert(!std::is_copy_assignable_v<gl::Texture2D>);
static_assert(!std::is_copy_constructible_v<gl::Texture3D>);
static_assert(!std::is_copy_constructible_v<gl::TextureCube>);
static_assert(!std::is_copy_constructible_v<gl::Texture2DArray>);
static_assert(!std::is_copy_constructible_v<gl::Framebuffer>);
static_assert(!std::is_copy_constructible_v<gl::Buffer>);
static_assert(!std::is_copy_constructible_v<gl::Program>);
static_assert(!std::is_copy_constructible_v<gl::VertexArray>);
static_assert(std::is_nothrow_move_assignable_v<gl::Texture2D>);

TEST_CASE("Headless EGL context gives OpenGL 4.5 core", "[gl]") {
    auto& ctx = test::glContext();
    CHECK_THAT(ctx.description(), Catch::StartsWith("4.5"));
    GLint n = 0;
    glGetIntegerv(GL_MAX_DUAL_SOURCE_DRAW_BUFFERS, &n);
    CHECK(n >= 1);  // the compositing contract needs dual-source blending
}

TEST_CASE("RAII wrappers own, move and release GL names", "[gl]") {
    test::glContext();
    GLuint id = 0;
    {
        gl::Texture2D a(8, 4, GL_RGBA32F);
        id = a.id();
        CHECK(glIsTexture(id));
        gl::Texture2D b(std::move(a));
        CHECK(a.id() == 0);  // moved-from: empty
        CHECK(!a);
        CHECK(b.id() == id);
        CHECK(b.width() == 8);
        gl::Texture2D c;
        c = std::move(b);
        CHECK(c.id() == id);
    }
    CHECK_FALSE(glIsTexture(id));  // destroyed with its last owner
    gl::Texture3D t3(4, 4, 4, GL_RGBA16F);
    gl::TextureCube cube(8, GL_RGBA16F);
    gl::Texture2DArray arr(4, 4, 3, GL_R32F);
    CHECK(t3.ref().depth == 4);
    CHECK(cube.depth() == 6);
    CHECK(arr.depth() == 3);
    gl::Buffer buf(64);
    CHECK_THROWS_WITH(buf.update(nullptr, 128), Catch::Contains("exceed"));
    gl::Texture2D r(2, 2, GL_RGBA8);
    GLuint rid = r.release();
    CHECK(r.id() == 0);
    CHECK(glIsTexture(rid));  // release() does not delete
    glDeleteTextures(1, &rid);
    CHECK_THROWS_WITH(gl::Texture2D(0, 4, GL_RGBA8), Catch::Contains("must be positive"));
    gl::checkError("RAII test");
}

TEST_CASE("Shader errors name the file and the line", "[gl]") {
    test::glContext();
    auto builder = gl::ProgramBuilder("Broken")
                       .fullscreenVertex()
                       .fragment("engine/composite.glsl", gl::engineShader("composite.glsl"))
                       .fragment("tests/broken.frag.glsl", "void main() {\n  welkin_output(vec3(1.0), vec3(0.0));\n  undefined_fn();\n}\n");
    CHECK_THROWS_WITH(builder.build(), Catch::Contains("Broken") && Catch::Contains("tests/broken.frag.glsl:3"));
    CHECK_THAT(builder.assembled(GL_FRAGMENT_SHADER), Catch::StartsWith("#version 450 core"));
}

namespace {
// A layer of uniform radiance and transmittance.
class FlatLayer final : public SkyElement {
public:
    FlatLayer(std::string name, glm::vec3 radiance, glm::vec3 transmittance)
        : SkyElement(std::move(name)), radiance_(radiance), transmittance_(transmittance) {}

private:
    void doInit(InitContext&) override {
        program_ = gl::ProgramBuilder("Layer")
                       .fullscreenVertex()
                       .fragment("engine/composite.glsl", gl::engineShader("composite.glsl"))
                       .fragment("layer.frag", "uniform vec3 u_L; uniform vec3 u_T;\nvoid main() { welkin_output(u_L, u_T); }\n")
                       .build();
    }
    void doRender(const FrameContext& ctx) override {
        program_.set("u_L", radiance_);
        program_.set("u_T", transmittance_);
        program_.use();
        ctx.drawFullscreen();
    }
    void doRelease() override { program_ = {}; }
    glm::vec3 radiance_, transmittance_;
    gl::Program program_;
};

// Writes the view direction + 2 as radiance (positive), opaque. `specialised`: through
// gl::ProjectionPrograms (camera.glsl compiled for the camera's projection only).
class Probe final : public SkyElement {
public:
    explicit Probe(bool specialised = false) : SkyElement("probe"), specialised_(specialised) {}

private:
    void doInit(InitContext&) override {
        programs_ = gl::ProjectionPrograms(gl::ProgramBuilder("Probe")
                                               .fullscreenVertex()
                                               .fragment("engine/camera.glsl", gl::engineShader("camera.glsl"))
                                               .fragment("engine/composite.glsl", gl::engineShader("composite.glsl"))
                                               .fragment("probe.frag",
                                                         "void main() { vec3 d; if (!welkin_viewDirection(welkin_pixel(), d)) discard;\n"
                                                         "  welkin_output(d + 2.0, vec3(0.0)); }\n"));
        generic_ = gl::ProgramBuilder("Probe (generic)")
                       .fullscreenVertex()
                       .fragment("engine/camera.glsl", gl::engineShader("camera.glsl"))
                       .fragment("engine/composite.glsl", gl::engineShader("composite.glsl"))
                       .fragment("probe.frag",
                                 "void main() { vec3 d; if (!welkin_viewDirection(welkin_pixel(), d)) discard;\n"
                                 "  welkin_output(d + 2.0, vec3(0.0)); }\n")
                       .build();
    }
    void doRender(const FrameContext& ctx) override {
        (specialised_ ? programs_.get(ctx.camera.projection) : generic_).use();
        ctx.drawFullscreen();
    }
    void doRelease() override {
        programs_.releasePrograms();
        generic_ = {};
    }
    bool specialised_;
    gl::ProjectionPrograms programs_;
    gl::Program generic_;
};
}  // namespace

TEST_CASE("Compositing: dst = src + dst * T in registration order", "[gl][composite]") {
    test::glContext();
    SkyProcessor p;
    Camera cam;
    cam.width = 16;
    cam.height = 8;
    p.setCamera(cam);
    p.setExposure({.ev100 = 0});
    // Back to front: stars-like emitter, an attenuating sky, an opaque-in-red foreground.
    p.add(std::make_unique<FlatLayer>("back", glm::vec3(1e-5f, 2e-5f, 4e-5f), glm::vec3(0.0f)));
    p.add(std::make_unique<FlatLayer>("middle", glm::vec3(100.0f, 200.0f, 300.0f), glm::vec3(0.5f, 0.25f, 1.0f)));
    p.add(std::make_unique<FlatLayer>("front", glm::vec3(1.6e9f, 0.0f, 1.0f), glm::vec3(0.0f, 1.0f, 0.5f)));
    p.renderFrame();
    Image img = p.readHdr();
    // Analytic: ((0*T0 + L0) * T1 + L1) * T2 + L2.
    const double expected[3] = {(1e-5 * 0.5 + 100.0) * 0.0 + 1.6e9, (2e-5 * 0.25 + 200.0) * 1.0 + 0.0,
                                (4e-5 * 1.0 + 300.0) * 0.5 + 1.0};
    for (int c = 0; c < 3; ++c) {
        // float32 target: relative precision ~6e-8 per operation.
        CHECK(img.at(7, 3, c) == Approx(expected[c]).epsilon(1e-6));
        CHECK(img.at(0, 7, c) == Approx(expected[c]).epsilon(1e-6));
    }
    // The faint end survives beside the bright end: starlight alone through a transparent layer.
    SkyProcessor q;
    q.setCamera(cam);
    q.add(std::make_unique<FlatLayer>("star", glm::vec3(1e-5f), glm::vec3(0.0f)));
    q.add(std::make_unique<FlatLayer>("glass", glm::vec3(0.0f), glm::vec3(1.0f)));
    q.renderFrame();
    CHECK(q.readHdr().at(3, 3, 1) == Approx(1e-5).epsilon(1e-6));
}

TEST_CASE("Each projection puts a known direction on the expected pixel (GPU)", "[gl][camera]") {
    test::glContext();
    struct Case {
        Projection projection;
        int w, h;
        double azDeg, altDeg;  // direction
        double px, py;         // expected pixel position from the documented formulas
    };
    const double W = 64;
    auto fish = [&](double az, double alt) {
        double r = (90 - alt) / 90 * W / 2;
        return glm::dvec2(W / 2 - r * std::sin(az * M_PI / 180), W / 2 - r * std::cos(az * M_PI / 180));
    };
    std::vector<Case> cases = {
        {Projection::Fisheye, 64, 64, 90, 30, fish(90, 30).x, fish(90, 30).y},     // east: left half
        {Projection::Fisheye, 64, 64, 0, 60, fish(0, 60).x, fish(0, 60).y},       // north: upper half
        {Projection::Fisheye, 64, 64, 225, 10, fish(225, 10).x, fish(225, 10).y},  // south-west
        {Projection::Equirect, 64, 32, 90, 45, 16, 8},                              // u = 90/360, v = 45/180
        {Projection::Equirect, 64, 32, 300, -30, 64 * 300.0 / 360, 32 * 120.0 / 180},
        {Projection::Perspective, 48, 32, 180, 20, 24, 16},                         // view centre
        // 15 deg above the view direction in its vertical plane: y = H/2 (1 - tan 15 / tan 30).
        {Projection::Perspective, 48, 32, 180, 35, 24, 16 * (1 - std::tan(15 * M_PI / 180) / std::tan(30 * M_PI / 180))},
        // 10 deg to the west (right, looking south) on the horizon-parallel great circle through
        // the view direction is not a simple az/alt; use az 190 at alt 20 and the pinhole model.
        {Projection::Perspective, 48, 32, 190, 20, -1, -1},
        {Projection::CubeFace, 32, 32, 0, 90, 16, 16},                              // face +Y = zenith
        // Face +Y (up): s = x, t = z (cube axes x east, z south) on the plane y = 1. Direction
        // east-ish 30 deg from the zenith at azimuth 90: cube (sin 30, cos 30, 0) -> s = tan 30.
        {Projection::CubeFace, 32, 32, 90, 60, 16 * (1 + std::tan(30 * M_PI / 180)), 16},
        // ... and towards the south (az 180): cube z = +sin 30 -> t = tan 30, lower half.
        {Projection::CubeFace, 32, 32, 180, 60, 16, 16 * (1 + std::tan(30 * M_PI / 180))},
    };
    // Pinhole position of a direction for the perspective camera (az 180, alt 20, fov 60),
    // written out from the definition: right = (cos az, -sin az, 0), up = right x forward.
    for (auto& k : cases) {
        if (k.px >= 0) continue;
        glm::dvec3 f = directionFromAzAlt(M_PI, 20 * M_PI / 180), r(std::cos(M_PI), -std::sin(M_PI), 0.0);
        glm::dvec3 u = glm::cross(r, f), d = directionFromAzAlt(k.azDeg * M_PI / 180, k.altDeg * M_PI / 180);
        double tanY = std::tan(30 * M_PI / 180), tanX = tanY * k.w / k.h;
        k.px = (glm::dot(d, r) / glm::dot(d, f) / tanX + 1) * k.w / 2;
        k.py = (1 - glm::dot(d, u) / glm::dot(d, f) / tanY) * k.h / 2;
        REQUIRE(k.px > 24.5);  // west of south is on the right when looking south
    }
    for (bool specialised : {false, true})
    for (const auto& k : cases) {
        SkyProcessor p;
        Camera cam;
        cam.projection = k.projection;
        cam.width = k.w;
        cam.height = k.h;
        cam.azimuthRad = M_PI;
        cam.altitudeRad = 20 * M_PI / 180;
        cam.cubeFace = 2;
        p.setCamera(cam);
        p.add(std::make_unique<Probe>(specialised));
        p.renderFrame();
        Image img = p.readHdr();
        // Bilinear interpolation between the four pixel centres around the exact position: the
        // direction field is smooth, so this recovers the direction at (px, py) to second order.
        double fx = k.px - 0.5, fy = k.py - 0.5;
        int x0 = std::clamp(int(std::floor(fx)), 0, k.w - 2), y0 = std::clamp(int(std::floor(fy)), 0, k.h - 2);
        double tx = fx - x0, ty = fy - y0;
        glm::dvec3 got(0.0);
        for (int c = 0; c < 3; ++c) {
            double top = (1 - tx) * img.at(x0, y0, c) + tx * img.at(x0 + 1, y0, c);
            double bottom = (1 - tx) * img.at(x0, y0 + 1, c) + tx * img.at(x0 + 1, y0 + 1, c);
            got[c] = (1 - ty) * top + ty * bottom - 2.0;
        }
        glm::dvec3 want = directionFromAzAlt(k.azDeg * M_PI / 180, k.altDeg * M_PI / 180);
 INFO((specialised ? "specialised " : "generic ") << "projection " << toString(k.projection) << " az " << k.azDeg << " alt " << k.altDeg << " at " << k.px << ", " << k.py);
        // Interpolation error ~ (pixel angle)^2 / 8 plus float32 output: < 0.5 deg at these sizes;
        // an off-by-one-pixel or mirrored convention errs by >= 2.8 deg.
        CHECK(std::acos(std::clamp(glm::dot(glm::normalize(got), want), -1.0, 1.0)) < 0.5 * M_PI / 180);
    }
}

TEST_CASE("renderInto a host framebuffer respects the host's depth", "[gl][composite]") {
    test::glContext();
    const int w = 8, h = 8;
    gl::Texture2D colour(w, h, GL_RGBA32F);
    gl::Renderbuffer depth(w, h, GL_DEPTH_COMPONENT24);
    auto fbo = gl::Framebuffer::create();
    fbo.attach(GL_COLOR_ATTACHMENT0, colour);
    fbo.attach(GL_DEPTH_ATTACHMENT, depth);
    fbo.checkComplete("host");
    fbo.bind();
    const float grey[4] = {5, 5, 5, 1};
    glClearBufferfv(GL_COLOR, 0, grey);
    glClearBufferfi(GL_DEPTH_STENCIL, 0, 1.0f, 0);
    // The host's "geometry": the left half at depth 0.5.
    glEnable(GL_SCISSOR_TEST);
    glScissor(0, 0, w / 2, h);
    glClearBufferfi(GL_DEPTH_STENCIL, 0, 0.5f, 0);
    glDisable(GL_SCISSOR_TEST);

    SkyProcessor p;
    Camera cam;
    cam.width = w;
    cam.height = h;
    p.setCamera(cam);
    p.add(std::make_unique<FlatLayer>("sky", glm::vec3(10.0f), glm::vec3(0.5f)));
    // The host's state before the call, which must survive it.
    fbo.bind();
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    glDepthMask(GL_FALSE);
    glEnable(GL_CULL_FACE);
    glDisable(GL_BLEND);
    glBlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA);
    glViewport(1, 2, 3, 4);
    p.renderInto({.framebuffer = fbo.id(), .width = w, .height = h, .depthTest = true});
    GLint vp[4], func = 0, fb = 0, src = 0;
    GLboolean mask = GL_TRUE;
    glGetIntegerv(GL_VIEWPORT, vp);
    glGetIntegerv(GL_DEPTH_FUNC, &func);
    glGetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &fb);
    glGetIntegerv(GL_BLEND_SRC_RGB, &src);
    glGetBooleanv(GL_DEPTH_WRITEMASK, &mask);
    CHECK(vp[0] == 1);
    CHECK(vp[3] == 4);
    CHECK(func == GL_LESS);
    CHECK(mask == GL_FALSE);
    CHECK(glIsEnabled(GL_DEPTH_TEST));
    CHECK(glIsEnabled(GL_CULL_FACE));
    CHECK_FALSE(glIsEnabled(GL_BLEND));
    CHECK(src == GL_SRC_ALPHA);
    CHECK(fb == GLint(fbo.id()));
    glDisable(GL_DEPTH_TEST);
    glDisable(GL_CULL_FACE);
    glDepthMask(GL_TRUE);
    auto px = colour.readRgbaFloat();  // bottom-up rows
    CHECK(px[(3 * w + 1) * 4] == Approx(5.0));               // covered by host geometry: untouched
    CHECK(px[(3 * w + 6) * 4] == Approx(5.0 * 0.5 + 10.0));  // open sky: composited
    CHECK_THROWS_WITH(p.renderInto({.framebuffer = fbo.id(), .width = 4, .height = 4}), Catch::Contains("differs"));
}

TEST_CASE("Automatic exposure as a camera (eye.adaptation off) follows the log-average luminance", "[gl][tonemap]") {
    test::glContext();
    float firstGrey = -1;
    for (float L : {1e-4f, 1.0f, 3e4f}) {
        SkyProcessor p;
        Camera cam;
        cam.width = 32;
        cam.height = 16;
        p.setCamera(cam);
        p.setExposure({.automatic = true});
        p.vars().set(eye::keys::adaptation, false);  // the eye's model: tests/engine/test_eye.cpp
        p.vars().set(eye::keys::mesopic, false);
        p.add(std::make_unique<FlatLayer>("uniform", glm::vec3(L), glm::vec3(0.0f)));
        p.renderFrame();
        // EV100 = log2(L * 100 / 12.5); the mip reduction of a uniform image is exact to float
        // rounding, so 0.01 EV is generous.
        CHECK(p.lastEv100() == Approx(std::log2(L * 8.0)).margin(0.01));
        Image ldr = p.readToneMapped();
        // A uniform field metered at its own level tone-maps to the same mid-grey whatever the
        // level (8-bit output: one code value of tolerance).
        if (firstGrey < 0) firstGrey = ldr.at(5, 5, 1);
        CHECK(ldr.at(5, 5, 1) == Approx(firstGrey).margin(1.0 / 255));
        CHECK(ldr.at(5, 5, 1) > 0.2f);
        CHECK(ldr.at(5, 5, 1) < 0.6f);
    }
}

TEST_CASE("Two processors in one process are independent", "[gl][processor]") {
    test::glContext();
    SkyProcessor a, b;
    Camera ca, cb;
    ca.width = 8;
    ca.height = 8;
    cb.width = 12;
    cb.height = 6;
    a.setCamera(ca);
    b.setCamera(cb);
    a.add(std::make_unique<FlatLayer>("x", glm::vec3(1.0f), glm::vec3(0.0f)));
    b.add(std::make_unique<FlatLayer>("x", glm::vec3(2.0f), glm::vec3(0.0f)));
    a.renderFrame();
    b.renderFrame();
    a.renderFrame();
    CHECK(a.readHdr().width == 8);
    CHECK(b.readHdr().width == 12);
    CHECK(a.readHdr().at(1, 1, 0) == 1.0f);
    CHECK(b.readHdr().at(1, 1, 0) == 2.0f);
    a.vars().set(keys::quality, 3);
    CHECK(keys::quality.value(b.vars()) == 1);
}

TEST_CASE("The astronomy step writes the Sun's direction unless the host owns it", "[gl][processor]") {
    test::glContext();
    Camera cam;
    cam.width = 4;
    cam.height = 4;
    const glm::dvec3 pinned = glm::normalize(glm::dvec3(0.0, -1.0, 1.0));  // 45 deg up in the south
    // Equator, 2026-03-20 12:07 UTC at longitude 0: the Sun is within ~1 deg of the zenith.
    for (bool astronomy : {true, false}) {
        SkyProcessor p(SkyVars::earth(), Logger(), {.astronomy = astronomy});
        p.setCamera(cam);
        p.setTime(UtcInstant::parse("2026-03-20T12:07:00Z"));
        p.vars().set(keys::sunDirection, pinned);
        p.renderFrame();
        glm::dvec3 sun = p.vars().get(keys::sunDirection);
        if (astronomy)
            CHECK(sun.z > std::cos(2.0 * M_PI / 180));  // within 2 deg of the zenith (equinox noon)
        else
            CHECK(sun == pinned);
    }
}

TEST_CASE("Automatic exposure ignores empty background pixels", "[gl][tonemap]") {
    test::glContext();
    SkyProcessor p;
    Camera cam;
    cam.projection = Projection::Fisheye;  // corners are outside the image circle
    cam.width = cam.height = 32;
    p.setCamera(cam);
    p.setExposure({.automatic = true});
    p.add(std::make_unique<FlatLayer>("uniform", glm::vec3(50.0f), glm::vec3(0.0f)));
    p.renderFrame();
    // The corners hold 21 % of the pixels but are outside the image and unlit: the meter reads
    // the 50 cd/m^2 field alone (float log-average of a uniform field: 1e-4).
    CHECK(p.adaptationLuminance().x == Approx(50.0).epsilon(1e-4));
}

TEST_CASE("Destroying one headless context leaves another current", "[gl]") {
    auto& shared = test::glContext();
    {
        auto other = gl::HeadlessContext::create({}, Logger());
        shared.makeCurrent();  // the other context exists but is not current
    }
    // Still current: GL calls work.
    gl::Texture2D t(2, 2, GL_RGBA8);
    CHECK(glIsTexture(t.id()));
}

TEST_CASE("GL debug output reaches the context's logger", "[gl]") {
    std::vector<std::string> seen;
    Logger log([&](LogLevel, std::string_view m) { seen.emplace_back(m); }, LogLevel::Debug);
    {
        auto ctx = gl::HeadlessContext::create({.debug = true}, log);
        glEnable(GL_TEXTURE_2D);  // not a capability in the core profile: GL_INVALID_ENUM
        CHECK(glGetError() == GL_INVALID_ENUM);
    }
    test::glContext();  // back to the shared context for the following tests
    REQUIRE_FALSE(seen.empty());
    CHECK_THAT(seen.front(), Catch::StartsWith("GL["));
}
