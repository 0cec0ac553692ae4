// Keyframe blend (light_keyframes.hpp): the table shown for the light's current elevation from up
// to four complete tables at consecutive grid elevations (or two, extrapolated, or one), as the
// sum of u_w[i] x table i (weights summing to 1: Catmull-Rom, linear, or 1 alone). Radiance is
// mixed in logarithm where every table is above 1e-12 (the light's transmittance makes it close to
// exponential in the elevation near the horizon; a cubic in log radiance stays positive),
// linearly (clamped at 0) otherwise. Unused inputs repeat table A with weight 0. Fragment pass
// (sky view, SKY_VIEW_BLEND: outputs smooth, Mie without phase and the total with the Mie phase
// at the texel's angle to the light at the *current* elevation) or compute pass (aerial
// perspective volume, AERIAL_BLEND). Needs atmosphere.glsl before it.
// The keyframes hold log(max(radiance, 1e-30)) (KEYFRAME_TO_LOG below, once per complete table),
// so a run costs four fetches and one exponential per channel.
uniform vec4 u_w;
uniform float u_muS;  // current cos zenith of the light

vec3 keyframeMix(vec3 a, vec3 b, vec3 c, vec3 d) {
    if (u_w.x == 1.0) return exp(a);
    const float logTiny = -27.631;  // log(1e-12)
    vec3 lg = exp(u_w.x * a + u_w.y * b + u_w.z * c + u_w.w * d);
    if (all(greaterThan(min(min(a, b), min(c, d)), vec3(logTiny)))) return lg;
    vec3 lin = max(u_w.x * exp(a) + u_w.y * exp(b) + u_w.z * exp(c) + u_w.w * exp(d), vec3(0.0));
    return mix(lin, lg, vec3(greaterThan(min(min(a, b), min(c, d)), vec3(logTiny))));
}

#ifdef KEYFRAME_TO_LOG
// In place: a complete keyframe's radiance to its logarithm (rgb; alpha kept).
layout(local_size_x = 8, local_size_y = 8, local_size_z = 1) in;
#ifdef KEYFRAME_3D
layout(rgba32f, binding = WELKIN_BINDING_LUT_IMAGE) uniform image3D u_table;
#else
layout(rgba32f, binding = WELKIN_BINDING_LUT_IMAGE) uniform image2D u_table;
#endif
uniform ivec3 u_size;

void main() {
    ivec3 p = ivec3(gl_GlobalInvocationID);
    if (any(greaterThanEqual(p, u_size))) return;
#ifdef KEYFRAME_3D
    vec4 v = imageLoad(u_table, p);
    imageStore(u_table, p, vec4(log(max(v.rgb, vec3(1e-30))), v.a));
#else
    vec4 v = imageLoad(u_table, p.xy);
    imageStore(u_table, p.xy, vec4(log(max(v.rgb, vec3(1e-30))), v.a));
#endif
}
#endif

#ifdef SKY_VIEW_BLEND
layout(binding = WELKIN_BINDING_BLEND_A) uniform sampler2D u_smoothA;
layout(binding = WELKIN_BINDING_BLEND_A_MIE) uniform sampler2D u_mieA;
layout(binding = WELKIN_BINDING_BLEND_B) uniform sampler2D u_smoothB;
layout(binding = WELKIN_BINDING_BLEND_B_MIE) uniform sampler2D u_mieB;
layout(binding = WELKIN_BINDING_BLEND_C) uniform sampler2D u_smoothC;
layout(binding = WELKIN_BINDING_BLEND_C_MIE) uniform sampler2D u_mieC;
layout(binding = WELKIN_BINDING_BLEND_D) uniform sampler2D u_smoothD;
layout(binding = WELKIN_BINDING_BLEND_D_MIE) uniform sampler2D u_mieD;
uniform float u_h;
uniform ivec2 u_size;
layout(location = 0) out vec4 o_smooth;
layout(location = 1) out vec4 o_mie;
layout(location = 2) out vec4 o_total;

void main() {
    ivec2 p = ivec2(gl_FragCoord.xy);
    vec3 s = keyframeMix(texelFetch(u_smoothA, p, 0).rgb, texelFetch(u_smoothB, p, 0).rgb, texelFetch(u_smoothC, p, 0).rgb,
                         texelFetch(u_smoothD, p, 0).rgb);
    vec3 m = keyframeMix(texelFetch(u_mieA, p, 0).rgb, texelFetch(u_mieB, p, 0).rgb, texelFetch(u_mieC, p, 0).rgb,
                         texelFetch(u_mieD, p, 0).rgb);
    vec2 size = vec2(u_size);
    vec2 ma = skyViewMuAz(u_h, gl_FragCoord.xy / size, size);
    float mu = ma.x, az = ma.y;
    float sinV = sqrt(max(1.0 - mu * mu, 0.0)), sinS = sqrt(max(1.0 - u_muS * u_muS, 0.0));
    float nu = clamp(sinV * sinS * cos(az) + mu * u_muS, -1.0, 1.0);
    o_smooth = vec4(s, 1.0);
    o_mie = vec4(m, 1.0);
    o_total = vec4(s + m * miePhase(nu), 1.0);
}
#endif

#ifdef AERIAL_BLEND
layout(local_size_x = 8, local_size_y = 8, local_size_z = 1) in;
layout(binding = WELKIN_BINDING_BLEND_A) uniform sampler3D u_inA;
layout(binding = WELKIN_BINDING_BLEND_AERIAL_B) uniform sampler3D u_inB;
layout(binding = WELKIN_BINDING_BLEND_AERIAL_C) uniform sampler3D u_inC;
layout(binding = WELKIN_BINDING_BLEND_AERIAL_D) uniform sampler3D u_inD;
layout(rgba32f, binding = WELKIN_BINDING_LUT_IMAGE) uniform writeonly image3D u_in;
uniform int u_size;

void main() {
    ivec3 p = ivec3(gl_GlobalInvocationID);
    if (any(greaterThanEqual(p, ivec3(u_size)))) return;
    imageStore(u_in, p, vec4(keyframeMix(texelFetch(u_inA, p, 0).rgb, texelFetch(u_inB, p, 0).rgb, texelFetch(u_inC, p, 0).rgb,
                                         texelFetch(u_inD, p, 0).rgb), 1.0));
    // The transmittance along the view rays is written by every build (light-independent).
}
#endif
