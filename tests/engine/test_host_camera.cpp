// The host's camera (Camera::fromViewProjection), its depth conventions, applyToScene(), the
// tone map of a host's HDR texture and the host's GL errors: issue 18's game-loop embedding.
// References: glm's own lookAt/perspective/frustum matrices (an independent construction of the
// same cameras), and the az/alt/fov camera the library had before.
#include <catch2/catch.hpp>

#include "elements_present.hpp"
#include "gl_test_context.hpp"
#include "uniform_field.hpp"

#include <welkin/camera.hpp>
#include <welkin/element.hpp>
#include <welkin/gl/objects.hpp>
#include <welkin/gl/shader.hpp>
#include <welkin/processor.hpp>

#include <epoxy/gl.h>
#include <glm/gtc/matrix_transform.hpp>

#include <cmath>
#include <limits>
#include <string>
#include <vector>

using namespace welkin;

namespace {
constexpr double kDeg = M_PI / 180;

// A view matrix (host world -> view) of an eye at `eye` looking along `forward` with `up`.
glm::dmat4 lookAlong(const glm::dvec3& eye, const glm::dvec3& forward, const glm::dvec3& up) {
    return glm::lookAt(eye, eye + forward, up);
}

// The same camera as welkin's az/alt/fov one, in a Y-up host world (x east, y up, -z north).
glm::dvec3 yUpFromEnu(const glm::dvec3& e) { return {e.x, e.z, -e.y}; }

double angle(const glm::dvec3& a, const glm::dvec3& b) {
    return std::atan2(glm::length(glm::cross(a, b)), glm::dot(a, b));
}

// Every pixel corner and centre of a small grid: where the two cameras must agree.
std::vector<glm::dvec2> samplePixels(int w, int h) {
    std::vector<glm::dvec2> out;
    for (int j = 0; j <= 4; ++j)
        for (int i = 0; i <= 4; ++i) out.emplace_back(w * i / 4.0, h * j / 4.0);
    out.emplace_back(w * 0.37, h * 0.61);
    return out;
}
}  // namespace

TEST_CASE("A host camera from a view and a projection matrix sees what welkin's own camera sees", "[cpu][camera][host]") {
    Camera own;
    own.azimuthRad = 130 * kDeg;
    own.altitudeRad = 25 * kDeg;
    own.verticalFovRad = 50 * kDeg;
    own.width = 160;
    own.height = 90;
    const glm::dmat3 b = own.basis();
    // The same view from a Y-up host: eye anywhere (a floating origin), metres.
    const glm::dvec3 eye(1234.5, 17.0, -987.0);
    const glm::dmat4 view = lookAlong(eye, yUpFromEnu(b[2]), yUpFromEnu(b[1]));
    const glm::dmat4 proj = glm::perspective(own.verticalFovRad, 160.0 / 90.0, 0.1, 1e4);
    const Camera host = Camera::fromViewProjection(view, proj, enuFromYUp(), 160, 90);
    REQUIRE(host.host);
    CHECK(host.azimuthRad == Approx(own.azimuthRad).margin(1e-9));  // the optical axis, derived
    CHECK(host.altitudeRad == Approx(own.altitudeRad).margin(1e-9));
    CHECK(host.verticalFovRad == Approx(own.verticalFovRad).margin(1e-9));
    for (const glm::dvec2& px : samplePixels(160, 90)) {
        const glm::dvec3 a = *own.directionAt(px), c = *host.directionAt(px);
        // Both are double-precision constructions of one ray: 1e-9 rad is rounding.
        CHECK(angle(a, c) < 1e-9);
        const glm::dvec2 back = *host.pixelOf(c);
        CHECK(glm::length(back - px) < 1e-6);
        const glm::dvec4 clip = *host.clipFromDirection(c);
        CHECK(glm::length(host.pixelFromClip(clip) - px) < 1e-6);
    }
    // The eye in ENU: the host's position through enuFromYUp (x, -z, y).
    CHECK(glm::length(host.eyeEnuMeters() - glm::dvec3(1234.5, 987.0, 17.0)) < 1e-9);
}

TEST_CASE("A camera rolled 90 degrees sees the unrolled camera's directions, rotated", "[cpu][camera][host]") {
    const glm::dvec3 fwd = glm::normalize(glm::dvec3(0.3, 0.2, -1.0)), up(0, 1, 0);
    const glm::dvec3 right = glm::normalize(glm::cross(fwd, up));
    const glm::dvec3 trueUp = glm::cross(right, fwd);
    const glm::dmat4 proj = glm::perspective(70 * kDeg, 1.0, 0.5, 100.0);  // square: the roll maps the frame onto itself
    const int n = 64;
    const Camera flat = Camera::fromViewProjection(lookAlong({}, fwd, trueUp), proj, enuFromYUp(), n, n);
    // Rolled by +90 deg about the view axis: the camera's up is the old right.
    const Camera rolled = Camera::fromViewProjection(lookAlong({}, fwd, right), proj, enuFromYUp(), n, n);
    for (const glm::dvec2& px : samplePixels(n, n)) {
        // The rolled camera's up is the unrolled one's right: its image is the unrolled image
        // turned a quarter counter-clockwise, so pixel (x, y) of the rolled camera is pixel
        // (W - y, x) of the unrolled one (pixel y points down).
        const glm::dvec2 q(n - px.y, px.x);
        CHECK(angle(*rolled.directionAt(px), *flat.directionAt(q)) < 1e-9);
    }
    // And no roll means a level right vector; the rolled basis' right is vertical.
    CHECK(std::abs(flat.basis()[0].z) < 1e-12);
    CHECK(std::abs(std::abs(rolled.basis()[0].z) - std::abs(glm::dot(trueUp, up))) < 1e-9);
}

TEST_CASE("A Z-up host and a Y-up host with the same camera agree", "[cpu][camera][host]") {
    const glm::dvec3 fwdEnu = glm::normalize(glm::dvec3(-0.4, 0.8, 0.3));
    const glm::dvec3 upEnu(0, 0, 1);
    const glm::dmat4 proj = glm::perspective(45 * kDeg, 4.0 / 3.0, 1.0, 1e5);
    const glm::dvec3 eyeEnu(10, 20, 3);
    const Camera zUp = Camera::fromViewProjection(lookAlong(eyeEnu, fwdEnu, upEnu), proj, enuFromZUp(), 80, 60);
    const Camera yUp = Camera::fromViewProjection(lookAlong(yUpFromEnu(eyeEnu), yUpFromEnu(fwdEnu), yUpFromEnu(upEnu)), proj,
                                                  enuFromYUp(), 80, 60);
    for (const glm::dvec2& px : samplePixels(80, 60)) CHECK(angle(*zUp.directionAt(px), *yUp.directionAt(px)) < 1e-9);
    CHECK(glm::length(zUp.eyeEnuMeters() - yUp.eyeEnuMeters()) < 1e-9);
    // A host in centimetres: same directions, the eye scaled to metres.
    const Camera cm = Camera::fromViewProjection(lookAlong(eyeEnu * 100.0, fwdEnu, upEnu), proj, enuFromZUp(0.01), 80, 60);
    for (const glm::dvec2& px : samplePixels(80, 60)) CHECK(angle(*zUp.directionAt(px), *cm.directionAt(px)) < 1e-9);
    CHECK(glm::length(cm.eyeEnuMeters() - eyeEnu) < 1e-9);
}

TEST_CASE("A floating origin changes nothing in the sky", "[cpu][camera][host]") {
    const glm::dvec3 fwd = glm::normalize(glm::dvec3(1, 0.1, -0.5));
    const glm::dmat4 proj = glm::perspective(60 * kDeg, 2.0, 0.1, 1e4);
    // The eye 1e7 units from the host's origin, and the same eye after the host re-based its
    // world at the eye (the origin moved to where the eye is, in ENU).
    const glm::dvec3 far(1e7, 5.0, -3e6);
    const Camera a = Camera::fromViewProjection(lookAlong(far, fwd, {0, 1, 0}), proj, enuFromYUp(1.0, -glm::dvec3(1e7, 3e6, 5.0)), 64, 32);
    const Camera b = Camera::fromViewProjection(lookAlong({}, fwd, {0, 1, 0}), proj, enuFromYUp(), 64, 32);
    for (const glm::dvec2& px : samplePixels(64, 32)) CHECK(angle(*a.directionAt(px), *b.directionAt(px)) < 1e-9);
    // 1e7 m of translation cancelled in double: 1e-8 m is rounding of the inverse view.
    CHECK(glm::length(a.eyeEnuMeters()) < 1e-6);
}

TEST_CASE("An off-axis frustum maps pixels to the rays through its own window", "[cpu][camera][host]") {
    // glm::frustum: near-plane window [l, r] x [b, t] at distance n, looking down -z (Z-up host,
    // identity view: the host's view space is ENU... rotated: -z is down, so look north instead).
    const double l = -0.2, r = 0.6, bo = -0.1, t = 0.3, n = 0.5;
    const glm::dmat4 proj = glm::frustum(l, r, bo, t, n, 100.0);
    const glm::dvec3 north(0, 1, 0), up(0, 0, 1), east(1, 0, 0);
    const Camera c = Camera::fromViewProjection(lookAlong({}, north, up), proj, enuFromZUp(), 80, 40);
    for (const glm::dvec2& px : samplePixels(80, 40)) {
        // The ray through the window point (x, y) of the near plane, in ENU: view x = east, view y = up.
        const double x = l + (r - l) * px.x / 80, y = t - (t - bo) * px.y / 40;
        const glm::dvec3 want = glm::normalize(x * east + y * up + n * north);
        CHECK(angle(*c.directionAt(px), want) < 1e-9);
    }
    // The optical axis is the view's -z (north), not the frustum's centre.
    CHECK(angle(c.basis()[2], north) < 1e-12);
}

TEST_CASE("Host depth reads back distances in every depth convention", "[cpu][camera][host]") {
    const glm::dvec3 fwd = glm::normalize(glm::dvec3(0.2, 0.3, -1.0));
    const glm::dmat4 view = lookAlong({}, fwd, {0, 1, 0});
    const double n = 0.25, f = 5000.0;
    struct Case {
        const char* name;
        DepthMode mode;
        glm::dmat4 proj;
    };
    // Projections as hosts build them: OpenGL's, [0, 1] (glm's _ZO), reversed-Z [0, 1] (the
    // standard [0, 1] with z' = 1 - z), and reversed-Z with an infinite far plane (near / -z).
    glm::dmat4 rev = glm::perspectiveRH_ZO(50 * kDeg, 1.5, n, f);
    rev[2][2] = -rev[2][2] - 1.0;  // z' = w - z: (A z + B) -> (-z) - (A z + B)
    rev[3][2] = -rev[3][2];
    glm::dmat4 revInf(0.0);
    revInf[0][0] = 1.0 / (std::tan(25 * kDeg) * 1.5);
    revInf[1][1] = 1.0 / std::tan(25 * kDeg);
    revInf[2][3] = -1.0;
    revInf[3][2] = n;
    const std::vector<Case> cases{{"standard [-1, 1]", {}, glm::perspectiveRH_NO(50 * kDeg, 1.5, n, f)},
                                  {"standard [0, 1]", {.zeroToOne = true}, glm::perspectiveRH_ZO(50 * kDeg, 1.5, n, f)},
                                  {"reversed [0, 1]", {.reversedZ = true, .zeroToOne = true}, rev},
                                  {"reversed infinite [0, 1]", {.reversedZ = true, .zeroToOne = true}, revInf}};
    for (const Case& k : cases) {
        SECTION(k.name) {
            const Camera c = Camera::fromViewProjection(view, k.proj, enuFromYUp(), 90, 60, k.mode);
            for (double dist : {0.3, 2.0, 75.0, 1800.0}) {
                const glm::dvec2 px(23.5, 41.5);
                const glm::dvec3 dirEnu = *c.directionAt(px);
                // The host's own pipeline: the point at `dist` along the pixel's ray, through its
                // view and projection, the perspective divide, the viewport's depth range.
                const glm::dvec3 pWorld = yUpFromEnu(dirEnu) * dist;
                const glm::dvec4 clip = k.proj * view * glm::dvec4(pWorld, 1.0);
                const double ndc = clip.z / clip.w;
                const double window = k.mode.zeroToOne ? ndc : 0.5 * ndc + 0.5;
                // Double arithmetic throughout: a relative 1e-6 is the conditioning of the
                // depth -> distance inversion at 1800 m with a 0.25 m near plane.
                CHECK(sceneDistanceMeters(c, window, dirEnu) == Approx(dist).epsilon(1e-6));
            }
            CHECK(std::isinf(sceneDistanceMeters(c, k.mode.reversedZ ? 0.0 : 1.0, *c.directionAt({45, 30}))));
        }
    }
    // A camera not made from matrices reads the depth with HostDepth's planes.
    Camera own;
    own.width = 90;
    own.height = 60;
    own.depth = {.reversedZ = true, .zeroToOne = true};
    const HostDepth hd{.depthTexture = 1, .nearM = n, .farM = std::numeric_limits<double>::infinity(), .metresPerUnit = 2.0};
    const glm::dvec3 d = *own.directionAt({10, 10});
    const double zView = -glm::dot(d, own.basis()[2]) * 40.0;  // a point 40 units along the ray
    CHECK(sceneDistanceMeters(own, n / -zView, d, hd) == Approx(80.0).epsilon(1e-9));  // reversed infinite: depth = n / -z
}

TEST_CASE("fromViewProjection rejects what it cannot use, in one line", "[cpu][camera][host]") {
    const glm::dmat4 view(1.0), proj = glm::perspective(1.0, 1.0, 0.1, 10.0);
    CHECK_THROWS_WITH(Camera::fromViewProjection(view, glm::ortho(-1.0, 1.0, -1.0, 1.0, 0.1, 10.0), enuFromZUp(), 8, 8),
                      Catch::Contains("orthographic"));
    glm::dmat4 nan = view;
    nan[1][1] = std::nan("");
    CHECK_THROWS_WITH(Camera::fromViewProjection(nan, proj, enuFromZUp(), 8, 8), Catch::Contains("view matrix is not finite"));
    glm::dmat4 skew = enuFromZUp();
    skew[0][1] = 0.5;
    CHECK_THROWS_WITH(Camera::fromViewProjection(view, proj, skew, 8, 8), Catch::Contains("worldToEnu is not a rotation"));
    CHECK_THROWS_WITH(Camera::fromViewProjection(view, proj, enuFromZUp(), 0, 8), Catch::Contains("width 0 not in [1, 16384]"));
    CHECK_THROWS_WITH(enuFromYUp(0.0), Catch::Contains("metresPerUnit 0 not in (0, inf)"));
}

// ---- GL: the host's depth, scene pass, tone map and errors --------------------------------------

namespace {
// Over the host's scene: writes the distance to the host's geometry (metres, camera.glsl's
// welkin_sceneDistance) as radiance over black, in the air pass; 1e6 where nothing was drawn.
class DistanceProbe final : public SkyElement {
public:
    DistanceProbe() : SkyElement("distance") {}

private:
    void doInit(InitContext&) override {
        program_ = gl::ProgramBuilder("DistanceProbe")
                       .fullscreenVertex()
                       .fragment("engine/camera.glsl", gl::engineShader("camera.glsl"))
                       .fragment("engine/composite.glsl", gl::engineShader("composite.glsl"))
                       .fragment("probe.frag", R"(
layout(binding = WELKIN_BINDING_SCENE_DEPTH) uniform sampler2D u_depth;
void main() {
    float d = texelFetch(u_depth, ivec2(gl_FragCoord.xy), 0).r;
    vec3 dir;
    welkin_viewDirection(welkin_pixel(), dir);
    welkin_output(vec3(welkin_depthIsFar(d) ? 1e6 : welkin_sceneDistance(d, dir)), vec3(0.0));
}
)")
                       .build();
    }
    void doRender(const FrameContext&) override {}
    void doApplyToScene(const FrameContext& ctx, ScenePass pass) override {
        if (pass != ScenePass::Air) return;
        glBindTextureUnit(gl::binding::kSceneDepth, ctx.depth->depthTexture);
        program_.use();
        ctx.drawFullscreen();
    }
    void doRelease() override { program_ = {}; }
    gl::Program program_;
};

struct HostTarget {
    gl::Texture2D colour, depth;
    gl::Framebuffer fbo;
    int w, h;
    HostTarget(int w_, int h_) : colour(w_, h_, GL_RGBA32F), depth(w_, h_, GL_DEPTH_COMPONENT32F), fbo(gl::Framebuffer::create()), w(w_), h(h_) {
        fbo.attach(GL_COLOR_ATTACHMENT0, colour);
        fbo.attach(GL_DEPTH_ATTACHMENT, depth);
        fbo.checkComplete("host target");
    }
    // GL rows are bottom-up.
    glm::vec4 at(const std::vector<float>& px, int x, int yDown) const {
        const size_t i = (size_t(h - 1 - yDown) * size_t(w) + size_t(x)) * 4;
        return {px[i], px[i + 1], px[i + 2], px[i + 3]};
    }
};
}  // namespace

TEST_CASE("Reversed-Z and [0, 1] depth hosts see the sky behind their geometry", "[gl][camera][host]") {
    test::glContext();
    const int w = 16, h = 8;
    for (bool reversed : {false, true})
        for (bool zeroToOne : {false, true}) {
            CAPTURE(reversed, zeroToOne);
            HostTarget t(w, h);
            t.fbo.bind();
            glClipControl(GL_LOWER_LEFT, zeroToOne ? GL_ZERO_TO_ONE : GL_NEGATIVE_ONE_TO_ONE);
            const float grey[4] = {5, 5, 5, 1};
            glClearBufferfv(GL_COLOR, 0, grey);
            const float farDepth = reversed ? 0.0f : 1.0f;
            glClearBufferfv(GL_DEPTH, 0, &farDepth);
            // The host's geometry on the left half, very far away but not at the far plane: the
            // sky must still not cover it (reversed-Z's precision is near 0).
            const float geom = reversed ? 1e-6f : 1.0f - 1e-6f;
            glEnable(GL_SCISSOR_TEST);
            glScissor(0, 0, w / 2, h);
            glClearBufferfv(GL_DEPTH, 0, &geom);
            glDisable(GL_SCISSOR_TEST);
            glDepthFunc(reversed ? GL_GREATER : GL_LESS);
            glDepthRange(0.0, 1.0);

            SkyProcessor p;
            const glm::dmat4 proj = glm::perspective(1.0, 2.0, 0.1, 100.0);
            p.setCamera(Camera::fromViewProjection(glm::dmat4(1.0), proj, enuFromYUp(), w, h, {.reversedZ = reversed, .zeroToOne = zeroToOne}));
            p.add(std::make_unique<test::UniformField>(glm::vec3(10.0f), "veil", glm::vec3(0.5f)));
            t.fbo.bind();
            p.renderInto({.framebuffer = t.fbo.id(), .width = w, .height = h, .depthTest = true});
            // The host's clip control and depth state survive the call.
            GLint mode = 0, func = 0;
            glGetIntegerv(GL_CLIP_DEPTH_MODE, &mode);
            glGetIntegerv(GL_DEPTH_FUNC, &func);
            CHECK(mode == (zeroToOne ? GL_ZERO_TO_ONE : GL_NEGATIVE_ONE_TO_ONE));
            CHECK(func == (reversed ? GL_GREATER : GL_LESS));
            glClipControl(GL_LOWER_LEFT, GL_NEGATIVE_ONE_TO_ONE);
            auto px = t.colour.readRgbaFloat();
            for (int y = 0; y < h; ++y) {
                CHECK(t.at(px, 2, y).r == Approx(5.0f));               // the host's geometry: untouched
                CHECK(t.at(px, w - 3, y).r == Approx(5.0f * 0.5f + 10.0f));  // open sky: composited
            }
        }
}

TEST_CASE("applyToScene gives elements the distance to the host's geometry in any depth convention", "[gl][camera][host]") {
    test::glContext();
    const int w = 12, h = 6;
    const double dist = 37.0;  // metres along the centre pixel's ray
    for (bool reversed : {false, true}) {
        CAPTURE(reversed);
        HostTarget t(w, h);
        const glm::dvec3 fwd = glm::normalize(glm::dvec3(0.3, 0.1, -1));
        const glm::dmat4 view = lookAlong({5, 2, 1}, fwd, {0, 1, 0});
        glm::dmat4 proj = glm::perspectiveRH_ZO(0.8, 2.0, 0.5, 1000.0);
        if (reversed) {
            proj[2][2] = -proj[2][2] - 1.0;
            proj[3][2] = -proj[3][2];
        }
        const DepthMode mode{.reversedZ = reversed, .zeroToOne = true};
        const Camera cam = Camera::fromViewProjection(view, proj, enuFromYUp(), w, h, mode);
        // Every pixel's depth is the window depth of the point `dist` along its own ray.
        std::vector<float> depth(size_t(w * h));
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x) {
                const glm::dvec3 d = *cam.directionAt({x + 0.5, y + 0.5});
                const glm::dvec3 world = glm::dvec3(5, 2, 1) + yUpFromEnu(d) * dist;
                const glm::dvec4 c = proj * view * glm::dvec4(world, 1);
                depth[size_t((h - 1 - y) * w + x)] = float(c.z / c.w);
            }
        depth[0] = reversed ? 0.0f : 1.0f;  // one pixel of sky (bottom-left)
        glTextureSubImage2D(t.depth.id(), 0, 0, 0, w, h, GL_DEPTH_COMPONENT, GL_FLOAT, depth.data());
        t.fbo.bind();
        const float black[4] = {0, 0, 0, 1};
        glClearBufferfv(GL_COLOR, 0, black);
        SkyProcessor p;
        p.setCamera(cam);
        p.add(std::make_unique<DistanceProbe>());
        const RenderTarget target{.framebuffer = t.fbo.id(), .width = w, .height = h, .depth = HostDepth{.depthTexture = t.depth.id()}};
        p.renderInto(target);
        p.applyToScene(target);
        auto px = t.colour.readRgbaFloat();
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x) {
                if (x == 0 && y == h - 1) {
                    CHECK(t.at(px, x, y).r == 1e6f);  // the far plane: no geometry
                    continue;
                }
                // Float depth with a 0.5 m near plane: at 37 m one depth ulp is ~1e-4 m relative
                // 3e-6 (standard) and far better reversed; 1e-3 relative covers the GPU's float
                // reconstruction (the reversed-Z case is the precise one).
                CHECK(t.at(px, x, y).r == Approx(dist).epsilon(reversed ? 2e-4 : 1e-3));
            }
    }
    SkyProcessor p;
    CHECK_THROWS_WITH(p.applyToScene({.framebuffer = 0, .width = 1280, .height = 720}), Catch::Contains("RenderTarget::depth is required"));
}

TEST_CASE("applyToScene runs only the passes asked for", "[gl][host]") {
    test::glContext();
    // The distance probe draws in the air pass: asking for the surfaces only leaves the host's
    // colour as it was; asking for the air only draws it.
    const int w = 4, h = 4;
    HostTarget t(w, h);
    const float half = 0.5f;
    glClearTexImage(t.depth.id(), 0, GL_DEPTH_COMPONENT, GL_FLOAT, &half);
    SkyProcessor p;
    p.setCamera(Camera::fromViewProjection(glm::dmat4(1.0), glm::perspective(1.0, 1.0, 0.5, 100.0), enuFromYUp(), w, h));
    p.add(std::make_unique<DistanceProbe>());
    const RenderTarget target{.framebuffer = t.fbo.id(), .width = w, .height = h, .depth = HostDepth{.depthTexture = t.depth.id()}};
    t.fbo.bind();
    const float grey[4] = {7, 7, 7, 1};
    glClearBufferfv(GL_COLOR, 0, grey);
    p.renderInto(target);
    p.applyToScene(target, {.surfaces = true, .air = false});
    CHECK(t.at(t.colour.readRgbaFloat(), 1, 1).r == 7.0f);
    p.applyToScene(target, {.surfaces = false, .air = true});
    CHECK(t.at(t.colour.readRgbaFloat(), 1, 1).r != 7.0f);
}

TEST_CASE("toneMapInto tone-maps a host's HDR texture like welkin's own frame", "[gl][tonemap][host]") {
    test::glContext();
    const int w = 16, h = 8;
    SkyProcessor p;
    Camera cam;
    cam.width = w;
    cam.height = h;
    p.setCamera(cam);
    p.setAnimationTime(0.0);
    p.setExposure({.automatic = true});
    p.add(std::make_unique<test::UniformField>(glm::vec3(2500.0f, 3000.0f, 4000.0f)));
    p.renderFrame();
    const Image own = p.readToneMapped();
    const double ownEv = p.lastEv100();
    // The host's HDR texture with the same radiance (RGBA16F: a host's usual format; 3000 cd/m^2
    // is exact to 2 in 16-bit float), a sampler-free texture whose filter must not change.
    gl::Texture2D hostHdr(w, h, GL_RGBA16F);
    hostHdr.setFilter(GL_NEAREST);
    std::vector<float> rgba(size_t(w * h * 4));
    for (size_t i = 0; i < rgba.size(); i += 4) {
        rgba[i] = 2500.0f;
        rgba[i + 1] = 3000.0f;
        rgba[i + 2] = 4000.0f;
        rgba[i + 3] = 1.0f;
    }
    glTextureSubImage2D(hostHdr.id(), 0, 0, 0, w, h, GL_RGBA, GL_FLOAT, rgba.data());
    gl::Texture2D ldr(w, h, GL_RGBA8);
    auto fbo = gl::Framebuffer::create();
    fbo.attach(GL_COLOR_ATTACHMENT0, ldr);
    p.resetAdaptation();
    p.toneMapInto(fbo.id(), hostHdr.id());
    CHECK(p.lastEv100() == Approx(ownEv).margin(0.01));  // the same scene metered the same: 0.01 EV is float rounding
    auto px = ldr.readRgbaFloat();
    // 8-bit output: one code value.
    CHECK(px[4 * 5 + 1] == Approx(own.at(5, 0, 1)).margin(1.0 / 255));
    GLint filter = 0;
    glGetTextureParameteriv(hostHdr.id(), GL_TEXTURE_MIN_FILTER, &filter);
    CHECK(filter == GL_NEAREST);
    CHECK_THROWS_WITH(p.toneMapInto(fbo.id(), 0u), Catch::Contains("hostHdrTexture 0 is not a texture"));
    gl::Texture2D small(4, 4, GL_RGBA16F);
    CHECK_THROWS_WITH(p.toneMapInto(fbo.id(), small.id()), Catch::Contains("differs from the camera's 16x8"));
}

TEST_CASE("A GL error the host left pending is the host's, not welkin's", "[gl][host]") {
    test::glContext();
    std::vector<std::string> messages;
    Logger log([&](LogLevel, std::string_view m) { messages.emplace_back(m); }, LogLevel::Debug);
    for (bool validation : {false, true}) {
        CAPTURE(validation);
        messages.clear();
        SkyProcessor p(SkyVars::earth(), log, ProcessorOptions{.validation = validation});
        Camera cam;
        cam.width = 8;
        cam.height = 4;
        p.setCamera(cam);
        p.add(std::make_unique<test::UniformField>(glm::vec3(1.0f)));
        glEnable(0x7FFF);  // GL_INVALID_ENUM, left by "the host"
        CHECK_NOTHROW(p.renderFrame());
        REQUIRE(!messages.empty());
        CHECK(messages[0].find("the host left GL error(s) pending") != std::string::npos);
        CHECK(messages[0].find("GL_INVALID_ENUM") != std::string::npos);
        CHECK(glGetError() == GL_NO_ERROR);
        // welkin's own errors are still welkin's: an element that makes one throws, named in
        // validation mode, at the end of the call otherwise.
        class Faulty final : public SkyElement {
        public:
            Faulty() : SkyElement("faulty") {}

        private:
            void doInit(InitContext&) override {}
            void doRender(const FrameContext&) override { glBindBuffer(0x7FFF, 0); }  // GL_INVALID_ENUM
            void doRelease() override {}
        };
        p.add(std::make_unique<Faulty>());
        CHECK_THROWS_WITH(p.renderFrame(), Catch::Contains(validation ? "faulty::render(): GL error GL_INVALID_ENUM" : "SkyProcessor::renderFrame(): GL error"));
        while (glGetError() != GL_NO_ERROR) {
        }
    }
}

// ---- The real elements over a host's scene ------------------------------------------------------

#include <welkin/elements/registry.hpp>
#include <welkin/keys.hpp>
#include <nlohmann/json.hpp>

namespace {
// A host scene: flat ground (ENU z = 0) seen from `eyeHeightM` looking north `pitchRad` down
// through a reversed-Z infinite projection (vertical field of view `fovRad`, square), colour
// `radiance` (cd/m^2) where the ground is and the far plane elsewhere: its depth per pixel from
// the ground's distance along each ray, as the host's rasteriser would write it.
struct GroundScene {
    HostTarget t;
    Camera cam;
    std::vector<double> distance;  // metres per pixel (top row first), inf where no ground
    GroundScene(int n, double eyeHeightM, double pitchRad, double fovRad, float radiance) : t(n, n), distance(size_t(n * n)) {
        const double f = 1.0 / std::tan(fovRad / 2), nearM = 0.1;
        glm::dmat4 proj(0.0);
        proj[0][0] = proj[1][1] = f;
        proj[2][3] = -1.0;
        proj[3][2] = nearM;  // reversed-Z, infinite far: window depth = near / -z
        const glm::dvec3 eye(0, 0, eyeHeightM), fwd(0, std::cos(pitchRad), -std::sin(pitchRad));
        cam = Camera::fromViewProjection(lookAlong(eye, fwd, {0, 0, 1}), proj, enuFromZUp(), n, n,
                                         {.reversedZ = true, .zeroToOne = true});
        std::vector<float> depth(size_t(n * n));
        for (int y = 0; y < n; ++y)
            for (int x = 0; x < n; ++x) {
                const glm::dvec3 d = *cam.directionAt({x + 0.5, y + 0.5});
                const double dist = d.z < 0 ? eyeHeightM / -d.z : std::numeric_limits<double>::infinity();
                distance[size_t(y * n + x)] = dist;
                const double zView = -dist * glm::dot(d, fwd);  // view z: minus the distance along the axis
                depth[size_t((n - 1 - y) * n + x)] = std::isinf(dist) ? 0.0f : float(nearM / -zView);
            }
        glTextureSubImage2D(t.depth.id(), 0, 0, 0, n, n, GL_DEPTH_COMPONENT, GL_FLOAT, depth.data());
        t.fbo.bind();
        const float c[4] = {radiance, radiance, radiance, 1};
        glClearBufferfv(GL_COLOR, 0, c);
    }
    RenderTarget target() const { return {.framebuffer = t.fbo.id(), .width = t.w, .height = t.h, .depth = HostDepth{.depthTexture = t.depth.id()}}; }
};

std::unique_ptr<SkyProcessor> noonOverMalta(const std::string& elements, const std::string& preset = "") {
    auto p = std::make_unique<SkyProcessor>();
    for (const auto& n : elements::expandElementList(elements)) p->add(elements::makeElement(n));
    if (!preset.empty()) p->vars().setFromString("clouds.preset", preset);
    p->setObserver({.latitudeRad = 35.9 * kDeg, .longitudeRad = 14.5 * kDeg, .heightMeters = 0});
    p->setTime(UtcInstant::parse("2026-06-21T10:00:00Z"));
    p->setAnimationTime(0.0);
    return p;
}
}  // namespace

TEST_CASE("applyToScene: the air in front of the host's ground brightens it with distance", "[gl][host][sky]") {
    test::glContext();
    // Black ground seen from 2 m, looking north 0.5 deg down with a 2 deg field: the rows span
    // the ground from ~80 m to the horizon; the aerial perspective alone shows on it.
    const int n = 24;
    GroundScene g(n, 2.0, 0.5 * kDeg, 2.0 * kDeg, 0.0f);
    auto p = noonOverMalta("sky");
    p->setCamera(g.cam);
    p->renderInto(g.target());
    const auto before = g.t.colour.readRgbaFloat();
    p->applyToScene(g.target());
    auto px = g.t.colour.readRgbaFloat();
    for (size_t i = 0; i < px.size(); ++i) REQUIRE(std::isfinite(px[i]));
    CHECK(p->vars().get(keys::hostScene));
    double lastDist = 0, lastG = -1;
    int groundRows = 0;
    for (int y = n - 1; y >= 0; --y) {  // from the bottom (near) upwards (far)
        const double dist = g.distance[size_t(y * n + n / 2)];
        const glm::vec4 c = g.t.at(px, n / 2, y);
        if (std::isinf(dist)) {
            // The sky (drawn by renderInto) is left as it was.
            CHECK(c.g == g.t.at(before, n / 2, y).g);
            continue;
        }
        ++groundRows;
        CHECK(dist > lastDist);
        // More air, more light: in-scattering grows with the distance (strictly: the volume's
        // slices interpolate linearly between monotone values).
        CHECK(c.g > lastG);
        CHECK(c.b > c.r);  // Rayleigh: the air's light is blue
        lastDist = dist;
        lastG = c.g;
        if (dist > 3000 && dist < 6000) {
            // 3-6 km of noon air in front of black ground: a quarter to three quarters of the
            // horizon sky's 5000-8000 cd/m^2 (the haze's extinction length is ~10-20 km).
            CHECK(c.g > 500.0f);
            CHECK(c.g < 6000.0f);
        }
        if (dist < 150) CHECK(c.g < 150.0f);  // ~100 m of air: a few per cent of the horizon
    }
    CHECK(groundRows > n / 2);
}

#ifdef WELKIN_HAS_ELEMENT_clouds  // the Clouds element, by name
TEST_CASE("applyToScene: the clouds' shadows fall on the host's ground", "[gl][host][clouds]") {
    test::glContext();
    // A bright ground (1e5 cd/m^2: the aerial perspective's few hundred are then < 1 %) seen from
    // 3 km under the fair cumulus at noon; the same scene without clouds is the reference, so the
    // ratio is the shadow pass's factor.
    const int n = 32;
    auto render = [&](const std::string& elements) {
        // Looking down 60 deg from 3 km with a 90 deg field: 2-15 km of ground ahead.
        GroundScene g(n, 3000.0, 60 * kDeg, 90 * kDeg, 1e5f);
        auto p = noonOverMalta(elements, elements == "sky" ? "" : "fair");
        p->setCamera(g.cam);
        p->renderInto(g.target());
        p->applyToScene(g.target());
        return g.t.colour.readRgbaFloat();
    };
    const auto clear = render("sky"), cloudy = render("sky,clouds");
    int shadowed = 0, lit = 0;
    for (size_t i = 0; i < clear.size(); i += 4) {
        const double f = cloudy[i + 1] / clear[i + 1];
        REQUIRE(std::isfinite(f));
        CHECK(f >= 0.0);
        // A sunlit patch under a broken deck is at most the clear direct + diffuse over the
        // observer's share: < 3x at noon (the diffuse is > 1/3 of the direct only under a deck).
        CHECK(f < 3.0);
        if (f < 0.7) ++shadowed;  // a cloud's shadow: the Sun's direct light (3/4 of the total at noon) mostly gone
        if (f > 0.95) ++lit;
    }
    // Fair-weather cumulus (1-2 oktas) over a 6 km square: both shadow and sunlit ground.
    CHECK(shadowed > 0);
    CHECK(lit > shadowed);
}
#endif

TEST_CASE("The elements draw the same sky through a host's rolled camera", "[gl][host][camera]") {
    test::glContext();
    // Welkin's own camera, and the same camera given by a host's matrices rolled 90 deg (square
    // image): the host's frame is welkin's turned a quarter, pixel (x, y) <- (W - 1 - y, x).
    // Sky (per-pixel LUT fetches), Planet (the Sun's disk, sprites through
    // welkin_clipFromDirection) and Grid (lines and welkin_pixelAngle) through one camera block.
    // (Measured: the sky and the Sun's disk agree to 1e-5 relative.)
    const int n = 48;
    Camera own;
    own.azimuthRad = 95 * kDeg;  // towards the morning Sun over Malta
    own.altitudeRad = 30 * kDeg;
    own.verticalFovRad = 60 * kDeg;
    own.width = own.height = n;
    const glm::dmat3 b = own.basis();
    const glm::dmat4 proj = glm::perspective(own.verticalFovRad, 1.0, 0.1, 100.0);
    const Camera rolled = Camera::fromViewProjection(lookAlong({}, b[2], b[0]), proj, enuFromZUp(), n, n);  // up = old right
    // The Planet and the Grid by name, where their folders are present (the Sky alone without).
    std::string names = "sky";
#ifdef WELKIN_HAS_ELEMENT_planet
    names += ",planet";
#endif
#ifdef WELKIN_HAS_ELEMENT_grid
    names += ",grid";
#endif
    auto render = [&](const Camera& cam) {
        auto p = noonOverMalta(names);
#ifdef WELKIN_HAS_ELEMENT_grid
        // The grid's text labels stay upright on the screen whatever the roll (as they should):
        // only its lines are compared.
        p->vars().setFromString("grid.markers", "false");
#endif
        p->setTime(UtcInstant::parse("2026-06-21T07:00:00Z"));
        p->setCamera(cam);
        p->setExposure({.automatic = false, .ev100 = 14});
        p->renderFrame();
        return p->readHdr();
    };
    const Image a = render(own), r = render(rolled);
    double worst = 0, sum = 0;
    for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x) {
            // Rolled pixel (x, y) shows unrolled pixel (n - 1 - y, x) (pixel centres map exactly).
            const double want = a.at(n - 1 - y, x, 1), got = r.at(x, y, 1);
            const double rel = std::abs(got - want) / std::max(want, 1.0);
            worst = std::max(worst, rel);
            sum += rel;
        }
    // The same rays up to float rounding of the camera block's matrices (~1e-7 rad): the sky's
    // LUT fetches agree to 1e-4; a grid line's anti-aliased edge or the Sun's disk rim can move
    // by a float ulp of a pixel, so the largest error is bounded by 5 % and the mean by 0.1 %.
    CHECK(sum / (n * n) < 1e-3);
    CHECK(worst < 0.05);
}
