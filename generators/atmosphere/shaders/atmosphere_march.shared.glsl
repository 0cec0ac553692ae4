// The sky LUTs' marches, one source for GLSL and C++ (welkin/glsl_cpp.hpp): the transmittance to
// the top of the atmosphere and the multiple-scattering LUT's texel (Hillaire 2020). The passes
// that need them include this file after atmosphere.glsl; sky_model.cpp includes it inside a
// struct (atmosphere_shared::SkyMarch) whose members are what the marches call of the atmosphere.
//
// What the includer provides (GLSL: atmosphere.glsl's block wrappers; C++: SkyMarch's members on
// a SkyModel and its transmittance Lut2D): atm_bottom(), atm_groundAlbedoRgb(), atm_extinction(h),
// atm_scatteringRayleigh(h), atm_scatteringMie(h) (1/m), distanceToTop(h, mu),
// distanceToBottom(h, mu), rayIntersectsGround(h, mu), heightAt(h, mu, t),
// atm_perigeeFraction(h, mu, d) and, with ATM_USE_TRANSMITTANCE, transmittanceToLight(h, muS,
// angularRadius) (the LUT read); with ATM_MARCH_INCIDENT also miePhase(nu) (the atmosphere's
// aerosol phase), atm_msLutAt(h, muS) (the multiple-scattering LUT read) and atm_groundSkyAt(muS)
// (the sky's irradiance on the ground per lux, from the ground row; zero where there is none).
// Units: h, t, d in m, the results per lux of the light.

// exp(-optical depth) from (h, mu) to the top of the atmosphere, `steps` midpoint samples dense
// at the ray's perigee (atm_warp). C++: cpu::transmittanceToTop().
vec3 transmittanceToTop(real h, real mu, int steps) {
    real d = distanceToTop(h, mu);
    real p = atm_perigeeFraction(h, mu, d);
    vec3 depth = vec3(0.0);
    for (int i = 0; i < steps; ++i) {
        real s0 = real(i) / real(steps), s1 = real(i + 1) / real(steps), sm = (real(i) + 0.5) / real(steps);
        real dt = d * (atm_warp(s1, p) - atm_warp(s0, p));
        depth += atm_extinction(heightAt(h, mu, d * atm_warp(sm, p))) * dt;
    }
    return exp(-depth);
}

#ifdef ATM_USE_TRANSMITTANCE
// The multiple-scattering LUT's texel: for a point at height h with the light at cos zenith muS,
// the second-order radiance L2 and the transfer f_ms gathered over `directions` Fibonacci
// directions of the sphere with an isotropic phase, each marched in `steps` samples, Psi_ms =
// L2 / (1 - f_ms), per lux of a light of angular radius `angular` (rad). C++:
// cpu::multiScatteringTexel().
vec3 atm_multiScatteringTexel(real h, real muS, int directions, int steps, real angular) {
    vec3 sun = vec3(sqrt(max(1.0 - muS * muS, 0.0)), 0.0, muS);
    real r = atm_bottom() + h;
    vec3 L2 = vec3(0.0);
    vec3 fms = vec3(0.0);
    for (int i = 0; i < directions; ++i) {
        vec3 v = atm_fibonacciDirection(i, directions);
        real mu = v.z;
        real nu = dot(v, sun);
        bool ground = rayIntersectsGround(h, mu);
        real d = ground ? distanceToBottom(h, mu) : distanceToTop(h, mu);
        real p = atm_perigeeFraction(h, mu, d);
        vec3 thr = vec3(1.0);
        vec3 L = vec3(0.0);
        vec3 f = vec3(0.0);
        for (int k = 0; k < steps; ++k) {
            real s0 = real(k) / real(steps), s1 = real(k + 1) / real(steps), sm = (real(k) + 0.5) / real(steps);
            real dt = d * (atm_warp(s1, p) - atm_warp(s0, p));
            real t = d * atm_warp(sm, p);
            real hp = heightAt(h, mu, t);
            real rp = atm_bottom() + hp;
            real muSp = clamp((r * muS + t * nu) / rp, -1.0, 1.0);
            vec3 sigmaS = atm_scatteringRayleigh(hp) + atm_scatteringMie(hp);
            vec3 sigmaT = atm_extinction(hp);
            vec3 seg = atm_segmentFactor(sigmaT, dt);
            vec3 Tl = transmittanceToLight(hp, muSp, angular);
            L += thr * sigmaS * Tl * seg / (4.0 * ATM_PI);
            f += thr * sigmaS * seg;
            thr *= exp(-sigmaT * dt);
        }
        if (ground) {
            real muSg = clamp((r * muS + d * nu) / atm_bottom(), -1.0, 1.0);
            vec3 Tg = transmittanceToLight(0.0, muSg, angular);
            L += thr * Tg * max(muSg, 0.0) * atm_groundAlbedoRgb() / ATM_PI;
        }
        L2 += L;
        fms += f;
    }
    // Isotropic phase 1/(4 pi) times the solid angle 4 pi / n of each direction.
    L2 /= real(directions);
    fms /= real(directions);
    return L2 / (1.0 - min(fms, vec3(0.999)));
}
#endif

#ifdef ATM_MARCH_INCIDENT
// Radiance per lux arriving at (h, muS) from the unit direction v (local frame: x towards the
// light, z up): single scattering with the phase functions plus Hillaire's isotropic higher
// orders (the multiple-scattering LUT) along the ray, `steps` samples, delta-M extinction for the
// scattered light (a fraction fDelta of the Mie scattering stays in the beam), and the ground lit
// by the direct light and by the sky. The gather of the SH and ground-irradiance texels
// (sh_lut.glsl; C++: incidentRadiance() in sky_model.cpp).
vec3 atm_incidentRadiance(real h, real muS, vec3 v, int steps, real angular, real fDelta) {
    real r = atm_bottom() + h;
    real mu = v.z;
    real nu = v.x * sqrt(max(1.0 - muS * muS, 0.0)) + v.z * muS;
    real pR = rayleighPhase(nu);
    real pM = miePhase(nu);
    bool ground = rayIntersectsGround(h, mu);
    real d = ground ? distanceToBottom(h, mu) : distanceToTop(h, mu);
    real p = atm_perigeeFraction(h, mu, d);
    vec3 thr = vec3(1.0);
    vec3 L = vec3(0.0);
    for (int k = 0; k < steps; ++k) {
        real s0 = real(k) / real(steps), s1 = real(k + 1) / real(steps), sm = (real(k) + 0.5) / real(steps);
        real dt = d * (atm_warp(s1, p) - atm_warp(s0, p));
        real t = d * atm_warp(sm, p);
        real hp = heightAt(h, mu, t);
        real rp = atm_bottom() + hp;
        real muSp = clamp((r * muS + t * nu) / rp, -1.0, 1.0);
        vec3 sR = atm_scatteringRayleigh(hp);
        vec3 sM = atm_scatteringMie(hp);
        vec3 sigmaT = atm_extinction(hp) - fDelta * sM;  // delta-M (see sky_model.cpp)
        vec3 seg = atm_segmentFactor(sigmaT, dt);
        vec3 Tl = transmittanceToLight(hp, muSp, angular);
        vec3 ps = atm_msLutAt(hp, muSp);
        L += thr * ((sR * pR + sM * pM) * Tl + (sR + sM) * ps) * seg;
        thr *= exp(-sigmaT * dt);
    }
    if (ground) {
        real muSg = clamp((r * muS + d * nu) / atm_bottom(), -1.0, 1.0);
        vec3 e = transmittanceToLight(0.0, muSg, angular) * max(muSg, 0.0);
        e += atm_groundSkyAt(muSg);
        L += thr * e * atm_groundAlbedoRgb() / ATM_PI;
    }
    return L;
}
#endif
