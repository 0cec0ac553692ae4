// Shader compile errors name the file and line on every driver's log format: the [gl] test in
// test_gl.cpp checks the driver it runs on (llvmpipe in CI); these check the formats of the
// others, as an NVIDIA driver (580, H100) and Mesa actually printed them.
#include "../../engine/src/gl/shader_log.hpp"

#include <catch2/catch.hpp>

using welkin::gl::detail::mapShaderLog;

TEST_CASE("shader logs: Mesa, NVIDIA and generic formats map to file:line", "[cpu][gl-log]") {
    const std::vector<std::string> names = {"engine/composite.glsl", "tests/broken.frag.glsl"};
    // Chunk 2 starts at line 200001, so line 200003 is its third line (Mesa's column is dropped).
    CHECK(mapShaderLog("0:200003(3): error: no function with name 'undefined_fn'\n", names, 100000) ==
          "tests/broken.frag.glsl:3: error: no function with name 'undefined_fn'");
    CHECK(mapShaderLog("0(200003) : error C1503: undefined variable \"undefined_fn\"\n", names, 100000) ==
          "tests/broken.frag.glsl:3 : error C1503: undefined variable \"undefined_fn\"");
    CHECK(mapShaderLog("ERROR: 0:100017: 'x' : undeclared identifier\n", names, 100000) ==
          "ERROR: engine/composite.glsl:17: 'x' : undeclared identifier");
    // Lines below the first chunk belong to the generated header; several lines are joined.
    CHECK(mapShaderLog("0(12) : warning C7050: unused\n0(100002) : error C0000: syntax error\n", names, 100000) ==
          "<generated header>:12 : warning C7050: unused | engine/composite.glsl:2 : error C0000: syntax error");
}
