// The cloud density function, one source for GLSL and C++ (welkin/glsl_cpp.hpp): cloud_density.glsl
// wraps it with its uniform block and samplers for the shaders, and the CPU twin (cpu:: in
// welkin/generators/cloud_density.hpp, which documents the contract and the sources: Papp 2018
// eqs. 5.1-5.5; Schneider & Vos 2015, Schneider 2017) compiles it in double on read-back textures.
// Every function takes the layer's parameters as a CloudLayer (the std140 block's seven vec4) and
// the textures it reads as samplers; textures are read at level 0.
//   real cld_layerAltitude(L, vec3 p)          altitude above the ground, m
//   vec2 cld_layerWeatherUv(L, vec3 p)         weather-map uv (repeat)
//   vec2 cloudHeightGradient(a, wb, wt, type)  the height profile (below)
//   real cld_layerDensity(L, weather, base, detail, vec3 p, int lod)  relative density in [0, 1]
//   vec2 cloudShellIntersectRadii(R, rb, rt, r, mu)  entry, exit (m) through the shell [rb, rt]
//   real cld_layerDepthAlong(L, weather, base, detail, vec3 p, vec3 dir, int n, real maxDist)
//                                              density x m from p along dir (cheap LOD, n steps)
//   real cld_layerCirrus(L, curl, vec2 xy)     cirrus relative density in [0, 1]
// p is ENU metres relative to the observer's ground point (planet centre at (0, 0, -R)).

#define CLOUD_LOD_CHEAP 0
#define CLOUD_LOD_FULL 1
// The shape constants (cloud_density.hpp's kShapeLo ... kDetailFlip document them; its C++ twin
// checks at compile time that they are these numbers).
#define CLD_SHAPE_LO 0.66
#define CLD_SHAPE_HI 0.93
#define CLD_CU_BASE 0.07
#define CLD_CU_TOP0 0.5
#define CLD_SC_BASE 0.1
#define CLD_SC_TOP0 0.65
#define CLD_EROSION 0.35
#define CLD_DETAIL_FLIP 4.0

// The block WelkinClouds of cloud_density.glsl (CloudLayerBlock in C++), member for member.
struct CloudLayer {
    vec4 radii;         // R, R + bottom, R + top, R + cirrus height (m)
    vec4 shape;         // coverage, detail scale, scattering (1/m), cirrus coverage
    vec4 weather;       // offset xy (m, mod extent), extent (m), 1 / extent
    vec4 noise;         // base, detail, curl periods (m), w cloud type (0 stratocumulus, 1 cumulus)
    vec4 scrollBase;    // base-noise scroll (m, mod period)
    vec4 scrollDetail;  // detail-noise scroll (m, mod period)
    vec4 cirrus;        // cirrus offset xy (m, mod curl period)
};

real cld_remap(real v, real lo, real hi, real newLo, real newHi) { return (v - lo) / (hi - lo) * (newHi - newLo) + newLo; }

real cld_layerAltitude(IN(CloudLayer) L, vec3 p) {
    real R = L.radii.x;
    vec3 q = p + vec3(0.0, 0.0, R);
    // |q| - R = (|q|^2 - R^2) / (|q| + R), with |q|^2 - R^2 = x^2 + y^2 + z^2 + 2 R z: no cancellation.
    return (dot(p, p) + 2.0 * R * p.z) / (length(q) + R);
}

vec2 cld_layerWeatherUv(IN(CloudLayer) L, vec3 p) { return (vec2(p) + vec2(L.weather)) * L.weather.w; }

// The height gradient at layer fraction a (0 bottom, 1 top) of a cloud whose base and top sit at
// fractions wb, wt of the layer (weather G, B), for cloud type `type` in [0, 1]: x the profile in
// [0, 1], y the position within the cloud's own vertical extent in [0, 1]. Two cloud types,
// blended by `type` (clouds.cloud_type), as Schneider & Vos 2015 and Schneider (GPU Pro 7, 2016)
// select a vertical density gradient per cloud type:
// - stratocumulus (0): a sheet between the weather map's base wb and top wt (Papp eq. 5.2's
//   H_scale), full within 10 % of its thickness above the base and rounded over its top 35 %;
// - cumulus (1): every base at the layer's bottom, the lifting condensation level that the
//   fair-weather cumulus of one air mass share (WMO International Cloud Atlas 2017, "Cumulus":
//   "flat bases"); the weather map's top wt (its domes) is the tower's height. Full density
//   within 7 % of the height above the base (a sharp, flat base), then a long taper over
//   50-100 % of the height: the coverage remap cuts ever more of the Perlin-Worley shape
//   upwards, leaving rounded turrets (cauliflower tops) rather than a flat lid.
vec2 cloudHeightGradient(real a, real wb, real wt, real type) {
    real tS = (a - wb) / max(wt - wb, 1e-3);
    real tC = a / max(wt, 1e-3);
    real pS = smoothstep(0.0, CLD_SC_BASE, tS) * (1.0 - smoothstep(CLD_SC_TOP0, 1.0, tS));
    real pC = smoothstep(0.0, CLD_CU_BASE, tC) * (1.0 - smoothstep(CLD_CU_TOP0, 1.0, tC));
    real t = clamp(mix(tS, tC, type), 0.0, 1.0);
    // H_gradient (Papp eq. 5.3): denser upwards in the cloud, 0.75 at its base to 1 at its top.
    return vec2(mix(pS, pC, type) * (0.75 + 0.25 * t), t);
}

real cld_layerDensity(IN(CloudLayer) L, IN(sampler2D) weather, IN(sampler3D) base, IN(sampler3D) detail, vec3 p, int lod) {
    real h = cld_layerAltitude(L, p);
    real bottom = L.radii.y - L.radii.x, top = L.radii.z - L.radii.x;
    if (h < bottom || h > top) return 0.0;
    real a = (h - bottom) / (top - bottom);  // Papp eq. 5.1: altitude fraction in the layer
    vec4 w = clamp(textureLod(weather, cld_layerWeatherUv(L, p), 0.0), 0.0, 1.0);
    // Coverage (Papp eq. 5.4): the weather map's density scaled by clouds.coverage.
    real cov = w.r * clamp(L.shape.x, 0.0, 1.0);
    if (cov <= 0.0) return 0.0;
    vec2 hg = cloudHeightGradient(a, w.g, w.b, clamp(L.noise.w, 0.0, 1.0));
    if (hg.x <= 0.0) return 0.0;
    // Base shape (Schneider & Vos 2015): the Perlin-Worley R eroded by its Worley fBm GBA,
    // remap(R, fbm - 1, 1, 0, 1); then stretched from its measured range [CLD_SHAPE_LO,
    // CLD_SHAPE_HI] to [0, 1] so that the coverage cut below bites, times the height gradient.
    vec4 n = textureLod(base, (vec3(p.x, p.y, h) + vec3(L.scrollBase)) / L.noise.x, 0.0);
    real fbm = 0.625 * n.g + 0.25 * n.b + 0.125 * n.a;
    real pw = cld_remap(n.r, fbm - 1.0, 1.0, 0.0, 1.0);
    real shape = clamp(cld_remap(pw, CLD_SHAPE_LO, CLD_SHAPE_HI, 0.0, 1.0), 0.0, 1.0) * hg.x;
    // Coverage cut into the shape: remap(shape, 1 - cov, 1, 0, 1) * cov = shape - (1 - cov): where
    // the weather map is thin only the shape's highest lobes survive (billowy edges).
    real baseDensity = max(shape + cov - 1.0, 0.0);
    if (lod == CLOUD_LOD_CHEAP || baseDensity <= 0.0) return baseDensity;
    // Erosion by the detail noise (Papp eq. 5.5, in Schneider's remap form): the Worley fBm near
    // the cloud's base (eroding the cells' cores leaves wisps), its inverse above (eroding the cell
    // borders leaves round billows: cauliflower), switching over the lowest 1/CLD_DETAIL_FLIP of
    // the cloud; strength CLD_EROSION x clouds.detail_scale.
    vec4 dn = textureLod(detail, (vec3(p.x, p.y, h) + vec3(L.scrollDetail)) / L.noise.y, 0.0);
    real dfbm = 0.625 * dn.r + 0.25 * dn.g + 0.125 * dn.b;
    real mod_ = mix(dfbm, 1.0 - dfbm, clamp(hg.y * CLD_DETAIL_FLIP, 0.0, 1.0));
    real e = min(CLD_EROSION * L.shape.y * mod_, 0.9);
    return clamp((baseDensity - e) / (1.0 - e), 0.0, 1.0);
}

// Both roots of |r + t d| = s (t^2 + 2 b t + c = 0, b = r mu, c = (r - s)(r + s)), near first, in
// the cancellation-free form (q = -(b + sign(b) sqrt(disc)), roots q and c / q; Press et al.,
// Numerical Recipes 5.6); disc < 0: no root (x > y returned).
vec2 cld_sphereRoots(real r, real mu, real s) {
    real b = r * mu, c = (r - s) * (r + s);
    real disc = b * b - c;
    if (disc < 0.0) return vec2(1.0, -1.0);
    real q = -(b + (b >= 0.0 ? sqrt(disc) : -sqrt(disc)));
    real t2 = q != 0.0 ? c / q : 0.0;
    return vec2(min(q, t2), max(q, t2));
}

// Entry and exit distances (m) through the shell [rb, rt] above a planet of radius R from radius
// r with cos zenith mu; the first crossing only; exit < 0: no crossing.
vec2 cloudShellIntersectRadii(real R, real rb, real rt, real r, real mu) {
    vec2 g = cld_sphereRoots(r, mu, R), lb = cld_sphereRoots(r, mu, rb), lt = cld_sphereRoots(r, mu, rt);
    if (r < rb) {
        if (r >= R && mu < 0.0 && g.x <= g.y) return vec2(-1.0);  // the ground comes first
        return vec2(lb.y, lt.y);
    }
    if (r <= rt) {
        if (mu < 0.0 && lb.x <= lb.y) return vec2(0.0, lb.x);  // leaves through the base
        return vec2(0.0, lt.y);
    }
    if (mu >= 0.0 || lt.x > lt.y) return vec2(-1.0);
    if (lb.x <= lb.y) return vec2(lt.x, lb.x);
    return vec2(lt.x, lt.y);
}

// The path integral of the relative density (density x m; x the extinction per unit density it
// is an optical depth) from p along the unit direction dir through the cumulus, at the full LOD
// (the density the view march and the path tracer see: the cheap LOD, without the detail
// erosion, overstated the depth through an eroded cumulus about twofold and left a cumulus lit
// from behind at half the path tracer's luminance, skyelements/clouds/README.md): n steps growing x1.5 (the first the shortest, so near structure is resolved; Schneider & Vos
// 2015 march ~6 samples over a few cloud cells), midpoint rule, over min(maxDist, the distance to
// the shell's exit along dir). The Clouds element's light march (towards a light) and its depth to
// the cloud's far side (away from it: clear air behind an isolated cumulus counts as clear) are
// this function; in a uniform deck both are exact.
real cld_layerDepthAlong(IN(CloudLayer) L, IN(sampler2D) weather, IN(sampler3D) base, IN(sampler3D) detail, vec3 p, vec3 dir, int n,
                         real maxDist) {
    vec3 q = p + vec3(0.0, 0.0, L.radii.x);
    real r = length(q);
    vec2 seg = cloudShellIntersectRadii(L.radii.x, L.radii.y, L.radii.z, r, dot(q, dir) / r);
    real total = seg.y > 0.0 ? min(maxDist, seg.y) : maxDist;
    // sum of 1.5^i for i < n: (1.5^n - 1) / 0.5
    real ds = total * 0.5 / (pow(1.5, real(n)) - 1.0);
    real t = 0.0;
    real depth = 0.0;
    for (int i = 0; i < n; ++i) {
        depth += cld_layerDensity(L, weather, base, detail, p + dir * (t + 0.5 * ds), CLOUD_LOD_FULL) * ds;
        t += ds;
        ds *= 1.5;
    }
    return depth;
}

real cld_layerCirrus(IN(CloudLayer) L, IN(sampler2D) curl, vec2 xy) {
    real cc = clamp(L.shape.w, 0.0, 1.0);
    if (cc <= 0.0) return 0.0;
    // The curl noise's RG (a divergence-free field, encoded 0.5 + 0.5 v) advects the lookup of
    // its B (the fBm potential): streaky, sheared fibres (SevenSky's high-altitude map, Papp 6.3).
    vec2 uv = (xy + vec2(L.cirrus)) / L.noise.z;
    vec4 c = textureLod(curl, uv, 0.0);
    vec2 warp = (vec2(c) * 2.0 - 1.0) * 0.05;
    real n = textureLod(curl, uv + warp, 0.0).b;
    return clamp(n + cc - 1.0, 0.0, 1.0);
}
