// Perceptual point sources (welkin/point_source.hpp is the model and its CPU twin): the sky's
// luminance behind a point, the eye's threshold for it, and the drawn size and contrast. Shared
// by the Stars and the Planet (its unresolved bodies); the uniforms are set by
// welkin::generators::setPerceptualPointUniforms (welkin/generators/point_sources.hpp).
layout(binding = WELKIN_BINDING_SUN_VIEW_LUT) uniform sampler2D u_ppSunLut;    // sky.sun_view_total_lut
layout(binding = WELKIN_BINDING_MOON_VIEW_LUT) uniform sampler2D u_ppMoonLut;  // sky.moon_view_total_lut
uniform int u_ppMode;        // 0 physical (nothing here is used), 1 perceptual
uniform int u_ppSky;         // bit 0: the Sun's sky-view LUT is bound, bit 1: the Moon's
uniform vec3 u_ppSunDir;     // unit ENU
uniform vec3 u_ppMoonDir;
uniform vec3 u_ppSunE;       // the light's illuminance above the air / kLutScale, lux per channel
uniform vec3 u_ppMoonE;
uniform float u_ppSH;        // sin(theta_H / 2), the sky view's horizon parameter
uniform vec2 u_ppLutSize;    // sky-view LUT size, texels
uniform float u_ppNight;     // the night sky's own luminance (airglow, ...), cd/m^2
uniform float u_ppContrast;  // Weber contrast at the threshold (render.point_contrast)

// The sky view's (u, v) of a direction (mirrors skyViewUvS() of generators/atmosphere.glsl).
vec2 pp_skyViewUv(vec3 dir, vec3 light) {
    vec2 a = dir.xy, b = light.xy;
    float cosAz = clamp(dot(a, b) * inversesqrt(max(dot(a, a) * dot(b, b), 1e-30)), -1.0, 1.0);
    float s = sqrt(clamp(0.5 - 0.5 * clamp(dir.z, -1.0, 1.0), 0.0, 1.0));
    float half_ = floor(u_ppLutSize.y / 2.0);
    bool sky = s <= u_ppSH;
    float x = sqrt(clamp(sky ? (u_ppSH - s) / u_ppSH : (s - u_ppSH) / (1.0 - u_ppSH), 0.0, 1.0));
    float dv = (x * (half_ - 1.0) + 0.5) / u_ppLutSize.y;
    float u = sqrt(clamp(0.5 - 0.5 * cosAz, 0.0, 1.0));
    return vec2(0.5 / u_ppLutSize.x + u * (1.0 - 1.0 / u_ppLutSize.x), sky ? 0.5 + dv : 0.5 - dv);
}

// Luminance of the sky behind direction `dir` (cd/m^2): the Sun's and the Moon's sky-view LUTs
// (the Sky element's LUT path, Mie phase at the texel's angle) and the night sky's floor.
float pp_background(vec3 dir) {
    vec3 L = vec3(0.0);
    if ((u_ppSky & 1) != 0) L += textureLod(u_ppSunLut, pp_skyViewUv(dir, u_ppSunDir), 0.0).rgb * u_ppSunE;
    if ((u_ppSky & 2) != 0) L += textureLod(u_ppMoonLut, pp_skyViewUv(dir, u_ppMoonDir), 0.0).rgb * u_ppMoonE;
    return dot(L, vec3(0.2126, 0.7152, 0.0722)) + u_ppNight;
}

// The eye's threshold for a point and the drawn size and contrast above it (Schaefer 1990):
// point_threshold.shared.glsl of the engine's shaders, which engine/src/point_source.cpp
// compiles in double.
#include "../../../engine/shaders/point_threshold.shared.glsl"

// Schaefer's (1990) threshold illuminance (lux) for a background B (cd/m^2).
float pp_thresholdLux(float B) { return welkin_pointThresholdFootCandles(B) * WELKIN_LUX_PER_FOOT_CANDLE; }

// (FWHM in px, Weber contrast) of a point of illuminance `eyeLux` at the eye over background B;
// (0, 0) when the eye would not see it. f0: the FWHM at the threshold, px.
vec2 pp_point(float eyeLux, float B, float f0) {
    float R = eyeLux / pp_thresholdLux(B);
    if (!(R >= 1.0)) return vec2(0.0);
    return welkin_pointSizeContrast(R, f0, u_ppContrast);
}
