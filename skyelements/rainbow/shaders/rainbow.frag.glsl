// The Rainbow's per-pixel pass (the offline path, and every projection): the curtain
// (rainbow_curtain.glsl) and, with WELKIN_RAINBOW_CLOUDS, the rain under the clouds of the
// weather map, composited as radiance + transmittance.
// Needs engine/camera.glsl, engine/composite.glsl, optics/mie_angle.glsl, cloud_shadow.glsl and
// rainbow_curtain.glsl before it.
#ifdef WELKIN_RAINBOW_CLOUDS
layout(binding = WELKIN_BINDING_CLOUD_WEATHER_MAP) uniform sampler2D u_weather;  // A: rain density
uniform float u_weatherExtent;   // m
uniform vec2 u_weatherOffset;    // m
uniform float u_cloudBottom, u_cloudTop;  // m above the ground
uniform float u_cloudType;       // clouds.cloud_type: 0 stratocumulus (base from the map's G), 1 cumulus (base at the bottom)
uniform float u_rainRateScale;   // mm/h at weather A = 1 (clouds.rain_density x 20)
uniform vec3 u_scaPerWater, u_extPerWater;  // 1/m per kg/m^3 of liquid water
uniform float u_marchMax;        // m: farthest rain sample
#endif

void main() {
    vec3 dir;
    if (!welkin_viewDirection(welkin_pixel(), dir)) discard;
    vec3 radiance = vec3(0.0), transmittance = vec3(1.0), phase;
    float s = rainbow_curtain(dir, radiance, transmittance, phase);
    float sinEl = rainbow_sinEl();

#ifndef WELKIN_RAINBOW_CLOUDS
    if (!(s > 0.0)) discard;
#else
    if (!(s > 0.0)) {
        float cosTheta = clamp(dot(dir, u_light), -1.0, 1.0);
        phase = texture(u_phase, welkin_mieUFromAngle(acos(cosTheta))).rgb;
    }
    // (b) Rain under the clouds of the weather map: A x rate scale, from the cloud's base to the
    // ground. 32 steps to u_marchMax (or the ray's exit from below the layer's top).
    {
        float tEnd = u_marchMax;
        if (dir.z > 1e-4) tEnd = min(tEnd, (u_cloudTop - u_obsHeight) / dir.z);
        if (dir.z < -1e-4) tEnd = min(tEnd, -u_obsHeight / dir.z);
        const int N = 32;
        float dt = max(tEnd, 0.0) / float(N);
        for (int i = 0; i < N; ++i) {
            float t = (float(i) + 0.5) * dt;
            vec3 p = vec3(t * dir.xy, u_obsHeight + t * dir.z);
            vec4 w = texture(u_weather, (p.xy + u_weatherOffset) / u_weatherExtent);
            // The cloud's base, as the density function places it (cloud_density.glsl's height
            // gradient): the map's G for a stratocumulus sheet, the layer's bottom for cumulus.
            float base = u_cloudBottom + mix(w.g, 0.0, clamp(u_cloudType, 0.0, 1.0)) * (u_cloudTop - u_cloudBottom);
            float rate = w.a * u_rainRateScale;
            if (rate <= 0.0 || p.z > base || p.z < 0.0) continue;
            float water = 0.0889e-3 * pow(rate, 0.84);   // kg/m^3, Marshall-Palmer (mie_tables.hpp)
            vec3 bs = u_scaPerWater * water, be = u_extPerWater * water;
            // Light through the rain on its way to the point: down the column from the cloud's base,
            // or in from the side of the shower, taken as 1 km away (a shower cell's radius; the
            // weather map is not marched towards the light).
            vec3 sun = exp(-be * min((base - p.z) / max(sinEl, 0.05), 1000.0)) * rainbow_cloudShadow(p);
            vec3 stepT = exp(-be * dt);
            radiance += transmittance * (u_E * phase * sun + u_skyE * (0.5 / 3.14159265)) * bs * (1.0 - stepT) /
                        max(be, vec3(1e-12));
            transmittance *= stepT;
        }
    }
#endif
    welkin_output(radiance, transmittance);
}
