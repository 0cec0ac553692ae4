// Transmittance LUT pass (fragment): exp(-optical depth) from (h, mu) to the top of the
// atmosphere (C++: cpu::transmittanceToTop()). Needs atmosphere.glsl before it.
uniform int u_steps;
uniform ivec2 u_size;  // LUT size, texels
out vec4 o_transmittance;

// The march, transmittanceToTop(): atmosphere_march.shared.glsl (sky_model.cpp compiles it in double).
#include "atmosphere_march.shared.glsl"

void main() {
    vec2 size = vec2(u_size);
    vec2 hm = transmittanceHMu(gl_FragCoord.xy / size, size);
    o_transmittance = vec4(transmittanceToTop(hm.x, hm.y, u_steps), 1.0);
}
