// The cloud density function (any stage; include after the generated header):
//   float cloudDensity(vec3 p, int lod)      relative density in [0, 1]; lod CLOUD_LOD_CHEAP
//                                            (weather + height profile + base shape: light
//                                            marches, shadows) or CLOUD_LOD_FULL (+ detail erosion)
//   float cloudAltitude(vec3 p)              altitude above the ground, m
//   vec2  cloudWeatherUv(vec3 p)             weather-map uv (repeat)
//   vec2  cloudShellIntersect(float r, float mu)  entry, exit distance (m) through the layer from
//                                            radius r (m from the planet's centre), cos zenith mu;
//                                            exit < 0: no crossing; first crossing only
//   float cirrusDensity(vec2 xy)             cirrus relative density in [0, 1] at ENU (x, y)
// p is ENU metres relative to the observer's ground point (observer at (0, 0, height), planet
// centre at (0, 0, -R)). Extinction = density * cld_shape.z (1/m). Twin of
// welkin/generators/cloud_density.hpp (cpu::), which documents the contract and the sources
// (Papp 2018 eqs. 5.1-5.5; Schneider & Vos 2015, Schneider 2017). Textures are read at level 0.
layout(std140, binding = WELKIN_BINDING_CLOUD_UBO) uniform WelkinClouds {
    vec4 cld_radii;         // R, R + bottom, R + top, R + cirrus height (m)
    vec4 cld_shape;         // coverage, detail scale, scattering (1/m), cirrus coverage
    vec4 cld_weather;       // offset xy (m, mod extent), extent (m), 1 / extent
    vec4 cld_noise;         // base, detail, curl periods (m), w cloud type (0 stratocumulus, 1 cumulus)
    vec4 cld_scrollBase;    // base-noise scroll (m, mod period)
    vec4 cld_scrollDetail;  // detail-noise scroll (m, mod period)
    vec4 cld_cirrus;        // cirrus offset xy (m, mod curl period)
};
layout(binding = WELKIN_BINDING_CLOUD_WEATHER_MAP) uniform sampler2D u_cloudWeather;
layout(binding = WELKIN_BINDING_CLOUD_NOISE_BASE) uniform sampler3D u_cloudNoiseBase;
layout(binding = WELKIN_BINDING_CLOUD_NOISE_DETAIL) uniform sampler3D u_cloudNoiseDetail;
layout(binding = WELKIN_BINDING_CLOUD_CURL_NOISE) uniform sampler2D u_cloudCurl;

#define CLOUD_LOD_CHEAP 0
#define CLOUD_LOD_FULL 1
// The shape constants, the same numbers as cloud_density.cpp's (documented there).
#define CLD_SHAPE_LO 0.66
#define CLD_SHAPE_HI 0.93
#define CLD_CU_BASE 0.07
#define CLD_CU_TOP0 0.5
#define CLD_SC_BASE 0.1
#define CLD_SC_TOP0 0.65
#define CLD_EROSION 0.35
#define CLD_DETAIL_FLIP 4.0

float cld_remap(float v, float lo, float hi, float newLo, float newHi) { return (v - lo) / (hi - lo) * (newHi - newLo) + newLo; }

float cloudAltitude(vec3 p) {
    float R = cld_radii.x;
    vec3 q = p + vec3(0.0, 0.0, R);
    return (dot(p, p) + 2.0 * R * p.z) / (length(q) + R);  // |q| - R without cancellation
}

vec2 cloudWeatherUv(vec3 p) { return (p.xy + cld_weather.xy) * cld_weather.w; }

// The height gradient of a cloud type (cpu::heightGradient documents the shapes and sources):
// x the profile in [0, 1], y the position within the cloud's own vertical extent in [0, 1].
vec2 cloudHeightGradient(float a, float wb, float wt, float type) {
    float tS = (a - wb) / max(wt - wb, 1e-3);
    float tC = a / max(wt, 1e-3);
    float pS = smoothstep(0.0, CLD_SC_BASE, tS) * (1.0 - smoothstep(CLD_SC_TOP0, 1.0, tS));
    float pC = smoothstep(0.0, CLD_CU_BASE, tC) * (1.0 - smoothstep(CLD_CU_TOP0, 1.0, tC));
    float t = clamp(mix(tS, tC, type), 0.0, 1.0);
    return vec2(mix(pS, pC, type) * (0.75 + 0.25 * t), t);
}

float cloudDensity(vec3 p, int lod) {
    float h = cloudAltitude(p);
    float bottom = cld_radii.y - cld_radii.x, top = cld_radii.z - cld_radii.x;
    if (h < bottom || h > top) return 0.0;
    float a = (h - bottom) / (top - bottom);
    vec4 w = clamp(textureLod(u_cloudWeather, cloudWeatherUv(p), 0.0), 0.0, 1.0);
    float cov = w.r * clamp(cld_shape.x, 0.0, 1.0);
    if (cov <= 0.0) return 0.0;
    vec2 hg = cloudHeightGradient(a, w.g, w.b, clamp(cld_noise.w, 0.0, 1.0));
    if (hg.x <= 0.0) return 0.0;
    vec4 n = textureLod(u_cloudNoiseBase, (vec3(p.xy, h) + cld_scrollBase.xyz) / cld_noise.x, 0.0);
    float fbm = 0.625 * n.g + 0.25 * n.b + 0.125 * n.a;
    float pw = cld_remap(n.r, fbm - 1.0, 1.0, 0.0, 1.0);
    float shape = clamp(cld_remap(pw, CLD_SHAPE_LO, CLD_SHAPE_HI, 0.0, 1.0), 0.0, 1.0) * hg.x;
    float base = max(shape + cov - 1.0, 0.0);
    if (lod == CLOUD_LOD_CHEAP || base <= 0.0) return base;
    vec4 dn = textureLod(u_cloudNoiseDetail, (vec3(p.xy, h) + cld_scrollDetail.xyz) / cld_noise.y, 0.0);
    float dfbm = 0.625 * dn.r + 0.25 * dn.g + 0.125 * dn.b;
    float mod_ = mix(dfbm, 1.0 - dfbm, clamp(hg.y * CLD_DETAIL_FLIP, 0.0, 1.0));
    float e = min(CLD_EROSION * cld_shape.y * mod_, 0.9);
    return clamp((base - e) / (1.0 - e), 0.0, 1.0);
}

// Both roots of |r + t d| = s (t^2 + 2 b t + c = 0, b = r mu, c = (r - s)(r + s)), near first, in
// the cancellation-free form (q = -(b + sign(b) sqrt(disc)), roots q and c / q; Press et al.,
// Numerical Recipes 5.6); disc < 0: no root (x > y returned).
vec2 cld_sphereRoots(float r, float mu, float s) {
    float b = r * mu, c = (r - s) * (r + s);
    float disc = b * b - c;
    if (disc < 0.0) return vec2(1.0, -1.0);
    float q = -(b + (b >= 0.0 ? sqrt(disc) : -sqrt(disc)));
    float t2 = q != 0.0 ? c / q : 0.0;
    return vec2(min(q, t2), max(q, t2));
}

vec2 cloudShellIntersectRadii(float R, float rb, float rt, float r, float mu) {
    vec2 g = cld_sphereRoots(r, mu, R), lb = cld_sphereRoots(r, mu, rb), lt = cld_sphereRoots(r, mu, rt);
    if (r < rb) {
        if (r >= R && mu < 0.0 && g.x <= g.y) return vec2(-1.0);  // the ground comes first
        return vec2(lb.y, lt.y);
    }
    if (r <= rt) {
        if (mu < 0.0 && lb.x <= lb.y) return vec2(0.0, lb.x);  // leaves through the base
        return vec2(0.0, lt.y);
    }
    if (mu >= 0.0 || lt.x > lt.y) return vec2(-1.0);
    if (lb.x <= lb.y) return vec2(lt.x, lb.x);
    return vec2(lt.x, lt.y);
}

vec2 cloudShellIntersect(float r, float mu) { return cloudShellIntersectRadii(cld_radii.x, cld_radii.y, cld_radii.z, r, mu); }

float cirrusDensity(vec2 xy) {
    float cc = clamp(cld_shape.w, 0.0, 1.0);
    if (cc <= 0.0) return 0.0;
    vec2 uv = (xy + cld_cirrus.xy) / cld_noise.z;
    vec4 c = textureLod(u_cloudCurl, uv, 0.0);
    vec2 warp = (c.rg * 2.0 - 1.0) * 0.05;
    float n = textureLod(u_cloudCurl, uv + warp, 0.0).b;
    return clamp(n + cc - 1.0, 0.0, 1.0);
}
