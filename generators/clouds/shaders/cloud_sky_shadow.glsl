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
// light's sky-view radiance. Twin of cpu::skyShadowLoss() (cloud_sky_shadow.hpp). Needs
// atmosphere.glsl (ATM_USE_TRANSMITTANCE) before it.
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

// Transmittance of the direct light at a point xy (ENU, m, horizontal from the observer) at
// height hp above the ground. Below the cloud base: the map's value at the ground point the light
// ray through the point reaches (the map holds the transmittance from the ground up through the
// whole layer, and nothing below the base attenuates). Inside the layer: that value (traced from
// the base) to the power of the fraction of the layer above the point (optical depth taken as
// uniform in height: a cheap approximation where the clouds themselves are drawn). Above the top
// and outside the map: lit (1).
float shadowAt(vec2 xy, float hp) {
    if (hp >= u_layer.y) return 1.0;
    vec2 g = xy - min(hp, u_layer.x) * u_mapLight.xy / max(u_mapLight.z, 1e-3);
    vec2 uv = (g + u_map.xy) * u_map.z + 0.5;
    if (any(lessThan(uv, vec2(0.0))) || any(greaterThan(uv, vec2(1.0)))) return 1.0;
    float s = texture(u_shadowMap, uv).r;
    if (hp > u_layer.x) s = exp2(log2(max(s, 1e-30)) * (u_layer.y - hp) / (u_layer.y - u_layer.x));
    return s;
}

void main() {
    vec2 size = vec2(u_size);
    vec2 uv = gl_FragCoord.xy / size;
    float mu = skyViewMuAz(u_h, uv, size).x;
    float az = 2.0 * ATM_PI * uv.x;
    float sinV = sqrt(max(1.0 - mu * mu, 0.0));
    vec3 dir = vec3(sinV * sin(az), sinV * cos(az), mu);
    float muS = u_light.z, nu = clamp(dot(dir, u_light), -1.0, 1.0);
    // The same ground decision as the sky-view LUT (its rows below the horizon end on the ground).
    bool ground = uv.y < 0.5;
    float h = clamp(u_h, 0.0, atm_thickness());
    float d = ground ? distanceToBottom(h, mu) : distanceToTop(h, mu);
    // Where the ray can be shadowed: below the cloud top, and while the ground point its light
    // ray reaches can still be inside the map (beyond: lit, so not marched).
    float r = atm_bottom() + h, top = atm_bottom() + u_layer.y;
    float tEnd = d;
    if (!ground) {
        // Up to the cloud-top sphere (from inside it; a ray that misses the ground only climbs
        // past its perigee), nothing from above it. A ray down to the ground stays below the top.
        float b = r * mu, c = r * r - top * top;
        tEnd = h < u_layer.y ? min(tEnd, -b + sqrt(max(b * b - c, 0.0))) : 0.0;
    }
    // The map's square (half-diagonal), moved by the wind's shift since it was built, seen from
    // points up to the cloud base (displaced along the light by base x tan(light zenith)).
    float reach = 0.7072 * u_map.w + length(u_map.xy) + u_layer.x * length(u_mapLight.xy) / max(u_mapLight.z, 1e-3) + 1.0;
    tEnd = min(tEnd, reach / max(sinV, 1e-4));
    vec3 lossR = vec3(0.0), lossM = vec3(0.0);
    float phaseR = rayleighPhase(nu);
    vec3 thrD = vec3(1.0);
    float dt = tEnd / float(u_steps);
    for (int k = 0; k < u_steps && tEnd > 0.0; ++k) {
        float t = (float(k) + 0.5) * dt;
        float hp = heightAt(h, mu, t);
        float rp = atm_bottom() + hp;
        float muSp = clamp((r * muS + t * nu) / rp, -1.0, 1.0);
        vec3 sR = atm_scatteringRayleigh(hp), sM = atm_scatteringMie(hp);
        vec3 sigmaD = atm_extinction(hp) - atm_shFactors.w * sM;  // delta-M, as the sky-view march
        vec3 seg = atm_segmentFactor(sigmaD, dt);
        float lost = 1.0 - shadowAt(t * dir.xy, hp);
        vec3 tl = transmittanceToLight(hp, muSp, u_angular) * (lost * thrD) * seg;
        lossR += sR * tl * phaseR;
        lossM += sM * tl;
        thrD *= exp(-sigmaD * dt);
    }
    if (ground && tEnd >= d && d >= 0.0) {  // d = 0: the observer's own ground (standing on it)
        // The ground reached inside the map: its directly lit part, shadowed.
        float muSg = clamp((r * muS + d * nu) / atm_bottom(), -1.0, 1.0);
        float lost = 1.0 - shadowAt(d * dir.xy, 0.0);
        lossR += thrD * transmittanceToLight(0.0, muSg, u_angular) * max(muSg, 0.0) * lost * atm_groundAlbedo.rgb / ATM_PI;
    }
    o_smooth = vec4(lossR * u_scale, 1.0);
    o_mie = vec4(lossM * u_scale, 1.0);
}
