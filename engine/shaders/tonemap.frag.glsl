// Tone mapping (docs/eye.md; the CPU twin is welkin/eye.hpp): the per-pixel mesopic colour (the
// rods' desaturated, blue-shifted percept below the photopic range), the exposure (manual, or
// the eye's adaptation state written by adapt.frag.glsl), a display curve and the sRGB transfer
// function.
layout(binding = WELKIN_BINDING_HDR_TEXTURE) uniform sampler2D u_hdr;
layout(binding = WELKIN_BINDING_EYE_STATE_TEXTURE) uniform sampler2D u_state;  // adapt.frag.glsl's (cone, rod, exposure, 1)
uniform int u_auto;              // 1: the exposure of u_state
uniform float u_exposure;        // manual: scene cd/m^2 -> display value before the curve
uniform int u_curve;             // 0 ACES fit, 1 Hable, 2 Reinhard on luminance, 3 none (clip)
uniform int u_mesopic;           // 1: per-pixel mesopic colour
uniform float u_log10Scotopic;   // log10 of eye.scotopic_cd_m2: rods only below
uniform float u_log10Photopic;   // log10 of eye.photopic_cd_m2: cones only above
uniform vec3 u_rodColor;         // linear sRGB of the rod hue with Y = 1, divided by (V'/Y) of white
in vec2 v_ndc;
out vec4 o_color;

const vec3 kLuminance = vec3(0.2126, 0.7152, 0.0722);

vec3 welkin_mesopic(vec3 c) {
    float Y = dot(c, kLuminance);
    float X = dot(c, vec3(0.4124, 0.3576, 0.1805));
    float Z = dot(c, vec3(0.0193, 0.1192, 0.9505));
    float V = X > 0.0 ? max(Y * (1.33 * (1.0 + (Y + Z) / X) - 1.68), 0.0) : 0.0;  // Larson et al. 1997
    float w = Y > 0.0 ? 1.0 - smoothstep(u_log10Scotopic, u_log10Photopic, log(Y) / log(10.0)) : 1.0;
    return mix(c, u_rodColor * V, w);
}

vec3 welkin_aces(vec3 x) {
    // Narkowicz's fit of the ACES reference rendering transform (input scaled by 0.6).
    x *= 0.6;
    return clamp((x * (2.51 * x + 0.03)) / (x * (2.43 * x + 0.59) + 0.14), 0.0, 1.0);
}

vec3 welkin_hableF(vec3 x) {
    // Hable's filmic curve (Uncharted 2): shoulder 0.15, linear 0.50 at angle 0.10, toe 0.20, 0.02/0.30.
    return (x * (0.15 * x + 0.05) + 0.004) / (x * (0.15 * x + 0.50) + 0.06) - 0.02 / 0.30;
}

vec3 welkin_curve(vec3 x) {
    if (u_curve == 0) return welkin_aces(x);
    if (u_curve == 1) return clamp(welkin_hableF(2.0 * x) / welkin_hableF(vec3(11.2)), 0.0, 1.0);  // exposure bias 2, white 11.2
    if (u_curve == 2) return clamp(x / (1.0 + dot(x, kLuminance)), 0.0, 1.0);
    return clamp(x, 0.0, 1.0);
}

vec3 welkin_srgbEncode(vec3 c) {
    return mix(12.92 * c, 1.055 * pow(c, vec3(1.0 / 2.4)) - 0.055, step(vec3(0.0031308), c));
}

void main() {
    vec3 L = texelFetch(u_hdr, ivec2(gl_FragCoord.xy), 0).rgb;  // same size as the target
    if (u_mesopic != 0) L = welkin_mesopic(L);
    float exposure = u_auto != 0 ? texelFetch(u_state, ivec2(0), 0).z : u_exposure;
    o_color = vec4(welkin_srgbEncode(welkin_curve(L * exposure)), 1.0);
}
