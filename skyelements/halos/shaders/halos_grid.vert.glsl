// The Halos element's real-time display (perspective projection): a grid of u_cellPx-pixel
// cells, no attributes. Each vertex passes the unnormalised view ray r = dir / (dir . forward),
// which is affine in the pixel, as its components in the table's frame (x towards the light's
// azimuth, y across it, z up; while a refill of the table is under way, turned about y by the
// table's lag in elevation so that its light lands on the current one: Halos::doRender),
// interpolated without perspective: exact at every pixel. Under the crystal layer the ground
// hides it below the horizon, mu < u_muHorizon: a clip distance, r.z - muH |r| (not affine in
// the pixel, but muH is small, |muH| < 0.06 below 10 km: the interpolated |r| errs by < 0.2 %
// over a cell, the cut by < 1e-4 rad).
//
// The pieces drawn (u_list 1): those that halos_cells.comp.glsl listed for this draw, each a
// whole cell (slot 0) or a quarter of one (slots 1-4), two triangles a piece (vertex id = 6 entry
// + corner; an entry is 5 cell + slot). Built twice: without HALOS_SMOOTH for the leaves that fetch
// the table per pixel (halos_grid.frag.glsl: the vertex passes the ray), with it for the smooth
// ones, where the vertex fetches the table and the pixels interpolate its value
// (halos_smooth.frag.glsl). u_list 0: every cell whole, in order (the grid before the adaptive
// cells: tests and benchmarks).
// Needs engine/camera.glsl before it.
uniform ivec2 u_grid;       // cells across, down
uniform float u_cellPx;     // cell size, pixels
uniform vec3 u_lightX;      // unit vector towards the light's azimuth (horizontal, or turned by the table's lag)
uniform vec3 u_lightY;      // up x u_lightX
uniform vec3 u_lightZ;      // u_lightX x u_lightY: up, when the table holds the current light's elevation
uniform float u_muHorizon;  // sine of the horizon's elevation (under the layer; -2 above it: no cut)
uniform int u_list;         // 1: the leaves of the list at u_listOffset; 0: every cell whole
uniform uint u_listOffset;  // the list's first entry in u_leaves
layout(std430, binding = WELKIN_BINDING_HALOS_CELLS) readonly buffer HalosCells {
    uint u_draws[8];        // the two lists' indirect draw commands (halos_cells.comp.glsl)
    uint u_leaves[];        // 5 cell + slot
};
#ifdef HALOS_SMOOTH
layout(binding = WELKIN_BINDING_HALOS_TABLE) uniform sampler2D u_haloTable;
noperspective out vec4 v_c;  // the table at this vertex's ray (what halos_grid.frag.glsl fetches there)
#else
noperspective out vec3 v_r;  // (x, y, z) of the unnormalised view ray in the light's frame
#endif

void main() {
    const vec2 corners[6] = vec2[6](vec2(0, 0), vec2(1, 0), vec2(1, 1), vec2(0, 0), vec2(1, 1), vec2(0, 1));
    uint entry = u_list != 0 ? u_leaves[u_listOffset + uint(gl_VertexID) / 6u] : 5u * (uint(gl_VertexID) / 6u);
    uint cell = entry / 5u, slot = entry % 5u;
    ivec2 c = ivec2(int(cell) % u_grid.x, int(cell) / u_grid.x);
    float side = u_cellPx;
    vec2 offset = vec2(0.0);
    if (slot >= 1u) {
        side = 0.5 * u_cellPx;
        offset = vec2(float((slot - 1u) & 1u), float((slot - 1u) >> 1u)) * side;
    }
    vec2 size = welkin_viewport.xy;
    vec2 px = min(vec2(c) * u_cellPx + offset + corners[gl_VertexID % 6] * side, size);
    vec3 d;
    welkin_viewDirection(px, d);
    vec3 r = d / dot(d, mat3(welkin_cameraToWorld)[2]);  // > 0: a perspective image is in front
    vec3 q = vec3(dot(r, u_lightX), dot(r, u_lightY), dot(r, u_lightZ));
#ifdef HALOS_SMOOTH
    vec3 a = abs(q);
    v_c = textureLod(u_haloTable, vec2(q.x + q.z, q.x - q.z) / (a.x + a.y + a.z) * 0.5 + 0.5, 0.0);
#else
    v_r = q;
#endif
    gl_ClipDistance[0] = r.z - u_muHorizon * length(r);
    gl_Position = vec4(2.0 * px.x / size.x - 1.0, 1.0 - 2.0 * px.y / size.y, 0.0, 1.0);
}
