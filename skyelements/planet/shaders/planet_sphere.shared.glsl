// A body's sphere seen as a disk, one source for the Planet pass (planet.frag.glsl includes it) and
// its CPU twin (planet.cpp compiles it in double, welkin/glsl_cpp.hpp; WELKIN_PI comes from the
// engine's camera_projection.shared.glsl on the GPU, from the including C++ on the CPU).

// Outward unit normal where the view ray `d` meets the body's sphere (d within its disk):
// rho = sin(theta) / sin(radius) is the ray's place on the disk, 0 centre, 1 limb.
vec3 planet_normal(vec3 d, vec3 c, real s, OUT(real) rho) {
    real cosT = dot(d, c);
    vec3 perp = d - c * cosT;
    real sinT = length(perp);
    rho = sinT / s;
    real r = min(rho, 1.0);
    real w = sqrt(max(1.0 - r * r, 0.0));
    vec3 e = sinT > 0.0 ? perp / sinT : vec3(0.0);
    return normalize(-(r * sinT + cosT * w) * c + (r * cosT - sinT * w) * e);
}

// The normal map's normal t (tangent space: east, north... the map's G points south) on the
// sphere's normal n with east and north tangents tE, tN.
vec3 planet_mapNormal(vec3 t, vec3 tE, vec3 tN, vec3 n) { return normalize(t.x * tE - t.y * tN + t.z * n); }
