// SkyLighting: projection of the captured radiance cube (level 0) onto the nine real SH of
// l <= 2, each texel weighted by its exact solid angle. One work group per face; each writes
// its 27 partial sums (9 coefficients x RGB, cd/m^2 x sr ... i.e. L_lm's share) to the storage
// buffer at face * 27; the CPU adds the six faces in double precision.
layout(local_size_x = 64) in;
layout(binding = WELKIN_BINDING_LIGHTING_SOURCE_IMAGE, rgba32f) uniform readonly imageCube u_cube;
layout(std430, binding = WELKIN_BINDING_LIGHTING_SSBO) buffer LightingSums { float lighting_sums[]; };
uniform int u_size;

shared float s_sum[64 * 27];

void main() {
    int face = int(gl_WorkGroupID.x), tid = int(gl_LocalInvocationID.x);
    float acc[27];
    for (int k = 0; k < 27; ++k) acc[k] = 0.0;
    for (int idx = tid; idx < u_size * u_size; idx += 64) {
        ivec2 ij = ivec2(idx % u_size, idx / u_size);
        vec3 d = lighting_texelDirection(face, ij, u_size);
        vec3 L = imageLoad(u_cube, ivec3(ij, face)).rgb * lighting_texelSolidAngle(ij, u_size);
        float y[9];
        y[0] = 0.282094792;
        y[1] = 0.488602512 * d.y;
        y[2] = 0.488602512 * d.z;
        y[3] = 0.488602512 * d.x;
        y[4] = 1.092548431 * d.x * d.y;
        y[5] = 1.092548431 * d.y * d.z;
        y[6] = 0.315391565 * (3.0 * d.z * d.z - 1.0);
        y[7] = 1.092548431 * d.x * d.z;
        y[8] = 0.546274215 * (d.x * d.x - d.y * d.y);
        for (int k = 0; k < 9; ++k) {
            acc[3 * k] += L.r * y[k];
            acc[3 * k + 1] += L.g * y[k];
            acc[3 * k + 2] += L.b * y[k];
        }
    }
    for (int k = 0; k < 27; ++k) s_sum[tid * 27 + k] = acc[k];
    barrier();
    for (int stride = 32; stride > 0; stride >>= 1) {
        if (tid < stride)
            for (int k = 0; k < 27; ++k) s_sum[tid * 27 + k] += s_sum[(tid + stride) * 27 + k];
        barrier();
    }
    if (tid < 27) lighting_sums[face * 27 + tid] = s_sum[tid];
}
