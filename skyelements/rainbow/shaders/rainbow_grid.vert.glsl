// The Rainbow's display (perspective projection): a grid of u_cellPx-pixel cells over the screen,
// two triangles a cell, 6 vertices a cell, no attributes (vertex id = 6 cell + corner). The cells
// only bound the work: each vertex passes the unnormalised ray r = dir / (dir . forward), which is
// affine in the pixel, as its components on the anti-light frame (A.r, E1.r, E2.r) and its height
// r.z, interpolated without perspective (noperspective: affine in the pixel, so exact); the
// fragment shader (rainbow_grid.frag.glsl) gets the cache coordinate and the elevation from them.
// The curtain's edges clip the cells: its sector's vertical planes exactly (their clip distances
// are linear in r), its cones of constant elevation widened by 0.5 deg (their clip distances are
// not linear in r: within a 64-pixel cell the interpolation errs by < 0.2 deg), the fragment
// shader then cutting those exactly. Fragments far outside the curtain are never shaded.
// Needs engine/camera.glsl and rainbow_polar.glsl before it.
uniform ivec2 u_grid;           // cells across, down
uniform float u_cellPx;         // cell size, pixels
uniform vec2 u_axis;            // horizontal unit vector to the curtain's middle
uniform float u_cosHalfWidth;   // cos of the curtain's azimuthal half-width
uniform vec2 u_elLoClip, u_elHiClip;  // (cos, sin) of the widened lowest and highest elevations
noperspective out vec4 v_ray;   // (A.r, E1.r, E2.r, r.z)

void main() {
    const ivec2 corners[6] = ivec2[6](ivec2(0, 0), ivec2(1, 0), ivec2(1, 1), ivec2(0, 0), ivec2(1, 1), ivec2(0, 1));
    int cell = gl_VertexID / 6;
    ivec2 c = ivec2(cell % u_grid.x, cell / u_grid.x);
    vec2 size = welkin_viewport.xy;
    vec2 px = min(vec2(c + corners[gl_VertexID % 6]) * u_cellPx, size);
    vec3 d;
    welkin_viewDirection(px, d);
    vec3 r = d / dot(d, mat3(welkin_cameraToWorld)[2]);  // > 0: a perspective image is in front
    v_ray = vec4(dot(r, u_polarA), dot(r, u_polarE1), dot(r, u_polarE2), r.z);
    gl_Position = vec4(2.0 * px.x / size.x - 1.0, 1.0 - 2.0 * px.y / size.y, 0.0, 1.0);
    float h = length(r.xy);
    gl_ClipDistance[0] = r.z * u_elLoClip.x - h * u_elLoClip.y;   // elevation >= lowest - 0.5 deg
    gl_ClipDistance[1] = h * u_elHiClip.y - r.z * u_elHiClip.x;   // elevation <= highest + 0.5 deg
    gl_ClipDistance[2] = dot(r.xy, u_axis) - u_cosHalfWidth * h;  // within the sector
}
