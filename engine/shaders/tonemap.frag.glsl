// Tone mapping: exposure (EV100 or automatic from the log-average luminance), a filmic curve and
// the sRGB transfer function.
layout(binding = WELKIN_BINDING_HDR_TEXTURE) uniform sampler2D u_hdr;
layout(binding = WELKIN_BINDING_LOG_LUM_TEXTURE) uniform sampler2D u_logLum;  // (sum w ln L, sum w) averaged, top mip used
uniform float u_ev100;         // manual exposure
uniform int u_auto;            // 1: automatic exposure
uniform float u_compensation;  // EV added to the automatic exposure
uniform int u_logLumLevel;     // last mip level of u_logLum
in vec2 v_ndc;
out vec4 o_color;

float welkin_autoEv100() {
    vec2 m = texelFetch(u_logLum, ivec2(0), u_logLumLevel).rg;
    float logAvg = m.y > 0.0 ? m.x / m.y : log(1e-7);
    // EV100 = log2(Lavg * S / K) with S = 100 and K = 12.5 (reflected-light meter calibration),
    // kept in the manual range [-20, 30].
    return clamp(log2(exp(logAvg) * 100.0 / 12.5), -20.0, 30.0);
}

vec3 welkin_filmic(vec3 x) {
    // Narkowicz's fit of the ACES reference rendering transform (input scaled by 0.6).
    x *= 0.6;
    return clamp((x * (2.51 * x + 0.03)) / (x * (2.43 * x + 0.59) + 0.14), 0.0, 1.0);
}

vec3 welkin_srgbEncode(vec3 c) {
    return mix(12.92 * c, 1.055 * pow(c, vec3(1.0 / 2.4)) - 0.055, step(vec3(0.0031308), c));
}

void main() {
    vec3 L = texelFetch(u_hdr, ivec2(gl_FragCoord.xy), 0).rgb;  // same size as the target
    float ev = u_auto != 0 ? welkin_autoEv100() - u_compensation : u_ev100;
    // Saturation-based exposure: luminance 1.2 * 2^EV100 maps to 1.
    float exposure = 1.0 / (1.2 * exp2(ev));
    o_color = vec4(welkin_srgbEncode(welkin_filmic(L * exposure)), 1.0);
}
