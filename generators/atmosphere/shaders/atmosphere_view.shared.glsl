// The view-ray march, one source for GLSL and C++ (welkin/glsl_cpp.hpp): the sky's single and
// multiple scattering along a ray (integrateScattering(): the sky-view and eclipse LUTs, the
// per-pixel sky, the SH passes' second iteration), its samples (atm_raySampleAir(): also the
// aerial-perspective volume), the orders >= 2 from the multiple-scattering field (msInscatter())
// and the ground's irradiance (atm_groundIrradiance()). atmosphere.glsl includes it (with
// ATM_USE_TRANSMITTANCE and ATM_USE_MULTISCATTERING); sky_model.cpp includes it inside
// atmosphere_shared::SkyMarch, the C++ twins cpu::integrate(), cpu::integrateEclipse(),
// cpu::msInscatter(), cpu::groundIrradiance() (and atmosphere_march.shared.glsl's marches).
//
// What the includer provides, besides atmosphere_march.shared.glsl's list (atm_bottom(),
// atm_groundAlbedoRgb(), atm_extinction(h), atm_scatteringRayleigh(h), atm_scatteringMie(h),
// distanceToTop(h, mu), distanceToBottom(h, mu), rayIntersectsGround(h, mu), heightAt(h, mu, t),
// atm_perigeeFraction(h, mu, d), transmittanceToLight(h, muS, angularRadius)):
//   atm_thickness()              top - bottom radius (m)
//   atm_msDirectional()          whether the orders >= 2 come from the SH field (else Psi_ms)
//   atm_shBands()                the field's SH bands L (<= ATM_SH_BANDS)
//   atm_shFactorsLo(), atm_shFactorsHi()  the phase functions' band factors and the delta-M
//                                fraction as AtmosphereBlock packs them (see atm_shMieBand())
//   atm_msUv(h, muS)             the multiple-scattering LUT's uv (also the SH layers')
//   atm_msLutUv(uv)              Psi_ms at uv (per lux)
//   atm_shLutAt(uv, k)           SH coefficient k of the field at uv
//   atm_shGroundAt(muS)          the sky's irradiance on the ground per lux (the field's ground row)
//   atm_eclipseMarch()           whether the march takes a solar eclipse's shadow
//   atm_eclipseAlong(t)          with it: atm_eclipseAt() of the point t metres along the ray
//                                (visible fraction, multiple-scattering factor); else vec2(1.0)
// Units: h, t, d in m; radiance and irradiance per lux of the light.

// Irradiance of the horizontal ground per lux of the light at muS: the direct light, plus the
// sky's with the directional field. C++: cpu::groundIrradiance().
vec3 atm_groundIrradiance(real muS, real lightAngularRadius) {
    vec3 e = transmittanceToLight(0.0, muS, lightAngularRadius) * max(muS, 0.0);
    if (atm_msDirectional()) e += atm_shGroundAt(muS);
    return e;
}

// In-scattered radiance per lux of scattering orders >= 2 at a point (scattering coefficients sR,
// sM). Directional: the SH field convolved with the phase functions (Funk-Hecke: band l scaled by
// the phase function's Legendre moment; delta-M: the forward fraction stays in the beam; the Mie
// bands windowed; factors from cpu::phaseMoments()). The basis is evaluated as in atm_shBasis(),
// each function used as soon as it is known (no array of 28 basis values: with one, the second SH
// pass at l <= 6 came out wrong on Mesa llvmpipe 22.3, rows of texels 2-15 % off the CPU twin).
// C++: cpu::msInscatter().
vec3 msInscatter(real h, real mu, real muS, real nu, vec3 sR, vec3 sM) {
    vec2 uv = atm_msUv(h, muS);
    if (!atm_msDirectional()) return (sR + sM) * atm_msLutUv(uv);
    real sinS = sqrt(max(1.0 - muS * muS, 0.0));
    // x = cos(azimuth from the light) sin(zenith); undefined with the light at the zenith, where
    // the field is symmetric: below sinS = 1e-3 float rounding of nu - mu muS would dominate.
    real x = sinS > 1e-3 ? clamp((nu - mu * muS) / sinS, -1.0, 1.0) : 0.0;
    vec4 f1 = atm_shFactorsLo();
    vec4 f2 = atm_shFactorsHi();
    int bands = atm_shBands();
    vec3 aR = vec3(0.0), aM = vec3(0.0);
    real y = sqrt(max(0.0, 1.0 - x * x - mu * mu));
    real cm = 1.0, sm = 0.0, pmm = 1.0;
    for (int mm = 0; mm <= bands; ++mm) {
        real a = pmm, b = 0.0;
        for (int l = mm; l <= bands; ++l) {
            int k = l * (l + 1) / 2 + mm;
            vec3 c = atm_shLutAt(uv, k) * (ATM_SH_N(k) * a * cm);
            aM += c * atm_shMieBand(l, f1, f2);
            if (l == 0) aR += c;
            if (l == 2) aR += c * f1.z;
            real next = (real(2 * l + 1) * mu * a - real(l + mm) * b) / real(l + 1 - mm);
            b = a;
            a = next;
        }
        pmm *= real(2 * mm + 1);
        real cn = x * cm - y * sm;
        sm = x * sm + y * cm;
        cm = cn;
    }
    return sR * max(aR, vec3(0.0)) + sM * max(aM, vec3(0.0));
}

// What a view-ray march needs at the point t metres along a ray from height h (direction cosine
// mu, light at muS, view-light cosine nu), for a segment of length dt: scattering coefficients,
// true and delta-M extinction, the segment's integration factor, transmittance to the light and
// the orders >= 2 in-scattering. Shared by the sky-view and aerial-perspective marches.
struct RaySample {
    vec3 sR, sM, sigmaT, sigmaD, seg, Tl, ms;
};
// `groundAir`: the sample's height clamped to >= 0 (a ray towards the ground that the host's
// terrain stops, not the planet's sphere: the aerial-perspective volume).
RaySample atm_raySampleAir(real h, real mu, real muS, real nu, real t, real dt, real lightAngularRadius, bool groundAir) {
    RaySample q;
    real r = atm_bottom() + h;
    real hp = groundAir ? max(heightAt(h, mu, t), 0.0) : heightAt(h, mu, t);
    real rp = atm_bottom() + hp;
    real muSp = clamp((r * muS + t * nu) / rp, -1.0, 1.0);
    q.sR = atm_scatteringRayleigh(hp);
    q.sM = atm_scatteringMie(hp);
    q.sigmaT = atm_extinction(hp);
    q.sigmaD = q.sigmaT - atm_shFactorsLo().w * q.sM;
    q.seg = atm_segmentFactor(q.sigmaD, dt);
    q.Tl = transmittanceToLight(hp, muSp, lightAngularRadius);
    real muP = clamp((r * mu + t) / rp, -1.0, 1.0);
    q.ms = msInscatter(hp, muP, muSp, nu, q.sR, q.sM);
    return q;
}
RaySample atm_raySample(real h, real mu, real muS, real nu, real t, real dt, real lightAngularRadius) {
    return atm_raySampleAir(h, mu, muS, nu, t, dt, lightAngularRadius, false);
}

// The aerial-perspective volume's march over one distance slice [t0, t1] of a ray (`substeps`
// midpoint samples through air no lower than the ground when `groundAir`), adding to the
// in-scattered radiance L and the exact and delta-M transmittances thr, thrD. C++:
// cpu::aerialTexel().
void atm_aerialSlice(real h, real mu, real muS, real nu, real t0, real t1, int substeps, real lightAngularRadius, bool groundAir,
                     real phaseR, real phaseM, INOUT(vec3) L, INOUT(vec3) thr, INOUT(vec3) thrD) {
    real dt = (t1 - t0) / real(substeps);
    for (int s = 0; s < substeps && dt > 0.0; ++s) {
        real t = t0 + (real(s) + 0.5) * dt;
        RaySample q = atm_raySampleAir(h, mu, muS, nu, t, dt, lightAngularRadius, groundAir);
        L += thrD * ((q.sR * phaseR + q.sM * phaseM) * q.Tl + q.ms) * q.seg;
        thr *= exp(-q.sigmaT * dt);
        thrD *= exp(-q.sigmaD * dt);
    }
}

struct Scattering {
    vec3 smooth_;     // Rayleigh single (phase applied), multiple scattering and ground
    vec3 mieNoPhase;  // Mie single scattering without its phase function
    vec3 transmittance;
    bool hitGround;
};
// Single and multiple scattering along a view ray from height h (clamped to the atmosphere),
// `steps` samples up to the ground, the top or maxDistance (m), dense at the perigee unless
// `quadratic`; then the Lambertian ground, lit by the light and the sky. groundMode: -1 decide
// from the geometry, 0 never hits, 1 hits (sky-view rows at the horizon). With atm_eclipseMarch(),
// each sample's light and orders >= 2 and the ground's light take the eclipse's factors.
// C++: cpu::integrate(), cpu::integrateEclipse().
Scattering integrateScattering(real h, real mu, real muS, real nu, real maxDistance, int steps, bool quadratic,
                               real lightAngularRadius, int groundMode) {
    Scattering o;
    o.smooth_ = vec3(0.0);
    o.mieNoPhase = vec3(0.0);
    h = clamp(h, 0.0, atm_thickness());
    o.hitGround = groundMode < 0 ? rayIntersectsGround(h, mu) : groundMode == 1;
    real d = o.hitGround ? distanceToBottom(h, mu) : distanceToTop(h, mu);
    if (d > maxDistance) o.hitGround = false;
    d = min(d, maxDistance);
    real p = quadratic ? 0.0 : atm_perigeeFraction(h, mu, d);
    real r = atm_bottom() + h;
    real phaseR = rayleighPhase(nu);
    vec3 thr = vec3(1.0), thrD = vec3(1.0);  // exact (background) and delta-M (scattered light)
    // The eclipse's multiple-scattering weight (atmosphere.shared.glsl, atm_eclMsWeight()).
    // (Only an eclipse's march reads it: the ordinary sky's rays skip it.)
    real eclAxis = 1.0;
    if (atm_eclipseMarch())
        eclAxis = atm_eclMsWeight(nu, mu, muS, atm_eclCosRing(mu, muS, nu),
                                  atm_eclForwardShare(atm_shFactorsLo().w, atm_scatteringMie(0.0).y, atm_scatteringRayleigh(0.0).y),
                                  atm_eclHaze(atm_scatteringMie(0.0).y));
    for (int k = 0; k < steps && d > 0.0; ++k) {
        real s0 = real(k) / real(steps), s1 = real(k + 1) / real(steps), sm = (real(k) + 0.5) / real(steps);
        real dt = d * (atm_warp(s1, p) - atm_warp(s0, p)), t = d * atm_warp(sm, p);
        RaySample q = atm_raySample(h, mu, muS, nu, t, dt, lightAngularRadius);
        if (atm_eclipseMarch()) {
            vec2 ecl = atm_eclipseAlong(t);
            q.Tl *= ecl.x;
            q.ms *= max(mix(ecl.x, ecl.y, eclAxis), 0.0);  // the weight may exceed 1 (low views' gain): never negative
        }
        o.smooth_ += thrD * (q.sR * q.Tl * phaseR + q.ms) * q.seg;
        o.mieNoPhase += thrD * q.sM * q.Tl * q.seg;
        thr *= exp(-q.sigmaT * dt);
        thrD *= exp(-q.sigmaD * dt);
    }
    if (o.hitGround) {
        // The ground: Lambertian, lit by the light and by the sky.
        real muSg = clamp((r * muS + d * nu) / atm_bottom(), -1.0, 1.0);
        if (atm_eclipseMarch()) {
            // Direct light by the ground point's own visible fraction, the sky's by the model's.
            vec2 eg = atm_eclipseAlong(d);
            vec3 eDirect = transmittanceToLight(0.0, muSg, lightAngularRadius) * max(muSg, 0.0);
            vec3 eAll = atm_groundIrradiance(muSg, lightAngularRadius);
            o.smooth_ += thrD * (eDirect * eg.x + (eAll - eDirect) * eg.y) * atm_groundAlbedoRgb() / ATM_PI;
        } else {
            o.smooth_ += thrD * atm_groundIrradiance(muSg, lightAngularRadius) * atm_groundAlbedoRgb() / ATM_PI;
        }
    }
    o.transmittance = thr;
    return o;
}
