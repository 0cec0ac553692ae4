// Weather-map resolve (compute): G = 1 - G (the max-blended 1 - base back to the base fraction);
// where top < base (a shape's thinning rim) both become their mean; G = B = 0 where no cloud was
// drawn (R = 0): cld_weatherResolve() of weather_shape.shared.glsl (the end of cpu::weatherTexel()
// compiles it in double).
layout(local_size_x = 8, local_size_y = 8) in;
layout(rgba16f, binding = WELKIN_BINDING_LUT_IMAGE) uniform image2D o_weather;
uniform int u_size;
// After cloud_noise.glsl (the shared file's cld_weatherFade() calls cn_perlinFbm2()).
#include "weather_shape.shared.glsl"
void main() {
    ivec2 t = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(t, ivec2(u_size)))) return;
    imageStore(o_weather, t, cld_weatherResolve(imageLoad(o_weather, t)));
}
