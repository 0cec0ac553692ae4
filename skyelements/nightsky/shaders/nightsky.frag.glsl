// NightSky: the diffuse night sky (Milky Way, airglow, zodiacal light, light pollution), one
// fullscreen pass. Needs engine/camera.glsl and engine/composite.glsl before it. Emits radiance
// (cd/m^2, linear sRGB), hides nothing (transmittance 1). The model and its CPU twins:
// skyelements/nightsky/include/welkin/elements/nightsky.hpp.
layout(binding = WELKIN_BINDING_USER_TEXTURE_UNIT_FIRST) uniform sampler2D u_mwTex;  // calibrated x 1e4

uniform mat3 u_enuToIcrs;     // transpose of stars.frame_icrs_to_enu
uniform mat3 u_icrsToEcl;     // ICRS -> J2000 ecliptic
uniform float u_sunEclLon;    // the Sun's ecliptic longitude, rad
uniform vec3 u_airglow;       // airglow at the zenith, cd/m^2 per channel
uniform float u_airglowR2;    // (R / (R + h))^2 of the airglow layer
uniform vec3 u_lp;            // light pollution at the zenith, cd/m^2 per channel
uniform float u_lpR2;         // (R / (R + h))^2 of the light-pollution layer
uniform vec3 u_zodi;          // colour x cd/m^2 per Table 17 unit x nightsky.zodiacal_scale
uniform float u_zodiTable[NIGHT_ZODI_N];  // 19 rows (dLambda) x 11 columns (beta), row-major
uniform vec3 u_mwFloor;       // uniform Milky Way floor, cd/m^2 per channel
uniform float u_mwScale;      // nightsky.milky_way_scale x 1e-4 (the texture's storage scale); 0 off
uniform float u_texelsPerRad; // panorama width / 2 pi
uniform int u_extinction;     // 1: apply u_ext (nothing attenuates this element later)
uniform vec3 u_ext[NIGHT_TABLE_N];  // transmittance at altitude -5 deg + 95 deg u^2, u = i / (N - 1)

const float kTableLo = -0.0872664626;  // -5 deg
const float kTableSpan = 1.6580627894; // 95 deg

vec3 night_extinction(float h) {
    if (h < kTableLo) return vec3(0.0);
    float x = sqrt(clamp((h - kTableLo) / kTableSpan, 0.0, 1.0)) * float(NIGHT_TABLE_N - 1);
    int i = min(int(x), NIGHT_TABLE_N - 2);
    return mix(u_ext[i], u_ext[i + 1], x - float(i));
}

// Van Rhijn's factor of a thin shell: 1 / sqrt(1 - r2 sin^2 z), sin^2 z = 1 - d.z^2.
float night_vanRhijn(float cz, float r2) { return inversesqrt(max(1.0 - r2 * (1.0 - cz * cz), 1e-6)); }

// Table 17 index of |dLambda| (deg, [0, 180]): 5-deg steps to 45, then 15-deg steps.
float night_rowCoord(float dl) { return dl < 45.0 ? dl / 5.0 : 9.0 + (dl - 45.0) / 15.0; }
// ... and of |beta| (deg, [0, 90]): 5-deg steps to 30, then 15-deg steps.
float night_colCoord(float b) { return b < 30.0 ? b / 5.0 : 6.0 + (b - 30.0) / 15.0; }

float night_zodiacal(vec3 icrs) {
    vec3 e = u_icrsToEcl * icrs;
    float lon = atan(e.y, e.x);
    float beta = degrees(asin(clamp(abs(e.z), 0.0, 1.0)));
    float dl = abs(mod(lon - u_sunEclLon + WELKIN_PI, 2.0 * WELKIN_PI) - WELKIN_PI);
    float r = clamp(night_rowCoord(degrees(dl)), 0.0, 18.0), c = clamp(night_colCoord(beta), 0.0, 10.0);
    int i = min(int(r), 17), j = min(int(c), 9);
    float fr = r - float(i), fc = c - float(j);
    float a = mix(u_zodiTable[i * 11 + j], u_zodiTable[i * 11 + j + 1], fc);
    float b = mix(u_zodiTable[(i + 1) * 11 + j], u_zodiTable[(i + 1) * 11 + j + 1], fc);
    return mix(a, b, fr);
}

void main() {
    vec3 dir;
    if (!welkin_viewDirection(welkin_pixel(), dir)) discard;  // outside a fisheye's circle
    vec3 L = u_airglow * night_vanRhijn(dir.z, u_airglowR2) + u_lp * night_vanRhijn(dir.z, u_lpR2);
    vec3 icrs = normalize(u_enuToIcrs * dir);
    L += u_zodi * night_zodiacal(icrs);
    if (u_mwScale > 0.0) {
        // Panorama in J2000 equatorial: u = (90 deg - RA) / 360 deg, v = (90 deg - Dec) / 180 deg
        // from the top row (uploaded first, so t = v). The level of detail from the pixel's
        // angular size (smallest scale: no aliasing), so the seam and the poles need no gradients.
        float u = fract((0.5 * WELKIN_PI - atan(icrs.y, icrs.x)) / (2.0 * WELKIN_PI));
        float v = acos(clamp(icrs.z, -1.0, 1.0)) / WELKIN_PI;
        vec2 s = welkin_pixelScale(dir);
        float lod = s.x > 0.0 ? max(log2(u_texelsPerRad / s.x), 0.0) : 0.0;
        L += u_mwScale * textureLod(u_mwTex, vec2(u, v), lod).rgb;
    }
    L += u_mwFloor;
    if (u_extinction == 1) L *= night_extinction(asin(clamp(dir.z, -1.0, 1.0)));
    welkin_output(L, vec3(1.0));
}
