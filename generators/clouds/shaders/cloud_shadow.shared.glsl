// The cloud shadow map's column, one source for the pass (cloud_shadow_map.glsl includes it after
// cloud_density.glsl) and C++ (cpu::cloudShadowTransmittance() in cloud_shadow.cpp compiles it in
// double inside a struct whose members are the density it reads; welkin/glsl_cpp.hpp). The
// includer provides cloudDensity(p, lod) and cirrusDensity(xy) (cloud_density.glsl's wrappers of
// the shared density: relative density in [0, 1] at ENU metres relative to the observer's ground
// point, the planet's centre at (0, 0, -R)) and CLOUD_LOD_CHEAP.

// Distance along the unit ray L from the ground point (xy, 0) to where it leaves the sphere of
// radius R + H (H >= 0): the root of t^2 + 2 b t + q = 0 with b = xy.L + R Lz, q = |xy|^2 -
// H (2R + H), in the form without cancellation (float: R ~ 6e6 m).
real cld_exitDistance(vec2 xy, vec3 L, real R, real H) {
    real b = dot(xy, vec2(L)) + R * L.z;
    real q = dot(xy, xy) - H * (2.0 * R + H);
    real s = sqrt(max(b * b - q, 0.0));
    return b > 0.0 ? -q / (b + s) : s - b;
}

// Optical depth towards the light L (unit, ENU, z >= 0) above the ground point xy (m): the cumulus
// layer (radii.x ground, .y bottom, .z top, .w cirrus radius, m; shape.z extinction per unit
// density, 1/m; shape.x coverage, shape.w cirrus amount) marched in `steps` midpoints between its
// two spheres when `clouds` (its textures bound), plus the cirrus sheet's depth cirrusTau x its
// density, slanted by its cosine of zenith, when `cirrus`.
real cld_shadowOpticalDepth(vec2 xy, vec3 L, vec4 radii, vec4 shape, int steps, bool clouds, bool cirrus, real cirrusTau) {
    real R = radii.x;
    real tau = 0.0;
    if (clouds && shape.x > 0.0 && shape.z > 0.0) {
        real t0 = cld_exitDistance(xy, L, R, radii.y - R);
        real t1 = cld_exitDistance(xy, L, R, radii.z - R);
        real dt = (t1 - t0) / real(steps);
        for (int i = 0; i < steps; ++i) {
            real t = t0 + (real(i) + 0.5) * dt;
            tau += shape.z * cloudDensity(vec3(xy, 0.0) + t * L, CLOUD_LOD_CHEAP) * dt;
        }
    }
    if (cirrus && cirrusTau > 0.0 && shape.w > 0.0) {
        // Where the ray crosses the cirrus sphere rc, and its cosine of zenith there:
        // sqrt(1 - (|c x L| / rc)^2) with c = (xy, R) from the planet's centre.
        real rc = radii.w;
        real tc = cld_exitDistance(xy, L, R, rc - R);
        vec3 k = cross(vec3(xy, R), L);
        real mu = sqrt(max(1.0 - dot(k, k) / (rc * rc), 0.0));
        tau += cirrusTau * cirrusDensity(xy + tc * vec2(L)) / max(mu, 1e-3);
    }
    return tau;
}
