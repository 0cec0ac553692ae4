// One source for the GPU maths and its CPU twin (docs/architecture.md): an embedded shader's
// `#include "x.shared.glsl"` is expanded at build time, ProgramBuilder makes the included text a
// chunk of its own (errors name it and its line; the includer keeps its line numbers), and the
// same text compiles as C++ over GLM (welkin/glsl_cpp.hpp).
#include <catch2/catch.hpp>

#include "gl_test_context.hpp"

#include <epoxy/gl.h>

#include <welkin/embedded/atmosphere_shaders.hpp>
#include <welkin/embedded/clouds_shaders.hpp>
#include <welkin/gl/shader.hpp>
#include <welkin/glsl_cpp.hpp>

#include <string>
#include <type_traits>

using namespace welkin;

namespace {
// What EmbedShaders.cmake makes of "line 1 / #include "b.shared.glsl" / line 3" (b: two lines).
constexpr const char* kExpanded =
    "layout(local_size_x = 1) in;\n"
    "//@welkin-include-begin b.shared.glsl\n"
    "real twice(real x) { return 2.0 * x; }\n"
    "BROKEN_IN_SHARED\n"
    "//@welkin-include-end\n"
    "void main() { BROKEN_IN_HOST; }\n";

// A shared function written in the dialect, compiled here as C++ (double).
namespace welkin_test_shared {
using namespace welkin::glsl::dp;
vec2 halfAndSquare(IN(vec3) p, OUT(real) sum) {
    sum = p.x + p.y + p.z;
    return vec2(p) * 0.5 + vec2(dot(p, p), real(uint(3u)));
}
}  // namespace welkin_test_shared
}  // namespace

TEST_CASE("Shared GLSL: an expanded include is a chunk of its own, the includer resumes at its next line", "[cpu][gl_shader]") {
    const std::string a = gl::ProgramBuilder("Split").compute("tests/host.glsl", kExpanded).assembled(GL_COMPUTE_SHADER);
    // Chunk k starts at line k * 100000 + its first line (shader.hpp): host line 1, then the
    // shared file from its line 1, then the host again from line 3 (line 2 was the #include).
    CHECK_THAT(a, Catch::Contains("#line 100001\nlayout(local_size_x = 1) in;\n"));
    CHECK_THAT(a, Catch::Contains("#line 200001\nreal twice(real x)"));
    CHECK_THAT(a, Catch::Contains("#line 300003\nvoid main()"));
    CHECK_THAT(a, !Catch::Contains("@welkin-include"));
    // The dialect is defined for GLSL in the generated header.
    CHECK_THAT(a, Catch::Contains("#define real float\n"));
    CHECK_THAT(a, Catch::Contains("#define IN(T) in T\n"));
}

TEST_CASE("Shared GLSL: the embedded shaders carry their shared files expanded", "[cpu][gl_shader]") {
    const std::string d(embedded::clouds_shaders("cloud_density.glsl"));
    CHECK_THAT(d, Catch::Contains("//@welkin-include-begin cloud_density.shared.glsl\n"));
    CHECK_THAT(d, Catch::Contains("real cld_layerDensity("));
    CHECK_THAT(d, !Catch::Contains("#include"));
    const std::string atm(embedded::atmosphere_shaders("atmosphere.glsl"));
    CHECK_THAT(atm, Catch::Contains("real distanceToTop(real R, real Ht, real h, real mu)"));
    CHECK_THAT(atm, !Catch::Contains("#include"));
}

TEST_CASE("Shared GLSL: the dialect compiles as C++ in double", "[cpu][gl_shader]") {
    welkin::glsl::dp::real sum = 0.0;
    const glm::dvec2 r = welkin_test_shared::halfAndSquare(glm::dvec3(1.0, 2.0, 3.0), sum);
    CHECK(sum == 6.0);
    CHECK(r.x == 0.5 + 14.0);  // 1/2 + |p|^2, exact in double
    CHECK(r.y == 1.0 + 3.0);
    static_assert(std::is_same_v<welkin::glsl::dp::real, double> && sizeof(welkin::glsl::dp::uint) == 4);
}

TEST_CASE("Shared GLSL: compile errors name the shared file or the includer, with their own lines", "[gl][gl_shader]") {
    test::glContext();
    // Only the shared file broken: the error is at its line 2.
    std::string sharedBroken = kExpanded;
    sharedBroken.replace(sharedBroken.find("BROKEN_IN_HOST;"), 15, "");
    CHECK_THROWS_WITH(gl::ProgramBuilder("Shared").compute("tests/host.glsl", sharedBroken).build(),
                      Catch::Contains("tests/b.shared.glsl:2"));
    // Only the includer broken after the include: its own line 3.
    std::string hostBroken = kExpanded;
    hostBroken.replace(hostBroken.find("BROKEN_IN_SHARED\n"), 17, "");
    CHECK_THROWS_WITH(gl::ProgramBuilder("Host").compute("tests/host.glsl", hostBroken).build(), Catch::Contains("tests/host.glsl:3"));
}
