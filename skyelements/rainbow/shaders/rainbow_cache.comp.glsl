// The Rainbow's direction cache, filled by a compute pass (rainbow_polar.glsl for the mapping):
// rgb the curtain's radiance (cd/m^2), a its grey transmittance. A texel whose direction misses the
// curtain takes the value of the nearest direction inside it (its elevation and azimuth clamped to
// the curtain's): the display clips the mesh at the curtain's edges, and bilinear filtering there
// then blends values of the curtain only, never a rim of "no rain".
// Needs optics/mie_angle.glsl, cloud_shadow.glsl, rainbow_curtain.glsl, rainbow_polar.glsl.
// Workgroups of one row segment (64 x 1): a refill spread over frames fills any number of rows.
layout(local_size_x = 64, local_size_y = 1) in;
layout(binding = WELKIN_BINDING_LUT_IMAGE, rgba32f) writeonly uniform image2D u_cache;
uniform ivec2 u_cacheSize;            // texels: u, psi
uniform int u_rowOffset;              // first row (psi) of this dispatch (a refill spread over frames)
uniform float u_sinElLo, u_sinElHi;   // the curtain's elevation range (sines), inset by a hair
uniform float u_halfWidth;            // the curtain's azimuthal half-width, rad, inset by a hair

vec3 rainbow_clampToCurtain(vec3 d) {
    float z = clamp(d.z, u_sinElLo, u_sinElHi);
    float h = length(d.xy);
    vec2 hd = h > 1e-6 ? d.xy / h : u_axis;
    float c = dot(hd, u_axis);
    if (c < cos(u_halfWidth)) {
        // Onto the sector's edge on the same side of the axis.
        float side = u_axis.x * hd.y - u_axis.y * hd.x >= 0.0 ? 1.0 : -1.0;
        float a = side * u_halfWidth;
        hd = vec2(u_axis.x * cos(a) - u_axis.y * sin(a), u_axis.x * sin(a) + u_axis.y * cos(a));
    }
    return vec3(hd * sqrt(max(1.0 - z * z, 0.0)), z);
}

void main() {
    ivec2 ij = ivec2(gl_GlobalInvocationID.xy) + ivec2(0, u_rowOffset);
    if (any(greaterThanEqual(ij, u_cacheSize))) return;
    float x = (float(ij.x) + 0.5) / float(u_cacheSize.x);
    float psi = rainbow_psiFromY((float(ij.y) + 0.5) / float(u_cacheSize.y));
    vec3 dir = rainbow_clampToCurtain(rainbow_polarDirection(x, psi));
    vec3 radiance = vec3(0.0), transmittance = vec3(1.0), phase;
    rainbow_curtain(dir, radiance, transmittance, phase);
    imageStore(u_cache, ij, vec4(max(radiance, vec3(0.0)), clamp(transmittance.g, 0.0, 1.0)));
}
