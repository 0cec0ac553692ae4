// The cloud-path LUT's mapping (one source: cloud_path.glsl includes it for the shaders,
// cloud_path_lut.cpp compiles it in double for cloudPathX() ... cloudPathAltitude(); the GLSL
// subset of welkin/glsl_cpp.hpp). x: cos(view zenith) mu in [-1, 1], square-root spaced around the
// horizon; y: altitude h (m) in thirds, [0, bottom] below the layer, [bottom, top] inside it,
// [top, top + CLOUD_PATH_ABOVE_M] above (clamped beyond). bottom, top: the layer's heights (m).
#define CLOUD_PATH_ABOVE_M 50000.0

real cloudPathX(real mu) { return 0.5 + 0.5 * sign(mu) * sqrt(abs(mu)); }
real cloudPathMu(real x) {
    real s = 2.0 * x - 1.0;
    return sign(s) * s * s;
}
real cloudPathY(real h, real bottom, real top) {
    if (h < bottom) return max(h, 0.0) / bottom / 3.0;
    if (h <= top) return (1.0 + (h - bottom) / (top - bottom)) / 3.0;
    return (2.0 + min((h - top) / CLOUD_PATH_ABOVE_M, 1.0)) / 3.0;
}
real cloudPathAltitude(real y, real bottom, real top) {
    real t = 3.0 * y;
    if (t < 1.0) return t * bottom;
    if (t <= 2.0) return bottom + (t - 1.0) * (top - bottom);
    return top + (t - 2.0) * CLOUD_PATH_ABOVE_M;
}
