// SkyLighting: one mip of the GGX-prefiltered specular cube, a brute-force sum over every texel
// of a source level of the radiance cube (split-sum approximation with n = v = r: weight
// D(h) / 4 x max(n . l, 0) x Omega(l), normalised by the weights' sum; D the GGX (Trowbridge-
// Reitz) distribution of alpha = roughness^2). One invocation per output texel.
layout(local_size_x = 8, local_size_y = 8) in;
layout(binding = WELKIN_BINDING_LIGHTING_SOURCE_IMAGE, rgba32f) uniform readonly imageCube u_source;
layout(binding = WELKIN_BINDING_LIGHTING_OUTPUT_IMAGE, rgba32f) uniform writeonly imageCube u_out;
uniform int u_outSize, u_sourceSize;
uniform float u_alpha;

void main() {
    ivec3 id = ivec3(gl_GlobalInvocationID);
    if (id.x >= u_outSize || id.y >= u_outSize) return;
    vec3 n = lighting_texelDirection(id.z, id.xy, u_outSize);
    float a2 = u_alpha * u_alpha;
    vec3 sum = vec3(0.0);
    float wsum = 0.0;
    for (int face = 0; face < 6; ++face)
        for (int j = 0; j < u_sourceSize; ++j)
            for (int i = 0; i < u_sourceSize; ++i) {
                vec3 l = lighting_texelDirection(face, ivec2(i, j), u_sourceSize);
                float nl = dot(n, l);
                if (nl <= 0.0) continue;
                vec3 h = normalize(n + l);
                float nh = max(dot(n, h), 0.0);
                float q = nh * nh * (a2 - 1.0) + 1.0;
                float D = a2 / (LIGHTING_PI * q * q);
                float w = 0.25 * D * nl * lighting_texelSolidAngle(ivec2(i, j), u_sourceSize);
                sum += w * imageLoad(u_source, ivec3(i, j, face)).rgb;
                wsum += w;
            }
    imageStore(u_out, id, vec4(wsum > 0.0 ? sum / wsum : vec3(0.0), 1.0));
}
