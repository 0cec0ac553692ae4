// SkyLighting's shared functions (engine/src/lighting.cpp mirrors them in double precision):
// cube-map texel directions in the camera's CubeFace convention (OpenGL face order, cube axes
// x east, y up, z south; texel row 0 at t = -1) and their exact solid angles.
const float LIGHTING_PI = 3.14159265358979;

// The cube's axes and faces (lighting_cubeDir, lighting_cubeToEnu, lighting_enuToCube):
// lighting_cube.shared.glsl, which camera.cpp compiles in double.
#include "lighting_cube.shared.glsl"
// Unit ENU direction through the centre of texel (i, j) of a face of size n.
vec3 lighting_texelDirection(int face, ivec2 ij, int n) {
    vec2 st = 2.0 * (vec2(ij) + 0.5) / float(n) - 1.0;
    return normalize(lighting_cubeToEnu(lighting_cubeDir(face, st.x, st.y)));
}
// Solid angle (sr) of texel (i, j) of a face of size n: the exact integral of the cube face's
// area element, A(x, y) = atan(x y / sqrt(x^2 + y^2 + 1)) at the texel's four corners.
float lighting_cornerArea(float x, float y) { return atan(x * y, sqrt(x * x + y * y + 1.0)); }
float lighting_texelSolidAngle(ivec2 ij, int n) {
    vec2 a = 2.0 * vec2(ij) / float(n) - 1.0, b = 2.0 * vec2(ij + 1) / float(n) - 1.0;
    return lighting_cornerArea(a.x, a.y) - lighting_cornerArea(a.x, b.y) - lighting_cornerArea(b.x, a.y) + lighting_cornerArea(b.x, b.y);
}
