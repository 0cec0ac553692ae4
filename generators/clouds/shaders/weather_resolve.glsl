// Weather-map resolve (compute): G = 1 - G (the max-blended 1 - base back to the base fraction);
// where top < base (a shape's thinning rim) both become their mean; G = B = 0 where no cloud was
// drawn (R = 0). Twin: the end of cpu::weatherTexel().
layout(local_size_x = 8, local_size_y = 8) in;
layout(rgba16f, binding = WELKIN_BINDING_LUT_IMAGE) uniform image2D o_weather;
uniform int u_size;
void main() {
    ivec2 t = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(t, ivec2(u_size)))) return;
    vec4 w = imageLoad(o_weather, t);
    float base = 1.0 - w.g, top = w.b;
    if (top < base) base = top = 0.5 * (base + top);  // a rim: zero thickness (B >= G kept)
    imageStore(o_weather, t, w.r > 0.0 ? vec4(w.r, base, top, w.a) : vec4(0.0));
}
