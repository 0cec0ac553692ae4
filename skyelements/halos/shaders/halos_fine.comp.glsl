// The Halos element's fine table (Halos::updateFineTable; skyelements/halos/README.md, "The
// default display"): the drawn grid table (the octahedral half sky, N x N) sampled bilinearly at
// the centres of a table u_size x u_size texels (a multiple of N), which the adaptive cells'
// fetching pieces read nearest-texel (halos_grid.frag.glsl with the fine table bound): each pixel
// then gets the bilinear value at the fine texel centre nearest its ray, at most half a fine
// texel away, for one unfiltered read.
layout(local_size_x = 8, local_size_y = 8) in;
layout(binding = WELKIN_BINDING_HALOS_TABLE) uniform sampler2D u_haloTable;
layout(binding = WELKIN_BINDING_HALOS_FINE, rgba16f) writeonly uniform image2D u_fine;
uniform int u_size;

void main() {
    ivec2 p = ivec2(gl_GlobalInvocationID.xy);
    if (p.x >= u_size || p.y >= u_size) return;
    imageStore(u_fine, p, textureLod(u_haloTable, (vec2(p) + 0.5) / float(u_size), 0.0));
}
