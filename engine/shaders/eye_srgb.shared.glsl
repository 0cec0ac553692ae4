// The tone map's sRGB transfer function without pow, one source for GLSL (tonemap.frag.glsl
// includes it) and C++ (eye.cpp compiles it in double: welkin::eye::srgbEncodeFast(), tested
// against the exact curve welkin::eye::srgbEncode()).

// IEC 61966-2-1's encoding of linear c in [0, 1]: 12.92 c below 0.0031308, above it
// 1.055 c^(1/2.4) - 0.055 = 1.055 s^(5/6) - 0.055 with s = sqrt(c), as a (3, 3) rational in s
// fitted to the exact curve on s in [0.05595, 1] (iteratively reweighted least squares towards the
// minimax rational; largest error 5.6e-6).
vec3 welkin_srgbEncodeFast(vec3 c) {
    vec3 s = sqrt(max(c, vec3(0.0)));
    vec3 p = -0.048761095 + s * (1.186980722 + s * (17.284672827 + s * 17.052349011));
    vec3 q = 1.0 + s * (14.054653614 + s * (19.586260445 + s * 0.834515499));
    // A select per channel (mix by a bool vector), not a blend by step(): the same values, fewer
    // instructions for llvmpipe (docs/eye.md "The tone map's arithmetic").
    return mix(p / q, 12.92 * c, lessThan(c, vec3(0.0031308)));
}
