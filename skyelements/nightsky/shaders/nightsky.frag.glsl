// NightSky: the diffuse night sky (Milky Way, airglow, zodiacal light, light pollution), one
// fullscreen pass. Needs engine/camera.glsl and engine/composite.glsl before it. Emits radiance
// (cd/m^2, linear sRGB), hides nothing (transmittance 1). The model and its CPU twins:
// skyelements/nightsky/include/welkin/elements/nightsky.hpp.
// Two program variants: the default reads the terms fixed to the stars (Milky Way, its floor,
// zodiacal light) from the ICRS cube maps built by nightsky_cube.frag.glsl, two fetches and no
// inverse trigonometry per pixel; NIGHT_DIRECT (NightSky::setDirectLookup, the default on
// llvmpipe) evaluates the panorama's mapping per pixel (an atan and an acos) and fetches once.
#ifdef NIGHT_DIRECT
// The folded panorama (nightsky_fold.frag.glsl): the calibrated Milky Way, its floor and the
// zodiacal light for the Sun's ecliptic longitude, over the panorama's J2000 equirectangular
// mapping and mips, cd/m^2 x 1e4 (RGBA32F).
layout(binding = WELKIN_BINDING_MILKY_WAY_TEXTURE) uniform sampler2D u_mwTex;
#else
// Milky Way + floor over ICRS directions, cd/m^2 x 1e4, mipmapped; the zodiacal light likewise
// in a small cube (smooth: 1.4 deg texels, one level).
layout(binding = WELKIN_BINDING_MILKY_WAY_TEXTURE) uniform samplerCube u_cube;
layout(binding = WELKIN_BINDING_ZODIACAL_TEXTURE) uniform samplerCube u_zodiCube;
#endif

uniform mat3 u_enuToIcrs;     // transpose of stars.frame_icrs_to_enu
uniform vec3 u_airglow;       // airglow at the zenith, cd/m^2 per channel
uniform float u_airglowR2;    // (R / (R + h))^2 of the airglow layer
uniform vec3 u_lp;            // light pollution at the zenith, cd/m^2 per channel
uniform float u_lpR2;         // (R / (R + h))^2 of the light-pollution layer
uniform float u_texelsPerRad; // panorama width / 2 pi (both paths: the cube's level 0 where the panorama's)
#ifdef NIGHT_EXTINCTION  // the program used when nothing attenuates this element later
uniform vec3 u_ext[NIGHT_TABLE_N];  // transmittance at altitude -5 deg + 95 deg u^2, u = i / (N - 1)
#endif

const float kTableLo = -0.0872664626;  // -5 deg
const float kTableSpan = 1.6580627894; // 95 deg

// asin(x) for x in [-1, 1] without the library call: Abramowitz & Stegun 4.4.45,
// asin x = pi/2 - sqrt(1 - x) (a0 + a1 x + a2 x^2 + a3 x^3) for x in [0, 1], |error| <= 5e-5 rad
// (0.003 deg: 1/500 of the extinction table's finest step), odd in x.
float night_asin(float x) {
    float a = abs(x);
    float r = 1.5707963050 - sqrt(max(1.0 - a, 0.0)) * (1.5707288 + a * (-0.2121144 + a * (0.0742610 + a * -0.0187293)));
    return x < 0.0 ? -r : r;
}

#ifdef NIGHT_EXTINCTION
vec3 night_extinction(float h) {
    if (h < kTableLo) return vec3(0.0);
    float x = sqrt(clamp((h - kTableLo) / kTableSpan, 0.0, 1.0)) * float(NIGHT_TABLE_N - 1);
    int i = min(int(x), NIGHT_TABLE_N - 2);
    return mix(u_ext[i], u_ext[i + 1], x - float(i));
}
#endif

// Van Rhijn's factor of a thin shell, night_vanRhijn(cos z, r2): nightsky_vanrhijn.shared.glsl, which
// nightsky.cpp's vanRhijn() compiles in double.
#include "nightsky_vanrhijn.shared.glsl"

void main() {
    vec3 dir;
    if (!welkin_viewDirection(welkin_pixel(), dir)) discard;  // outside a fisheye's circle
    vec3 L = u_airglow * night_vanRhijn(dir.z, u_airglowR2) + u_lp * night_vanRhijn(dir.z, u_lpR2);
    vec3 icrs = u_enuToIcrs * dir;
    // The level of detail from the screen derivatives of the direction (radians per pixel, the
    // larger axis: no moire where a pixel spans many texels), continuous across the panorama's
    // seam and the cube's edges; as cheap as a quad's differences (welkin_pixelScale per pixel
    // cost ~4 ms of a 20 ms pass at 1280x720 on llvmpipe).
#ifdef NIGHT_LOD0
    // A pinhole whose every pixel is smaller than a texel (the element checks it on the CPU): the
    // level below is 0 at every pixel; a constant lets llvmpipe pick one level per group of pixels.
    const float lod = 0.0;
#else
    float radPerPx = max(length(dFdx(dir)), length(dFdy(dir)));
    float lod = max(log2(u_texelsPerRad * radPerPx), 0.0);
#endif
#ifdef NIGHT_DIRECT
    // Panorama coordinates, J2000 equatorial: u = (90 deg - RA) / 360 deg, v = (90 deg - Dec) /
    // 180 deg from the top row (uploaded first, so t = v).
    icrs = normalize(icrs);
    vec2 uv = vec2(fract((0.5 * WELKIN_PI - atan(icrs.y, icrs.x)) / (2.0 * WELKIN_PI)), acos(clamp(icrs.z, -1.0, 1.0)) / WELKIN_PI);
    L += 1e-4 * textureLod(u_mwTex, uv, lod).rgb;  // kMwStorageScale
#else
    L += 1e-4 * (textureLod(u_cube, icrs, lod).rgb + textureLod(u_zodiCube, icrs, 0.0).rgb);  // kMwStorageScale
#endif
#ifdef NIGHT_EXTINCTION
    L *= night_extinction(night_asin(clamp(dir.z, -1.0, 1.0)));
#endif
    welkin_output(L, vec3(1.0));
}
