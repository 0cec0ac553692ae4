// Curl noise pass (compute, after cloud_noise.glsl): the cirrus' 2-D tileable map (SevenSky's
// HIGH_ALTITUDE_CLOUD_MAP). Potential psi = 2-D Perlin fBm (4 cells, 5 octaves); RG = its curl
// (d psi/dy, -d psi/dx) by central differences over one texel, divided by 8 (|v| <= ~0.6 with the
// default seed: none clamped, tested), clamped, encoded 0.5 + 0.5 v; B = psi in [0, 1]; A = 1. Bridson et al. 2007.
// The texel is cloudCurlNoise() of cloud_noise.shared.glsl, which cpu::curlNoise() compiles in double.
layout(local_size_x = 8, local_size_y = 8) in;
layout(rgba8, binding = WELKIN_BINDING_LUT_IMAGE) uniform writeonly image2D o_curl;
uniform int u_size;
uniform uint u_seed;

void main() {
    ivec2 t = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(t, ivec2(u_size)))) return;
    vec2 p = (vec2(t) + 0.5) / float(u_size);
    imageStore(o_curl, t, cloudCurlNoise(p, 1.0 / float(u_size), u_seed));
}
