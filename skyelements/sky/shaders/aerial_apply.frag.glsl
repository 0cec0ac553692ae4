// AerialPerspective::apply(): composites the aerial perspective over a host's frame from its
// depth buffer (dual-source blending: dst = inscatter + dst * T). Needs engine/camera.glsl,
// engine/composite.glsl, generators/atmosphere.glsl and sky/aerial_perspective.glsl before it.
// The host's depth is read by welkin_sceneDistance() (camera.glsl): the host's projection and
// depth convention are in the camera block.
layout(binding = WELKIN_BINDING_SCENE_DEPTH) uniform sampler2D u_depth;

void main() {
    vec2 pixel = welkin_pixel();
    float d = texelFetch(u_depth, ivec2(gl_FragCoord.xy), 0).r;
    if (welkin_depthIsFar(d)) discard;  // nothing drawn: the sky element covers it
    vec3 dir;
    welkin_viewDirection(pixel, dir);
    float dist = welkin_sceneDistance(d, dir);
    vec3 T;
    vec3 L = welkin_aerialPerspective(dir, dist, T);
    welkin_output(L, T);
}
