// SkyLighting: SevenSky's 16x16 sky light map and its six axis lights. Texel (i, j) covers
// azimuth [i, i+1) x 2pi/16 (from north through east) and altitude [j, j+1) x pi/16 - pi/2 (row
// 0 the nadir's); its value is the mean radiance over its solid angle (8 x 8 sub-directions,
// each weighted by cos(altitude), read from the radiance cube at level u_lod). Then the axis
// lights, D_axis = sum over the texels on that side of L |d . axis| Omega (d the texel's centre),
// lux, written to the storage buffer at u_offset (+E, -E, +N, -N, +U, -U, RGB each).
layout(local_size_x = 16, local_size_y = 16) in;
layout(binding = WELKIN_BINDING_LIGHTING_CUBE) uniform samplerCube u_cube;
layout(binding = WELKIN_BINDING_LIGHTING_OUTPUT_IMAGE, rgba32f) uniform writeonly image2D u_map;
layout(std430, binding = WELKIN_BINDING_LIGHTING_SSBO) buffer LightingSums { float lighting_sums[]; };
uniform float u_lod;
uniform int u_offset;

shared vec3 s_weighted[256];  // L Omega
shared vec3 s_dir[256];       // the texel's centre direction

vec3 lighting_azAlt(float az, float alt) { return vec3(cos(alt) * sin(az), cos(alt) * cos(az), sin(alt)); }

void main() {
    ivec2 ij = ivec2(gl_LocalInvocationID.xy);
    const float dAz = 2.0 * LIGHTING_PI / 16.0, dAlt = LIGHTING_PI / 16.0;
    float az0 = float(ij.x) * dAz, alt0 = float(ij.y) * dAlt - 0.5 * LIGHTING_PI;
    vec3 sum = vec3(0.0);
    float wsum = 0.0;
    for (int b = 0; b < 8; ++b)
        for (int a = 0; a < 8; ++a) {
            float az = az0 + (float(a) + 0.5) / 8.0 * dAz, alt = alt0 + (float(b) + 0.5) / 8.0 * dAlt;
            float w = cos(alt);
            sum += w * textureLod(u_cube, lighting_enuToCube(lighting_azAlt(az, alt)), u_lod).rgb;
            wsum += w;
        }
    vec3 L = sum / wsum;
    imageStore(u_map, ij, vec4(L, 1.0));
    float omega = dAz * (sin(alt0 + dAlt) - sin(alt0));
    int t = ij.y * 16 + ij.x;
    s_weighted[t] = L * omega;
    s_dir[t] = lighting_azAlt(az0 + 0.5 * dAz, alt0 + 0.5 * dAlt);
    barrier();
    if (t < 6) {
        int axis = t / 2;
        float sgn = (t % 2 == 0) ? 1.0 : -1.0;
        vec3 D = vec3(0.0);
        for (int k = 0; k < 256; ++k) D += s_weighted[k] * max(sgn * s_dir[k][axis], 0.0);
        lighting_sums[u_offset + 3 * t] = D.r;
        lighting_sums[u_offset + 3 * t + 1] = D.g;
        lighting_sums[u_offset + 3 * t + 2] = D.b;
    }
}
