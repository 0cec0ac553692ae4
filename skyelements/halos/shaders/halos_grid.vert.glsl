// The Halos element's real-time display (perspective projection): a grid of u_cellPx-pixel
// cells, two triangles a cell, no attributes (vertex id = 6 cell + corner). The cells only bound
// the work: each vertex passes the unnormalised view ray r = dir / (dir . forward), which is
// affine in the pixel, as its components in the table's frame (x towards the light's azimuth, y
// across it, z up; while a refill of the table is under way, turned about y by the table's lag in
// elevation so that its light lands on the current one: Halos::doRender), interpolated without
// perspective: exact at every pixel. The fragment shader
// (halos_grid.frag.glsl) maps it to the octahedral table. Under the crystal layer the ground
// hides it below the horizon, mu < u_muHorizon: a clip distance, r.z - muH |r| (not affine in
// the pixel, but muH is small, |muH| < 0.06 below 10 km: the interpolated |r| errs by < 0.2 %
// over a cell, the cut by < 1e-4 rad).
// Needs engine/camera.glsl before it.
uniform ivec2 u_grid;       // cells across, down
uniform float u_cellPx;     // cell size, pixels
uniform vec3 u_lightX;      // unit vector towards the light's azimuth (horizontal, or turned by the table's lag)
uniform vec3 u_lightY;      // up x u_lightX
uniform vec3 u_lightZ;      // u_lightX x u_lightY: up, when the table holds the current light's elevation
uniform float u_muHorizon;  // sine of the horizon's elevation (under the layer; -2 above it: no cut)
noperspective out vec3 v_r; // (x, y, z) of the unnormalised view ray in the light's frame

void main() {
    const ivec2 corners[6] = ivec2[6](ivec2(0, 0), ivec2(1, 0), ivec2(1, 1), ivec2(0, 0), ivec2(1, 1), ivec2(0, 1));
    int cell = gl_VertexID / 6;
    ivec2 c = ivec2(cell % u_grid.x, cell / u_grid.x);
    vec2 size = welkin_viewport.xy;
    vec2 px = min(vec2(c + corners[gl_VertexID % 6]) * u_cellPx, size);
    vec3 d;
    welkin_viewDirection(px, d);
    vec3 r = d / dot(d, mat3(welkin_cameraToWorld)[2]);  // > 0: a perspective image is in front
    v_r = vec3(dot(r, u_lightX), dot(r, u_lightY), dot(r, u_lightZ));
    gl_ClipDistance[0] = r.z - u_muHorizon * length(r);
    gl_Position = vec4(2.0 * px.x / size.x - 1.0, 1.0 - 2.0 * px.y / size.y, 0.0, 1.0);
}
