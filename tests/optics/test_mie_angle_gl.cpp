// The Mie tables' angle mapping: the GLSL function (shaders/mie_angle.glsl) the Rainbow samples
// the tables with equals the C++ one the tables are built with.
#include <catch2/catch.hpp>

#include "gl_test_context.hpp"

#include <welkin/embedded/optics_shaders.hpp>
#include <welkin/generators/mie_tables.hpp>
#include <welkin/gl/objects.hpp>
#include <welkin/gl/shader.hpp>

#include <epoxy/gl.h>

#include <cmath>

using namespace welkin;

TEST_CASE("Mie angle mapping: GLSL and C++ agree", "[gl][rainbow]") {
    test::glContext();
    constexpr int N = 181;  // theta = 0, 1, ..., 180 deg, one per pixel
    gl::Texture2D target(N, 1, GL_RGBA32F);
    gl::Framebuffer fbo = gl::Framebuffer::create();
    fbo.attach(GL_COLOR_ATTACHMENT0, target);
    fbo.checkComplete("mie angle test");
    gl::VertexArray vao = gl::VertexArray::create();
    gl::Program prog = gl::ProgramBuilder("mie angle test")
                           .fullscreenVertex()
                           .fragment("optics/mie_angle.glsl", embedded::optics_shaders("mie_angle.glsl"))
                           .fragment("test.frag",
                                     "out vec4 o; void main() { float t = radians(floor(gl_FragCoord.x));"
                                     " o = vec4(welkin_mieUFromAngle(t), t, 0.0, 1.0); }")
                           .build();
    fbo.bind();
    glViewport(0, 0, N, 1);
    glDisable(GL_BLEND);
    vao.bind();
    prog.use();
    glDrawArrays(GL_TRIANGLES, 0, 3);
    const std::vector<float> px = target.readRgbaFloat();
    for (int i = 0; i < N; ++i) {
        const double theta = px[4 * std::size_t(i) + 1];
        CAPTURE(i);
        // float32 in the shader: ~1e-7 relative in u.
        CHECK(px[4 * std::size_t(i)] == Approx(generators::mieUFromAngle(theta)).margin(2e-6));
    }
}
