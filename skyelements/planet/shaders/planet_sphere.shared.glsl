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

// The visible fraction of a disk of angular radius rs (the Sun) behind a disk of radius re (the
// Earth) at centre distance d >= 0 (rs > 0): one minus the two circles' lens over the Sun's area.
real planet_lensFraction(real rs, real re, real d) {
    if (d >= rs + re) return 1.0;
    if (d <= re - rs) return 0.0;
    if (d <= rs - re) return 1.0 - (re * re) / (rs * rs);
    real a1 = acos(clamp((d * d + rs * rs - re * re) / (2.0 * d * rs), -1.0, 1.0));
    real a2 = acos(clamp((d * d + re * re - rs * rs) / (2.0 * d * re), -1.0, 1.0));
    real lens = rs * rs * (a1 - 0.5 * sin(2.0 * a1)) + re * re * (a2 - 0.5 * sin(2.0 * a2));
    return clamp(1.0 - lens / (WELKIN_PI * rs * rs), 0.0, 1.0);
}
