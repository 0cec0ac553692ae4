// Eclipse sky-view pass (fragment, two outputs): during a solar eclipse the Sun's sky is no
// longer symmetric about the Sun's vertical, so this table covers the whole circle of azimuth:
// u = az / 2 pi (az from north through east, wrap repeat), v the sky view's latitude rows
// (skyViewUvS().y). Output 0: Rayleigh single scattering with its phase, multiple scattering and
// the lit ground; output 1: Mie single scattering without its phase; per lux of the Sun above the
// air, times kLutScale, every point marched seeing the Moon's shadow (ATM_ECLIPSE); output 2:
// both, with the Mie phase at the texel's own angle to the Sun (SkyQuality::bakedMiePhase: one
// fetch per pixel in the Sky pass, as the ordinary sky view's total table). Twin of
// cpu::eclipseRadiance(). Needs atmosphere.glsl (ATM_USE_TRANSMITTANCE, ATM_USE_MULTISCATTERING,
// ATM_ECLIPSE) before it.
uniform float u_h;        // observer height above the ground, m, clamped into the atmosphere
uniform vec3 u_sunDir;    // unit ENU (apparent)
uniform int u_steps;
uniform ivec2 u_size;     // texels: azimuth, latitude (the sky view's height)
uniform float u_scale;    // kLutScale
uniform float u_angular;  // the Sun's angular radius, rad
layout(location = 0) out vec4 o_smooth;
layout(location = 1) out vec4 o_mie;
layout(location = 2) out vec4 o_total;

void main() {
    vec2 size = vec2(u_size);
    vec2 uv = gl_FragCoord.xy / size;
    float mu = skyViewMuAz(u_h, uv, size).x;
    float az = uv.x * 2.0 * ATM_PI;
    float sinV = sqrt(max(1.0 - mu * mu, 0.0));
    vec3 dir = vec3(sinV * sin(az), sinV * cos(az), mu);
    float nu = clamp(dot(dir, u_sunDir), -1.0, 1.0);
    atm_eclOrigin = vec3(0.0);
    atm_eclView = dir;
    Scattering s = integrateScattering(u_h, mu, u_sunDir.z, nu, 1e30, u_steps, true, u_angular, uv.y >= 0.5 ? 0 : 1);
    o_smooth = vec4(s.smooth_ * u_scale, 1.0);
    o_mie = vec4(s.mieNoPhase * u_scale, 1.0);
    o_total = vec4((s.smooth_ + s.mieNoPhase * miePhase(nu)) * u_scale, 1.0);
}
