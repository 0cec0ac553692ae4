// Keyframe blend (light_keyframes.hpp): the table shown for the light's current elevation from up
// to four complete tables at consecutive grid elevations (or two, extrapolated, or one), as the
// sum of u_w[i] x table i (weights summing to 1: Catmull-Rom, linear, or 1 alone). Radiance is
// mixed in logarithm where every table is above 1e-12 (the light's transmittance makes it close to
// exponential in the elevation near the horizon; a cubic in log radiance stays positive),
// linearly (clamped at 0) otherwise. Unused inputs repeat table A with weight 0. Fragment pass
// (sky view, SKY_VIEW_BLEND: outputs smooth, Mie without phase and the total with the Mie phase
// at the texel's angle to the light at the *current* elevation) or compute pass (aerial
// perspective volume, AERIAL_BLEND). Needs atmosphere.glsl before it.
// The 3-D (aerial) keyframes hold log(max(radiance, 1e-30)) (KEYFRAME_TO_LOG below, once per
// complete table). The sky-view keyframes hold the six log radiances of a texel (smooth and Mie,
// RGB) packed at 21 bits each into one RGBA32UI texel (KEYFRAME_PACK, once per complete table;
// log radiance in [KF_LOG_MIN, KF_LOG_MAX] in steps of 4.8e-5, a relative step of 4.8e-5 in the
// radiance), so a blend run costs one fetch per table and one exponential per channel: the fetches
// are what the pass spends its time on (two per table before: 1.8 against 0.9 ms at `high`).
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

const float KF_LOG_MIN = -70.0;  // log(1e-30): the floor of every keyframe
const float KF_LOG_MAX = 30.0;   // log(1e13): above any radiance per lux x kLutScale (1e4)
const float KF_STEPS = 2097151.0;  // 2^21 - 1

// Six log radiances from one packed texel: x, y, z hold a, c, e in their low 21 bits and the low
// 11 bits of b, d, f in their top 11; w holds the top 10 bits of b, d, f.
void keyframeUnpack(uvec4 w, out vec3 smoothLog, out vec3 mieLog) {
    const uint m21 = 0x1FFFFFu, m10 = 0x3FFu;
    uint a = w.x & m21, c = w.y & m21, e = w.z & m21;
    uint b = (w.x >> 21) | ((w.w & m10) << 11);
    uint d = (w.y >> 21) | (((w.w >> 10) & m10) << 11);
    uint f = (w.z >> 21) | (((w.w >> 20) & m10) << 11);
    const float k = (KF_LOG_MAX - KF_LOG_MIN) / KF_STEPS;
    smoothLog = vec3(float(a), float(b), float(c)) * k + KF_LOG_MIN;
    mieLog = vec3(float(d), float(e), float(f)) * k + KF_LOG_MIN;
}

#ifdef KEYFRAME_PACK
// A complete sky-view keyframe (radiance, fp32 smooth and Mie) into its packed texture.
layout(local_size_x = 8, local_size_y = 8, local_size_z = 1) in;
layout(binding = WELKIN_BINDING_BLEND_A) uniform sampler2D u_srcSmooth;
layout(binding = WELKIN_BINDING_BLEND_A_MIE) uniform sampler2D u_srcMie;
layout(rgba32ui, binding = WELKIN_BINDING_LUT_IMAGE) uniform writeonly uimage2D u_packed;
uniform ivec2 u_size;

uint keyframeQuantise(float radiance) {
    float l = log(max(radiance, 1e-30));
    return uint(clamp(floor((l - KF_LOG_MIN) / (KF_LOG_MAX - KF_LOG_MIN) * KF_STEPS + 0.5), 0.0, KF_STEPS));
}

void main() {
    ivec2 p = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(p, u_size))) return;
    vec3 s = texelFetch(u_srcSmooth, p, 0).rgb, m = texelFetch(u_srcMie, p, 0).rgb;
    uint a = keyframeQuantise(s.r), b = keyframeQuantise(s.g), c = keyframeQuantise(s.b);
    uint d = keyframeQuantise(m.r), e = keyframeQuantise(m.g), f = keyframeQuantise(m.b);
    imageStore(u_packed, p, uvec4(a | (b << 21), c | (d << 21), e | (f << 21), (b >> 11) | ((d >> 11) << 10) | ((f >> 11) << 20)));
}
#endif

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
layout(binding = WELKIN_BINDING_BLEND_A) uniform usampler2D u_packedA;
layout(binding = WELKIN_BINDING_BLEND_B) uniform usampler2D u_packedB;
layout(binding = WELKIN_BINDING_BLEND_C) uniform usampler2D u_packedC;
layout(binding = WELKIN_BINDING_BLEND_D) uniform usampler2D u_packedD;
uniform float u_h;
uniform ivec2 u_size;
layout(location = 0) out vec4 o_smooth;
layout(location = 1) out vec4 o_mie;
layout(location = 2) out vec4 o_total;

void main() {
    ivec2 p = ivec2(gl_FragCoord.xy);
    vec3 sA, mA, sB, mB, sC, mC, sD, mD;
    keyframeUnpack(texelFetch(u_packedA, p, 0), sA, mA);
    keyframeUnpack(texelFetch(u_packedB, p, 0), sB, mB);
    keyframeUnpack(texelFetch(u_packedC, p, 0), sC, mC);
    keyframeUnpack(texelFetch(u_packedD, p, 0), sD, mD);
    vec3 s = keyframeMix(sA, sB, sC, sD);
    vec3 m = keyframeMix(mA, mB, mC, mD);
    vec2 size = vec2(u_size);
    float nu = skyViewTexelView(u_h, gl_FragCoord.xy / size, size, u_muS).z;  // the sky-view texel's (atmosphere.shared.glsl)
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
