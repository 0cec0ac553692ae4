// The tone map's display curves, one source for GLSL (tonemap.frag.glsl includes it) and C++
// (eye.cpp compiles it in double: welkin::eye::acesFit(), welkin::eye::hable()). Linear radiance
// relative to the exposure's white in, display-linear [0, 1] out.

// Narkowicz's fit of the ACES reference rendering transform (input scaled by 0.6).
vec3 welkin_aces(vec3 x) {
    x *= 0.6;
    return clamp((x * (2.51 * x + 0.03)) / (x * (2.43 * x + 0.59) + 0.14), 0.0, 1.0);
}

// Hable's filmic curve (Uncharted 2): shoulder 0.15, linear 0.50 at angle 0.10, toe 0.20, 0.02/0.30.
vec3 welkin_hableF(vec3 x) {
    return (x * (0.15 * x + 0.05) + 0.004) / (x * (0.15 * x + 0.50) + 0.06) - 0.02 / 0.30;
}
// The curve with exposure bias 2 and white 11.2.
vec3 welkin_hable(vec3 x) { return clamp(welkin_hableF(2.0 * x) / welkin_hableF(vec3(11.2)), 0.0, 1.0); }
