// Hidden timing (not run by CI: `welkin_tests "[night_cells_timing]"`): what the night sky's pass
// would cost drawn through a grid of screen cells instead of per pixel (issue 22 item 2; README
// "Cost", "the screen in cells instead of pixels"). Standalone passes at 1280x720 into RGBA32F,
// the issue's view (south, 30 deg up, 60 deg field), a 2048x1024 RGBA32F equirectangular texture
// (the folded panorama's size and
// format, bilinear, level 0: the fast path's fixed level), each timed in process CPU time with
// glFinish around it, the passes alternated for 15 rounds (median), as ratios to a trivial pass:
//
//   per pixel:       the pixel's direction, a 3x3 rotation, atan and acos, one fetch (today's pass
//                    less its van Rhijn factors and its blend);
//   per-vertex map:  cells of C pixels, two triangles each; each vertex does the direction, the
//                    rotation and the atan/acos, the fragment interpolates the texture coordinate
//                    and fetches (no trigonometry per pixel);
//   per-vertex colour: the same cells, each vertex fetches, the fragment writes the interpolated
//                    colour (no fetch per pixel: what a "smooth" cell would cost).
//
// Also prints how far the per-vertex coordinate's image is from the per-pixel one (a texture of
// random texels: the worst case for a coordinate error).
#include <catch2/catch.hpp>

#include "cpu_timing.hpp"
#include "gl_test_context.hpp"

#include <welkin/gl/objects.hpp>
#include <welkin/gl/shader.hpp>

#include <epoxy/gl.h>
#include <glm/glm.hpp>
#include <glm/gtc/type_ptr.hpp>

#include <cmath>
#include <cstdio>
#include <functional>
#include <numbers>
#include <random>
#include <string>
#include <vector>

using namespace welkin;

namespace {
constexpr const char* kCommon = R"(
uniform mat3 u_rot;      // camera space (x right, y up, -z forward) to the panorama's frame
uniform vec2 u_size;     // pixels
uniform float u_tanHalf; // tan of half the vertical field
const float PI = 3.14159265358979;
vec3 dirAt(vec2 px) {
    vec2 ndc = px / u_size * 2.0 - 1.0;
    return normalize(u_rot * vec3(ndc.x * u_tanHalf * u_size.x / u_size.y, ndc.y * u_tanHalf, -1.0));
}
vec2 uvOf(vec3 d) { return vec2(atan(d.y, d.x) * (0.5 / PI) + 0.5, acos(clamp(d.z, -1.0, 1.0)) / PI); }
)";
constexpr const char* kGridVertex = R"(
uniform ivec2 u_grid;
uniform float u_cellPx;
layout(binding = 0) uniform sampler2D u_tex;
out vec3 v_col;
noperspective out vec2 v_uv;
void main() {
    const ivec2 corners[6] = ivec2[6](ivec2(0, 0), ivec2(1, 0), ivec2(1, 1), ivec2(0, 0), ivec2(1, 1), ivec2(0, 1));
    int cell = gl_VertexID / 6;
    ivec2 c = ivec2(cell % u_grid.x, cell / u_grid.x);
    vec2 px = min(vec2(c + corners[gl_VertexID % 6]) * u_cellPx, u_size);
    vec2 uv = uvOf(dirAt(px));
    // The cell's vertices agree on the side of the seam (u wraps: REPEAT): within 0.5 of the centre's.
    float uc = uvOf(dirAt(min((vec2(c) + 0.5) * u_cellPx, u_size))).x;
    uv.x += round(uc - uv.x);
    v_uv = uv;
#ifdef VERTEX_COLOUR
    v_col = textureLod(u_tex, uv, 0.0).rgb;
#else
    v_col = vec3(0.0);
#endif
    gl_Position = vec4(px / u_size * 2.0 - 1.0, 0.0, 1.0);
}
)";
}  // namespace

TEST_CASE("Night sky timing: per pixel, per-vertex mapping, per-vertex colour on a grid of cells", "[.][night_cells_timing]") {
    test::glContext();
    GLint viewport0[4];
    glGetIntegerv(GL_VIEWPORT, viewport0);  // restored at the end: the context is shared
    constexpr int W = 1280, H = 720;
    constexpr double kDeg = std::numbers::pi / 180.0;
    // The texture: random texels in [0.5, 1.5] (its detail at every texel), RGBA32F, bilinear.
    gl::Texture2D tex(2048, 1024, GL_RGBA32F);
    {
        std::mt19937 rng(7);
        std::uniform_real_distribution<float> u(0.5f, 1.5f);
        std::vector<float> px(size_t(2048) * 1024 * 4);
        for (float& v : px) v = u(rng);
        glTextureSubImage2D(tex.id(), 0, 0, 0, 2048, 1024, GL_RGBA, GL_FLOAT, px.data());
        tex.setFilter(GL_LINEAR);
        glTextureParameteri(tex.id(), GL_TEXTURE_WRAP_S, GL_REPEAT);
        glTextureParameteri(tex.id(), GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    }
    gl::Texture2D target(W, H, GL_RGBA32F);
    gl::Framebuffer fbo = gl::Framebuffer::create();
    fbo.attach(GL_COLOR_ATTACHMENT0, target);
    fbo.checkComplete("night cells timing");
    gl::VertexArray vao = gl::VertexArray::create();
    // The camera: azimuth 180 deg, altitude 30 deg in ENU; then a fixed rotation ENU -> panorama
    // frame (about x by 54 deg, the co-latitude of Malta, and z by 30 deg: any rotation will do).
    const double az = 180 * kDeg, alt = 30 * kDeg;
    const glm::dvec3 f(std::sin(az) * std::cos(alt), std::cos(az) * std::cos(alt), std::sin(alt));
    const glm::dvec3 r = glm::normalize(glm::cross(f, glm::dvec3(0, 0, 1))), up = glm::cross(r, f);
    const glm::dmat3 camToEnu(r, up, -f);
    const double a = 54 * kDeg, b = 30 * kDeg;
    const glm::dmat3 rx(1, 0, 0, 0, std::cos(a), std::sin(a), 0, -std::sin(a), std::cos(a));
    const glm::dmat3 rz(std::cos(b), std::sin(b), 0, -std::sin(b), std::cos(b), 0, 0, 0, 1);
    const glm::mat3 rot(rz * rx * camToEnu);
    auto setCommon = [&](const gl::Program& p) {
        p.use();
        glUniformMatrix3fv(glGetUniformLocation(p.id(), "u_rot"), 1, GL_FALSE, glm::value_ptr(rot));
        p.set("u_size", glm::vec2(W, H));
        p.set("u_tanHalf", float(std::tan(30 * kDeg)));
    };
    gl::Program trivial = gl::ProgramBuilder("trivial").fullscreenVertex().fragment("trivial.frag", "out vec4 o; void main() { o = vec4(gl_FragCoord.xy * 1e-3, 0.5, 1.0); }").build();
    gl::Program perPixel = gl::ProgramBuilder("per pixel")
                               .fullscreenVertex()
                               .fragment("common", kCommon)
                               .fragment("perpixel.frag", "layout(binding = 0) uniform sampler2D u_tex; out vec4 o;\n"
                                                          "void main() { o = vec4(textureLod(u_tex, uvOf(dirAt(gl_FragCoord.xy)), 0.0).rgb, 1.0); }")
                               .build();
    auto gridProgram = [&](bool colour) {
        gl::ProgramBuilder bld(colour ? "per-vertex colour" : "per-vertex map");
        if (colour) bld.define("VERTEX_COLOUR");
        bld.vertex("common", kCommon).vertex("grid.vert", kGridVertex);
        bld.fragment("grid.frag", colour ? "in vec3 v_col; out vec4 o; void main() { o = vec4(v_col, 1.0); }"
                                         : "layout(binding = 0) uniform sampler2D u_tex; noperspective in vec2 v_uv; out vec4 o;\n"
                                           "void main() { o = vec4(textureLod(u_tex, v_uv, 0.0).rgb, 1.0); }");
        return bld.build();
    };
    gl::Program mapGrid = gridProgram(false), colourGrid = gridProgram(true);
    auto drawFull = [&](const gl::Program& p, bool common) {
        return [&, common] {
            fbo.bind();
            glViewport(0, 0, W, H);
            glDisable(GL_BLEND);
            vao.bind();
            glBindTextureUnit(0, tex.id());
            if (common) setCommon(p);
            else p.use();
            glDrawArrays(GL_TRIANGLES, 0, 3);
        };
    };
    auto drawGrid = [&](const gl::Program& p, int cellPx) {
        return [&, cellPx] {
            fbo.bind();
            glViewport(0, 0, W, H);
            glDisable(GL_BLEND);
            vao.bind();
            glBindTextureUnit(0, tex.id());
            setCommon(p);
            const int gx = (W + cellPx - 1) / cellPx, gy = (H + cellPx - 1) / cellPx;
            p.set("u_grid", glm::ivec2(gx, gy));
            p.set("u_cellPx", float(cellPx));
            glDrawArrays(GL_TRIANGLES, 0, 6 * gx * gy);
        };
    };
    struct Pass {
        std::string name;
        std::function<void()> draw;
        std::vector<double> ms;
    };
    std::vector<Pass> passes = {{"trivial pass (reference)", drawFull(trivial, false), {}},
                                {"per pixel: direction, rotation, atan, acos, fetch", drawFull(perPixel, true), {}},
                                {"per-vertex map, 16 px cells, fetch", drawGrid(mapGrid, 16), {}},
                                {"per-vertex map, 32 px cells, fetch", drawGrid(mapGrid, 32), {}},
                                {"per-vertex map, 64 px cells, fetch", drawGrid(mapGrid, 64), {}},
                                {"per-vertex colour, 8 px cells, no fetch", drawGrid(colourGrid, 8), {}},
                                {"per-vertex colour, 16 px cells, no fetch", drawGrid(colourGrid, 16), {}},
                                {"per-vertex colour, 32 px cells, no fetch", drawGrid(colourGrid, 32), {}}};
    auto readImage = [&] {
        std::vector<float> px(size_t(W) * H * 4);
        glGetTextureImage(target.id(), 0, GL_RGBA, GL_FLOAT, GLsizei(px.size() * sizeof(float)), px.data());
        return px;
    };
    // The per-vertex coordinate's image against the per-pixel one (before timing: also the warm-up).
    passes[1].draw();
    const std::vector<float> exact = readImage();
    for (int k : {2, 3, 4}) {
        passes[size_t(k)].draw();
        const std::vector<float> img = readImage();
        double sum = 0, worst = 0;
        for (size_t i = 0; i < img.size(); i += 4) {
            const double e = std::abs(double(img[i + 1]) - exact[i + 1]) / exact[i + 1];
            sum += e;
            worst = std::max(worst, e);
        }
        std::printf("%s: against per pixel, mean relative difference %.2e, largest %.2e (random texels in [0.5, 1.5])\n",
                    passes[size_t(k)].name.c_str(), sum / (img.size() / 4), worst);
        // 16-pixel cells (1.3 deg at this view, ~7 texels): the interpolated coordinate errs by a
        // small fraction of a texel (measured 2026-11-27: mean 0.45 %, largest 8 % on these
        // random texels, where a whole texel's error gives ~30 %); bound 1 %. The larger cells
        // are printed (measured 1.7 % and 6.4 % mean), not bounded: they are too coarse for the
        // panorama's 0.18 deg detail, which is the finding.
        if (k == 2) CHECK(sum / (img.size() / 4) < 0.01);
    }
    for (auto& p : passes) p.draw();  // warm-up: llvmpipe compiles at first draw
    glFinish();
    for (int round = 0; round < 15; ++round)
        for (auto& p : passes) {
            glFinish();
            const double t0 = test::cpuMs();
            p.draw();
            glFinish();
            p.ms.push_back(test::cpuMs() - t0);
        }
    const double ref = test::medianOf(passes[0].ms);
    REQUIRE(ref > 0.0);  // the trivial pass measured: the ratios below are meaningful
    std::printf("night sky cells, 1280x720, process CPU ms (median of 15, alternated), x trivial pass:\n");
    for (auto& p : passes) {
        const double m = test::medianOf(p.ms);
        std::printf("  %-55s %7.3f ms  %5.2f\n", p.name.c_str(), m, m / ref);
    }
    glViewport(viewport0[0], viewport0[1], viewport0[2], viewport0[3]);
}
