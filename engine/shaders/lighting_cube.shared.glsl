// Cube-map face directions in the camera's CubeFace convention (OpenGL face order, cube axes x
// east, y up, z south), one source for the shaders (lighting_common.glsl includes it) and C++
// (camera.cpp compiles it in double, welkin/glsl_cpp.hpp).

// Direction (cube axes) of face coordinates (s, t) in [-1, 1], OpenGL's cube-map convention.
vec3 lighting_cubeDir(int face, real s, real t) {
    if (face == 0) return vec3(1.0, -t, -s);
    if (face == 1) return vec3(-1.0, -t, s);
    if (face == 2) return vec3(s, 1.0, t);
    if (face == 3) return vec3(s, -1.0, -t);
    if (face == 4) return vec3(s, -t, 1.0);
    return vec3(-s, -t, -1.0);
}
// Cube axes (x east, y up, z south) -> ENU, and back.
vec3 lighting_cubeToEnu(vec3 c) { return vec3(c.x, -c.z, c.y); }
vec3 lighting_enuToCube(vec3 e) { return vec3(e.x, e.z, -e.y); }
