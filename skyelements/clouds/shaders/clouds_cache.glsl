// The Clouds element's direction cache (the real-time path, clouds.reprojection; Clouds::renderCached):
// texel (u, v) in [0, 1]^2 holds the clouds seen along the direction of azimuth 2 pi u (from
// east through north: the ENU frame's atan(y, x)) and of z = dir.z = s |s| with s = 2 v - 1, so
// that texels crowd at the horizon (z ~ 0), where the clouds are far and small:
// dz/dv = 4 |s|, 0 at the horizon. The C++ twin is clouds.cpp's cacheDirection (tests).
const float CLD_CACHE_PI = 3.14159265358979;

vec3 clouds_cacheDirection(vec2 uv) {
    float s = 2.0 * uv.y - 1.0;
    float z = s * abs(s);
    float phi = 2.0 * CLD_CACHE_PI * uv.x;
    float rho = sqrt(max(1.0 - z * z, 0.0));
    return vec3(rho * cos(phi), rho * sin(phi), z);
}

vec2 clouds_cacheUv(vec3 dir) {
    float z = clamp(dir.z, -1.0, 1.0);
    float s = sign(z) * sqrt(abs(z));
    float phi = atan(dir.y, dir.x);
    return vec2(phi / (2.0 * CLD_CACHE_PI), 0.5 + 0.5 * s);
}

#ifdef CLOUDS_CACHE_SHOW
layout(binding = WELKIN_BINDING_CLOUD_CACHE_RADIANCE) uniform sampler2D u_cacheL;
layout(binding = WELKIN_BINDING_CLOUD_CACHE_TRANSMITTANCE) uniform sampler2D u_cacheT;
void main() {
    vec3 dir;
    if (!welkin_viewDirection(welkin_pixel(), dir)) discard;
    vec2 uv = clouds_cacheUv(dir);
    // The seam at azimuth 0: atan's jump from 1 to 0 in u makes the hardware's derivatives
    // huge there; without mipmaps the level is 0 anyway, textureLod says so.
    welkin_output(textureLod(u_cacheL, uv, 0.0).rgb, textureLod(u_cacheT, uv, 0.0).rgb);
}
#endif
