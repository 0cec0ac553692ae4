// Text: one instanced quad per glyph (welkin/gl/text.hpp). Needs engine/camera.glsl before it
// (the viewport, welkin_clipOffset). Per instance: the anchor's clip position (or, with w = 0, a
// world direction to project with welkin_clipFromDirection), the glyph's box in
// pixels from the anchor (x0, y0, x1, y1; x right, y down), its atlas box (u0, v0, u1, v1) and
// its radiance (cd/m^2 per channel at full coverage).
layout(location = 0) in vec4 a_anchor;
layout(location = 1) in vec4 a_box;
layout(location = 2) in vec4 a_uv;
layout(location = 3) in vec4 a_radiance;

out vec2 v_uv;
flat out vec3 v_radiance;

void main() {
    const vec2 corner[6] = vec2[6](vec2(0, 0), vec2(1, 0), vec2(1, 1), vec2(0, 0), vec2(1, 1), vec2(0, 1));
    // w = 0: the anchor is a world direction (TextBatch::addAt()), projected here.
    vec4 anchor = a_anchor.w == 0.0 ? welkin_clipFromDirection(a_anchor.xyz) : a_anchor;
    if (anchor.w <= 0.0) {
        gl_Position = WELKIN_CLIP_INVISIBLE;
        return;
    }
    vec2 c = corner[gl_VertexID];
    // The anchor snapped to a whole pixel, so glyphs drawn at the atlas' size map texel to pixel.
    vec2 anchorPx = vec2(anchor.x / anchor.w + 1.0, 1.0 - anchor.y / anchor.w) * 0.5 * welkin_viewport.xy;
    vec2 snap = floor(anchorPx + 0.5) - anchorPx;
    v_uv = mix(a_uv.xy, a_uv.zw, c);
    v_radiance = a_radiance.rgb;
    gl_Position = welkin_clipOffset(anchor, mix(a_box.xy, a_box.zw, c) + snap);
}
