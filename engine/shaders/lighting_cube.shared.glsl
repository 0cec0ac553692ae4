// Directions of the camera's conventions, one source for the shaders (camera.glsl and
// lighting_common.glsl include it) and C++ (camera.cpp compiles it in double, welkin/glsl_cpp.hpp):
// ENU from azimuth and altitude, and the cube-map faces (CubeFace: OpenGL face order, cube axes
// x east, y up, z south). Guarded: a program may include both camera.glsl and lighting_common.glsl.
#ifndef WELKIN_LIGHTING_CUBE_SHARED
#define WELKIN_LIGHTING_CUBE_SHARED

// Unit ENU direction (x east, y north, z up) at azimuth az (rad, from north through east) and
// altitude alt (rad).
vec3 welkin_directionFromAzAlt(real az, real alt) {
    real c = cos(alt);
    return vec3(c * sin(az), c * cos(az), sin(alt));
}

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

#endif
