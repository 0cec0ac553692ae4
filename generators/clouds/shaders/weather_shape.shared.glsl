// The weather map's shapes, one source for GLSL (weather_map.frag.glsl, weather_resolve.glsl) and
// C++ (weather_map.cpp compiles it in double: cpu::shapeTexel(), cpu::weatherTexel()). Needs
// cn_perlinFbm2() (cloud_noise.shared.glsl; C++: cpu::perlinFbm2()) before it.

// A shape's fade at `local` (the shape's frame, in semi-axes): its core fading over its
// noise-perturbed edge. Edge noise: 2-D Perlin fBm (4 cells over 4 semi-axes, 3 octaves) at the
// shape's own offset (in [0, 1)^2, from its seed); the radius is stretched by +-35 %, the fade
// runs from rr = 0.5 to 1 (a soft core). The shape's texel is its values times the fade (the
// cloud thins towards its rim), max-blended over the shapes.
real cld_weatherFade(vec2 local, vec2 offset, uint seed) {
    real r = length(local);
    real n = cn_perlinFbm2(local * 0.25 + offset, 4, 3, seed);
    real rr = r * (1.0 + 0.7 * (n - 0.5));
    return 1.0 - smoothstep(0.5, 1.0, rr);
}

// The resolved texel from the max-blended w = (density, 1 - base fraction, top fraction, rain):
// the base fraction back from 1 - base; where top < base (a shape's thinning rim: zero thickness)
// both become their mean; all 0 where no cloud was drawn (density 0).
vec4 cld_weatherResolve(vec4 w) {
    real base = 1.0 - w.y;
    real top = w.z;
    if (top < base) {
        base = 0.5 * (base + top);
        top = base;
    }
    return w.x > 0.0 ? vec4(w.x, base, top, w.w) : vec4(0.0);
}
