// Weather-map shapes (vertex; after cloud_noise.glsl): instance k draws shape k / 9 at tile offset
// (k % 9 % 3 - 1, k % 9 / 3 - 1) x extent, as a quad of +-1.6 semi-axes around its centre (the
// noisy edge stays within 1 / (1 - 0.35) = 1.54 semi-axes). Twin: cpu::weatherTexel().
struct WeatherShape {
    vec4 geo;   // centre (m, map coordinates, wrapped), semi-axes (m)
    vec4 val;   // rotation (rad), density, 1 - base fraction, top fraction
    vec4 more;  // rain, edge-noise offset (2), unused
    uvec4 ids;  // seed, unused
};
layout(std430, binding = WELKIN_BINDING_WEATHER_SHAPES_SSBO) readonly buffer WeatherShapes { WeatherShape u_shapes[]; };
uniform float u_extent;  // m
out vec2 v_local;        // position in the shape's frame, semi-axis units
flat out int v_shape;

void main() {
    int s = gl_InstanceID / 9, o = gl_InstanceID % 9;
    vec2 offset = vec2(float(o % 3 - 1), float(o / 3 - 1)) * u_extent;
    const vec2 corners[6] = vec2[6](vec2(-1, -1), vec2(1, -1), vec2(1, 1), vec2(-1, -1), vec2(1, 1), vec2(-1, 1));
    vec2 local = corners[gl_VertexID] * 1.6;
    WeatherShape sh = u_shapes[s];
    float c = cos(sh.val.x), sn = sin(sh.val.x);
    vec2 d = local * sh.geo.zw;
    vec2 m = sh.geo.xy + offset + vec2(c * d.x - sn * d.y, sn * d.x + c * d.y);
    v_local = local;
    v_shape = s;
    gl_Position = vec4(m / u_extent * 2.0 - 1.0, 0.0, 1.0);
}
