// Sky-view LUT pass (fragment, two outputs): for the observer at height u_h and a light at cos
// zenith u_muS, the radiance per lux of the light (times kLutScale) in every direction
// (horizon-dense latitude, azimuth from the light in [0, pi]). Output 0: Rayleigh single
// scattering with its phase, multiple scattering and the lit ground; output 1: Mie single
// scattering without its phase (applied per pixel, so the glow around the light stays sharp);
// output 2: both, with the Mie phase at the texel's own angle to the light (for presets that
// trade the aureole's sharpness for one texture fetch per pixel: SkyQuality::bakedMiePhase).
// Twin of cpu::skyViewTexel(). Needs atmosphere.glsl (ATM_USE_TRANSMITTANCE,
// ATM_USE_MULTISCATTERING) before it.
uniform float u_h;        // observer height above the ground, m, clamped into the atmosphere
uniform float u_muS;      // cos zenith of the light
uniform int u_steps;
uniform ivec2 u_size;
uniform float u_scale;    // kLutScale
uniform float u_angular;  // light's angular radius, rad
layout(location = 0) out vec4 o_smooth;
layout(location = 1) out vec4 o_mie;
layout(location = 2) out vec4 o_total;

void main() {
    vec2 size = vec2(u_size);
    vec2 uv = gl_FragCoord.xy / size;
    vec3 view = skyViewTexelView(u_h, uv, size, u_muS);  // atmosphere.shared.glsl, as cpu::skyViewTexel()
    float mu = view.x, nu = view.z;
    Scattering s = integrateScattering(u_h, mu, u_muS, nu, 1e30, u_steps, true, u_angular, uv.y >= 0.5 ? 0 : 1);
    o_smooth = vec4(s.smooth_ * u_scale, 1.0);
    o_mie = vec4(s.mieNoPhase * u_scale, 1.0);
    o_total = vec4((s.smooth_ + s.mieNoPhase * miePhase(nu)) * u_scale, 1.0);
}
