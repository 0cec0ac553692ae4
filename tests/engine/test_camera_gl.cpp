// GL tier: the camera's vertex side (welkin_clipFromDirection and friends in camera.glsl) against
// the fragment side (welkin_viewDirection) and the C++ twins, and the bindings table.
#include <catch2/catch.hpp>

#include "camera_cases.hpp"

#include "gl_test_context.hpp"

#include <welkin/camera.hpp>
#include <welkin/gl/bindings.hpp>
#include <welkin/gl/objects.hpp>
#include <welkin/gl/projection_programs.hpp>
#include <welkin/gl/shader.hpp>

#include <epoxy/gl.h>
#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <cmath>
#include <optional>
#include <tuple>
#include <set>
#include <string>
#include <vector>

using namespace welkin;

namespace {
constexpr double kDeg = M_PI / 180;
constexpr int kMaxPoints = 64;

// One vertex per direction (u_dirs[gl_VertexID]) at welkin_clipFromDirection; the fragment writes
// its own welkin_viewDirection and the point's index, plus what the vertex stage computed.
constexpr const char* kPointsVert = R"(
uniform vec4 u_dirs[64];
flat out vec4 v_clip;
flat out vec4 v_j01;   // pixel Jacobian columns 0 and 1
flat out vec4 v_j2s;   // column 2, pixel scale (smallest, largest)
flat out float v_index;
void main() {
    vec3 d = u_dirs[gl_VertexID].xyz;
    vec4 c = welkin_clipFromDirection(d);
    mat3x2 J = welkin_pixelJacobian(d);
    v_clip = c;
    v_j01 = vec4(J[0], J[1]);
    v_j2s = vec4(J[2], welkin_pixelScale(d));
    v_index = float(gl_VertexID + 1);
    gl_Position = c;
}
)";
constexpr const char* kPointsFrag = R"(
flat in vec4 v_clip;
flat in vec4 v_j01;
flat in vec4 v_j2s;
flat in float v_index;
layout(location = 0) out vec4 o_view;
layout(location = 1) out vec4 o_clip;
layout(location = 2) out vec4 o_j01;
layout(location = 3) out vec4 o_j2s;
void main() {
    vec3 d;
    bool ok = welkin_viewDirection(welkin_pixel(), d);
    o_view = vec4(ok ? d : vec3(0.0), v_index);
    o_clip = v_clip;
    o_j01 = v_j01;
    o_j2s = v_j2s;
}
)";

// Sprites: a quad of +-u_halfPx pixels around each direction, 2 instances per direction (the
// equirect seam twin), or 1 when u_copies is 1.
constexpr const char* kQuadsVert = R"(
uniform vec4 u_dirs[64];
uniform int u_copies;
uniform float u_halfPx;
flat out float v_index;
void main() {
    int sprite = gl_InstanceID / u_copies, copy = gl_InstanceID % u_copies;
    const vec2 corner[6] = vec2[6](vec2(-1, -1), vec2(1, -1), vec2(1, 1), vec2(-1, -1), vec2(1, 1), vec2(-1, 1));
    vec4 c = welkin_clipFromDirectionWrapped(u_dirs[sprite].xyz, copy);
    v_index = float(sprite + 1);
    gl_Position = welkin_clipOffset(c, u_halfPx * corner[gl_VertexID]);
}
)";
constexpr const char* kQuadsFrag = R"(
flat in float v_index;
layout(location = 0) out vec4 o_index;
void main() { o_index = vec4(v_index); }
)";

gl::ProgramBuilder recipe(const char* label, const char* vert, const char* frag) {
    auto camera = gl::engineShader("camera.glsl");
    return gl::ProgramBuilder(label)
        .vertex("engine/camera.glsl", camera)
        .vertex("tests/points.vert", vert)
        .fragment("engine/camera.glsl", camera)
        .fragment("tests/points.frag", frag);
}

// A float framebuffer of `targets` RGBA32F colour attachments at the camera's size, with the
// camera block bound and the viewport set as the processor does.
struct Target {
    std::vector<gl::Texture2D> colour;
    gl::Framebuffer fbo;
    gl::Buffer ubo;
    gl::VertexArray vao;

    Target(const Camera& cam, int targets) : fbo(gl::Framebuffer::create()), vao(gl::VertexArray::create()) {
        std::vector<GLenum> buffers;
        for (int i = 0; i < targets; ++i) {
            colour.emplace_back(cam.width, cam.height, GL_RGBA32F);
            fbo.attach(GL_COLOR_ATTACHMENT0 + i, colour.back());
            buffers.push_back(GL_COLOR_ATTACHMENT0 + i);
        }
        fbo.checkComplete("camera test");
        fbo.bind();
        glDrawBuffers(GLsizei(buffers.size()), buffers.data());
        const float zero[4] = {0, 0, 0, 0};
        for (int i = 0; i < targets; ++i) glClearBufferfv(GL_COLOR, i, zero);
        CameraBlock block = makeCameraBlock(cam, 0.0);
        ubo = gl::Buffer(sizeof block, &block);
        ubo.bindBase(GL_UNIFORM_BUFFER, gl::binding::kCameraUbo);
        glViewport(0, 0, cam.width, cam.height);
        vao.bind();
        glDisable(GL_BLEND);
        glDisable(GL_DEPTH_TEST);
    }
    // RGBA of image pixel (x, y), y down (GL stores rows bottom-up).
    static glm::dvec4 at(const std::vector<float>& px, const Camera& cam, int x, int y) {
        size_t i = (size_t(cam.height - 1 - y) * size_t(cam.width) + size_t(x)) * 4;
        return {px[i], px[i + 1], px[i + 2], px[i + 3]};
    }
};

void uploadDirections(const gl::Program& p, const std::vector<glm::dvec3>& dirs) {
    std::vector<glm::vec4> v;
    for (const auto& d : dirs) v.emplace_back(glm::vec3(d), 0.0f);
    glProgramUniform4fv(p.id(), p.location("u_dirs"), GLsizei(v.size()), &v[0].x);
}

// The float the GPU sees, back in double (the expected positions are computed from it).
glm::dvec3 asFloat(const glm::dvec3& d) { return glm::dvec3(glm::vec3(d)); }

double angleBetween(const glm::dvec3& a, const glm::dvec3& b) {
    return std::atan2(glm::length(glm::cross(a, b)), glm::dot(a, b));
}

std::vector<Camera> cameras() {
    std::vector<Camera> out;
    auto persp = [&](double fovDeg, double azDeg, double altDeg) {
        Camera c;
        c.verticalFovRad = fovDeg * kDeg;
        c.azimuthRad = azDeg * kDeg;
        c.altitudeRad = altDeg * kDeg;
        c.width = 64;
        c.height = 48;
        out.push_back(c);
    };
    persp(0.5, 200, 35);
    persp(60, 10, -20);
    persp(60, 135, 90);
    persp(179, 300, 5);
    // The host's cameras (Camera::fromViewProjection): rolled 30 deg, an off-axis frustum, a
    // Y-up world, reversed-Z; the shaders see them through the same camera block.
    {
        const glm::dvec3 fwd = glm::normalize(glm::dvec3(0.4, 0.3, -1.0));
        const glm::dvec3 up = glm::rotate(glm::dmat4(1.0), 30 * kDeg, fwd) * glm::dvec4(0, 1, 0, 0);
        const glm::dmat4 view = glm::lookAt(glm::dvec3(3, 2, 1), glm::dvec3(3, 2, 1) + fwd, up);
        out.push_back(Camera::fromViewProjection(view, glm::frustum(-0.3, 0.7, -0.2, 0.4, 0.5, 100.0), enuFromYUp(), 64, 48,
                                                 {.reversedZ = true, .zeroToOne = true}));
        out.push_back(Camera::fromViewProjection(view, glm::perspective(80 * kDeg, 1.25, 0.1, 1e3), enuFromYUp(), 60, 48));
    }
    test::appendNonPerspectiveCameras(out);
    return out;
}
}  // namespace

TEST_CASE("welkin_clipFromDirection lands on the pixel whose view direction it is (GPU)", "[gl][camera]") {
    test::glContext();
    gl::ProjectionPrograms specialised(recipe("clip points", kPointsVert, kPointsFrag));
    gl::Program generic = recipe("clip points (generic)", kPointsVert, kPointsFrag).build();
    for (const Camera& cam : cameras()) {
        const std::string what = std::string(toString(cam.projection)) + " fov " + std::to_string(cam.verticalFovRad / kDeg) +
                                 " face " + std::to_string(cam.cubeFace);
        INFO(what);
        // Visible directions in the frame, >= 3 px apart (one pixel each), >= 0.02 px from a
        // pixel's edge (a point exactly on an edge may light either pixel; the GPU's float
        // clip position errs by < 1e-3 px here); from random pixel positions (so every frame,
        // even 0.5 deg wide, has some) and from random directions on the sphere; plus directions
        // the projection does not show (behind, below the horizon, another face, off the frame).
        std::vector<glm::dvec3> visible, hidden;
        std::vector<glm::dvec2> where;
        unsigned s = 12345;
        auto next = [&] {
            s = s * 1664525u + 1013904223u;
            return (s >> 8) / double(1u << 24);
        };
        for (int k = 0; k < 4000 && visible.size() < 40; ++k) {
            std::optional<glm::dvec3> d;
            if (k % 2 == 0) {
                d = cam.directionAt({next() * cam.width, next() * cam.height});
            } else {
                double z = 2 * next() - 1, phi = 2 * M_PI * next(), r = std::sqrt(1 - z * z);
                d = glm::dvec3(r * std::cos(phi), r * std::sin(phi), z);
            }
            if (!d) continue;
            glm::dvec3 f = asFloat(*d);
            auto p = cam.pixelOf(f);
            bool onImage = p && p->x >= 0 && p->x < cam.width && p->y >= 0 && p->y < cam.height;
            if (!onImage) {
                if (hidden.size() < 20) hidden.push_back(f);
                continue;
            }
            glm::dvec2 frac = *p - glm::floor(*p);
            if (std::min({frac.x, frac.y, 1 - frac.x, 1 - frac.y}) < 0.02) continue;
            bool apart = true;
            for (const auto& q : where) apart = apart && glm::length(q - *p) >= 3;
            if (!apart) continue;
            visible.push_back(f);
            where.push_back(*p);
        }
        REQUIRE(visible.size() >= 10);
        REQUIRE(hidden.size() + visible.size() <= size_t(kMaxPoints));
        if (cam.projection != Projection::Equirect) REQUIRE(hidden.size() >= 5);
        std::vector<glm::dvec3> all = visible;
        all.insert(all.end(), hidden.begin(), hidden.end());

        for (bool useSpecialised : {false, true}) {
            INFO((useSpecialised ? "specialised" : "generic"));
            Target t(cam, 4);
            const gl::Program& prog = useSpecialised ? specialised.get(cam.projection) : generic;
            prog.use();
            uploadDirections(prog, all);
            glDrawArrays(GL_POINTS, 0, GLsizei(all.size()));
            gl::checkError("clip points");
            std::vector<std::vector<float>> px;
            for (auto& tex : t.colour) px.push_back(tex.readRgbaFloat());

            std::vector<std::vector<glm::ivec2>> hits(all.size());
            for (int y = 0; y < cam.height; ++y)
                for (int x = 0; x < cam.width; ++x) {
                    int idx = int(std::lround(Target::at(px[0], cam, x, y).w));
                    if (idx > 0) hits.at(size_t(idx - 1)).push_back({x, y});
                }
            for (size_t i = 0; i < all.size(); ++i) {
                const glm::dvec3& d = all[i];
                INFO("direction " << i << ": " << d.x << " " << d.y << " " << d.z);
                if (i >= visible.size()) {
                    CHECK(hits[i].empty());  // not visible: no fragment anywhere
                    continue;
                }
                REQUIRE(hits[i].size() == 1);  // a 1-pixel point: exactly one fragment
                const glm::ivec2 h = hits[i][0];
                // It is the pixel containing the exact position (>= 0.02 px from its edges).
                CHECK(h == glm::ivec2(glm::floor(where[i])));
                glm::dvec4 view = Target::at(px[0], cam, h.x, h.y);
                glm::dvec3 gpuDir(view);
                glm::dvec3 cpuDir = *cam.directionAt(glm::dvec2(h) + 0.5);
                // GLSL welkin_viewDirection vs C++ directionAt at the same pixel centre: float32
                // arithmetic, < 2e-6 rad (the narrowest pixel here is 1.8e-4 rad).
                CHECK(angleBetween(gpuDir, cpuDir) < 2e-6);
                // The direction drawn is within the pixel's half-diagonal of the pixel centre's
                // direction, in pixels through the smallest local scale (+1 % for its variation
                // over half a pixel).
                const glm::dvec2 scale = *cam.pixelScale(d);
                CHECK(angleBetween(gpuDir, d) * scale.x < 0.5 * std::sqrt(2.0) * 1.01);
                // The vertex stage's numbers equal the C++ twin's: float32, relative 1e-5 of the
                // largest component (1e-4 for the Jacobian, a difference quotient of them).
                glm::dvec4 clip = *cam.clipFromDirection(d);
                glm::dvec4 gpuClip = Target::at(px[1], cam, h.x, h.y);
                double cmax = std::max({std::abs(clip.x), std::abs(clip.y), std::abs(clip.w), 1e-3});
                // A pinhole's clip rows are 1/tan(fov/2) long (229 at 0.5 deg): their products with
                // the unit direction cancel down to the clip value, so float32 rounding is also
                // ~1e-7 of the row's length (2e-7: two roundings, the row's and the product's).
                const double tanY = std::tan(cam.verticalFovRad / 2);
                const double rowLength = cam.projection == Projection::Perspective ? 1.0 / std::min(tanY, tanY * cam.width / cam.height) : 1.0;
                for (int k = 0; k < 4; ++k) CHECK(std::abs(gpuClip[k] - clip[k]) < 1e-5 * cmax + 2e-7 * rowLength);
                glm::dmat3x2 J = *cam.pixelJacobian(d);
                glm::dvec4 j01 = Target::at(px[2], cam, h.x, h.y), j2s = Target::at(px[3], cam, h.x, h.y);
                const double gpuJ[6] = {j01.x, j01.y, j01.z, j01.w, j2s.x, j2s.y};
                for (int k = 0; k < 6; ++k) CHECK(std::abs(gpuJ[k] - J[k / 2][k % 2]) < 1e-4 * scale.y);
                CHECK(j2s.z == Approx(scale.x).epsilon(1e-4));
                CHECK(j2s.w == Approx(scale.y).epsilon(1e-4));
            }
            // And nothing else was drawn.
            size_t lit = 0;
            for (const auto& v : hits) lit += v.size();
            CHECK(lit == visible.size());
        }
    }
}

TEST_CASE("Sprites straddling the equirect seam are drawn whole with their twin (GPU)", "[gl][camera]") {
    test::glContext();
    gl::Program prog = recipe("seam quads", kQuadsVert, kQuadsFrag).build();
    for (Projection projection : {Projection::Equirect, Projection::Fisheye, Projection::CubeFace, Projection::Perspective}) {
        Camera cam;
        cam.projection = projection;
        cam.width = 72;
        cam.height = 36;
        cam.cubeFace = 2;
        if (projection == Projection::CubeFace) cam.width = cam.height = 36;
        INFO(toString(projection));
        // Directions within half a pixel of the seam on either side, and one in the middle; for
        // the other projections, directions through pixels near their left and right edges.
        std::vector<glm::dvec2> targets = {{0.3, 10.3}, {cam.width - 0.3, 20.3}, {cam.width / 2 + 0.3, 30.3}};
        if (projection != Projection::Equirect)  // inside a fisheye's circle; only the twin's absence matters
            targets = {{cam.width / 2 - 8.7, cam.height / 2 - 6.7}, {cam.width / 2 + 8.3, cam.height / 2 + 0.3}};
        std::vector<glm::dvec3> dirs;
        for (auto p : targets) {
            auto d = cam.directionAt(p);
            REQUIRE(d);
            dirs.push_back(asFloat(*d));
        }
        const double halfPx = 1.5;  // a 3x3-pixel sprite
        for (int copies : {1, 2}) {
            INFO("copies " << copies);
            Target t(cam, 1);
            prog.use();
            uploadDirections(prog, dirs);
            prog.set("u_copies", copies);
            prog.set("u_halfPx", float(halfPx));
            glDrawArraysInstanced(GL_TRIANGLES, 0, 6, GLsizei(dirs.size() * size_t(copies)));
            gl::checkError("seam quads");
            auto px = t.colour[0].readRgbaFloat();
            // Expected: the pixel centres inside each copy's square, from the C++ twin.
            std::set<std::tuple<int, int, int>> want, got;
            for (size_t i = 0; i < dirs.size(); ++i)
                for (int copy = 0; copy < copies; ++copy) {
                    auto clip = cam.clipFromDirection(dirs[i], copy);
                    if (!clip) continue;
                    glm::dvec2 c = cam.pixelFromClip(*clip);
                    for (int y = 0; y < cam.height; ++y)
                        for (int x = 0; x < cam.width; ++x)
                            if (std::abs(x + 0.5 - c.x) < halfPx && std::abs(y + 0.5 - c.y) < halfPx) want.insert({int(i) + 1, x, y});
                }
            for (int y = 0; y < cam.height; ++y)
                for (int x = 0; x < cam.width; ++x)
                    if (int idx = int(std::lround(Target::at(px, cam, x, y).x)); idx > 0) got.insert({idx, x, y});
            CHECK(got == want);
            if (projection == Projection::Equirect) {
                // Written out: the sprite 0.3 px right of the seam covers columns 0 and 1, and
                // column W-1 only through its twin; the one 0.3 px left of it, W-2, W-1 and 0.
                auto lit = [&](int idx, int x, int y) { return got.count({idx, x, y}) == 1; };
                CHECK(lit(1, 0, 10));
                CHECK(lit(1, 1, 10));
                CHECK(lit(1, cam.width - 1, 10) == (copies == 2));
                CHECK(lit(2, cam.width - 2, 20));
                CHECK(lit(2, 0, 20) == (copies == 2));
                CHECK(got.size() == size_t(copies == 2 ? 3 * 9 : 3 * 9 - 2 * 3));
            }
        }
    }
}

TEST_CASE("The bindings table reaches every stage and fits the context's limits", "[gl]") {
    test::glContext();
    // Unique GLSL names.
    std::set<std::string_view> names;
    for (const auto& e : gl::binding::kTable) CHECK(names.insert(e.glslName).second);
    // Each stage's generated header defines every entry and its own stage macro.
    auto b = recipe("bindings", kPointsVert, kPointsFrag);
    for (GLenum stage : {GLenum(GL_VERTEX_SHADER), GLenum(GL_FRAGMENT_SHADER)}) {
        std::string src = b.assembled(stage);
        for (const auto& e : gl::binding::kTable)
            CHECK_THAT(src, Catch::Contains("#define " + std::string(e.glslName) + " " + std::to_string(e.value) + "\n"));
        CHECK_THAT(src, Catch::Contains(stage == GL_VERTEX_SHADER ? "#define WELKIN_VERTEX_SHADER" : "#define WELKIN_FRAGMENT_SHADER"));
    }
    // The driver sees them: the linked program's camera block and a LUT sampler sit at the C++
    // constants.
    gl::Program p = gl::ProgramBuilder("bindings")
                        .fullscreenVertex()
                        .fragment("engine/camera.glsl", gl::engineShader("camera.glsl"))
                        .fragment("tests/bindings.frag",
                                  "layout(binding = WELKIN_BINDING_VIEW_TRANSMITTANCE_LUT) uniform sampler1D u_lut;\n"
                                  "out vec4 o;\nvoid main() { o = texture(u_lut, welkin_pixel().x) + welkin_time; }\n")
                        .build();
    GLint blockBinding = -1, unit = -1;
    glGetActiveUniformBlockiv(p.id(), glGetUniformBlockIndex(p.id(), "WelkinCamera"), GL_UNIFORM_BLOCK_BINDING, &blockBinding);
    glGetUniformiv(p.id(), p.location("u_lut"), &unit);
    CHECK(blockBinding == gl::binding::kCameraUbo);
    CHECK(unit == gl::binding::kViewTransmittanceLut);
    // The private ranges (elements' own bindings) exist on this context (GL 4.5 guarantees them; checked, not assumed).
    auto limit = [](GLenum name) {
        GLint v = 0;
        glGetIntegerv(name, &v);
        return v;
    };
    CHECK(limit(GL_MAX_COMBINED_TEXTURE_IMAGE_UNITS) > gl::binding::kPrivateTextureUnitLast);
    CHECK(limit(GL_MAX_IMAGE_UNITS) > gl::binding::kPrivateImageUnitLast);
    CHECK(limit(GL_MAX_UNIFORM_BUFFER_BINDINGS) > gl::binding::kPrivateUboLast);
    CHECK(limit(GL_MAX_SHADER_STORAGE_BUFFER_BINDINGS) > gl::binding::kPrivateSsboLast);
    gl::checkError("bindings");
}
