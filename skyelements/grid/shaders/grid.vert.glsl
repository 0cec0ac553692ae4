// Grid element: one instanced quad per run of marked tiles (grid.cpp marks the tiles that the
// lines, their antialiasing and the markers can reach), so grid.frag.glsl runs only near the
// lines. Per instance: the run's rectangle in pixels (x0, y0, x1, y1; origin top-left, y down).
layout(location = 0) in vec4 a_rect;
uniform vec2 u_sizePx;  // camera width, height (pixels)
void main() {
    const vec2 corner[6] = vec2[6](vec2(0, 0), vec2(1, 0), vec2(1, 1), vec2(0, 0), vec2(1, 1), vec2(0, 1));
    vec2 px = mix(a_rect.xy, a_rect.zw, corner[gl_VertexID]);
    // z = w (the far plane), like the fullscreen triangle: behind a host's geometry.
    gl_Position = vec4(px.x / u_sizePx.x * 2.0 - 1.0, 1.0 - px.y / u_sizePx.y * 2.0, 1.0, 1.0);
}
