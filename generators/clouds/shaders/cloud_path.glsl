// Reading the cloud-path LUT (after cloud_density.glsl): (entry, exit) distances in m of the view
// ray through the cloud layer, from altitude h (m) with cos(view zenith) mu. exit <= entry: no
// crossing. Mapping twin of cloud_path_lut.hpp (cloudPathX, cloudPathY).
#define CLOUD_PATH_ABOVE_M 50000.0
layout(binding = WELKIN_BINDING_CLOUD_PATH_LUT) uniform sampler2D u_cloudPathLut;

float cloudPathX(float mu) { return 0.5 + 0.5 * sign(mu) * sqrt(abs(mu)); }
float cloudPathMu(float x) { float s = 2.0 * x - 1.0; return sign(s) * s * s; }
float cloudPathY(float h, float bottom, float top) {
    if (h < bottom) return max(h, 0.0) / bottom / 3.0;
    if (h <= top) return (1.0 + (h - bottom) / (top - bottom)) / 3.0;
    return (2.0 + min((h - top) / CLOUD_PATH_ABOVE_M, 1.0)) / 3.0;
}
float cloudPathAltitude(float y, float bottom, float top) {
    float t = 3.0 * y;
    if (t < 1.0) return t * bottom;
    if (t <= 2.0) return bottom + (t - 1.0) * (top - bottom);
    return top + (t - 2.0) * CLOUD_PATH_ABOVE_M;
}

vec2 cloudPathLookup(float h, float mu) {
    vec2 size = vec2(textureSize(u_cloudPathLut, 0));
    vec2 xy = vec2(cloudPathX(mu), cloudPathY(h, cld_radii.y - cld_radii.x, cld_radii.z - cld_radii.x));
    return textureLod(u_cloudPathLut, (xy * (size - 1.0) + 0.5) / size, 0.0).rg;
}
