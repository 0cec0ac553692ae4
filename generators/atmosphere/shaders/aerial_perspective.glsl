// Aerial perspective volume pass (compute): for each direction of the sky-view parameterisation
// (azimuth from the Sun, horizon-dense latitude) one ray is marched from the observer and, at
// the end of each distance slice k (d_k = D ((k + 1) / N)^2), the in-scattered radiance per lux
// (times kLutScale) and the transmittance so far are stored. The slice's march is atm_aerialSlice() of
// atmosphere_view.shared.glsl, which cpu::aerialTexel() compiles in double. Needs
// atmosphere.glsl (ATM_USE_TRANSMITTANCE, ATM_USE_MULTISCATTERING) before it.
layout(local_size_x = 8, local_size_y = 8, local_size_z = 1) in;
layout(rgba32f, binding = WELKIN_BINDING_LUT_IMAGE) uniform writeonly image3D u_inscatter;
layout(rgba32f, binding = WELKIN_BINDING_SECOND_LUT_IMAGE) uniform writeonly image3D u_transmittance;
uniform float u_h;
uniform float u_muS;
uniform int u_size;        // N
uniform int u_substeps;    // samples per slice
uniform float u_maxDistance;
uniform float u_scale;
uniform float u_angular;
uniform int u_groupOffset;  // first work group of this dispatch (a table built over several runs)
uniform int u_groupsX;      // work groups per row of the whole table

void main() {
    int g = int(gl_WorkGroupID.x) + u_groupOffset;
    ivec2 ij = ivec2(g % u_groupsX, g / u_groupsX) * 8 + ivec2(gl_LocalInvocationID.xy);
    if (ij.x >= u_size || ij.y >= u_size) return;
    float n = float(u_size);
    vec3 view = skyViewTexelView(u_h, (vec2(ij) + 0.5) / n, vec2(n), u_muS);  // atmosphere.shared.glsl, as cpu::aerialTexel()
    float mu = view.x, nu = view.z;
    // Rays towards the ground are stopped by the host's geometry (its terrain), not by the
    // planet's sphere: they run on to the last slice through air no lower than the ground (a
    // host's ground point 20 km away, seen 0.5 deg down from 2 m, is in near-ground air all
    // the way, not below it; an observer at height 0 would otherwise get no air at all).
    bool ground = ij.y < u_size / 2;
    float dEnd = ground ? u_maxDistance : distanceToTop(u_h, mu);
    float phaseR = rayleighPhase(nu), phaseM = miePhase(nu);
    vec3 L = vec3(0.0), thr = vec3(1.0), thrD = vec3(1.0);  // exact and delta-M (scattered light)
    float t0 = 0.0;
    for (int k = 0; k < u_size; ++k) {
        float f = float(k + 1) / n;
        float t1 = min(u_maxDistance * f * f, dEnd);
        atm_aerialSlice(u_h, mu, u_muS, nu, t0, t1, u_substeps, u_angular, ground, phaseR, phaseM, L, thr, thrD);
        t0 = max(t0, t1);
        imageStore(u_inscatter, ivec3(ij, k), vec4(L * u_scale, 1.0));
        imageStore(u_transmittance, ivec3(ij, k), vec4(thr, 1.0));
    }
}
