// The Halos element's real-time display: the octahedral table at the interpolated ray
// (halos_grid.vert.glsl). Its texel (s, t) = (x + z, x - z) / (|x| + |y| + |z|) holds the mixed
// phase function (1/sr, at the light's elevation) times the layer's scattered fraction 1 -
// exp(-tau slant) in rgb and the layer's transmittance exp(-tau slant) in a (Halos::updateOctTable:
// the pattern is symmetric about the light's vertical plane, so |y| folds the sky onto the half
// the table holds). Needs engine/composite.glsl before it.
layout(binding = WELKIN_BINDING_HALOS_TABLE) uniform sampler2D u_haloTable;
uniform vec3 u_E;           // the light's illuminance at the observer, lux per channel
noperspective in vec3 v_r;
#ifdef HALOS_FINE
uniform int u_fineSize;     // the fine table's texels per side
#endif

void main() {
    vec3 a = abs(v_r);
    vec2 st = vec2(v_r.x + v_r.z, v_r.x - v_r.z) / (a.x + a.y + a.z);
#ifdef HALOS_FINE
    // The fine table (Halos::updateFineTable), its texel read without the sampler's filtering
    // (the nearest one: the texel whose square holds the point).
    vec4 t = texelFetch(u_haloTable, clamp(ivec2((st * 0.5 + 0.5) * float(u_fineSize)), ivec2(0), ivec2(u_fineSize - 1)), 0);
#else
    vec4 t = textureLod(u_haloTable, st * 0.5 + 0.5, 0.0);
#endif
    welkin_output(u_E * t.rgb, t.aaa);
}
