// Multiple-scattering LUT pass (compute, 8x8 invocations per group: llvmpipe spreads groups over
// its threads, where a fragment pass this small is one 64x64 tile, one thread), Hillaire 2020: for a point at height h with the light
// at cos zenith muS, the second-order radiance L2 and the transfer f_ms gathered over the sphere
// with an isotropic phase, Psi_ms = L2 / (1 - f_ms), per lux of the light. Twin of
// cpu::multiScatteringTexel(). Needs atmosphere.glsl (ATM_USE_TRANSMITTANCE) before it.
uniform int u_directions;
uniform int u_steps;
uniform ivec2 u_size;  // texels: mu_s, height
layout(local_size_x = 8, local_size_y = 8, local_size_z = 1) in;
layout(MS_IMAGE_FORMAT, binding = WELKIN_BINDING_LUT_IMAGE) uniform writeonly image2D u_psi;

void main() {
    ivec2 ij = ivec2(gl_GlobalInvocationID.xy);
    if (ij.x >= u_size.x || ij.y >= u_size.y) return;
    vec2 hm = multiScatteringHMuS((vec2(ij) + 0.5) / vec2(u_size), vec2(u_size));
    float h = hm.x, muS = hm.y;
    vec3 sun = vec3(sqrt(max(1.0 - muS * muS, 0.0)), 0.0, muS);
    float angular = atm_solarIlluminance.w;
    float r = atm_bottom() + h;
    vec3 L2 = vec3(0.0), fms = vec3(0.0);
    for (int i = 0; i < u_directions; ++i) {
        vec3 v = atm_fibonacciDirection(i, u_directions);
        float mu = v.z, nu = dot(v, sun);
        bool ground = rayIntersectsGround(h, mu);
        float d = ground ? distanceToBottom(h, mu) : distanceToTop(h, mu);
        float p = atm_perigeeFraction(h, mu, d);
        vec3 thr = vec3(1.0), L = vec3(0.0), f = vec3(0.0);
        for (int k = 0; k < u_steps; ++k) {
            float s0 = float(k) / float(u_steps), s1 = float(k + 1) / float(u_steps), sm = (float(k) + 0.5) / float(u_steps);
            float dt = d * (atm_warp(s1, p) - atm_warp(s0, p)), t = d * atm_warp(sm, p);
            float hp = heightAt(h, mu, t);
            float rp = atm_bottom() + hp;
            float muSp = clamp((r * muS + t * nu) / rp, -1.0, 1.0);
            vec3 sigmaS = atm_scatteringRayleigh(hp) + atm_scatteringMie(hp);
            vec3 sigmaT = atm_extinction(hp);
            vec3 seg = atm_segmentFactor(sigmaT, dt);
            vec3 Tl = transmittanceToLight(hp, muSp, angular);
            L += thr * sigmaS * Tl * seg / (4.0 * ATM_PI);
            f += thr * sigmaS * seg;
            thr *= exp(-sigmaT * dt);
        }
        if (ground) {
            float muSg = clamp((r * muS + d * nu) / atm_bottom(), -1.0, 1.0);
            vec3 Tg = transmittanceToLight(0.0, muSg, angular);
            L += thr * Tg * max(muSg, 0.0) * atm_groundAlbedo.rgb / ATM_PI;
        }
        L2 += L;
        fms += f;
    }
    L2 /= float(u_directions);
    fms /= float(u_directions);
    imageStore(u_psi, ij, vec4(L2 / (1.0 - min(fms, vec3(0.999))), 1.0));
}
