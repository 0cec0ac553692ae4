// Spectral mode (sky_spectral.hpp): adds one wavelength triple's LUT, converted to linear sRGB by
// a 3x3 matrix, into the RGB LUT the Sky reads: dst = (accumulate ? dst : 0) + M src, clamped
// at 0 on the last triple (a colour outside the sRGB gamut, e.g. the deep-blue ozone twilight,
// can have a slightly negative red; the LUTs stay non-negative). Compute shader; define
// COMBINE_3D for volumes and COMBINE_FORMAT (rgba16f or rgba32f) for the destination's format.
layout(local_size_x = 8, local_size_y = 8, local_size_z = 1) in;
#ifdef COMBINE_3D
layout(binding = WELKIN_BINDING_COMBINE_SOURCE) uniform sampler3D u_src;
layout(COMBINE_FORMAT, binding = WELKIN_BINDING_LUT_IMAGE) uniform image3D u_dst;
#else
layout(binding = WELKIN_BINDING_COMBINE_SOURCE) uniform sampler2D u_src;
layout(COMBINE_FORMAT, binding = WELKIN_BINDING_LUT_IMAGE) uniform image2D u_dst;
#endif
uniform mat3 u_toRgb;
uniform int u_accumulate;  // 0: first triple (overwrite), 1: add
uniform int u_last;        // 1: last triple (clamp at 0)
uniform ivec3 u_size;

void main() {
    ivec3 p = ivec3(gl_GlobalInvocationID);
    if (any(greaterThanEqual(p, u_size))) return;
#ifdef COMBINE_3D
    vec4 s = texelFetch(u_src, p, 0);
    vec3 v = u_toRgb * s.rgb;
    if (u_accumulate != 0) v += imageLoad(u_dst, p).rgb;
    if (u_last != 0) v = max(v, vec3(0.0));
    imageStore(u_dst, p, vec4(v, s.a));
#else
    vec4 s = texelFetch(u_src, p.xy, 0);
    vec3 v = u_toRgb * s.rgb;
    if (u_accumulate != 0) v += imageLoad(u_dst, p.xy).rgb;
    if (u_last != 0) v = max(v, vec3(0.0));
    imageStore(u_dst, p.xy, vec4(v, s.a));
#endif
}
