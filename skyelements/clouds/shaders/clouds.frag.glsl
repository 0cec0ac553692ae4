// The Clouds element's pass: the cumulus shell ray-marched per pixel and the cirrus layer, lit by
// the Sun and the Moon through the atmosphere's transmittance (atmosphere.glsl), with ambient light
// from the sky's irradiance. Needs atmosphere.glsl (ATM_USE_TRANSMITTANCE) and the clouds'
// cloud_density.glsl before it. Sources of the model: skyelements/clouds/README.md and clouds.hpp.
//
// Frame: ENU at the observer's ground point, metres; observer at (0, 0, u_h), planet centre at
// (0, 0, -R). Radiance cd/m^2, illuminance lux.
uniform float u_h;           // observer height above the ground, m
uniform vec3 u_sunDir;       // unit vectors to the lights, ENU
uniform vec3 u_moonDir;
uniform vec3 u_sunE;         // illuminance above the atmosphere, lux per channel (0: no light)
uniform vec3 u_moonE;
uniform vec3 u_ambientE;     // the clear sky's diffuse horizontal illuminance at the ground, lux
uniform vec3 u_groundE;      // global horizontal illuminance at the ground under the clouds, lux
uniform int u_samples;       // view-ray samples through the cumulus layer
uniform int u_lightSamples;  // light-march samples
uniform int u_backSamples;   // march samples to the cloud's far side (cloudcpu::backSamples)
uniform float u_maxDistance; // longest march through the shell (m): beyond, the haze hides it
uniform float u_cirrusTau;   // vertical optical depth of cirrus at relative density 1

const float CLD_PI = 3.14159265358979;
// CLD_LIGHT_RADIUS: the Sun's angular radius (the transmittance's smooth horizon; the Moon's is
// nearly the same) and CLD_LIGHTS (bit 0 the Sun, bit 1 the Moon: the lights the march computes,
// Clouds::marchedLights; a light outside it lights no cloud or is dropped against the Sun): from
// clouds.cpp as defines. A variant per set of lights, not a uniform condition: a SIMD machine runs
// a branch whenever one lane takes it, and llvmpipe runs every branch (masked), so a light
// switched off by a uniform still cost its march (38 % of a daytime frame with the Moon's).
#ifndef CLD_LIGHTS
#define CLD_LIGHTS 3
#endif

// The droplets' phase functions and the light transfer (cld_hg, cld_draine, cld_scaledPhase,
// cld_lightTransfer, cld_ambientTransfer): clouds_transfer.shared.glsl, which clouds.cpp compiles
// in double as cloudcpu:: (one text). Its constants CLD_G_PEAK ... CLD_DIFFUSIVITY come from
// clouds.cpp as defines.
#include "clouds_transfer.shared.glsl"

// Interleaved gradient noise (Jimenez 2014, "Next generation post processing in Call of Duty:
// Advanced Warfare"): the ray offset in [0, 1), deterministic per pixel.
float cld_dither(vec2 px) { return fract(52.9829189 * fract(dot(px, vec2(0.06711056, 0.00583715)))); }

// Light reaching point p (altitude hp) from a light of direction l and top-of-atmosphere
// illuminance E: E x the atmosphere's transmittance from p towards the light (0 below p's
// horizon, smoothed over the disk).
vec3 cld_lightAt(vec3 p, float hp, vec3 l, vec3 E) {
    vec3 up = normalize(p + vec3(0.0, 0.0, cld_radii.x));
    return E * transmittanceToLight(hp, dot(up, l), CLD_LIGHT_RADIUS);
}

// Scaled optical depth from p towards the light l through the cumulus (full density, as the view march): n
// steps over at most 3 km (Schneider & Vos 2015 march ~6 samples over a few cloud cells), the
// steps growing geometrically (x1.5) so near self-shadowing is resolved (cloudDepthAlong, the
// shared density file's march).
float cld_lightDepth(vec3 p, vec3 l, int n) { return cloudDepthAlong(p, l, n, CLD_MARCH_MAX_M) * cld_shape.z * CLD_W_DRAINE; }

// Scaled optical depth from p to the cloud's far side along -l: the same march away from the
// light with u_backSamples steps over at most 3 km (to the shell's exit), so that the clear air
// behind an isolated cumulus counts as clear (exact in a uniform deck, as the light march).
float cld_backDepth(vec3 p, vec3 l) { return cloudDepthAlong(p, -l, u_backSamples, CLD_MARCH_MAX_M) * cld_shape.z * CLD_W_DRAINE; }

// Scaled optical depth across the cloud through p, perpendicular to the light l: the same march
// both ways along the horizontal direction normal to l (east-west when l is at the zenith), each
// with u_backSamples steps over at most 3 km. With cld_backDepth it gives the depth to the far
// side that the diffusion sees (cld_finiteBackDepth: a cumulus' light leaks out of its sides).
float cld_widthDepth(vec3 p, vec3 l) {
    vec3 up = normalize(p + vec3(0.0, 0.0, cld_radii.x));
    vec3 s = cross(l, up);
    float n = length(s);
    s = n > 1e-4 ? s / n : normalize(cross(up, vec3(0.0, 1.0, 0.0)));
    return (cloudDepthAlong(p, s, u_backSamples, CLD_MARCH_MAX_M) + cloudDepthAlong(p, -s, u_backSamples, CLD_MARCH_MAX_M)) * cld_shape.z * CLD_W_DRAINE;
}
// The lights' source per lux at p (cld_lightTransferTable with the finite cloud's depth to its far
// side); tauW: cld_widthDepth for this light (the march refreshes it every CLD_WIDTH_EVERY samples).
// tauUp: the scaled depth to the sky above p (cld_verticalDepths), for the lit face's cosine.
float cld_lightSource(vec3 p, vec3 dir, vec3 l, float tauW, float tauUp) {
    float tauL = cld_lightDepth(p, l, u_lightSamples), tauB = cld_backDepth(p, l);
    return cld_lightTransferTable(dot(dir, l), dir.z, tauL, cld_finiteBackDepth(tauB, tauW), cld_litFaceCosine(tauUp, tauL, l.z),
                                  cld_deckness(tauW, tauL + tauB));
}
// Scaled optical depths from p to the sky above it and to the air below it, through the cloud's own
// density (cloudDepthAlong up and down, u_backSamples steps over at most 3 km each, to the shell's
// exit): the ambient's hemispheres and the lit face's cosine. Exact in a deck, as the light march.
vec2 cld_verticalDepths(vec3 p) {
    vec3 up = normalize(p + vec3(0.0, 0.0, cld_radii.x));
    return vec2(cloudDepthAlong(p, up, u_backSamples, CLD_MARCH_MAX_M), cloudDepthAlong(p, -up, u_backSamples, CLD_MARCH_MAX_M)) * cld_shape.z * CLD_W_DRAINE;
}
// The width through a cumulus and the vertical depths change over hundreds of metres: the view
// march measures them once per block of CLD_WIDTH_EVERY samples, at the block's first sample in
// cloud (cld_cumulus). Outside any condition that varies per sample, so that llvmpipe, which runs a
// branch's body whenever it is reached (masked), pays their twelve density look-ups once a block
// rather than at every sample (skyelements/clouds/README.md, "A moving frame's cost").
const int CLD_WIDTH_EVERY = 4;

// Transmittance of the air between the observer (h, mu) and the point at distance d along the
// ray, from the transmittance LUT: the ratio of the two paths to the top of the atmosphere (rays
// that reach the ground are reversed: the ratio of the paths from the far end upwards).
vec3 cld_airTransmittance(float mu, float d) {
    float R = atm_bottom();
    float r = R + u_h;
    float rd = sqrt(max(d * d + 2.0 * r * mu * d + r * r, R * R));
    float hd = rd - R;
    float mud = clamp((r * mu + d) / rd, -1.0, 1.0);
    if (mu >= 0.0 || !rayIntersectsGround(u_h, mu)) {
        vec3 a = transmittanceFromLut(u_h, mu), b = transmittanceFromLut(hd, mud);
        return clamp(a / max(b, vec3(1e-20)), 0.0, 1.0);
    }
    vec3 a = transmittanceFromLut(hd, -mud), b = transmittanceFromLut(u_h, -mu);
    return clamp(a / max(b, vec3(1e-20)), 0.0, 1.0);
}

// In-scattered source of one sample (cd/m^2 per m) at p with extinction sigmaT (albedo 1).
vec3 cld_source(vec3 p, float hp, vec3 dir, float sigmaT, vec2 tauW, vec2 tauV) {
    vec3 S = vec3(0.0);
#if (CLD_LIGHTS & 1) != 0
    if (any(greaterThan(u_sunE, vec3(0.0)))) {
        vec3 E = cld_lightAt(p, hp, u_sunDir, u_sunE);
        if (any(greaterThan(E, vec3(0.0)))) S += E * cld_lightSource(p, dir, u_sunDir, tauW.x, tauV.x);
    }
#endif
#if (CLD_LIGHTS & 2) != 0
    if (any(greaterThan(u_moonE, vec3(0.0)))) {
        vec3 E = cld_lightAt(p, hp, u_moonDir, u_moonE);
        if (any(greaterThan(E, vec3(0.0)))) S += E * cld_lightSource(p, dir, u_moonDir, tauW.y, tauV.x);
    }
#endif
    // Ambient (skyelements/clouds/README.md, "Ambient"): the clear sky's diffuse light from above the layer and
    // the ground's from below it (the atmosphere's ground albedo, the Sky's and the path tracer's,
    // x the global illuminance under the clouds, which the
    // photometry pass solves for: the ground is lit by what came through them), each a uniform
    // hemisphere carried into the cloud by cld_ambientTransfer through the vertical optical depths
    // tauV to the sky above and the air below, marched through the cloud's density
    // (cld_verticalDepths; exact in a deck). Until 2026-11-27 evening: the local extinction over the
    // distances to the layer's top and bottom, which counted the clear air over a cumulus as cloud.
    vec3 up = normalize(p + vec3(0.0, 0.0, cld_radii.x));
    float tauUp = tauV.x, tauDown = tauV.y;
    float nuUp = dot(dir, up);
    S += u_ambientE * cld_ambientTransfer(nuUp, tauUp, tauDown);
    S += atm_groundAlbedoRgb() * u_groundE * cld_ambientTransfer(-nuUp, tauDown, tauUp);
    return S * sigmaT;
}

// The cumulus along the ray: radiance L (cd/m^2), transmittance T (grey), the transmittance-
// weighted mean distance of what scattered (m; for the haze). Returns false if the ray misses.
bool cld_cumulus(vec3 dir, vec2 px, out vec3 L, out float T, out float dMean) {
    L = vec3(0.0);
    T = 1.0;
    dMean = 0.0;
    if (cld_shape.x <= 0.0) return false;
    float r = cld_radii.x + u_h;
    vec2 seg = cloudShellIntersect(r, dir.z);
    if (seg.y <= 0.0) return false;
    float t0 = max(seg.x, 0.0), t1 = min(seg.y, t0 + u_maxDistance);
    if (t1 <= t0) return false;
    float sigma = cld_shape.z * CLD_W_DRAINE;  // delta-M scaled extinction
    float dt = (t1 - t0) / float(u_samples);
    float tDither = t0 + dt * cld_dither(px);
    vec3 o = vec3(0.0, 0.0, u_h);
    float wSum = 0.0;
    // The march in blocks of CLD_WIDTH_EVERY samples. Each block first finds its first sample in
    // cloud (a density look-up per sample) and marches there, once for the block, the cloud's width
    // across each light (cld_widthDepth) and the vertical depths to the sky above and the air below
    // (cld_verticalDepths); its samples then use them, the vertical depths carried to each sample's
    // height by its own extinction. Until 2026-11-28 the same refresh (at the first cloud sample
    // after clear air and every CLD_WIDTH_EVERY cloud samples) sat under a condition inside the
    // sample loop, and llvmpipe, which runs a branch's body whenever it is reached (masked), paid
    // the twelve density look-ups at every sample: in blocks the march's samples cost 0.85x
    // (skyelements/clouds/README.md, "A moving frame's cost").
    vec2 tauW = vec2(0.0);     // the width's scaled depths (Sun, Moon)
    vec2 tauVRef = vec2(0.0);  // the vertical depths (up, down) at the block's reference sample
    float hRef = 0.0;          // its altitude
    bool sunUp = any(greaterThan(u_sunE, vec3(0.0))), moonUp = any(greaterThan(u_moonE, vec3(0.0)));
    bool done = false;
    for (int i0 = 0; i0 < u_samples && !done; i0 += CLD_WIDTH_EVERY) {
        float tb = tDither + dt * float(i0);
        float tRef = tb;
        bool found = false;
        for (int k = 0; k < CLD_WIDTH_EVERY; ++k) {
            float tk = tb + dt * float(k);
            bool c = i0 + k < u_samples && cloudDensity(o + dir * tk, CLOUD_LOD_FULL) > 0.0;
            tRef = c && !found ? tk : tRef;
            found = found || c;
        }
        if (found) {
            vec3 pr = o + dir * tRef;
#if (CLD_LIGHTS & 1) != 0
            if (sunUp) tauW.x = cld_widthDepth(pr, u_sunDir);
#endif
#if (CLD_LIGHTS & 2) != 0
            if (moonUp) tauW.y = cld_widthDepth(pr, u_moonDir);
#endif
            tauVRef = cld_verticalDepths(pr);
            hRef = cloudAltitude(pr);
        }
        for (int k = 0; k < CLD_WIDTH_EVERY; ++k) {
            if (i0 + k >= u_samples) break;
            float t = tb + dt * float(k);
            vec3 p = o + dir * t;
            float d = cloudDensity(p, CLOUD_LOD_FULL);
            if (d <= 0.0) continue;
            float sigmaT = d * sigma;
            float hp = cloudAltitude(p);
            // the vertical depths carried from the block's reference to this sample's height by its
            // own extinction (first order: exact in a deck's linear profile over the step)
            float dz = hp - hRef;
            vec2 tauV = max(tauVRef + vec2(-sigmaT * dz, sigmaT * dz), vec2(0.0));
            vec3 S = cld_source(p, hp, dir, sigmaT, tauW, tauV);
            float Ts = exp(-sigmaT * dt);
            // Hillaire 2016 energy-conserving step: int_0^dt S e^(-sigmaT s) ds = (S - S Ts) / sigmaT
            L += T * (S - S * Ts) / sigmaT;
            float w = T * (1.0 - Ts);
            dMean += w * t;
            wSum += w;
            T *= Ts;
            if (T < CLD_T_CUT) { T = 0.0; done = true; break; }
        }
    }
    dMean = wSum > 0.0 ? dMean / wSum : t0;
    return wSum > 0.0;
}

// Cirrus: a thin layer at R + cirrus height, single scattering of the lights with an ice-crystal
// phase (HG g = 0.7) and the ambient term; optical depth u_cirrusTau x density over the slant
// path (1 / |cos| of the local zenith, capped at 10). Returns false if the ray misses it.
bool cld_cirrusLayer(vec3 dir, out vec3 L, out float T, out float d) {
    L = vec3(0.0);
    T = 1.0;
    d = 0.0;
    if (cld_shape.w <= 0.0) return false;
    float R = cld_radii.x, rc = cld_radii.w, r = R + u_h;
    float mu = dir.z;
    float disc = r * r * mu * mu - (r - rc) * (r + rc);
    if (disc < 0.0) return false;
    float s = sqrt(disc);
    if (r < rc) d = -r * mu + s;
    else {
        d = -r * mu - s;
        if (d <= 0.0) return false;
    }
    // hidden by the ground?
    if (r < rc && rayIntersectsGround(u_h, mu) && d > distanceToBottom(u_h, mu)) return false;
    vec3 p = vec3(0.0, 0.0, u_h) + dir * d;
    float c = cirrusDensity(p.xy);
    if (c <= 0.0) return false;
    vec3 up = normalize(p + vec3(0.0, 0.0, R));
    float tau = u_cirrusTau * c / max(abs(dot(up, dir)), 0.1);
    T = exp(-tau);
    float hp = rc - R;
    vec3 S = vec3(0.0);
    S += cld_lightAt(p, hp, u_sunDir, u_sunE) * cld_hg(dot(dir, u_sunDir), 0.7);
    S += cld_lightAt(p, hp, u_moonDir, u_moonE) * cld_hg(dot(dir, u_moonDir), 0.7);
    S += 0.5 * u_ambientE / CLD_PI;
    L = S * (1.0 - T);  // albedo 1: the scattered fraction of the light crossing the layer
    return true;
}

// Everything along the ray: radiance and per-channel transmittance. With `haze`, the air between
// the observer and each layer dims the cloud's light (transmittance Tair) and its in-scatter in
// front of the cloud is approximated by the sky's radiance along the ray, already in the
// compositor's target: transmittance 1 - Tair (1 - Tcloud). Near the Sun's and Moon's disks
// (which the target also holds) by the sky's mean radiance E_d / pi instead (see below).
void cloudsShade(vec3 dir, vec2 px, bool haze, out vec3 L, out vec3 T) {
    vec3 Lc, Li;
    float Tc, Ti, dc, di;
    bool cu = cld_cumulus(dir, px, Lc, Tc, dc);
    bool ci = cld_cirrusLayer(dir, Li, Ti, di);
    vec3 LcA = Lc, LiA = Li, TcA = vec3(Tc), TiA = vec3(Ti);
    if (haze) {
        // Away from the Sun's and Moon's disks the sky behind (dst) stands for the in-scatter:
        // transmittance 1 - Tair (1 - Tcloud). Within 2 deg of a disk (which dst also holds, at
        // up to 1e5 x the sky's radiance) the sky's mean radiance E_d / pi replaces it and the
        // cloud keeps its own transmittance, blended over 0.5-2 deg.
        float nearDisk = max(smoothstep(cos(0.035), cos(0.0087), dot(dir, u_sunDir)),
                             smoothstep(cos(0.035), cos(0.0087), dot(dir, u_moonDir)));
        vec3 haze = u_ambientE / CLD_PI;
        if (cu) {
            vec3 a = cld_airTransmittance(dir.z, dc);
            LcA = a * Lc + nearDisk * (1.0 - a) * (1.0 - Tc) * haze;
            // near a disk the full (unscaled) extinction: the peak's light leaves the disk's 0.5 deg
            TcA = mix(1.0 - a * (1.0 - Tc), vec3(pow(Tc, 1.0 / CLD_W_DRAINE)), nearDisk);
        }
        if (ci) {
            vec3 a = cld_airTransmittance(dir.z, di);
            LiA = a * Li + nearDisk * (1.0 - a) * (1.0 - Ti) * haze;
            TiA = mix(1.0 - a * (1.0 - Ti), vec3(Ti), nearDisk);
        }
    }
    // Nearest layer first: the cirrus is behind the cumulus unless the observer is above it.
    bool cirrusFirst = ci && u_h > cld_radii.w - cld_radii.x;
    if (cirrusFirst) { L = LiA + TiA * LcA; }
    else { L = LcA + TcA * LiA; }
    T = TcA * TiA;
}

#ifdef CLOUDS_STATS
// Photometry pass: an N x N grid of cosine-weighted directions over the upper hemisphere
// (Shirley & Chiu 1997 concentric map), then row N: pixel 0 the ray to the Sun, pixel 1 the ray
// to the Moon. Outputs the
// clouds' radiance (rgb) and transmittance (a, grey) without haze (at the ground).
uniform int u_statsN;
layout(location = 0) out vec4 o_stats;
void main() {
    ivec2 ij = ivec2(gl_FragCoord.xy);
    vec3 dir;
    if (ij.y >= u_statsN) {
        dir = ij.x == 1 ? u_moonDir : u_sunDir;
    } else {
        vec2 uv = 2.0 * (vec2(ij) + 0.5) / float(u_statsN) - 1.0;
        float rad, phi;
        if (abs(uv.x) > abs(uv.y)) { rad = uv.x; phi = 0.25 * CLD_PI * uv.y / uv.x; }
        else { rad = uv.y; phi = 0.5 * CLD_PI - 0.25 * CLD_PI * uv.x / uv.y; }
        vec2 xy = rad * vec2(cos(phi), sin(phi));
        dir = vec3(xy, sqrt(max(1.0 - dot(xy, xy), 0.0)));
    }
    vec3 L, T;
    cloudsShade(dir, vec2(ij), false, L, T);
    o_stats = vec4(L, dot(T, vec3(0.2126, 0.7152, 0.0722)));
}
#elif defined(CLOUDS_CACHE_FILL)
// The real-time path's cache (clouds_cache.glsl), a compute pass: one invocation per texel of one
// phase of the 2^k x 2^k Bayer order (u_phase in 0 .. 4^k - 1; -1: every texel), so that every
// SIMD lane marches a ray (a fragment pass discarding the other texels would leave llvmpipe's
// and a GPU's lanes idle). Bayer's recursion M(2n)[p] = 4 M(n)[p mod n] + M(2)[p div n] with
// M(2)[x, y] = 2 (x xor y) + y: bit i of the texel's offset in its block gives base-4 digit
// k - 1 - i of the phase, inverted here digit by digit (y = v & 1, x = (v >> 1) xor y).
layout(local_size_x = 8, local_size_y = 8) in;
layout(binding = WELKIN_BINDING_LUT_IMAGE, rgba16f) uniform writeonly image2D u_outL;
layout(binding = WELKIN_BINDING_SECOND_LUT_IMAGE, rgba16f) uniform writeonly image2D u_outT;
uniform ivec2 u_cacheSize;
uniform int u_phase;
uniform int u_cacheBits;  // k: 4^k frames refresh the whole cache
ivec2 cld_bayerOffset(int phase, int k) {
    ivec2 o = ivec2(0);
    for (int i = 0; i < k; ++i) {
        int v = (phase >> (2 * (k - 1 - i))) & 3;
        int y = v & 1, x = (v >> 1) ^ y;
        o += ivec2(x, y) << i;
    }
    return o;
}
void main() {
    ivec2 ij = ivec2(gl_GlobalInvocationID.xy);
    if (u_phase >= 0) ij = ij * (1 << u_cacheBits) + cld_bayerOffset(u_phase, u_cacheBits);
    if (any(greaterThanEqual(ij, u_cacheSize))) return;
    vec3 dir = clouds_cacheDirection((vec2(ij) + 0.5) / vec2(u_cacheSize));
    vec3 L, T;
    cloudsShade(dir, vec2(ij), true, L, T);
    imageStore(u_outL, ij, vec4(L, 1.0));
    imageStore(u_outT, ij, vec4(T, 1.0));
}
#else
void main() {
    vec3 dir;
    if (!welkin_viewDirection(welkin_pixel(), dir)) discard;
    vec3 L, T;
    cloudsShade(dir, welkin_pixel(), true, L, T);
    welkin_output(L, T);
}
#endif
