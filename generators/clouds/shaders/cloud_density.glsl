// The cloud density function (any stage; include after the generated header):
//   float cloudDensity(vec3 p, int lod)      relative density in [0, 1]; lod CLOUD_LOD_CHEAP
//                                            (weather + height profile + base shape: light
//                                            marches, shadows) or CLOUD_LOD_FULL (+ detail erosion)
//   float cloudAltitude(vec3 p)              altitude above the ground, m
//   vec2  cloudWeatherUv(vec3 p)             weather-map uv (repeat)
//   vec2  cloudShellIntersect(float r, float mu)  entry, exit distance (m) through the layer from
//                                            radius r (m from the planet's centre), cos zenith mu;
//                                            exit < 0: no crossing; first crossing only
//   float cloudDepthAlong(vec3 p, vec3 dir, int n, float maxDist)  density x m from p along the
//                                            unit dir through the layer (full LOD, n steps growing
//                                            x1.5 over min(maxDist, the shell's exit)); x extinction
//                                            per unit density = optical depth
//   float cirrusDensity(vec2 xy)             cirrus relative density in [0, 1] at ENU (x, y)
// p is ENU metres relative to the observer's ground point (observer at (0, 0, height), planet
// centre at (0, 0, -R)). Extinction = density * cld_shape.z (1/m). The maths is
// cloud_density.shared.glsl (included below; also CLOUD_LOD_*, CLD_*, cloudHeightGradient and
// cloudShellIntersectRadii), which the CPU twin (cpu:: in welkin/generators/cloud_density.hpp,
// the contract and the sources) compiles in double; this file binds it to the uniform block and
// the samplers. Textures are read at level 0.
#include "cloud_density.shared.glsl"
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

CloudLayer cld_layer() { return CloudLayer(cld_radii, cld_shape, cld_weather, cld_noise, cld_scrollBase, cld_scrollDetail, cld_cirrus); }

float cloudAltitude(vec3 p) { return cld_layerAltitude(cld_layer(), p); }

vec2 cloudWeatherUv(vec3 p) { return cld_layerWeatherUv(cld_layer(), p); }

float cloudDensity(vec3 p, int lod) {
    return cld_layerDensity(cld_layer(), u_cloudWeather, u_cloudNoiseBase, u_cloudNoiseDetail, p, lod);
}

vec2 cloudShellIntersect(float r, float mu) { return cloudShellIntersectRadii(cld_radii.x, cld_radii.y, cld_radii.z, r, mu); }

float cloudDepthAlong(vec3 p, vec3 dir, int n, float maxDist) {
    return cld_layerDepthAlong(cld_layer(), u_cloudWeather, u_cloudNoiseBase, u_cloudNoiseDetail, p, dir, n, maxDist);
}

float cirrusDensity(vec2 xy) { return cld_layerCirrus(cld_layer(), u_cloudCurl, xy); }
