// Keyframe blend (light_keyframes.hpp): the table shown for the light's current elevation from
// two complete tables built at elevations e_a and e_b, mixed at t = (e - e_a) / (e_b - e_a)
// (t outside [0, 1]: extrapolated along their trend). Radiance is mixed in logarithm where both
// are positive (the light's transmittance makes it close to exponential in the elevation near
// the horizon), linearly otherwise. Fragment pass (sky view, SKY_VIEW_BLEND: outputs smooth,
// Mie without phase and the total with the Mie phase at the texel's angle to the light at the
// *current* elevation) or compute pass (aerial perspective volume, AERIAL_BLEND). Needs
// atmosphere.glsl before it.
uniform float u_t;
uniform float u_muS;  // current cos zenith of the light

vec3 keyframeMix(vec3 a, vec3 b, float t) {
    if (t == 0.0) return a;
    const float tiny = 1e-12;
    vec3 lin = max(mix(a, b, t), vec3(0.0));
    vec3 lg = exp(mix(log(max(a, vec3(tiny))), log(max(b, vec3(tiny))), t));
    return mix(lin, lg, vec3(greaterThan(min(a, b), vec3(tiny))));
}

#ifdef SKY_VIEW_BLEND
layout(binding = WELKIN_BINDING_BLEND_A) uniform sampler2D u_smoothA;
layout(binding = WELKIN_BINDING_BLEND_A_MIE) uniform sampler2D u_mieA;
layout(binding = WELKIN_BINDING_BLEND_B) uniform sampler2D u_smoothB;
layout(binding = WELKIN_BINDING_BLEND_B_MIE) uniform sampler2D u_mieB;
uniform float u_h;
uniform ivec2 u_size;
layout(location = 0) out vec4 o_smooth;
layout(location = 1) out vec4 o_mie;
layout(location = 2) out vec4 o_total;

void main() {
    ivec2 p = ivec2(gl_FragCoord.xy);
    vec3 s = keyframeMix(texelFetch(u_smoothA, p, 0).rgb, texelFetch(u_smoothB, p, 0).rgb, u_t);
    vec3 m = keyframeMix(texelFetch(u_mieA, p, 0).rgb, texelFetch(u_mieB, p, 0).rgb, u_t);
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
layout(binding = WELKIN_BINDING_BLEND_AERIAL_TR_A) uniform sampler3D u_trA;
layout(rgba32f, binding = WELKIN_BINDING_LUT_IMAGE) uniform writeonly image3D u_in;
layout(rgba32f, binding = WELKIN_BINDING_SECOND_LUT_IMAGE) uniform writeonly image3D u_tr;
uniform int u_size;

void main() {
    ivec3 p = ivec3(gl_GlobalInvocationID);
    if (any(greaterThanEqual(p, ivec3(u_size)))) return;
    imageStore(u_in, p, vec4(keyframeMix(texelFetch(u_inA, p, 0).rgb, texelFetch(u_inB, p, 0).rgb, u_t), 1.0));
    // The transmittance along a view ray does not depend on the light: any table's.
    imageStore(u_tr, p, texelFetch(u_trA, p, 0));
}
#endif
