// The real-time sky model in GLSL; its optical functions and LUT parameterisations are
// atmosphere.shared.glsl (included below), which sky_model.cpp compiles in double as the CPU twin;
// the marches that remain here mirror sky_model.cpp's (same function names, same maths). Include
// it before any pass of the sky. The atmosphere arrives in a std140 uniform block at binding 1
// (welkin::generators::AtmosphereBlock); the LUTs as samplers that each pass declares itself.
//
// Geometry: h = height above the ground (m), mu = cos(view zenith), muS = cos(light zenith),
// nu = cos(view-light angle); r^2 - R^2 is always computed as h (2R + h) so rays grazing the
// ground keep their precision in float.
layout(std140, binding = WELKIN_BINDING_ATMOSPHERE_UBO) uniform WelkinAtmosphere {
    vec4 atm_radii;              // bottom radius, top radius, top - bottom (m), Mie phase kind
    vec4 atm_rayleigh;           // scattering rgb (1/m), Mie g
    vec4 atm_mieScattering;      // rgb (1/m), unused
    vec4 atm_mieExtinction;      // rgb (1/m), unused
    vec4 atm_absorption;         // ozone extinction rgb (1/m), unused
    vec4 atm_groundAlbedo;       // rgb, unused
    vec4 atm_solarIlluminance;   // rgb (lux), Sun's angular radius (rad)
    vec4 atm_shFactors;          // SH convolution (cpu::PhaseMoments): Mie l1, Mie l2, Rayleigh l2; delta-M fraction f
    vec4 atm_profiles[9];        // 3 profiles x (w0 e0 s0 l0)(c0 e1 s1 l1)(c1 0 0 0)
    vec4 atm_shFactors2;         // SH convolution: Mie l3 .. l6 (0 beyond ATM_SH_BANDS)
};

// The model's maths (geometry, density profiles, LUT parameterisations, phase functions):
// atmosphere.shared.glsl, which the CPU twins compile in double. Below, the versions of its
// functions that take the planet's radii read them from the block, under the same names.
#include "atmosphere.shared.glsl"

float atm_bottom() { return atm_radii.x; }
float atm_top() { return atm_radii.y; }
float atm_thickness() { return atm_radii.z; }
vec3 atm_groundAlbedoRgb() { return atm_groundAlbedo.rgb; }

float atm_density(int p, float h) { return atm_profileDensity(atm_profiles[3 * p], atm_profiles[3 * p + 1], atm_profiles[3 * p + 2], h); }
vec3 atm_scatteringRayleigh(float h) { return atm_rayleigh.rgb * atm_density(0, h); }
vec3 atm_scatteringMie(float h) { return atm_mieScattering.rgb * atm_density(1, h); }
vec3 atm_extinction(float h) {
    return atm_rayleigh.rgb * atm_density(0, h) + atm_mieExtinction.rgb * atm_density(1, h) +
           atm_absorption.rgb * atm_density(2, h);
}

float atm_rho2(float h) { return atm_rho2(atm_bottom(), h); }
float distanceToTop(float h, float mu) { return distanceToTop(atm_bottom(), atm_thickness(), h, mu); }
float distanceToBottom(float h, float mu) { return distanceToBottom(atm_bottom(), h, mu); }
bool rayIntersectsGround(float h, float mu) { return rayIntersectsGround(atm_bottom(), h, mu); }
float heightAt(float h, float mu, float t) { return heightAt(atm_bottom(), h, mu, t); }

vec2 transmittanceUv(float h, float mu, vec2 size) { return transmittanceUv(atm_bottom(), atm_thickness(), h, mu, size); }
vec2 transmittanceHMu(vec2 uv, vec2 size) { return transmittanceHMu(atm_bottom(), atm_thickness(), uv, size); }
vec2 multiScatteringUv(float h, float muS, vec2 size) { return multiScatteringUv(atm_thickness(), h, muS, size); }
vec2 multiScatteringHMuS(vec2 uv, vec2 size) { return multiScatteringHMuS(atm_thickness(), uv, size); }
float atm_horizonZenith(float h) { return atm_horizonZenith(atm_bottom(), h); }
// sin(theta_H / 2) of the observer's horizon (a per-frame constant for pixel shaders).
float atm_horizonS(float h) { return atm_horizonS(atm_bottom(), h); }
vec2 skyViewUvH(float thetaH, float mu, float azimuth, vec2 size) { return skyViewUvS(sin(0.5 * thetaH), mu, cos(azimuth), size); }
vec2 skyViewUv(float h, float mu, float azimuth, vec2 size) { return skyViewUvS(atm_horizonS(h), mu, cos(azimuth), size); }
vec2 skyViewMuAz(float h, vec2 uv, vec2 size) { return skyViewMuAzS(atm_horizonS(h), uv, size); }

float miePhase(float nu) { return miePhase(nu, atm_rayleigh.w, atm_radii.w < 0.5 ? 0 : 1); }
float atm_perigeeFraction(float h, float mu, float d) { return atm_perigeeFraction(atm_bottom(), h, mu, d); }

#ifdef ATM_ECLIPSE
// A solar eclipse: the Moon's shadow on the air (docs/eclipse.md). Every point of a march sees
// its own Sun and Moon: their directions and angular radii from that point (the Moon is ~3.8e8 m
// away, so they change across the hundreds of km a ray spans), and the single scattering and the
// directly lit ground take the limb-darkened visible fraction of the Sun's disk there. Twin of
// cpu::eclipseAt() in sky_model.cpp. Positions are ENU metres from the observer.
uniform vec3 u_eclMoonPos;      // the Moon's centre (the apparent Sun's frame: moon.position_m)
uniform float u_eclMoonRadius;  // the Moon's radius, m
uniform vec3 u_eclSunPos;       // the Sun's centre, m (sun.direction x sun.distance_m)
uniform float u_eclSunRadius;   // the Sun's radius, m
// The multiple-scattering field (cpu::EclipseMsTable): D on the plane through the observer
// perpendicular to the shadow's axis, basis u_eclMsE1/E2, grid centre u_eclMsCentre (m),
// covering +- u_eclMsHalf m (0: no field); linear filter, clamp to edge; 0 off the grid.
uniform sampler2D u_eclMsField;  // texture unit kEclipseMsFieldUnit (sky_luts.hpp), set by the pass
uniform vec3 u_eclMsE1;
uniform vec3 u_eclMsE2;
uniform vec2 u_eclMsCentre;
uniform float u_eclMsHalf;
vec3 atm_eclOrigin = vec3(0.0);   // the march's origin and unit direction (set by the pass)
vec3 atm_eclView = vec3(0.0, 0.0, 1.0);
bool atm_eclOn = true;  // false: a march of another light (the Moon's), which the shadow does not touch

// The visible fraction of the limb-darkened Sun behind the Moon at a point,
// atm_eclipseVisibleAt(p, ...) (and atm_eclipseFraction() of the disks' radii and separation):
// atmosphere.shared.glsl (cpu::eclipseAt(), cpu::eclipseFraction() compile it in double). 24 nodes
// over the band the Moon's limb cuts (cpu::eclipseFraction()'s default).
#define ATM_ECLIPSE_NODES 24
// At point p: x the visible fraction of the Sun (single scattering, the direct light); y the
// multiple-scattering model's factor: x plus the field's D (the fraction averaged over the air
// around p minus the fraction at p; docs/eclipse.md), clamped to [0, 1].
vec2 atm_eclipseAt(vec3 p) {
    if (!atm_eclOn) return vec2(1.0);
    float f = atm_eclipseVisibleAt(p, u_eclMoonPos, u_eclMoonRadius, u_eclSunPos, u_eclSunRadius, ATM_ECLIPSE_NODES);
    float D = 0.0;
    if (u_eclMsHalf > 0.0) {
        vec2 uv = (vec2(dot(p, u_eclMsE1), dot(p, u_eclMsE2)) - u_eclMsCentre) / (2.0 * u_eclMsHalf) + 0.5;
        if (all(greaterThanEqual(uv, vec2(0.0))) && all(lessThanEqual(uv, vec2(1.0)))) D = texture(u_eclMsField, uv).r;
    }
    return vec2(f, clamp(f + D, 0.0, 1.0));
}
// The multiple-scattering model's weight along a view ray (nu: the cosine of its angle to the
// Sun; twin of cpu::eclipseMsAxisWeight()): the orders >= 2 take mix(f, f + D, w),
// w = 1 - F (1 - sin(angle)), F = min(1, forward peak's share of the scattering at the ground /
// 0.16 (kEclipseForwardShare)). A ray near the shadow's axis gathers, through the forward peak,
// light scattered in the air along the axis, as dark as the point itself; through the rest of
// the scattering and across the axis, the kernel's average.
float atm_eclMsAxisWeight(float nu) {
    float sM = atm_scatteringMie(0.0).g, sR = atm_scatteringRayleigh(0.0).g;
    float F = min(1.0, atm_shFactors.w * sM / max(sM + sR, 1e-30) / 0.16);
    return 1.0 - F * (1.0 - sqrt(max(1.0 - nu * nu, 0.0)));
}
#endif

#ifdef ATM_USE_TRANSMITTANCE
// The transmittance LUT on texture unit 4 (define ATM_USE_TRANSMITTANCE before this file).
layout(binding = WELKIN_BINDING_TRANSMITTANCE_LUT) uniform sampler2D u_atmTransmittance;
#define ATM_TRANSMITTANCE_LUT u_atmTransmittance
vec3 transmittanceFromLut(float h, float mu) {
    return texture(ATM_TRANSMITTANCE_LUT, transmittanceUv(h, mu, vec2(textureSize(ATM_TRANSMITTANCE_LUT, 0)))).rgb;
}
vec3 transmittanceToLight(float h, float muS, float angularRadius) {
    h = max(h, 0.0);
    return transmittanceFromLut(h, muS) * atm_lightAboveHorizon(atm_bottom(), h, muS, angularRadius);
}
#endif

#if defined(ATM_USE_TRANSMITTANCE) && defined(ATM_USE_MULTISCATTERING)
// The multiple-scattering LUT on texture unit 5 (define ATM_USE_MULTISCATTERING).
layout(binding = WELKIN_BINDING_MULTISCATTERING_LUT) uniform sampler2D u_atmMultiScattering;
#define ATM_MULTISCATTERING_LUT u_atmMultiScattering
#ifdef ATM_MS_DIRECTIONAL
// The SH projection of the incident radiance field (layers 0 .. ATM_SH_COEFFICIENTS - 1) on
// texture unit 8; the next layer, row 0, holds the sky's irradiance on the ground over mu_s.
layout(binding = WELKIN_BINDING_SH_LUT) uniform sampler2DArray u_atmShLut;
#endif
// SH bands L of the directional field (SkyQuality::shBands, set by the pass's program).
#ifndef ATM_SH_BANDS
#define ATM_SH_BANDS 4
#endif
const int ATM_SH_COEFFICIENTS = (ATM_SH_BANDS + 1) * (ATM_SH_BANDS + 2) / 2;
const float ATM_SH_GROUND_LAYER = float(ATM_SH_COEFFICIENTS);
// N_lm = sqrt((2l + 1) / (4 pi) (l - m)! / (l + m)!), times sqrt(2) for m > 0, at l (l + 1) / 2 + m.
const float ATM_SH_NORM[28] = float[28](0.28209479, 0.48860251, 0.48860251, 0.63078313, 0.36418281, 0.18209141,
    0.74635267, 0.30469720, 0.09635371, 0.03933624, 0.84628438, 0.26761862, 0.06307831, 0.01685839, 0.00596034,
    0.93560258, 0.24157155, 0.04565273, 0.00931882, 0.00219647, 0.00069458, 1.01710724, 0.22195100, 0.03509353,
    0.00584892, 0.00106786, 0.00022767, 0.00006572);

// The real SH of bands l <= ATM_SH_BANDS that are even in y, at a unit vector given x and z
// (index l (l + 1) / 2 + m); twin of cpu::shBasis(): N_lm P_l^m(z) / sin^m * Re((x + i y)^m), the
// associated Legendre function (no Condon-Shortley phase) by its recurrence in l.
float[ATM_SH_COEFFICIENTS] atm_shBasis(float x, float z) {
    float Y[ATM_SH_COEFFICIENTS];
    float y = sqrt(max(0.0, 1.0 - x * x - z * z));
    float cm = 1.0, sm = 0.0, pmm = 1.0;
    for (int m = 0; m <= ATM_SH_BANDS; ++m) {
        float a = pmm, b = 0.0;
        for (int l = m; l <= ATM_SH_BANDS; ++l) {
            int k = l * (l + 1) / 2 + m;
            Y[k] = ATM_SH_NORM[k] * a * cm;
            float next = (float(2 * l + 1) * z * a - float(l + m) * b) / float(l + 1 - m);
            b = a;
            a = next;
        }
        pmm *= float(2 * m + 1);
        float c = x * cm - y * sm;
        sm = x * sm + y * cm;
        cm = c;
    }
    return Y;
}

// Irradiance of the horizontal ground per lux of the light at muS (direct light, plus the sky's
// with ATM_MS_DIRECTIONAL); twin of cpu::groundIrradiance().
vec3 atm_groundIrradiance(float muS, float lightAngularRadius) {
    vec3 e = transmittanceToLight(0.0, muS, lightAngularRadius) * max(muS, 0.0);
#ifdef ATM_MS_DIRECTIONAL
    vec2 size = vec2(textureSize(u_atmShLut, 0).xy);
    e += texture(u_atmShLut, vec3(multiScatteringUv(0.0, muS, vec2(size.x, 2.0)).x, 0.5 / size.y, ATM_SH_GROUND_LAYER)).rgb;
#endif
    return e;
}

// In-scattered radiance per lux of scattering orders >= 2 at a point; twin of cpu::msInscatter().
vec3 msInscatter(float h, float mu, float muS, float nu, vec3 sR, vec3 sM) {
    vec2 uv = multiScatteringUv(h, muS, vec2(textureSize(ATM_MULTISCATTERING_LUT, 0)));
#ifdef ATM_MS_DIRECTIONAL
    float sinS = sqrt(max(1.0 - muS * muS, 0.0));
    float x = sinS > 1e-3 ? clamp((nu - mu * muS) / sinS, -1.0, 1.0) : 0.0;  // see cpu::msInscatter()
    // Funk-Hecke: band l scaled by the phase function's Legendre moment; delta-M: the forward
    // fraction stays in the beam; the Mie bands windowed (factors from cpu::phaseMoments()). The
    // basis is evaluated as in atm_shBasis(), each function used as soon as it is known (no array
    // of 28 basis values: with one, the second SH pass at l <= 6 came out wrong on Mesa llvmpipe
    // 22.3, rows of texels 2-15 % off the CPU twin).
    vec4 f1 = atm_shFactors, f2 = atm_shFactors2;
    float bM[7] = float[7](1.0 - f1.w, f1.x, f1.y, f2.x, f2.y, f2.z, f2.w);
    vec3 aR = vec3(0.0), aM = vec3(0.0);
    float y = sqrt(max(0.0, 1.0 - x * x - mu * mu));
    float cm = 1.0, sm = 0.0, pmm = 1.0;
    for (int m = 0; m <= ATM_SH_BANDS; ++m) {
        float a = pmm, b = 0.0;
        for (int l = m; l <= ATM_SH_BANDS; ++l) {
            int k = l * (l + 1) / 2 + m;
            vec3 c = texture(u_atmShLut, vec3(uv, float(k))).rgb * (ATM_SH_NORM[k] * a * cm);
            aM += c * bM[l];
            if (l == 0) aR += c;
            if (l == 2) aR += c * f1.z;
            float next = (float(2 * l + 1) * mu * a - float(l + m) * b) / float(l + 1 - m);
            b = a;
            a = next;
        }
        pmm *= float(2 * m + 1);
        float cn = x * cm - y * sm;
        sm = x * sm + y * cm;
        cm = cn;
    }
    return sR * max(aR, vec3(0.0)) + sM * max(aM, vec3(0.0));
#else
    return (sR + sM) * texture(ATM_MULTISCATTERING_LUT, uv).rgb;
#endif
}
// What a view-ray march needs at the point t metres along a ray from height h (direction
// cosine mu, light at muS, view-light cosine nu), for a segment of length dt: scattering
// coefficients, true and delta-M extinction (see sky_model.cpp), the segment's integration
// factor, transmittance to the light and the orders >= 2 in-scattering. Shared by the sky-view
// and aerial-perspective marches.
struct RaySample {
    vec3 sR, sM, sigmaT, sigmaD, seg, Tl, ms;
};
// `groundAir`: the sample's height clamped to >= 0 (a ray towards the ground that the host's
// terrain stops, not the planet's sphere: the aerial-perspective volume).
RaySample atm_raySampleAir(float h, float mu, float muS, float nu, float t, float dt, float lightAngularRadius, bool groundAir) {
    RaySample q;
    float r = atm_bottom() + h;
    float hp = groundAir ? max(heightAt(h, mu, t), 0.0) : heightAt(h, mu, t);
    float rp = atm_bottom() + hp;
    float muSp = clamp((r * muS + t * nu) / rp, -1.0, 1.0);
    q.sR = atm_scatteringRayleigh(hp);
    q.sM = atm_scatteringMie(hp);
    q.sigmaT = atm_extinction(hp);
    q.sigmaD = q.sigmaT - atm_shFactors.w * q.sM;
    q.seg = atm_segmentFactor(q.sigmaD, dt);
    q.Tl = transmittanceToLight(hp, muSp, lightAngularRadius);
    float muP = clamp((r * mu + t) / rp, -1.0, 1.0);
    q.ms = msInscatter(hp, muP, muSp, nu, q.sR, q.sM);
    return q;
}
RaySample atm_raySample(float h, float mu, float muS, float nu, float t, float dt, float lightAngularRadius) {
    return atm_raySampleAir(h, mu, muS, nu, t, dt, lightAngularRadius, false);
}
struct Scattering {
    vec3 smooth_;     // Rayleigh single (phase applied), multiple scattering and ground
    vec3 mieNoPhase;  // Mie single scattering without its phase function
    vec3 transmittance;
    bool hitGround;
};
// groundMode: -1 decide from the geometry, 0 never hits, 1 hits (sky-view rows at the horizon).
Scattering integrateScattering(float h, float mu, float muS, float nu, float maxDistance, int steps, bool quadratic,
                               float lightAngularRadius, int groundMode) {
    Scattering o;
    o.smooth_ = vec3(0.0);
    o.mieNoPhase = vec3(0.0);
    h = clamp(h, 0.0, atm_thickness());
    o.hitGround = groundMode < 0 ? rayIntersectsGround(h, mu) : groundMode == 1;
    float d = o.hitGround ? distanceToBottom(h, mu) : distanceToTop(h, mu);
    if (d > maxDistance) o.hitGround = false;
    d = min(d, maxDistance);
    float p = quadratic ? 0.0 : atm_perigeeFraction(h, mu, d);
    float r = atm_bottom() + h;
    float phaseR = rayleighPhase(nu);
    vec3 thr = vec3(1.0), thrD = vec3(1.0);  // exact (background) and delta-M (scattered light)
#ifdef ATM_ECLIPSE
    float eclAxis = atm_eclMsAxisWeight(nu);
#endif
    for (int k = 0; k < steps && d > 0.0; ++k) {
        float s0 = float(k) / float(steps), s1 = float(k + 1) / float(steps), sm = (float(k) + 0.5) / float(steps);
        float dt = d * (atm_warp(s1, p) - atm_warp(s0, p)), t = d * atm_warp(sm, p);
        RaySample q = atm_raySample(h, mu, muS, nu, t, dt, lightAngularRadius);
#ifdef ATM_ECLIPSE
        vec2 ecl = atm_eclipseAt(atm_eclOrigin + t * atm_eclView);
        q.Tl *= ecl.x;
        q.ms *= mix(ecl.x, ecl.y, eclAxis);
#endif
        o.smooth_ += thrD * (q.sR * q.Tl * phaseR + q.ms) * q.seg;
        o.mieNoPhase += thrD * q.sM * q.Tl * q.seg;
        thr *= exp(-q.sigmaT * dt);
        thrD *= exp(-q.sigmaD * dt);
    }
    if (o.hitGround) {
        // The ground: Lambertian, lit by the light and by the sky.
        float muSg = clamp((r * muS + d * nu) / atm_bottom(), -1.0, 1.0);
#ifdef ATM_ECLIPSE
        // Direct light by the ground point's own visible fraction, the sky's by the model's.
        vec2 eg = atm_eclipseAt(atm_eclOrigin + d * atm_eclView);
        vec3 eDirect = transmittanceToLight(0.0, muSg, lightAngularRadius) * max(muSg, 0.0);
        vec3 eAll = atm_groundIrradiance(muSg, lightAngularRadius);
        o.smooth_ += thrD * (eDirect * eg.x + (eAll - eDirect) * eg.y) * atm_groundAlbedo.rgb / ATM_PI;
#else
        o.smooth_ += thrD * atm_groundIrradiance(muSg, lightAngularRadius) * atm_groundAlbedo.rgb / ATM_PI;
#endif
    }
    o.transmittance = thr;
    return o;
}
#endif

// Radiance per lux (without kLutScale) from a sky-view LUT pair for a view direction (mu, azimuth
// from the light in [0, pi], nu): the two halves of the latitude axis are never blended, so there
// is no band at the horizon. Twin of cpu::skyViewSample().
vec3 skyViewSampleH(sampler2D smoothLut, sampler2D mieLut, float thetaH, float mu, float az, float nu, float invScale) {
    vec2 size = vec2(textureSize(smoothLut, 0));
    vec2 uv = skyViewClampHalf(skyViewUvH(thetaH, mu, az, size), size);
    return (texture(smoothLut, uv).rgb + texture(mieLut, uv).rgb * miePhase(nu)) * invScale;
}
vec3 skyViewSample(sampler2D smoothLut, sampler2D mieLut, float h, float mu, float az, float nu, float invScale) {
    return skyViewSampleH(smoothLut, mieLut, atm_horizonZenith(h), mu, az, nu, invScale);
}
