// welkin_cloudShadow(): the clouds' shadow for the host's scene (any stage). The transmittance in
// [0, 1] of the direct light (the Sun, or the Moon at night: clouds.shadow_light_direction)
// through the clouds above an ENU point in metres (x east, y north, z up, origin at the observer).
// Set the sampler's unit and the two uniforms with CloudShadowMap::bindForHost() (C++), or:
//   welkin_cloudShadowMapping0 = (shift x, shift y, 1 / clouds.shadow_extent_m, -observer height)
//   welkin_cloudShadowMapping1 = (clouds.shadow_light_direction, clouds.bottom_m)
// shift = clouds.weather_offset_m - clouds.shadow_offset_m (the wind since the map was built).
// A point above the ground is traced back along the light to the ground point whose texel it
// shares (valid up to the cloud base; higher points use the base). Beyond the map's square the
// edge texel continues.
#ifndef WELKIN_BINDING_CLOUD_SHADOW_MAP
#define WELKIN_BINDING_CLOUD_SHADOW_MAP 9
#endif
layout(binding = WELKIN_BINDING_CLOUD_SHADOW_MAP) uniform sampler2D welkin_cloudShadowMap;
uniform vec4 welkin_cloudShadowMapping0;
uniform vec4 welkin_cloudShadowMapping1;

float welkin_cloudShadow(vec3 worldPosEnuM) {
    vec4 m0 = welkin_cloudShadowMapping0, m1 = welkin_cloudShadowMapping1;
    float h = clamp(worldPosEnuM.z - m0.w, 0.0, m1.w);  // height above the ground, m
    // The light's elevation is clamped to >= 0; 1e-3 keeps a horizon light finite (the
    // projection then leaves the map and the edge texel answers).
    vec2 g = worldPosEnuM.xy - h * m1.xy / max(m1.z, 1e-3);
    vec2 uv = (g + m0.xy) * m0.z + 0.5;
    return texture(welkin_cloudShadowMap, uv).r;
}
