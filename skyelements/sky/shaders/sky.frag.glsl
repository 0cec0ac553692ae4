// Sky element: radiance (cd/m^2) and transmittance of the atmosphere along each pixel's ray.
// Needs engine/camera.glsl, engine/composite.glsl and generators/atmosphere.glsl
// (ATM_USE_TRANSMITTANCE, and ATM_USE_MULTISCATTERING when SKY_PER_PIXEL) before it.
layout(binding = WELKIN_BINDING_SUN_VIEW_LUT) uniform sampler2D u_sunSmooth;
layout(binding = WELKIN_BINDING_SUN_VIEW_MIE_LUT) uniform sampler2D u_sunMie;
layout(binding = WELKIN_BINDING_MOON_VIEW_LUT) uniform sampler2D u_moonSmooth;
layout(binding = WELKIN_BINDING_MOON_VIEW_MIE_LUT) uniform sampler2D u_moonMie;
layout(binding = WELKIN_BINDING_VIEW_TRANSMITTANCE_LUT) uniform sampler1D u_viewTransmittance;  // sky.view_transmittance_lut
uniform float u_h;          // observer height above the ground, m (>= 0; may exceed the top)
uniform vec3 u_sunDir;      // unit ENU
uniform vec3 u_moonDir;
uniform vec3 u_sunE;        // lux per channel at the top of the atmosphere
uniform vec3 u_moonE;
uniform float u_invScale;   // 1 / kLutScale
uniform vec2 u_lutSize;     // sky-view LUT size, texels (height even)
uniform int u_steps;        // per-pixel ray march
uniform float u_moonAngular;
uniform float u_sH;         // sin(theta_H / 2), theta_H the zenith angle of the observer's horizon (LUT path)
// skyAtan2(): the tables' azimuth without the builtin atan (sky_atan.shared.glsl).
#include "sky_atan.shared.glsl"
#ifdef SKY_SHADOW_LOSS
// The direct light's shadow on the in-scattering (sky.shadow_loss_lut, e.g. the clouds'): the
// single scattering it removes, per lux x kLutScale, over absolute azimuth (u = az / 2 pi, wrap
// repeat) and the sky view's latitude. A program variant: without a shadow nothing is fetched.
layout(binding = WELKIN_BINDING_SHADOW_LOSS_LUT) uniform sampler2D u_lossSmooth;
layout(binding = WELKIN_BINDING_SHADOW_LOSS_MIE_LUT) uniform sampler2D u_lossMie;
uniform vec3 u_lossLight;  // the shadowed light, unit ENU
uniform vec3 u_lossE;      // its illuminance per channel / kLutScale (lux)
// v: the sky view's latitude coordinate of dir (the loss table has the sky view's height).
vec3 shadowLoss(vec3 dir, float v) {
    // From north through east (skyAtan2(): 0 at the zenith and nadir, where u does not matter).
    vec2 uv = vec2(skyAtan2(dir.x, dir.y) * (0.5 / ATM_PI), v);
    return (texture(u_lossSmooth, uv).rgb + texture(u_lossMie, uv).rgb * miePhase(clamp(dot(dir, u_lossLight), -1.0, 1.0))) * u_lossE;
}
#endif
#ifdef SKY_SPECTRAL
// Spectral mode, per pixel: one draw per wavelength triple (atmosphere block of that triple),
// its per-lux values converted to linear sRGB per lux; T = 1 (the first draw outputs T).
uniform mat3 u_toRgb;
#define SKY_TO_RGB(x) (u_toRgb * (x))
#else
#define SKY_TO_RGB(x) (x)
#endif


// Cosine of the azimuth of `dir` measured from the light's vertical plane (0 when either is
// vertical: every azimuth is then the same direction).
float cosAzimuthFrom(vec3 dir, vec3 light) {
    vec2 a = dir.xy, b = light.xy;
    return clamp(dot(a, b) * inversesqrt(max(dot(a, a) * dot(b, b), 1e-30)), -1.0, 1.0);
}

// Radiance of one light from its sky-view LUT(s), cd/m^2: `E` is the light's illuminance per
// channel divided by kLutScale. SKY_BAKED_PHASE: `smoothLut` holds everything with the Mie phase
// baked in; else the Mie part is fetched separately and its phase evaluated at the pixel's exact
// angle to the light. The LUT height is even, so skyViewUvS() keeps v inside its own half (sky
// or ground) by construction: no clamp is needed here (skyViewClampHalf).
vec3 skyViewLight(sampler2D smoothLut, sampler2D mieLut, vec3 dir, vec3 light, vec3 E, out float v) {
    vec2 uv = skyViewUvS(u_sH, dir.z, cosAzimuthFrom(dir, light), u_lutSize);
    v = uv.y;
#ifdef SKY_BAKED_PHASE
    return texture(smoothLut, uv).rgb * E;
#else
    return (texture(smoothLut, uv).rgb + texture(mieLut, uv).rgb * miePhase(clamp(dot(dir, light), -1.0, 1.0))) * E;
#endif
}

#ifdef SKY_PER_PIXEL
// Radiance per lux along a ray from height h (possibly above the atmosphere) for one light.
vec3 marchLight(float h, float mu, vec3 dir, vec3 light, float angular, out vec3 transmittance, out bool ground) {
    float R = atm_bottom(), Ht = atm_thickness();
    float muS = light.z, nu = clamp(dot(dir, light), -1.0, 1.0);
    transmittance = vec3(1.0);
    ground = false;
#ifdef ATM_ECLIPSE
    atm_eclOn = light == u_sunDir;  // the Moon's shadow darkens the Sun's light only
    atm_eclOrigin = vec3(0.0);
    atm_eclView = dir;
#endif
    if (h > Ht) {
        float t = atm_entryFromSpace(R, Ht, h, mu);  // atmosphere.shared.glsl, as cpu::skyRadiance()
        if (t < 0.0) return vec3(0.0);
        float r = R + h;
        float rt = atm_top();
        mu = clamp((r * mu + t) / rt, -1.0, 1.0);
        muS = clamp((r * muS + t * nu) / rt, -1.0, 1.0);
        h = Ht;
#ifdef ATM_ECLIPSE
        atm_eclOrigin = t * dir;  // the march starts where the ray enters the air
#endif
    }
    Scattering s = integrateScattering(h, mu, muS, nu, 1e30, u_steps, false, angular, -1);
    transmittance = s.transmittance;
    ground = s.hitGround;
    return SKY_TO_RGB(s.smooth_ + s.mieNoPhase * miePhase(nu));
}
#endif

void main() {
    vec3 dir;
    if (!welkin_viewDirection(welkin_pixel(), dir)) discard;
    float mu = clamp(dir.z, -1.0, 1.0);
    vec3 L;
    vec3 T;
#ifdef SKY_PER_PIXEL
    bool ground;
    L = marchLight(u_h, mu, dir, u_sunDir, atm_solarIlluminance.w, T, ground) * u_sunE;
#ifdef SKY_MOON
    vec3 Tm;
    bool gm;
    L += marchLight(u_h, mu, dir, u_moonDir, u_moonAngular, Tm, gm) * u_moonE;
#endif
    if (ground) T = vec3(0.0);
#else
    float v, vMoon;
#ifdef SKY_ECLIPSE
    // A solar eclipse: the Sun's table over absolute azimuth (sky.eclipse_view_lut, bound on the
    // Sun's units), u = az / 2 pi from north through east (skyAtan2(): 0 at the zenith and
    // nadir), v the sky view's latitude.
    {
        vec2 uvE = vec2(skyAtan2(dir.x, dir.y) * (0.5 / ATM_PI), skyViewUvS(u_sH, mu, 1.0, u_lutSize).y);
        v = uvE.y;
#ifdef SKY_BAKED_PHASE
        L = texture(u_sunSmooth, uvE).rgb * (u_sunE * u_invScale);  // the total table (sky.eclipse_view_total_lut)
#else
        L = (texture(u_sunSmooth, uvE).rgb + texture(u_sunMie, uvE).rgb * miePhase(clamp(dot(dir, u_sunDir), -1.0, 1.0))) *
            (u_sunE * u_invScale);
#endif
    }
#elif defined(SKY_NO_SUN)
    // Night (the Sun below kSkySunNightAltitudeRad, -21 deg): the Sun's sky-view LUT is 0 there
    // (skyelements/sky/README.md) and not fetched; the transmittance's row v is the sky view's latitude, the
    // same for any azimuth.
    L = vec3(0.0);
    v = skyViewUvS(u_sH, mu, 1.0, u_lutSize).y;
#else
    L = skyViewLight(u_sunSmooth, u_sunMie, dir, u_sunDir, u_sunE * u_invScale, v);
#endif
#ifdef SKY_MOON
    // (A separate program variant: llvmpipe evaluates both sides of a branch under a mask.)
    L += skyViewLight(u_moonSmooth, u_moonMie, dir, u_moonDir, u_moonE * u_invScale, vMoon);
#endif
#ifdef SKY_TRANSMITTANCE
    // Transmittance to the top along this latitude (0 on the ground half), from the 1-D row the
    // Sun's sky-view pass wrote at the same v (half the cost of the 2-D transmittance LUT).
    T = texture(u_viewTransmittance, v).rgb;
#else
    T = vec3(0.0);  // nothing behind the sky (the program variant for the first element)
#endif
#endif
#ifdef SKY_SHADOW_LOSS
#ifdef SKY_PER_PIXEL
    float v = skyViewUvS(u_sH, mu, 1.0, u_lutSize).y;
#endif
    // max: the loss and the sky view are two marches of the same light (different steps); where
    // the shadow removes nearly everything, rounding must not go below 0.
    L = max(L - shadowLoss(dir, v), vec3(0.0));
#endif
#ifdef SKY_SPECTRAL
    T = vec3(1.0);
#endif
#ifdef SKY_MULTIPLY
    // Night without the Moon (L = 0): blended as dst = 0 src + T dst (sky.night_multiply), the
    // transmittance as the one output, clamped as welkin_output() clamps it.
    welkin_radiance = vec4(clamp(T, vec3(0.0), vec3(1.0)), 1.0);
#else
    welkin_output(L, T);
#endif
}
