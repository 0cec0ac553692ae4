// The clouds' shadow on the atmosphere's in-scattering along a view ray, one source for GLSL
// (cloud_sky_shadow.glsl, after atmosphere.glsl) and C++ (cloud_sky_shadow.cpp compiles it in
// double inside a struct: cpu::skyShadowLoss()). The model: skyelements/clouds/README.md and
// cloud_sky_shadow.glsl's header.
//
// What the includer provides: atmosphere.glsl's block wrappers atm_bottom(), atm_thickness(),
// atm_groundAlbedoRgb(), atm_extinction(h), atm_scatteringRayleigh(h), atm_scatteringMie(h),
// distanceToTop(h, mu), distanceToBottom(h, mu), heightAt(h, mu, t), transmittanceToLight(h, muS,
// angularRadius) and atmosphere.shared.glsl (rayleighPhase(), atm_segmentFactor(), ATM_PI); and
// cld_skyShadowMapAt(uv): the shadow map's transmittance at uv (the clouds.shadow_map texture,
// linear, clamp to edge). Units: m, radiance per lux of the light.
//
// The shadow's inputs, as the pass's uniforms: mapLight the light the map was built for (unit ENU,
// z >= 0), map = (shift x, shift y, 1 / extent, extent) (m), layer = (cloud base, top) above the
// ground (m).

// Transmittance of the direct light at a point xy (ENU, m, horizontal from the observer) at height
// hp above the ground. Below the cloud base: the map's value at the ground point the light ray
// through the point reaches (the map holds the transmittance from the ground up through the whole
// layer, and nothing below the base attenuates). Inside the layer: that value (traced from the
// base) to the power of the fraction of the layer above the point (optical depth taken as uniform
// in height: a cheap approximation where the clouds themselves are drawn). Above the top and
// outside the map: lit (1).
real cld_skyShadowAt(vec2 xy, real hp, vec3 mapLight, vec4 map, vec2 layer) {
    if (hp >= layer.y) return 1.0;
    vec2 g = xy - min(hp, layer.x) * vec2(mapLight.x, mapLight.y) / max(mapLight.z, 1e-3);
    vec2 uv = (g + vec2(map.x, map.y)) * map.z + 0.5;
    if (any(lessThan(uv, vec2(0.0))) || any(greaterThan(uv, vec2(1.0)))) return 1.0;
    real s = cld_skyShadowMapAt(uv);
    if (hp > layer.x) s = exp2(log2(max(s, 1e-30)) * (layer.y - hp) / (layer.y - layer.x));
    return s;
}

// The single scattering of the light (unit ENU `light`, angular radius `angular`) that the clouds'
// shadow removes along the view ray `dir` (unit ENU) from the observer at height hObs: lossR the
// Rayleigh part with its phase (and the ground's directly lit part where the ray ends on the
// ground inside the map: `ground`, the sky-view rows below the horizon), lossM the Mie part
// without its phase, per lux; `steps` midpoint samples over the part of the ray that can be
// shadowed, delta-M extinction (fraction deltaM of the Mie scattering) as the sky-view march.
void cld_skyShadowLoss(real hObs, vec3 dir, bool ground, vec3 light, real angular, vec3 mapLight, vec4 map, vec2 layer, int steps,
                       real deltaM, OUT(vec3) lossR, OUT(vec3) lossM) {
    real mu = clamp(dir.z, -1.0, 1.0);
    real sinV = sqrt(max(1.0 - mu * mu, 0.0));
    real muS = light.z;
    real nu = clamp(dot(dir, light), -1.0, 1.0);
    real h = clamp(hObs, 0.0, atm_thickness());
    real d = ground ? distanceToBottom(h, mu) : distanceToTop(h, mu);
    // Where the ray can be shadowed: below the cloud top, and while the ground point its light
    // ray reaches can still be inside the map (beyond: lit, so not marched).
    real r = atm_bottom() + h;
    real top = atm_bottom() + layer.y;
    real tEnd = d;
    if (!ground) {
        // Up to the cloud-top sphere (from inside it; a ray that misses the ground only climbs
        // past its perigee), nothing from above it. A ray down to the ground stays below the top.
        real b = r * mu, c = r * r - top * top;
        tEnd = h < layer.y ? min(tEnd, -b + sqrt(max(b * b - c, 0.0))) : 0.0;
    }
    // The map's square (half-diagonal), moved by the wind's shift since it was built, seen from
    // points up to the cloud base (displaced along the light by base x tan(light zenith)).
    real reach = 0.7072 * map.w + length(vec2(map.x, map.y)) + layer.x * length(vec2(mapLight.x, mapLight.y)) / max(mapLight.z, 1e-3) + 1.0;
    tEnd = min(tEnd, reach / max(sinV, 1e-4));
    lossR = vec3(0.0);
    lossM = vec3(0.0);
    real phaseR = rayleighPhase(nu);
    vec3 thrD = vec3(1.0);
    real dt = tEnd / real(steps);
    for (int k = 0; k < steps && tEnd > 0.0; ++k) {
        real t = (real(k) + 0.5) * dt;
        real hp = heightAt(h, mu, t);
        real rp = atm_bottom() + hp;
        real muSp = clamp((r * muS + t * nu) / rp, -1.0, 1.0);
        vec3 sR = atm_scatteringRayleigh(hp), sM = atm_scatteringMie(hp);
        vec3 sigmaD = atm_extinction(hp) - deltaM * sM;  // delta-M, as the sky-view march
        vec3 seg = atm_segmentFactor(sigmaD, dt);
        real lost = 1.0 - cld_skyShadowAt(t * vec2(dir.x, dir.y), hp, mapLight, map, layer);
        vec3 tl = transmittanceToLight(hp, muSp, angular) * (lost * thrD) * seg;
        lossR += sR * tl * phaseR;
        lossM += sM * tl;
        thrD *= exp(-sigmaD * dt);
    }
    if (ground && tEnd >= d && d >= 0.0) {  // d = 0: the observer's own ground (standing on it)
        // The ground reached inside the map: its directly lit part, shadowed.
        real muSg = clamp((r * muS + d * nu) / atm_bottom(), -1.0, 1.0);
        real lost = 1.0 - cld_skyShadowAt(d * vec2(dir.x, dir.y), 0.0, mapLight, map, layer);
        lossR += thrD * transmittanceToLight(0.0, muSg, angular) * max(muSg, 0.0) * lost * atm_groundAlbedoRgb() / ATM_PI;
    }
}
