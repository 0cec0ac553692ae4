// The eye's meter in one compute dispatch (docs/eye.md "The meter in one dispatch"): the weighted
// log-averages of the HDR frame's photopic luminance Y and scotopic luminance V' (Larson et al.
// 1997, the rods' adaptation; welkin/eye.hpp) over a 128x128 grid of bilinear samples (several work groups, below), written as
// (mean w ln Y, mean w, mean w ln V', 1) into a 1x1 RGBA32F image, then takes the eye's adaptation
// step from it (welkin_eyeStep(), adapt.glsl, the chunk before this one) and writes the new state.
// adapt.frag.glsl takes the step again from the stored means when a frame is tone-mapped again
// with other settings (with the same ones ToneMapper skips it: the step would write the same texel).
// w = 0 outside the camera's image (fisheye) and where nothing emits light (Y below 1e-7 cd/m^2,
// far below the faintest night sky), so an empty background does not drag the exposure down.
//
// The same samples and weights as the 128x128 fragment pass and its mip chain it replaced (each
// grid point at the centre of a meter texel, the frame sampled bilinearly there), summed without
// seven mip levels: on llvmpipe each mip level was a draw whose read of the level before waited
// for it (~1 ms of wall clock a frame for ~0.3 ms of work).
//
// Over WELKIN_METER_GROUPS work groups (ToneMapper::kMeterGroups), so that llvmpipe's threads
// share the samples (one group runs on one thread): the 16x16 invocations of the sum are
// gl_GlobalInvocationID.xy, each sums its 8x8 block of samples wherever its group runs and writes
// it to the buffer; the last group to finish (an atomic counter, reset by that group) adds the 256
// block sums by one tree in a fixed order. So the means are the same floats whatever the number of
// groups and whichever finishes last (docs/eye.md, session 21).
layout(local_size_x = 16, local_size_y = 16 / WELKIN_METER_GROUPS) in;
layout(binding = WELKIN_BINDING_HDR_TEXTURE) uniform sampler2D u_hdr;  // bilinear, clamped
layout(binding = WELKIN_BINDING_METER_IMAGE, rgba32f) writeonly uniform image2D u_meter;
layout(binding = WELKIN_BINDING_EYE_STATE_TEXTURE) uniform sampler2D u_previous;  // the state before
layout(binding = WELKIN_TONEMAP_STATE_IMAGE, rgba32f) writeonly uniform image2D u_state;  // the new state (unit: ToneMapper)
// The block sums and the count of groups done (zero between dispatches).
layout(std430, binding = WELKIN_BINDING_METER_SSBO) coherent buffer MeterPartials {
    uint meter_groupsDone;
    uint meter_pad[3];
    vec4 meter_block[256];
};

const int kGrid = 128;         // samples per side (ToneMapper's kMeterGrid)
const int kPerInvocation = 8;  // kGrid / 16: each invocation sums an 8x8 block of samples
const uint kGroupSize = uint(256 / WELKIN_METER_GROUPS);
shared vec3 s_sum[256];
shared bool s_last;

vec3 welkin_logLumSample(vec2 uv) {
    vec2 pixel = vec2(uv.x, 1.0 - uv.y) * welkin_viewport.xy;
    vec3 dir;
    vec3 c = textureLod(u_hdr, uv, 0.0).rgb;
    float X = dot(c, vec3(0.4124, 0.3576, 0.1805));
    float Y = dot(c, vec3(0.2126, 0.7152, 0.0722));
    float Z = dot(c, vec3(0.0193, 0.1192, 0.9505));
    float V = X > 0.0 ? Y * (1.33 * (1.0 + (Y + Z) / X) - 1.68) : 0.0;
    float w = (welkin_viewDirection(pixel, dir) && Y > 1e-7) ? 1.0 : 0.0;
    return vec3(w * log(max(Y, 1e-7)), w, w * log(max(V, 1e-7)));
}

void main() {
    uvec2 id = gl_GlobalInvocationID.xy;  // 16x16 over the groups
    ivec2 first = ivec2(id) * kPerInvocation;
    vec3 sum = vec3(0.0);
    for (int j = 0; j < kPerInvocation; ++j)
        for (int i = 0; i < kPerInvocation; ++i) sum += welkin_logLumSample((vec2(first + ivec2(i, j)) + 0.5) / float(kGrid));
    uint local = gl_LocalInvocationIndex;
#if WELKIN_METER_GROUPS == 1
    s_sum[local] = sum;
    const bool last = true;
#else
    meter_block[id.y * 16u + id.x] = vec4(sum, 0.0);
    memoryBarrierBuffer();
    barrier();
    if (local == 0u) s_last = atomicAdd(meter_groupsDone, 1u) == uint(WELKIN_METER_GROUPS - 1);
    barrier();
    const bool last = s_last;  // uniform in the group
    if (last) {
        memoryBarrierBuffer();
        for (uint k = local; k < 256u; k += kGroupSize) s_sum[k] = meter_block[k].xyz;
    }
#endif
    if (last) {
        for (uint stride = 128u; stride > 0u; stride >>= 1) {
            barrier();
            for (uint k = local; k < stride; k += kGroupSize) s_sum[k] += s_sum[k + stride];
        }
        if (local == 0u) {
#if WELKIN_METER_GROUPS != 1
            meter_groupsDone = 0u;  // for the next frame's dispatch
#endif
            vec4 m = vec4(s_sum[0] / float(kGrid * kGrid), 1.0);
            imageStore(u_meter, ivec2(0), m);
            // The adaptation here rather than in a one-texel pass after it: that pass was a draw
            // llvmpipe flushed and waited for (~0.1 ms a frame, docs/eye.md).
            imageStore(u_state, ivec2(0), welkin_eyeStep(m, texelFetch(u_previous, ivec2(0), 0)));
        }
    }
}
