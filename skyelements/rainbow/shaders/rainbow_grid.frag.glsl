// The Rainbow's display: the cache coordinate of the pixel's ray, exactly, and one fetch
// (rainbow_grid.vert.glsl, rainbow_polar.glsl). u_scale follows the light's illuminance between
// refills (the ratio of its luminance now to its luminance when the cache was filled).
// Needs engine/composite.glsl and rainbow_polar.glsl before it.
layout(binding = WELKIN_BINDING_RAINBOW_CACHE) uniform sampler2D u_rainbowCache;
uniform float u_scale;
uniform vec2 u_sinEl;           // sines of the curtain's lowest and highest elevations
noperspective in vec4 v_ray;    // (A.r, E1.r, E2.r, r.z) of the unnormalised ray r

void main() {
    float inv = inversesqrt(dot(v_ray.xyz, v_ray.xyz));  // 1 / |r|: (A, E1, E2) is orthonormal
    float sinEl = v_ray.w * inv;
    if (sinEl < u_sinEl.x || sinEl > u_sinEl.y) discard;
    // x = sin(angle from the anti-light point / 2) = sqrt((1 - cos) / 2); y the pseudo-angle.
    float x = sqrt(max(0.5 - 0.5 * v_ray.x * inv, 0.0));
    vec4 c = texture(u_rainbowCache, vec2(x, rainbow_yFromComponents(v_ray.y, v_ray.z)));
    welkin_output(c.rgb * u_scale, vec3(c.a));
}
