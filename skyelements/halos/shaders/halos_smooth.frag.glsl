// The Halos element's real-time display, the smooth cells: the table (the phase function times
// the layer's scattered fraction in rgb, its transmittance in a) fetched at the cell's vertices
// (halos_grid.vert.glsl with HALOS_VERTEX_FETCH) and interpolated across the cell. Halos::
// classifyCells draws a cell this way only where that differs from the per-pixel fetch
// (halos_grid.frag.glsl) by less than Halos::kSmoothTolerance of the visible table's peak in rgb
// and Halos::kSmoothAlphaTolerance in the transmittance. (Evaluating the layer's factors per pixel
// instead, exp and sqrt, cost llvmpipe as much as the fetch they replace.)
// Needs engine/composite.glsl before it.
uniform vec3 u_E;           // the light's illuminance at the observer, lux per channel
noperspective in vec4 v_c;

void main() {
    welkin_output(u_E * v_c.rgb, v_c.aaa);
}
