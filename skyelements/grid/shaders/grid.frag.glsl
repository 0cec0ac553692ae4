// Grid element: altitude circles and azimuth lines (angular spacing), the horizon emphasised,
// and N/E/S/W glyphs; and/or declination circles and hour circles (J2000). Needs
// engine/camera.glsl and engine/composite.glsl before it.
uniform float u_altStep;         // radians
uniform float u_azStep;          // radians
uniform float u_lineWidthPx;     // pixels
uniform float u_horizonWidthPx;  // pixels
uniform float u_luminance;       // cd/m^2 of a fully covered pixel
uniform vec4 u_markers[4];       // N, E, S, W: pixel position (x, y), visible flag
uniform float u_glyphScale;      // pixels per glyph cell
uniform int u_frame;             // bit 0: horizontal grid, bit 1: equatorial grid, bit 2: ecliptic
uniform mat3 u_enuToIcrs;        // observer ENU -> ICRS (J2000)
uniform float u_raStep;          // radians
uniform float u_decStep;         // radians
uniform vec3 u_eclipticPole;     // ICRS unit vector of the J2000 ecliptic's north pole
// Refraction (rad) at apparent altitude h = -5 deg + 95 deg * u^2, u = i / (N - 1).
uniform float u_refrApparent[GRID_TABLE_N];

// 5x7 bitmaps, one row per 5 bits (top row first): N, E, S, W.
const int GLYPHS[28] = int[28](
    0x11, 0x19, 0x15, 0x13, 0x11, 0x11, 0x11,   // N
    0x1F, 0x10, 0x10, 0x1E, 0x10, 0x10, 0x1F,   // E
    0x0F, 0x10, 0x10, 0x0E, 0x01, 0x01, 0x1E,   // S
    0x11, 0x11, 0x11, 0x15, 0x15, 0x15, 0x0A);  // W

float glyphCoverage(int g, vec2 pixel, vec2 centre) {
    // Cell grid 5x7 with a one-cell margin; centre of the glyph at `centre`.
    vec2 q = (pixel - centre) / u_glyphScale + vec2(2.5, 3.5);
    if (q.x < 0.0 || q.y < 0.0 || q.x >= 5.0 || q.y >= 7.0) return 0.0;
    int col = int(q.x), row = int(q.y);
    int bits = GLYPHS[g * 7 + row];
    return float((bits >> (4 - col)) & 1);
}

// Antialiased coverage of a line at angular distance `d` (radians) with width `w` (radians).
float lineCoverage(float d, float w) {
    float aa = 0.5 * welkin_pixelAngle();
    return 1.0 - smoothstep(0.5 * w - aa, 0.5 * w + aa, d);
}

void main() {
    vec2 pixel = welkin_pixel();
    vec3 dir;
    if (!welkin_viewDirection(pixel, dir)) discard;
    float px = welkin_pixelAngle();
    float alt = asin(clamp(dir.z, -1.0, 1.0));
    float az = atan(dir.x, dir.y);

    // Altitude circles.
    float dAlt = abs(alt - u_altStep * round(alt / u_altStep));
    float cAlt = lineCoverage(dAlt, u_lineWidthPx * px);
    // Azimuth lines: distance on the sphere ~ |daz| cos(alt); stop them at the last altitude
    // circle below the poles (except the four cardinal ones) so they do not crowd the zenith.
    float cosAlt = cos(alt);
    float dAz = abs(az - u_azStep * round(az / u_azStep)) * cosAlt;
    float nearPole = step(0.5 * WELKIN_PI - u_altStep + 1e-4, abs(alt));
    float onCardinal = step(abs(az - 0.5 * WELKIN_PI * round(az / (0.5 * WELKIN_PI))) * cosAlt, 0.5 * u_lineWidthPx * px);
    float cAz = lineCoverage(dAz, u_lineWidthPx * px) * max(1.0 - nearPole, onCardinal);
    // The horizon, wider and warmer.
    float cHor = lineCoverage(abs(alt), u_horizonWidthPx * px);

    if ((u_frame & 1) == 0) cAlt = cAz = cHor = 0.0;
    float cover = max(max(cAlt, cAz), cHor);
    vec3 colour = mix(vec3(0.55, 0.7, 1.0), vec3(1.0, 0.8, 0.45), cHor / max(cover, 1e-6));

    vec3 q = vec3(0.0, 0.0, 1.0);
    if ((u_frame & 6) != 0) {
        // The geometric direction (refraction taken off) in ICRS axes.
        float x = sqrt(clamp((alt + 0.0872664626) / 1.6580627894, 0.0, 1.0)) * float(GRID_TABLE_N - 1);
        int i = min(int(x), GRID_TABLE_N - 2);
        float altGeo = alt - mix(u_refrApparent[i], u_refrApparent[i + 1], x - float(i));
        float h = length(dir.xy);
        vec2 sc = h > 0.0 ? dir.xy / h : vec2(0.0, 1.0);
        q = u_enuToIcrs * vec3(sc * cos(altGeo), sin(altGeo));
    }
    if ((u_frame & 2) != 0) {
        // Equatorial: ICRS RA/Dec.
        float dec = asin(clamp(q.z, -1.0, 1.0));
        float ra = atan(q.y, q.x);
        float cDec = lineCoverage(abs(dec - u_decStep * round(dec / u_decStep)), u_lineWidthPx * px);
        float cosDec = cos(dec);
        float dRa = abs(ra - u_raStep * round(ra / u_raStep)) * cosDec;
        float nearPoleEq = step(0.5 * WELKIN_PI - u_decStep + 1e-4, abs(dec));
        float cRa = lineCoverage(dRa, u_lineWidthPx * px) * (1.0 - nearPoleEq);
        float cEq = max(cDec, cRa);
        if (cEq > 0.0) {
            colour = mix(colour, vec3(0.45, 1.0, 0.7), cEq / max(max(cover, cEq), 1e-6));
            cover = max(cover, cEq);
        }
    }

    if ((u_frame & 4) != 0) {
        // The ecliptic: angular distance from its great circle; golden, 1.5 x as wide and twice
        // as bright as the other lines, over them.
        float cEcl = lineCoverage(abs(asin(clamp(dot(q, u_eclipticPole), -1.0, 1.0))), 1.5 * u_lineWidthPx * px);
        if (cEcl > 0.0) {
            colour = mix(colour, vec3(2.0, 1.56, 0.4), cEcl / max(max(cover, cEcl), 1e-6));
            cover = max(cover, cEcl);
        }
    }

    for (int i = 0; i < 4; ++i) {
        if (u_markers[i].z < 0.5) continue;
        float g = glyphCoverage(i, pixel, u_markers[i].xy);
        if (g > 0.0) {
            cover = 1.0;
            colour = i == 0 ? vec3(1.0, 0.3, 0.25) : vec3(1.0);
        }
    }
    welkin_output(colour * u_luminance * cover, vec3(1.0 - cover));
}
