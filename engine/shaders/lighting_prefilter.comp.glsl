// SkyLighting: one mip of the GGX-prefiltered specular cube, a brute-force sum over every texel
// of a source level of the radiance cube (split-sum approximation with n = v = r: weight
// D(h) / 4 x max(n . l, 0) x Omega(l), normalised by the weights' sum; D the GGX (Trowbridge-
// Reitz) distribution of alpha = roughness^2). One invocation per output texel. The source
// texels' directions and exact solid angles come from a table (lighting_texels, made once per
// cube size on the CPU in double precision; on the sums' binding, which this pass does not use):
// the inner loop is a fetch, a dot product and D.
layout(local_size_x = 8, local_size_y = 8) in;
layout(binding = WELKIN_BINDING_LIGHTING_SOURCE_IMAGE, rgba32f) uniform readonly imageCube u_source;
layout(binding = WELKIN_BINDING_LIGHTING_OUTPUT_IMAGE, rgba32f) uniform writeonly imageCube u_out;
layout(std430, binding = WELKIN_BINDING_LIGHTING_SSBO) readonly buffer LightingTexels { vec4 lighting_texels[]; };
uniform int u_outSize, u_sourceSize, u_sourceOffset;  // the source level's entries start at u_sourceOffset (face, row, column order)
uniform float u_alpha;

void main() {
    ivec3 id = ivec3(gl_GlobalInvocationID);
    if (id.x >= u_outSize || id.y >= u_outSize) return;
    vec3 n = lighting_texelDirection(id.z, id.xy, u_outSize);
    float a2 = u_alpha * u_alpha;
    vec3 sum = vec3(0.0);
    float wsum = 0.0;
    int k = u_sourceOffset;
    for (int face = 0; face < 6; ++face)
        for (int j = 0; j < u_sourceSize; ++j)
            for (int i = 0; i < u_sourceSize; ++i, ++k) {
                vec4 t = lighting_texels[k];  // direction (ENU), solid angle (sr)
                float nl = dot(n, t.xyz);
                if (nl <= 0.0) continue;
                // n . h for h = normalize(n + l), n and l unit: sqrt((1 + n.l) / 2).
                float nh2 = 0.5 * (1.0 + nl);
                float q = nh2 * (a2 - 1.0) + 1.0;
                float w = 0.25 * a2 / (LIGHTING_PI * q * q) * nl * t.w;
                sum += w * imageLoad(u_source, ivec3(i, j, face)).rgb;
                wsum += w;
            }
    imageStore(u_out, id, vec4(wsum > 0.0 ? sum / wsum : vec3(0.0), 1.0));
}
