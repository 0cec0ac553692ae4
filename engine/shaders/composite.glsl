// Compositing outputs of an element (dual-source blending): the processor blends
//   dst.rgb = radiance.rgb + dst.rgb * transmittance.rgb
// `welkin_radiance` is emitted or in-scattered radiance in cd/m^2 (linear sRGB primaries, Y =
// luminance); `welkin_transmittance` is the per-channel fraction of the light from behind that
// passes (1 = fully transparent, 0 = opaque).
layout(location = 0, index = 0) out vec4 welkin_radiance;
layout(location = 0, index = 1) out vec4 welkin_transmittance;

void welkin_output(vec3 radiance, vec3 transmittance) {
    welkin_radiance = vec4(max(radiance, vec3(0.0)), 1.0);
    welkin_transmittance = vec4(clamp(transmittance, vec3(0.0), vec3(1.0)), 1.0);
}
