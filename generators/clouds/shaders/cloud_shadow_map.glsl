// The cloud shadow map pass (fragment, one texel per fragment): twin of
// cpu::cloudShadowTransmittance() (generators/clouds/src/cloud_shadow.cpp; the model is in
// cloud_shadow.hpp). Distances in metres, the planet's centre at the origin of the march frame.
layout(binding = WELKIN_BINDING_CLOUD_WEATHER_MAP) uniform sampler2D u_weather;  // repeat, linear
uniform ivec2 u_size;          // map texels
uniform float u_extent;        // m, side of the mapped square
uniform vec2 u_weatherOffset;  // m (clouds.weather_offset_m)
uniform float u_weatherExtent; // m
uniform float u_bottom, u_top; // m above the ground
uniform float u_coverage;      // [0, 1]
uniform float u_sigma;         // 1/m at density 1
uniform float u_cirrusTau;     // vertical optical depth of the cirrus (kCirrusOpticalDepth x coverage)
uniform float u_cirrusHeight;  // m
uniform float u_radius;        // planet radius, m
uniform vec3 u_light;          // unit, ENU, z >= 0
uniform int u_steps;
uniform bool u_hasWeather;
out vec4 o_shadow;

// Distance along the unit ray L from the ground point (xy, R) (planet centre at the origin) to
// where it leaves the sphere of radius R + H (H >= 0): the root of t^2 + 2 b t + q = 0 with
// b = xy.L + R Lz, q = |xy|^2 - H (2R + H), in the form without cancellation (float: |c| ~ 6e6 m).
float exitDistance(vec2 xy, vec3 L, float R, float H) {
    float b = dot(xy, L.xy) + R * L.z;
    float q = dot(xy, xy) - H * (2.0 * R + H);
    float s = sqrt(max(b * b - q, 0.0));
    return b > 0.0 ? -q / (b + s) : s - b;
}

float density(vec2 xy, float h) {
    vec4 w = texture(u_weather, (xy + u_weatherOffset) / u_weatherExtent);
    float hb = u_bottom + w.g * (u_top - u_bottom), ht = u_bottom + w.b * (u_top - u_bottom);
    if (ht <= hb || u_coverage <= 0.0) return 0.0;
    float hs = 4.0 * (h - hb) * (ht - h) / ((ht - hb) * (ht - hb));
    float dcov = max(w.r + u_coverage - 1.0, 0.0) / u_coverage;
    return clamp(dcov * max(hs, 0.0), 0.0, 1.0);
}

void main() {
    vec2 xy = (gl_FragCoord.xy / vec2(u_size) - 0.5) * u_extent;
    // The march frame: the planet's centre at the origin, the ground point at (xy, R).
    float R = u_radius;
    float tau = 0.0;
    if (u_hasWeather && u_coverage > 0.0 && u_sigma > 0.0) {
        float t0 = exitDistance(xy, u_light, R, u_bottom), t1 = exitDistance(xy, u_light, R, u_top);
        float dt = (t1 - t0) / float(u_steps);
        for (int i = 0; i < u_steps; ++i) {
            float t = t0 + (float(i) + 0.5) * dt;
            // Height above the ground without cancellation: |p|^2 - R^2 = |q|^2 + t Lz (2R + t Lz)
            // with q = xy + t L.xy, and h = (|p|^2 - R^2) / (|p| + R).
            vec2 q = xy + t * u_light.xy;
            float num = dot(q, q) + t * u_light.z * (2.0 * R + t * u_light.z);
            float h = num / (sqrt(dot(q, q) + (R + t * u_light.z) * (R + t * u_light.z)) + R);
            tau += u_sigma * density(q, h) * dt;
        }
    }
    if (u_cirrusTau > 0.0) {
        // The ray's cosine of zenith where it crosses the sphere R + Hc: sqrt(1 - (|c x L| / rc)^2).
        float rc = R + u_cirrusHeight;
        vec3 k = cross(vec3(xy, R), u_light);
        float mu = sqrt(max(1.0 - dot(k, k) / (rc * rc), 0.0));
        tau += u_cirrusTau / max(mu, 1e-3);
    }
    o_shadow = vec4(exp(-tau), 0.0, 0.0, 1.0);
}
