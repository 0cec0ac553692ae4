// The cloud shadow map pass (fragment, one texel per fragment): twin of
// cpu::cloudShadowTransmittance() (generators/clouds/src/cloud_shadow.cpp; the model is in
// cloud_shadow.hpp). Needs cloud_density.glsl (the shared density, its block and textures) before
// it. Positions: ENU metres relative to the observer's ground point (cloud_density.glsl's frame).
uniform ivec2 u_size;     // map texels
uniform float u_extent;   // m, side of the mapped square
uniform float u_cirrusTau;  // optical depth of the cirrus at relative density 1 (kCirrusOpticalDepth)
uniform vec3 u_light;     // unit, ENU, z >= 0
uniform int u_steps;
uniform bool u_hasClouds; // the weather map and the base noise are bound
uniform bool u_hasCurl;   // the curl noise (the cirrus) is bound
out vec4 o_shadow;

// Distance along the unit ray L from the ground point (xy, 0) (the planet's centre at (0, 0, -R))
// to where it leaves the sphere of radius R + H (H >= 0): the root of t^2 + 2 b t + q = 0 with
// b = xy.L + R Lz, q = |xy|^2 - H (2R + H), in the form without cancellation (float: R ~ 6e6 m).
float exitDistance(vec2 xy, vec3 L, float R, float H) {
    float b = dot(xy, L.xy) + R * L.z;
    float q = dot(xy, xy) - H * (2.0 * R + H);
    float s = sqrt(max(b * b - q, 0.0));
    return b > 0.0 ? -q / (b + s) : s - b;
}

void main() {
    vec2 xy = (gl_FragCoord.xy / vec2(u_size) - 0.5) * u_extent;
    float R = cld_radii.x;
    float tau = 0.0;
    if (u_hasClouds && cld_shape.x > 0.0 && cld_shape.z > 0.0) {
        float t0 = exitDistance(xy, u_light, R, cld_radii.y - R), t1 = exitDistance(xy, u_light, R, cld_radii.z - R);
        float dt = (t1 - t0) / float(u_steps);
        for (int i = 0; i < u_steps; ++i) {
            float t = t0 + (float(i) + 0.5) * dt;
            tau += cld_shape.z * cloudDensity(vec3(xy, 0.0) + t * u_light, CLOUD_LOD_CHEAP) * dt;
        }
    }
    if (u_hasCurl && u_cirrusTau > 0.0 && cld_shape.w > 0.0) {
        // Where the ray crosses the cirrus sphere R + Hc, and its cosine of zenith there:
        // sqrt(1 - (|c x L| / rc)^2) with c = (xy, R) from the planet's centre.
        float rc = cld_radii.w;
        float tc = exitDistance(xy, u_light, R, rc - R);
        vec3 k = cross(vec3(xy, R), u_light);
        float mu = sqrt(max(1.0 - dot(k, k) / (rc * rc), 0.0));
        tau += u_cirrusTau * cirrusDensity(xy + tc * u_light.xy) / max(mu, 1e-3);
    }
    o_shadow = vec4(exp(-tau), 0.0, 0.0, 1.0);
}
