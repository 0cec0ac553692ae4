// The real-time sky model in GLSL; its optical functions and LUT parameterisations are
// atmosphere.shared.glsl (included below), which sky_model.cpp compiles in double as the CPU twin;
// the view-ray march is atmosphere_view.shared.glsl (included below with the LUTs it reads), the
// same text as cpu::integrate(). Include it before any pass of the sky. The atmosphere arrives in a std140 uniform block at binding 1
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
vec3 skyViewTexelView(float h, vec2 uv, vec2 size, float muS) { return skyViewTexelViewS(atm_horizonS(h), uv, size, muS); }

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
// The SH bands ATM_SH_BANDS of the directional field (SkyQuality::shBands, set by the pass's
// program; 4 if not) and ATM_SH_COEFFICIENTS: atmosphere.shared.glsl.
const float ATM_SH_GROUND_LAYER = float(ATM_SH_COEFFICIENTS);

// What the view-ray march (atmosphere_view.shared.glsl) reads: the multiple-scattering field
// (Psi_ms or, with ATM_MS_DIRECTIONAL, the SH LUT and its ground layer), the block's SH factors
// and the eclipse's shadow (ATM_ECLIPSE, the march's origin and direction atm_eclOrigin/View).
bool atm_msDirectional() {
#ifdef ATM_MS_DIRECTIONAL
    return true;
#else
    return false;
#endif
}
int atm_shBands() { return ATM_SH_BANDS; }
vec4 atm_shFactorsLo() { return atm_shFactors; }
vec4 atm_shFactorsHi() { return atm_shFactors2; }
vec2 atm_msUv(float h, float muS) { return multiScatteringUv(h, muS, vec2(textureSize(ATM_MULTISCATTERING_LUT, 0))); }
vec3 atm_msLutUv(vec2 uv) { return texture(ATM_MULTISCATTERING_LUT, uv).rgb; }
#ifdef ATM_MS_DIRECTIONAL
vec3 atm_shLutAt(vec2 uv, int k) { return texture(u_atmShLut, vec3(uv, float(k))).rgb; }
vec3 atm_shGroundAt(float muS) {
    vec2 size = vec2(textureSize(u_atmShLut, 0).xy);
    return texture(u_atmShLut, vec3(multiScatteringUv(0.0, muS, vec2(size.x, 2.0)).x, 0.5 / size.y, ATM_SH_GROUND_LAYER)).rgb;
}
#else
vec3 atm_shLutAt(vec2 uv, int k) { return vec3(0.0); }
vec3 atm_shGroundAt(float muS) { return vec3(0.0); }
#endif
#ifdef ATM_ECLIPSE
bool atm_eclipseMarch() { return true; }
vec2 atm_eclipseAlong(float t) { return atm_eclipseAt(atm_eclOrigin + t * atm_eclView); }
#else
bool atm_eclipseMarch() { return false; }
vec2 atm_eclipseAlong(float t) { return vec2(1.0); }
#endif
// msInscatter(), atm_groundIrradiance(), RaySample, atm_raySample(), atm_raySampleAir(),
// atm_aerialSlice(), Scattering, integrateScattering(): the CPU twins (sky_model.cpp) compile the
// same text in double.
#include "atmosphere_view.shared.glsl"
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
