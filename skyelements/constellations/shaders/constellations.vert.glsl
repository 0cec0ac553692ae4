// Constellations: one instanced screen-space quad per piece of a figure's great-circle arc (and,
// in equirect, its twin across the seam). Needs engine/camera.glsl before it. Per instance: the
// piece's two ends as J2000 (ICRS) unit directions. See
// skyelements/constellations/include/welkin/elements/constellations.hpp for the model.
layout(location = 0) in vec4 a_p0;
layout(location = 1) in vec4 a_p1;

uniform mat3 u_icrsToEnu;  // ICRS -> observer ENU, this frame
uniform int u_copies;      // 2 in equirect (the seam twin), else 1
uniform float u_widthPx;   // line width, px
uniform int u_clipHorizon; // 1: keep only the part above the apparent horizon (always in a fisheye)
// Refraction (rad) at geometric altitude h = -5 deg + 95 deg * u^2, u = i / (N - 1) (the Stars
// element's table).
uniform float u_refr[CONSTELLATIONS_TABLE_N];

out float v_across;          // px from the centre line
flat out float v_halfWidth;  // px

const float kTableLo = -0.0872664626;  // -5 deg
const float kTableSpan = 1.6580627894; // 95 deg

// Geometric ENU direction -> apparent (refracted) one.
vec3 apparent(vec3 p) {
    vec3 d = u_icrsToEnu * p;
    float h = asin(clamp(d.z, -1.0, 1.0));
    float x = sqrt(clamp((h - kTableLo) / kTableSpan, 0.0, 1.0)) * float(CONSTELLATIONS_TABLE_N - 1);
    int i = min(int(x), CONSTELLATIONS_TABLE_N - 2);
    float hApp = h + mix(u_refr[i], u_refr[i + 1], x - float(i));
    float horiz = length(d.xy);
    vec2 sc = horiz > 0.0 ? d.xy / horiz : vec2(0.0, 1.0);
    return vec3(sc * cos(hApp), sin(hApp));
}

void main() {
    int copy = gl_InstanceID % u_copies;
    vec3 d0 = apparent(a_p0.xyz), d1 = apparent(a_p1.xyz);
    int type = welkin_projectionType();
    gl_Position = WELKIN_CLIP_INVISIBLE;
    v_across = 0.0;
    v_halfWidth = 0.5 * u_widthPx;
    if (type == 1 || u_clipHorizon == 1) {
        // The part above the horizon (a piece is short: the chord's crossing is the arc's).
        if (d0.z < 0.0 && d1.z < 0.0) return;
        if (d0.z < 0.0) d0 = vec3(normalize(mix(d0, d1, d0.z / (d0.z - d1.z)).xy), 0.0);
        if (d1.z < 0.0) d1 = vec3(normalize(mix(d1, d0, d1.z / (d1.z - d0.z)).xy), 0.0);
    }
    vec4 c0 = welkin_clipFromDirection(d0), c1 = welkin_clipFromDirection(d1);
    if (type == 0 || type == 3) {
        // Pinhole: clip space is linear along the piece; keep the part in front of the camera.
        const float eps = 1e-4;
        if (c0.w < eps && c1.w < eps) return;
        if (c0.w < eps) c0 = mix(c0, c1, (eps - c0.w) / (c1.w - c0.w));
        if (c1.w < eps) c1 = mix(c1, c0, (eps - c1.w) / (c0.w - c1.w));
    } else if (type == 2) {
        // Equirect: end 1 on end 0's side of the seam; the twin is the pair shifted by a width.
        if (c1.x - c0.x > 1.0) c1.x -= 2.0;
        else if (c0.x - c1.x > 1.0) c1.x += 2.0;
        if (copy == 1) {
            float shift = c0.x >= 0.0 ? -2.0 : 2.0;
            c0.x += shift;
            c1.x += shift;
        }
    }
    if (c0.w <= 0.0 || c1.w <= 0.0) return;
    // Ends in pixels (x right, y down), then a quad of the line's width plus 1 px of antialiasing,
    // extended by as much past each end so the pieces of a polyline join without gaps.
    vec2 size = welkin_viewport.xy;
    vec2 p0 = vec2(c0.x / c0.w + 1.0, 1.0 - c0.y / c0.w) * 0.5 * size;
    vec2 p1 = vec2(c1.x / c1.w + 1.0, 1.0 - c1.y / c1.w) * 0.5 * size;
    vec2 t = p1 - p0;
    float len = length(t);
    t = len > 1e-6 ? t / len : vec2(1.0, 0.0);
    vec2 n = vec2(-t.y, t.x);
    float ext = 0.5 * u_widthPx + 1.0;
    const vec2 corner[6] = vec2[6](vec2(0, -1), vec2(1, -1), vec2(1, 1), vec2(0, -1), vec2(1, 1), vec2(0, 1));
    vec2 k = corner[gl_VertexID];
    vec2 px = (k.x < 0.5 ? p0 - ext * t : p1 + ext * t) + k.y * ext * n;
    v_across = k.y * ext;
    gl_Position = vec4(px.x / size.x * 2.0 - 1.0, 1.0 - px.y / size.y * 2.0, 1.0, 1.0);
}
