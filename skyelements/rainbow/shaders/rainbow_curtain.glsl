// The Rainbow's rain curtain: single scattering of the Sun's (or Moon's) light by rain drops along
// a view direction, with the drops' Mie phase function (rain.phase_lut). Shared by the per-pixel
// pass (rainbow.frag.glsl) and the direction cache's fill (rainbow_cache.comp.glsl).
// Needs optics/mie_angle.glsl and generators/clouds/cloud_shadow.glsl before it.
layout(binding = WELKIN_BINDING_MIE_PHASE_LUT) uniform sampler1D u_phase;  // rgb: 1/sr per channel
uniform vec3 u_light;        // unit vector to the light, world ENU
uniform vec3 u_E;            // light's illuminance at the rain, lux per channel
uniform vec3 u_sca;          // curtain: scattering coefficient, 1/m per channel
uniform float u_ext;         // curtain: extinction coefficient, 1/m (grey: the channels' luminance mean;
                             // for drops of r >= 5 um every channel is within 1 % of it (tested: < 2 %))
uniform float u_dist;        // curtain: horizontal distance of its near face, m
uniform float u_depth;       // curtain: horizontal depth, m
uniform float u_height;      // curtain: top above the ground, m
uniform vec2 u_axis;         // curtain: horizontal unit vector to its middle (the anti-light azimuth)
uniform float u_cosHalfWidth;// curtain: cos of its azimuthal half-width
uniform float u_obsHeight;   // observer above the ground, m
uniform vec3 u_skyE;         // the sky's diffuse horizontal illuminance, lux (0 without a Sky)
uniform int u_shadow;        // 1: the clouds' shadow (cloud_shadow.glsl) dims the light reaching the rain

// The clouds' transmittance of the direct light to a point of the rain at p (x, y from the
// observer, z above the ground; m); 1 without a shadow map. cloud_shadow.glsl takes ENU from the
// observer: z - the observer's height.
float rainbow_cloudShadow(vec3 p) {
    return u_shadow != 0 ? welkin_cloudShadow(vec3(p.xy, p.z - u_obsHeight)) : 1.0;
}
// Optical depth along the light from a point at height z and horizontal distance rho into the
// curtain: out through its top or back through its near face, whichever is shorter (the light
// comes from the observer's side of the curtain).
float lightPath(float z, float rho, float sinEl, float cosEl) {
    float up = (u_height - z) / max(sinEl, 1e-3);
    // No near face when the rain reaches the observer's vertical (u_dist = 0: a layer, not a curtain).
    float face = u_dist > 0.0 ? (rho - u_dist) / max(cosEl, 1e-3) : 1e30;
    return max(min(up, face), 0.0);
}

// The sine and cosine of the light's elevation (0 below the horizon: the light grazes).
float rainbow_sinEl() { return max(u_light.z, 0.0); }

// The curtain along the unit view direction `dir` (world ENU): adds its radiance (cd/m^2) to
// `radiance`, multiplies `transmittance` by the rain's (grey) transmittance, sets `phase` to the
// phase LUT's value for the direction (1/sr per channel; 0 where the ray misses the curtain) and
// returns the ray's length in the curtain, m (0: missed).
float rainbow_curtain(vec3 dir, inout vec3 radiance, inout vec3 transmittance, out vec3 phase) {
    float sinEl = max(u_light.z, 0.0), cosEl = sqrt(max(1.0 - u_light.z * u_light.z, 0.0));
    float s = 0.0;  // length of the view ray in the curtain, m

    // (a) The curtain: a sector of a cylindrical shell around the observer.
    float h = length(dir.xy);
    // Segment first; the phase lookup (acos, texture) only where some rain is: a ray missing the
    // curtain (the ground, the sky above it, outside its sector) is discarded (no blend either).
    phase = vec3(0.0);
    bool inSector = h > 1e-6 ? dot(dir.xy / h, u_axis) >= u_cosHalfWidth : u_dist <= 0.0;
    if (inSector && max(u_sca.r, max(u_sca.g, u_sca.b)) > 0.0) {
        float t0 = h > 1e-6 ? u_dist / h : 0.0;
        float t1 = h > 1e-6 ? (u_dist + u_depth) / h : 1e7;
        // Heights in [0, u_height] along z(t) = u_obsHeight + t dir.z.
        if (abs(dir.z) > 1e-7) {
            float ta = (0.0 - u_obsHeight) / dir.z, tb = (u_height - u_obsHeight) / dir.z;
            t0 = max(t0, min(ta, tb));
            t1 = min(t1, max(ta, tb));
        } else if (u_obsHeight < 0.0 || u_obsHeight > u_height) {
            t1 = t0;
        }
        t0 = max(t0, 0.0);
        s = t1 - t0;
        if (s > 0.0) {
            // Scattering angle between the light's travel (-u_light) and the scattered ray (-dir)
            // toward the observer: cos = dot(-u_light, -dir); pi at the anti-solar point.
            float cosTheta = clamp(dot(dir, u_light), -1.0, 1.0);
            phase = texture(u_phase, welkin_mieUFromAngle(acos(cosTheta))).rgb;
            // The light's optical depth is linear in t on each branch of lightPath: take the branch
            // at the segment's middle, l(t) = l0 + dl (t - t0); then
            //   L = E p b_sca int_0^s exp(-b_ext (t' + l0 + dl t')) dt'
            //     = E p b_sca exp(-b_ext l0) (1 - exp(-b_ext (1 + dl) s)) / (b_ext (1 + dl)).
            float tm = 0.5 * (t0 + t1);
            float zm = u_obsHeight + tm * dir.z, rm = tm * h;
            float up = (u_height - zm) / max(sinEl, 1e-3);
            float face = u_dist > 0.0 ? (rm - u_dist) / max(cosEl, 1e-3) : 1e30;
            float dl = up < face ? -dir.z / max(sinEl, 1e-3) : h / max(cosEl, 1e-3);
            float l0 = lightPath(u_obsHeight + t0 * dir.z, t0 * h, sinEl, cosEl);
            dl = max(dl, -0.999);
            // Grey extinction: three scalar exponentials per pixel instead of nine.
            float k = u_ext * (1.0 + dl);
            float integral = (1.0 - exp(-k * s)) / max(k, 1e-12);
            // The clouds' shadow at the segment's middle (the curtain is thin next to the shadows).
            float cs = rainbow_cloudShadow(vec3(tm * dir.xy, zm));
            radiance += u_E * phase * u_sca * (exp(-u_ext * l0) * integral * cs);
            float Ts = exp(-u_ext * s);
            transmittance *= Ts;
            // Skylight scattered once: a uniform sky of radiance E_d / pi over the upper hemisphere
            // seen through a phase function that puts half its weight there gives the source
            // b_sca E_d / (2 pi); along the ray, times (1 - T) / b_ext.
            radiance += u_skyE * (0.5 / 3.14159265) * (u_sca / max(u_ext, 1e-12)) * (1.0 - Ts);
        }
    }

    return s;
}
