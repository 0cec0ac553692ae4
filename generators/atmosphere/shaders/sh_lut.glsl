// Directional multiple-scattering LUT passes. Twins of cpu::groundIrradianceTexel() and
// cpu::shTexel(). Needs atmosphere.glsl (ATM_USE_TRANSMITTANCE, ATM_USE_MULTISCATTERING).
//  - SH_GROUND_PASS (fragment, a row of u_size.x texels over mu_s): the sky's irradiance on the
//    horizontal ground per lux, gathered over the upper hemisphere.
//  - otherwise (compute, one invocation per texel, one image layer per coefficient): at each
//    (h, mu_s) the incident radiance field per lux -- single scattering with the Rayleigh and
//    Mie phase functions, Hillaire's isotropic higher orders (Psi_ms) along each gathered ray,
//    and the ground lit by the light and the sky -- projected on the real spherical harmonics
//    l <= ATM_SH_BANDS (4 or 6) that are even in y (the field is symmetric about the light's
//    vertical plane). Local frame: x horizontal towards the light, z up. SH_IMAGE_FORMAT:
//    rgba32f or rgba16f.
//  - SH_ITERATION (with ATM_MS_DIRECTIONAL: the first pass's layers on unit 8): the same
//    projection (compute) or ground irradiance (with SH_GROUND_PASS), each gathered ray marched
//    like a view ray (integrateScattering()), so its orders >= 2 come from the first pass's
//    directional field; twins of cpu::shIterationTexel() and groundIrradianceIterationTexel().
uniform int u_directions;
uniform int u_steps;
#ifdef SH_ITERATION
// This draw's (dispatch's) directions [x, y) of u_directions: the second pass is split into
// several, each adding to the previous ones (see ShLut::doRun()).
uniform ivec2 u_directionRange;
#endif
uniform ivec2 u_size;  // texels: mu_s, height

#ifndef SH_GROUND_PASS
// The ground-irradiance row made by the SH_GROUND_PASS (texture unit 9).
layout(binding = WELKIN_BINDING_SH_GROUND_LUT) uniform sampler2D u_groundLut;
#endif

// What the incident-radiance march reads: the multiple-scattering LUT and the ground row.
vec3 atm_msLutAt(float h, float muS) {
    return texture(ATM_MULTISCATTERING_LUT, multiScatteringUv(h, muS, vec2(textureSize(ATM_MULTISCATTERING_LUT, 0)))).rgb;
}
vec3 atm_groundSkyAt(float muS) {
#ifndef SH_GROUND_PASS
    return texture(u_groundLut, vec2(multiScatteringUv(0.0, muS, vec2(u_size.x, 2.0)).x, 0.5)).rgb;
#else
    return vec3(0.0);
#endif
}
// Radiance per lux arriving at (h, muS) from direction v: atm_incidentRadiance() of
// atmosphere_march.shared.glsl (C++: incidentRadiance() in sky_model.cpp, the same text).
#define ATM_MARCH_INCIDENT
#include "atmosphere_march.shared.glsl"
vec3 atm_incidentRadiance(float h, float muS, vec3 v) {
    return atm_incidentRadiance(h, muS, v, u_steps, atm_solarIlluminance.w, atm_shFactors.w);
}

#ifdef SH_GROUND_PASS
out vec4 o_ground;
void main() {
    float muS = multiScatteringHMuS(vec2(gl_FragCoord.x / float(u_size.x), 0.0), vec2(u_size.x, 2.0)).y;
    // Equal-area directions of the upper hemisphere (z uniform in (0, 1]), 2 pi / n sr each.
    const float golden = ATM_PI * (3.0 - sqrt(5.0));
    vec3 E = vec3(0.0);
#ifdef SH_ITERATION
    for (int i = u_directionRange.x; i < u_directionRange.y; ++i) {
#else
    for (int i = 0; i < u_directions; ++i) {
#endif
        float z = 1.0 - (float(i) + 0.5) / float(u_directions), rr = sqrt(max(1.0 - z * z, 0.0));
        float phi = golden * float(i);
#ifdef SH_ITERATION
        // Second pass: each ray marched like a view ray through the first pass's field; twin of
        // cpu::groundIrradianceIterationTexel().
        float nu = rr * cos(phi) * sqrt(max(1.0 - muS * muS, 0.0)) + z * muS;
        Scattering s = integrateScattering(0.0, z, muS, nu, 1e30, u_steps, false, atm_solarIlluminance.w, -1);
        E += (s.smooth_ + s.mieNoPhase * miePhase(nu)) * z;
#else
        E += atm_incidentRadiance(0.0, muS, vec3(rr * cos(phi), rr * sin(phi), z)) * z;
#endif
    }
    o_ground = vec4(E * (2.0 * ATM_PI / float(u_directions)), 1.0);
}
#else
layout(local_size_x = 8, local_size_y = 8, local_size_z = 1) in;
#ifdef SH_ITERATION
layout(SH_IMAGE_FORMAT, binding = WELKIN_BINDING_LUT_IMAGE) uniform restrict image2DArray u_sh;  // added to after the first range
#else
layout(SH_IMAGE_FORMAT, binding = WELKIN_BINDING_LUT_IMAGE) uniform writeonly image2DArray u_sh;
#endif
void main() {
    ivec2 ij = ivec2(gl_GlobalInvocationID.xy);
    if (ij.x >= u_size.x || ij.y >= u_size.y) return;
    vec2 hm = multiScatteringHMuS((vec2(ij) + 0.5) / vec2(u_size), vec2(u_size));
    float h = hm.x, muS = hm.y;
    vec3 c[ATM_SH_COEFFICIENTS];
    for (int k = 0; k < ATM_SH_COEFFICIENTS; ++k) c[k] = vec3(0.0);
#ifdef SH_ITERATION
    for (int i = u_directionRange.x; i < u_directionRange.y; ++i) {
#else
    for (int i = 0; i < u_directions; ++i) {
#endif
        vec3 v = atm_fibonacciDirection(i, u_directions);
#ifdef SH_ITERATION
        float nu = v.x * sqrt(max(1.0 - muS * muS, 0.0)) + v.z * muS;
        Scattering s = integrateScattering(h, v.z, muS, nu, 1e30, u_steps, false, atm_solarIlluminance.w, -1);
        vec3 L = s.smooth_ + s.mieNoPhase * miePhase(nu);
#else
        vec3 L = atm_incidentRadiance(h, muS, v);
#endif
        AtmShBasis Y = atm_shBasis(v.x, v.z, ATM_SH_BANDS);
        for (int k = 0; k < ATM_SH_COEFFICIENTS; ++k) c[k] += L * Y.y[k];
    }
    float w = 4.0 * ATM_PI / float(u_directions);
    for (int k = 0; k < ATM_SH_COEFFICIENTS; ++k) {
        vec3 sum = c[k] * w;
#ifdef SH_ITERATION
        if (u_directionRange.x > 0) sum += imageLoad(u_sh, ivec3(ij, k)).rgb;
#endif
        imageStore(u_sh, ivec3(ij, k), vec4(sum, 1.0));
    }
}
#endif
