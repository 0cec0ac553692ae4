// Stars: one quad per star (and, in equirect, its twin across the seam). Needs
// engine/camera.glsl before it. Star i is 3 vec4 in the storage buffer: (J2000 ICRS unit
// direction, V magnitude), (proper motion, rad per Julian year, ICRS axes; 0), (linear sRGB of
// luminance 1; 0). See skyelements/stars/include/welkin/elements/stars.hpp for the model.
// Needs atmosphere/point_perceptual.glsl before it (render.point_sources = perceptual).
layout(std430, binding = WELKIN_BINDING_STARS_SSBO) readonly buffer StarBuffer { vec4 u_star[]; };

uniform mat3 u_icrsToEnu;    // ICRS -> observer ENU, this frame
uniform vec3 u_aberration;   // observer velocity / c, ICRS axes
uniform float u_years;       // Julian years since J2000.0 (proper motion)
uniform int u_copies;        // 2 in equirect (the seam twin), else 1
uniform float u_e0;          // illuminance of magnitude 0, lux
uniform float u_fwhmRad;     // angular FWHM of the PSF
uniform float u_minFwhmPx;   // smallest FWHM on the screen, px
uniform float u_glare;       // flux fraction in the halo of a bright star
uniform float u_glareMag;    // stars brighter than this get the halo
uniform float u_scint;       // scintillation strength (0 off)
uniform float u_time;        // seconds (of the simulated time, modulo an hour)
uniform uint u_seed;
uniform int u_extinction;    // 1: apply u_ext (no Sky composited over the stars)
// Tables over altitude h = -5 deg + 95 deg * u^2, u = i / (N - 1) (dense near the horizon):
uniform float u_refr[STARS_TABLE_N];  // refraction (rad) at geometric altitude h
uniform vec3 u_ext[STARS_TABLE_N];    // transmittance towards apparent altitude h

out vec2 v_offset;          // pixels from the star's centre (x right, y down)
flat out vec3 v_flux;       // per channel illuminance / pixel solid angle (lux / (sr per px^2))
flat out vec3 v_shape;      // core sigma (px), Moffat width a (px, 0 = no halo), halo fraction
flat out float v_haloR2;    // halo truncation radius^2, px^2
flat out vec4 v_pp;         // perceptual mode: peak radiance (cd/m^2, RGB), Gaussian sigma (px); 0: none

const float kTableLo = -0.0872664626;  // -5 deg
const float kTableSpan = 1.6580627894; // 95 deg

float tableCoord(float h) { return sqrt(clamp((h - kTableLo) / kTableSpan, 0.0, 1.0)) * float(STARS_TABLE_N - 1); }
float refractionAt(float h) {
    float x = tableCoord(h);
    int i = min(int(x), STARS_TABLE_N - 2);
    return mix(u_refr[i], u_refr[i + 1], x - float(i));
}
vec3 extinctionAt(float h) {
    float x = tableCoord(h);
    int i = min(int(x), STARS_TABLE_N - 2);
    return h < kTableLo ? vec3(0.0) : mix(u_ext[i], u_ext[i + 1], x - float(i));
}

uint stars_hash(uint x) {
    x ^= x >> 16; x *= 0x21f0aaadu;
    x ^= x >> 15; x *= 0xd35a2d97u;
    x ^= x >> 15;
    return x;
}
// Uniform in [-1, 1] for (star, seed, time step).
float stars_noise(uint star, int step) {
    uint h = stars_hash(star * 0x9e3779b9u ^ stars_hash(u_seed + uint(step) * 0x85ebca6bu));
    return float(h >> 8) * (2.0 / 16777215.0) - 1.0;
}

// The twinkling's amplitude (Kasten-Young air mass): stars.cpp compiles the same text in double.
#include "stars_scintillation.shared.glsl"

void main() {
    const vec2 corner[6] = vec2[6](vec2(-1, -1), vec2(1, -1), vec2(1, 1), vec2(-1, -1), vec2(1, 1), vec2(-1, 1));
    // One indexed draw, 4 vertices per star and copy (llvmpipe runs its vertex pipeline once per
    // instance, and shades a non-indexed quad's 6 corners 6 times: README "Cost").
#ifdef STARS_INSTANCED
    int instance = gl_InstanceID, vertex = gl_VertexID;  // the reference (Stars::setInstancedDraw)
#else
    // Vertex 4 i + k: corner k of star copy i (stars.cpp indexes (0 1 2, 0 2 3) + 4 i: the same
    // two triangles as corners 0-5 above).
    const int kCorner[4] = int[4](0, 1, 2, 5);
    int instance = gl_VertexID >> 2, vertex = kCorner[gl_VertexID & 3];
#endif
    int star = instance / u_copies;
    vec4 a = u_star[3 * star], b = u_star[3 * star + 1], c = u_star[3 * star + 2];
    // Place: proper motion, aberration, rotation (astro::starEnu), then refraction.
    vec3 p = normalize(a.xyz + u_years * b.xyz);
    p = normalize(p + u_aberration);
    vec3 d = u_icrsToEnu * p;
    float h = asin(clamp(d.z, -1.0, 1.0));
    float hApp = h + refractionAt(h);
    float horiz = length(d.xy);
    vec2 sc = horiz > 0.0 ? d.xy / horiz : vec2(0.0, 1.0);
    d = vec3(sc * cos(hApp), sin(hApp));

    vec4 clip = welkin_clipFromDirectionWrapped(d, instance % u_copies);
    vec2 s = welkin_pixelScale(d);  // (smallest, largest) px per radian
    if (clip.w <= 0.0 || s.x <= 0.0) {
        gl_Position = WELKIN_CLIP_INVISIBLE;
        return;
    }
    float fwhm = clamp(u_fwhmRad * s.x, u_minFwhmPx, 256.0);
    float sigma = fwhm / WELKIN_GAUSSIAN_FWHM_PER_SIGMA;  // point_threshold.shared.glsl (via point_perceptual.glsl)
    float glare = a.w < u_glareMag ? u_glare : 0.0;
    float halo = glare > 0.0 ? 2.0 * fwhm : 0.0;
    float radius = max(3.5 * sigma, 8.0 * halo);
    v_pp = vec4(0.0);

    // Flux: magnitude, colour, scintillation (Kasten-Young airmass), extinction without a Sky.
    vec3 E = u_e0 * exp2(-1.3287712 * a.w) * c.rgb;  // 10^(-0.4 m) = 2^(-0.4 log2(10) m)
    if (u_scint > 0.0) {
        float amp = stars_scintillationAmplitude(hApp, u_scint);  // stars_scintillation.shared.glsl
        float t = u_time * 10.0;
        int k = int(floor(t));
        float f = t - float(k);
        float n = mix(stars_noise(uint(star), k), stars_noise(uint(star), k + 1), f * f * (3.0 - 2.0 * f));
        E *= max(1.0 + amp * n, 0.0);
    }
    vec3 T = extinctionAt(hApp);
    if (u_ppMode == 1) {
        // Perceptual: the eye's threshold against the sky behind the star (welkin/point_source.hpp).
        // Not seen: not drawn. Seen: a Gaussian whose peak is the sky plus a Weber contrast over
        // it, drawn besides the physical PSF (the brighter wins per pixel, in the fragment shader).
        float B = pp_background(d);
        vec2 fc = pp_point(dot(E * T, vec3(0.2126, 0.7152, 0.0722)), B, u_minFwhmPx);
        if (fc.x <= 0.0) {
            gl_Position = WELKIN_CLIP_INVISIBLE;
            return;
        }
        // With the Sky composited later its transmittance multiplies what is drawn here: the
        // peak is divided by the star's luminance transmittance so that the sky shows it at C B.
        float tY = dot(T, vec3(0.2126, 0.7152, 0.0722));
        float peak = fc.y * B / (u_extinction == 1 ? 1.0 : max(tY, 1e-6));
        v_pp = vec4(peak * c.rgb * (u_extinction == 1 ? T / max(tY, 1e-6) : vec3(1.0)), fc.x / WELKIN_GAUSSIAN_FWHM_PER_SIGMA);
        radius = max(radius, 3.5 * v_pp.w);
    }
    if (u_extinction == 1) E *= T;

    v_flux = E * (s.x * s.y);  // divided by the pixel's solid angle 1 / (s.x s.y) sr
    v_shape = vec3(sigma, halo, glare);
    v_haloR2 = 64.0 * halo * halo;
    v_offset = radius * corner[vertex];
    gl_Position = welkin_clipOffset(clip, v_offset);
}
