// View-transmittance row (compute, 64 invocations per group): the transmittance from the observer
// (height u_h) to the top of the atmosphere along each latitude of the sky-view parameterisation,
// texel i at v = (i + 0.5) / N; 0 on the ground half (v < 1/2: the ray ends on the ground). The
// Sky's pixel shader reads it with the same v as its sky-view fetch, from a 1-D texture: half
// the cost of a 2-D transmittance-LUT fetch on llvmpipe, and no (h, mu) -> uv arithmetic.
// N >= the sky view's height, so a pixel's v (between the sky view's first and last row
// centres of its half) never blends the two halves. Needs atmosphere.glsl (ATM_USE_TRANSMITTANCE).
layout(local_size_x = 64, local_size_y = 1, local_size_z = 1) in;
layout(rgba32f, binding = WELKIN_BINDING_LUT_IMAGE) uniform writeonly image1D u_viewT;
uniform float u_h;       // observer height, m, clamped into the atmosphere
uniform int u_size;      // N texels
uniform int u_skyViewH;  // the sky view's height (its v -> mu mapping)

void main() {
    int i = int(gl_GlobalInvocationID.x);
    if (i >= u_size) return;
    float v = (float(i) + 0.5) / float(u_size);
    vec3 T = vec3(0.0);
    if (v >= 0.5) {
        float mu = skyViewMuAz(u_h, vec2(0.5, v), vec2(2.0, float(u_skyViewH))).x;
        T = transmittanceFromLut(u_h, mu);
    }
    imageStore(u_viewT, i, vec4(T, 1.0));
}
