// The clouds' shadow on the atmosphere's in-scattering (fragment, two outputs): for every view
// direction from the observer (u: absolute azimuth from north through east over [0, 2 pi),
// v: the sky-view LUT's horizon-dense latitude, skyViewMuAz()), the single scattering of the
// shadowing light that the clouds' shadow removes, per lux of that light (times kLutScale):
//   loss = integral over the ray below the cloud top of T_view(t) sigma_s(t) T_light(t) P (1 - S(p(t))) dt
// plus, where the ray reaches the ground inside the shadow map, the ground's direct term
// T_view(d) mu_g T_light(ground) albedo / pi (1 - S(ground)). S = the clouds.shadow_map
// transmittance of the direct light at the point (1 outside the map and above the cloud top).
// Output 0: Rayleigh with its phase (and the ground); output 1: Mie without its phase (applied
// per pixel by the Sky element, as for the sky-view LUT). The Sky element subtracts both from the
// light's sky-view radiance. The march is cld_skyShadowLoss() of cloud_sky_shadow.shared.glsl, which
// cpu::skyShadowLoss() (cloud_sky_shadow.hpp) compiles in double. Needs atmosphere.glsl
// (ATM_USE_TRANSMITTANCE) before it.
layout(binding = WELKIN_BINDING_CLOUD_SHADOW_MAP) uniform sampler2D u_shadowMap;
uniform float u_h;          // observer height above the ground, m (inside the atmosphere)
uniform vec3 u_light;       // the light whose scattering is shadowed: unit ENU (may be below the horizon)
uniform vec3 u_mapLight;    // clouds.shadow_light_direction: the light the map was built for (z >= 0)
uniform vec4 u_map;         // (shift x, shift y, 1 / extent, extent), m
uniform vec2 u_layer;       // cloud base and top above the ground, m
uniform float u_angular;    // the light's angular radius, rad
uniform int u_steps;
uniform ivec2 u_size;
uniform float u_scale;      // kLutScale
layout(location = 0) out vec4 o_smooth;
layout(location = 1) out vec4 o_mie;

// The shadow map's read for the shared march.
float cld_skyShadowMapAt(vec2 uv) { return texture(u_shadowMap, uv).r; }
#include "cloud_sky_shadow.shared.glsl"

void main() {
    vec2 size = vec2(u_size);
    vec2 uv = gl_FragCoord.xy / size;
    float mu = skyViewMuAz(u_h, uv, size).x;
    float az = 2.0 * ATM_PI * uv.x;
    float sinV = sqrt(max(1.0 - mu * mu, 0.0));
    vec3 dir = vec3(sinV * sin(az), sinV * cos(az), mu);
    // The same ground decision as the sky-view LUT (its rows below the horizon end on the ground).
    bool ground = uv.y < 0.5;
    vec3 lossR, lossM;
    cld_skyShadowLoss(u_h, dir, ground, u_light, u_angular, u_mapLight, u_map, u_layer, u_steps, atm_shFactors.w, lossR, lossM);
    o_smooth = vec4(lossR * u_scale, 1.0);
    o_mie = vec4(lossM * u_scale, 1.0);
}
