// AerialPerspective::apply(): composites the aerial perspective over a host's frame from its
// depth buffer (dual-source blending: dst = inscatter + dst * T). Needs engine/camera.glsl,
// engine/composite.glsl, generators/atmosphere.glsl and sky/aerial_perspective.glsl before it.
layout(binding = WELKIN_BINDING_SCENE_DEPTH) uniform sampler2D u_depth;
uniform float u_near, u_far;   // the host's perspective projection, metres
uniform float u_metresPerUnit;

void main() {
    vec2 pixel = welkin_pixel();
    float d = texelFetch(u_depth, ivec2(gl_FragCoord.xy), 0).r;
    if (d >= 1.0) discard;  // nothing drawn: the sky element covers it
    vec3 dir;
    welkin_viewDirection(pixel, dir);
    float zNdc = 2.0 * d - 1.0;
    float zEye = 2.0 * u_near * u_far / ((u_far + u_near) - zNdc * (u_far - u_near));
    vec3 fwd = welkin_cameraToWorld[2].xyz;
    float dist = zEye / max(dot(dir, fwd), 1e-4) * u_metresPerUnit;
    vec3 T;
    vec3 L = welkin_aerialPerspective(dir, dist, T);
    welkin_output(L, T);
}
