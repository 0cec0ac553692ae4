// The Halos element's real-time display, the smooth leaves: the octahedral table (the phase
// function times the layer's scattered fraction in rgb, its transmittance in a) fetched at the
// leaf's corners (halos_grid.vert.glsl with HALOS_SMOOTH) and interpolated across it, no fetch
// per pixel. halos_cells.comp.glsl draws a leaf this way only where that stays within its
// tolerance of the per-pixel fetch (halos_grid.frag.glsl). Needs engine/composite.glsl before it.
uniform vec3 u_E;            // the light's illuminance at the observer, lux per channel
noperspective in vec4 v_c;

void main() {
    welkin_output(u_E * v_c.rgb, v_c.aaa);
}
