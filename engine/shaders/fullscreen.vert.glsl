// Fullscreen triangle: draw 3 vertices with no attributes. v_ndc is the clip-space position.
out vec2 v_ndc;
void main() {
    vec2 p = vec2(float((gl_VertexID << 1) & 2), float(gl_VertexID & 2)) * 2.0 - 1.0;
    v_ndc = p;
    // z = 1 (the far plane): with depth testing against a host depth buffer (GL_LEQUAL) the sky
    // is drawn only where the host drew nothing.
    gl_Position = vec4(p, 1.0, 1.0);
}
