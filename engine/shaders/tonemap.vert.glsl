// The tone map's vertex stage: the fullscreen triangle of fullscreen.vert.glsl, and, with the
// automatic exposure, the exposure read from the eye's state (adapt.frag.glsl's texel) once per
// vertex and handed to every pixel as a flat varying: a per-pixel texelFetch of that one texel
// cost llvmpipe ~0.9 of a trivial fullscreen pass (a gather per pixel; docs/eye.md).
#ifdef WELKIN_TONEMAP_AUTO
layout(binding = WELKIN_BINDING_EYE_STATE_TEXTURE) uniform sampler2D u_state;  // (cone, rod, exposure, 1)
flat out float v_exposure;
#endif
out vec2 v_ndc;
void main() {
    vec2 p = vec2(float((gl_VertexID << 1) & 2), float(gl_VertexID & 2)) * 2.0 - 1.0;
    v_ndc = p;
#ifdef WELKIN_TONEMAP_AUTO
    v_exposure = texelFetch(u_state, ivec2(0), 0).z;
#endif
    gl_Position = vec4(p, 1.0, 1.0);
}
