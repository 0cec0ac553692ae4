// One source for the GPU maths and its CPU twin: the C++ side of the GLSL subset that shared
// shader files (`*.shared.glsl`) are written in. A shared file compiles as GLSL (embedded and
// assembled by gl::ProgramBuilder, whose generated header defines the same dialect) and as C++
// over GLM in double precision (this header), so the twin the tests trust is the shader's text.
//
//   // generators/<family>/src/foo.cpp (the family's shaders/ folder is on its include path)
//   #include <welkin/glsl_cpp.hpp>
//   namespace welkin::glsl::dp { namespace foo_shared {   // one namespace per shared file
//   #include "foo.shared.glsl"                            // real foo_f(vec3 p, IN(FooParams) q) ...
//   } }
//   double cpu::f(glm::dvec3 p) { return glsl::dp::foo_shared::foo_f(p, params); }
//
//   // GLSL: foo.glsl says `#include "foo.shared.glsl"` (expanded when embedded, errors keep the
//   // shared file's name and line) or the caller adds the chunk to its ProgramBuilder.
//
// The subset (what both languages read the same way):
// - Scalar type `real` (GLSL float, C++ double here); int, uint (32-bit unsigned), bool; vec2-4,
//   ivec2-4, uvec2-4, bvec2-4 (GLM's, double for vec), mat2-4, mat2x3, mat3x2 (GLSL's
//   column-major naming: mat3x2 has 3 columns of 2 rows; m * v, transpose, outerProduct); structs
//   (C++20 aggregates: `T(a, b)` constructs them in both); fixed-size arrays declared `real v[8];`, a constant one initialised
//   as `const real t[3] = ARRAY_OF(real, 3) 1.0, 2.0, 3.0 END_ARRAY;` (GLSL `real[3](...)`, C++
//   braces; no other array constructors). A function returns an array inside a struct
//   (`struct Basis { real y[9]; };`): both languages copy it.
// - Parameters: plain `T x` (in, by value), `IN(T) x` (in; a const reference in C++: structs and
//   samplers), `OUT(T) x` and `INOUT(T) x` (references in C++).
// - Float literals as `1.0` (never `1.0f`, never an int where a real is meant: GLM's templates do
//   not mix int and double), unsigned ones as `1u`. Components as .x .y .z .w / .r .g .b .a only:
//   no swizzles (`vec2(p.x, p.y)`, not `p.xy`).
// - Built-ins: GLM's (degrees, radians, min, max, clamp, mix, step, smoothstep, floor, fract, mod, abs, sign, sqrt,
//   inversesqrt, exp, exp2, log, log2, pow, sin, cos, tan, asin, acos, atan, dot, cross, length, distance,
//   normalize, any, all, lessThan, greaterThanEqual, ...); `textureLod(s, p, lod)` on a CPU sampler
//   type the including file provides (a free function textureLod(const S&, vecN, real) found
//   beside S or in the including namespace).
// - Constants as `#define NAME value` (prefixed: they are macros in C++ too); no uniforms, no
//   globals: a shared function gets its data through parameters, and the shader-side file wraps it
//   with its uniform block.
#pragma once
#include <glm/glm.hpp>

#include <cmath>
#include <cstdint>

// Parameter qualifiers of the shared dialect (GLSL side: gl::ProgramBuilder's generated header).
#define IN(T) const T&
#define OUT(T) T&
#define INOUT(T) T&
// A constant array's initialiser: `const real t[3] = ARRAY_OF(real, 3) 1.0, 2.0, 3.0 END_ARRAY;`.
#define ARRAY_OF(T, N) {
#define END_ARRAY }

namespace welkin::glsl {

/// Double precision: the CPU twins. Include a shared file inside a namespace nested in this one
/// (its names are then found before any outer declaration of the same name).
namespace dp {
using real = double;
using uint = std::uint32_t;
using vec2 = glm::dvec2;
using vec3 = glm::dvec3;
using vec4 = glm::dvec4;
using ivec2 = glm::ivec2;
using ivec3 = glm::ivec3;
using ivec4 = glm::ivec4;
using uvec2 = glm::uvec2;
using uvec3 = glm::uvec3;
using uvec4 = glm::uvec4;
using bvec2 = glm::bvec2;
using bvec3 = glm::bvec3;
using bvec4 = glm::bvec4;
using mat2 = glm::dmat2;
using mat3 = glm::dmat3;
using mat4 = glm::dmat4;
using mat2x3 = glm::dmat2x3;  // GLSL's naming: 2 columns of 3 rows
using mat3x2 = glm::dmat3x2;

// Scalars through <cmath> (GLM's versions of these take vectors), vectors through GLM.
using std::abs, std::acos, std::asin, std::atan, std::cos, std::exp, std::exp2, std::floor, std::log, std::log2, std::pow,
    std::sin, std::sqrt, std::tan;
using glm::abs, glm::acos, glm::all, glm::degrees, glm::radians, glm::any, glm::asin, glm::atan, glm::clamp, glm::cos, glm::cross,
    glm::distance, glm::dot, glm::equal, glm::exp, glm::exp2, glm::floor, glm::fract, glm::greaterThan, glm::greaterThanEqual,
    glm::inversesqrt, glm::length, glm::lessThan, glm::lessThanEqual, glm::log, glm::log2, glm::max, glm::min, glm::mix,
    glm::outerProduct, glm::transpose, glm::mod, glm::normalize, glm::notEqual, glm::pow, glm::sign, glm::sin, glm::smoothstep, glm::sqrt, glm::step,
    glm::tan;
}  // namespace dp

}  // namespace welkin::glsl
