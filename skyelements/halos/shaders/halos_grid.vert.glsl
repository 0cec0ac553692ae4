// The Halos element's real-time display (perspective projection): a grid of u_cellPx-pixel
// cells, two triangles a cell, no attributes (vertex id = 6 cell + corner). Each vertex computes
// what the per-pixel pass computes per pixel (halos.frag.glsl: the table coordinates, the layer's
// scattered fraction and transmittance) for the user's crystal layer (no cirrus: its density
// varies per pixel); the fragment shader (halos_grid.frag.glsl) interpolates them and makes one
// fetch. The azimuth from the light is passed twice, signed from the light's side and from the
// opposite side, so that neither fold (|phi| = 0 or pi) is interpolated across.
// Needs engine/camera.glsl before it.
uniform ivec2 u_grid;      // cells across, down
uniform float u_cellPx;    // cell size, pixels
uniform vec3 u_lightX;     // unit horizontal vector towards the light's azimuth
uniform vec3 u_lightY;     // up x u_lightX
uniform float u_tauUser;   // vertical optical depth of the crystal layer
uniform float u_h, u_R, u_layerH;  // observer height, planet radius, layer height, m
noperspective out vec4 v_coord;    // phi (signed, from the light), phi' (from the anti-light), elevation, dir.z - horizon
noperspective out vec2 v_layer;    // 1 - exp(-tau slant), exp(-tau slant)

void main() {
    const ivec2 corners[6] = ivec2[6](ivec2(0, 0), ivec2(1, 0), ivec2(1, 1), ivec2(0, 0), ivec2(1, 1), ivec2(0, 1));
    int cell = gl_VertexID / 6;
    ivec2 c = ivec2(cell % u_grid.x, cell / u_grid.x);
    vec2 size = welkin_viewport.xy;
    vec2 px = min(vec2(c + corners[gl_VertexID % 6]) * u_cellPx, size);
    vec3 dir;
    welkin_viewDirection(px, dir);
    float x = dot(dir, u_lightX), y = dot(dir, u_lightY);
    float el = asin(clamp(dir.z, -1.0, 1.0));
    // The horizon: below it the ground hides the layer (an observer under the layer).
    float r = u_R + u_h;
    float muHorizon = -sqrt(max(1.0 - u_R * u_R / (r * r), 0.0));
    v_coord = vec4(atan(y, x), atan(y, -x), el, dir.z - muHorizon);
    // The slant through the layer at its crossing (as halos.frag.glsl).
    float rc = u_R + u_layerH, mu = dir.z;
    float disc0 = r * r * mu * mu - (r - rc) * (r + rc);
    float disc = max(disc0, 0.0);
    float d = r < rc ? -r * mu + sqrt(disc) : -r * mu - sqrt(disc);
    vec3 p = vec3(0.0, 0.0, u_h) + dir * max(d, 0.0);
    vec3 up = normalize(p + vec3(0.0, 0.0, u_R));
    float tau = u_tauUser / max(abs(dot(up, dir)), 0.1);
    v_layer = disc0 < 0.0 || d <= 0.0 ? vec2(0.0, 1.0) : vec2(1.0 - exp(-tau), exp(-tau));  // misses the layer
    gl_Position = vec4(2.0 * px.x / size.x - 1.0, 1.0 - 2.0 * px.y / size.y, 0.0, 1.0);
}
