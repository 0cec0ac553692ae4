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

#include "weather_shape.shared.glsl"

void main() {
    WeatherShape sh = u_shapes[v_shape];
    // The shape's fade over its noisy edge: weather_shape.shared.glsl (cpu::shapeTexel() compiles it).
    float fade = cld_weatherFade(v_local, sh.more.yz, sh.ids.x);
    if (fade < 1e-3) discard;
    // The cloud thins towards its rim: (1 - base) and top are weighted by the fade, so
    // they fall to 0 with the fade and the max blend of overlapping shapes stays continuous (a
    // shape's rim never overrides its neighbour's heights); the resolve pass turns top < base
    // (the rim of a lone shape: zero thickness, domes) into base = top.
    o_weather = vec4(sh.val.y * fade, sh.val.z * fade, sh.val.w * fade, sh.more.x * fade);
}
