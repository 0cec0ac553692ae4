// Weather-map shapes (fragment; after cloud_noise.glsl and the vertex stage's block): the
// shape's core density fading over its noise-perturbed edge, max-blended (GL_MAX) into the map;
// G carries 1 - base fraction so that the max keeps the lowest base (weather_resolve.glsl flips
// it back). Twin: cpu::shapeTexel().
struct WeatherShape {
    vec4 geo;
    vec4 val;
    vec4 more;
    uvec4 ids;
};
layout(std430, binding = WELKIN_BINDING_WEATHER_SHAPES_SSBO) readonly buffer WeatherShapes { WeatherShape u_shapes[]; };
in vec2 v_local;
flat in int v_shape;
out vec4 o_weather;

void main() {
    WeatherShape sh = u_shapes[v_shape];
    float r = length(v_local);
    // Edge noise: 2-D Perlin fBm (4 cells over 4 semi-axes, 3 octaves) at the shape's own offset;
    // the radius is stretched by +-35 %, the fade runs from rr = 0.5 to 1 (a soft core).
    float n = cn_perlinFbm2(v_local * 0.25 + sh.more.yz, 4, 3, sh.ids.x);
    float rr = r * (1.0 + 0.7 * (n - 0.5));
    float fade = 1.0 - smoothstep(0.5, 1.0, rr);
    if (fade < 1e-3) discard;
    // The cloud thins towards its rim: (1 - base) and top are weighted by the fade, so
    // they fall to 0 with the fade and the max blend of overlapping shapes stays continuous (a
    // shape's rim never overrides its neighbour's heights); the resolve pass turns top < base
    // (the rim of a lone shape: zero thickness, domes) into base = top.
    o_weather = vec4(sh.val.y * fade, sh.val.z * fade, sh.val.w * fade, sh.more.x * fade);
}
