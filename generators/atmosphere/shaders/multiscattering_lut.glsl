// Multiple-scattering LUT pass (compute, 8x8 invocations per group: llvmpipe spreads groups over
// its threads, where a fragment pass this small is one 64x64 tile, one thread), Hillaire 2020: for a point at height h with the light
// at cos zenith muS, the second-order radiance L2 and the transfer f_ms gathered over the sphere
// with an isotropic phase, Psi_ms = L2 / (1 - f_ms), per lux of the light. The march:
// atmosphere_march.shared.glsl (C++: cpu::multiScatteringTexel()). Needs atmosphere.glsl (ATM_USE_TRANSMITTANCE) before it.
uniform int u_directions;
uniform int u_steps;
uniform ivec2 u_size;  // texels: mu_s, height
layout(local_size_x = 8, local_size_y = 8, local_size_z = 1) in;
layout(MS_IMAGE_FORMAT, binding = WELKIN_BINDING_LUT_IMAGE) uniform writeonly image2D u_psi;

// The texel's march: atmosphere_march.shared.glsl (sky_model.cpp compiles it in double).
#include "atmosphere_march.shared.glsl"

void main() {
    ivec2 ij = ivec2(gl_GlobalInvocationID.xy);
    if (ij.x >= u_size.x || ij.y >= u_size.y) return;
    vec2 hm = multiScatteringHMuS((vec2(ij) + 0.5) / vec2(u_size), vec2(u_size));
    imageStore(u_psi, ij, vec4(atm_multiScatteringTexel(hm.x, hm.y, u_directions, u_steps, atm_solarIlluminance.w), 1.0));
}
