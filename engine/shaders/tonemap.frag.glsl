// Tone mapping (docs/eye.md; the CPU twin is welkin/eye.hpp): the per-pixel mesopic colour (the
// rods' desaturated, blue-shifted percept below the photopic range), the exposure (manual, or
// the eye's adaptation state written by adapt.frag.glsl), a display curve and the sRGB transfer
// function.
//
// Cost (docs/eye.md, `welkin bench frame`): no branch and no transcendental function per
// channel. An RGBA32F
// frame is read with imageLoad (WELKIN_TONEMAP_IMAGE; half the cost of a texelFetch on
// llvmpipe), any other format through the sampler; the sRGB transfer function is a rational
// approximation in sqrt(x) (largest error 6e-6, 1/650 of an 8-bit step); the one log per pixel
// is the mesopic weight's, and only with eye.mesopic.
#ifdef WELKIN_TONEMAP_IMAGE
layout(binding = WELKIN_BINDING_HDR_IMAGE, rgba32f) readonly uniform image2D u_hdrImage;
#else
layout(binding = WELKIN_BINDING_HDR_TEXTURE) uniform sampler2D u_hdr;
#endif
#ifdef WELKIN_TONEMAP_AUTO
flat in float v_exposure;  // the exposure of adapt.frag.glsl's state, read once per vertex (tonemap.vert.glsl)
#endif
// The settings are compiled in (ToneMapper keeps one program per combination, built when first
// used): a branch on a uniform costs llvmpipe every path.
//   WELKIN_TONEMAP_AUTO     defined: the exposure of the eye's state (v_exposure); else u_exposure
//   WELKIN_TONEMAP_CURVE    0 ACES fit, 1 Hable, 2 Reinhard on luminance, 3 none (clip)
//   WELKIN_TONEMAP_MESOPIC  defined: per-pixel mesopic colour
//   WELKIN_TONEMAP_SRGB_TARGET defined: the target encodes sRGB on write (GL_FRAMEBUFFER_SRGB):
//                           the display-linear value out, no encoding here
uniform float u_exposure;        // manual: scene cd/m^2 -> display value before the curve
// The mesopic weight's ramp in log2 of the luminance: t = log2(Y) k - c is (log10 Y - log10
// eye.scotopic_cd_m2) / (log10 eye.photopic_cd_m2 - log10 eye.scotopic_cd_m2), one multiply-add
// in place of a division by log(10) and one by the span.
uniform vec2 u_rodRamp;          // (k, c) = (1, log2 scotopic) / (log2 photopic - log2 scotopic)
uniform vec3 u_rodColor;         // linear sRGB of the rod hue with Y = 1, divided by (V'/Y) of white
in vec2 v_ndc;
out vec4 o_color;

const vec3 kLuminance = vec3(0.2126, 0.7152, 0.0722);

// No branch for photopic pixels: llvmpipe runs both sides of a branch under a mask (the tone map
// cost the same on day and night frames, docs/eye.md), and at and above eye.photopic_cd_m2 the
// ramp is 1, w exactly 0 and mix() returns c unchanged.
vec3 welkin_mesopic(vec3 c) {
    float Y = dot(c, kLuminance);
    float X = dot(c, vec3(0.4124, 0.3576, 0.1805));
    float Z = dot(c, vec3(0.0193, 0.1192, 0.9505));
    float V = X > 0.0 ? max(Y * (1.33 * (1.0 + (Y + Z) / X) - 1.68), 0.0) : 0.0;  // Larson et al. 1997
    // log2 of Y > 0 from its bits: the exponent, and a cubic for the mantissa's (|error| 8e-4, so
    // w within 1e-4: far under an 8-bit code; the builtin's edge cases and its division cost
    // llvmpipe ~0.1 of a trivial pass more, `welkin bench frame`). Y <= 0: w = 1 below.
    int bits = floatBitsToInt(Y);
    float m = intBitsToFloat((bits & 0x007fffff) | 0x3f800000) - 1.0;
    float l = float((bits >> 23) - 127) + m * (1.4246257 + m * (-0.5894235 + m * 0.1656103));
    float t = clamp(l * u_rodRamp.x - u_rodRamp.y, 0.0, 1.0);
    float w = Y > 0.0 ? 1.0 - t * t * (3.0 - 2.0 * t) : 1.0;  // 1 - smoothstep
    return mix(c, u_rodColor * V, w);
}

// The display curves: welkin_aces(), welkin_hable(), eye_curves.shared.glsl (welkin::eye::acesFit()
// and welkin::eye::hable() compile it in double).
#include "eye_curves.shared.glsl"

vec3 welkin_curve(vec3 x) {
#if WELKIN_TONEMAP_CURVE == 0
    return welkin_aces(x);
#elif WELKIN_TONEMAP_CURVE == 1
    return welkin_hable(x);
#elif WELKIN_TONEMAP_CURVE == 2
    return clamp(x / (1.0 + dot(x, kLuminance)), 0.0, 1.0);
#else
    return clamp(x, 0.0, 1.0);
#endif
}

// The sRGB encoding: welkin_srgbEncodeFast(), eye_srgb.shared.glsl (welkin::eye::srgbEncodeFast()
// compiles it in double).
#include "eye_srgb.shared.glsl"

void main() {
#ifdef WELKIN_TONEMAP_IMAGE
    vec3 L = imageLoad(u_hdrImage, ivec2(gl_FragCoord.xy)).rgb;  // same size as the target
#else
    vec3 L = texelFetch(u_hdr, ivec2(gl_FragCoord.xy), 0).rgb;
#endif
#ifdef WELKIN_TONEMAP_MESOPIC
    L = welkin_mesopic(L);
#endif
#ifdef WELKIN_TONEMAP_AUTO
    float exposure = v_exposure;
#else
    float exposure = u_exposure;
#endif
#ifdef WELKIN_TONEMAP_SRGB_TARGET
    // An sRGB target with GL_FRAMEBUFFER_SRGB (ToneMapper::display): the encoding on write.
    o_color = vec4(welkin_curve(L * exposure), 1.0);
#else
    o_color = vec4(welkin_srgbEncodeFast(welkin_curve(L * exposure)), 1.0);
#endif
}
