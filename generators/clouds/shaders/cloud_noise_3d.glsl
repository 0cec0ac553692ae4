// Cloud noise pass (compute, after cloud_noise.glsl): one texel of the 3-D base or detail noise
// per invocation, written to an rgba8 image: cloudBaseNoise() or cloudDetailNoise() of
// cloud_noise.shared.glsl, which cpu::baseNoise() and cpu::detailNoise() compile in double.
//   base   (u_kind 0): R Perlin-Worley (Perlin fBm, 4 cells, 4 octaves, dilated by Worley fBm at 4
//          cells: remap(perlin, 0, 1, worley, 1), Schneider & Vos 2015), GBA Worley fBm at 8, 16,
//          32 cells per tile (2x, 4x, 8x).
//   detail (u_kind 1): RGB Worley fBm at 2, 4, 8 cells per tile, A 1.
layout(local_size_x = 4, local_size_y = 4, local_size_z = 4) in;
layout(rgba8, binding = WELKIN_BINDING_LUT_IMAGE) uniform writeonly image3D o_noise;
uniform int u_size;   // texels per edge
uniform uint u_seed;  // clouds.seed
uniform int u_kind;   // 0 base, 1 detail
uniform int u_z0;     // first slice of this dispatch

void main() {
    ivec3 t = ivec3(gl_GlobalInvocationID) + ivec3(0, 0, u_z0);
    if (any(greaterThanEqual(t, ivec3(u_size)))) return;
    vec3 p = (vec3(t) + 0.5) / float(u_size);
    imageStore(o_noise, t, u_kind == 0 ? cloudBaseNoise(p, u_seed) : cloudDetailNoise(p, u_seed));
}
