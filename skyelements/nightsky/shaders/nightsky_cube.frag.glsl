// NightSky's tables: one face of a cube map over ICRS (J2000) directions of the terms fixed to the
// stars, cd/m^2 x 1e4 (fp16): u_part 0 the calibrated Milky Way and its floor (built once, and
// when a key or the panorama changes), 1 the zodiacal light (a small cube, rebuilt when the Sun's
// ecliptic longitude moves: src/nightsky.cpp). The inverse trigonometry of the panorama's mapping
// runs once per cube texel instead of once per pixel.
layout(binding = WELKIN_BINDING_MILKY_WAY_TEXTURE) uniform sampler2D u_mwTex;  // calibrated x 1e4
layout(binding = WELKIN_BINDING_ZODIACAL_TEXTURE) uniform sampler2D u_zodiTex; // Table 17 units
uniform int u_part;        // 0: Milky Way + floor, 1: zodiacal light
uniform int u_face;        // 0..5: +X, -X, +Y, -Y, +Z, -Z (GL's cube-map faces, ICRS axes)
uniform float u_size;      // face size, texels
uniform vec3 u_zodi;       // colour x cd/m^2 per Table 17 unit x nightsky.zodiacal_scale x 1e4
uniform vec3 u_mwFloor;    // uniform Milky Way floor, cd/m^2 per channel x 1e4
uniform float u_mwScale;   // nightsky.milky_way_scale (0: off, or no panorama)
uniform float u_texelsPerRad;  // panorama width / 2 pi
layout(location = 0) out vec4 o_rgba;

const float kPi = 3.14159265358979;

void main() {
    // The texel centre's direction: GL's cube-map selection rules inverted (OpenGL 4.5 core
    // section 8.13, table 8.19): face texel (i, j) at s = (i + 0.5) / N, t = (j + 0.5) / N, row j
    // is the framebuffer's row j.
    vec2 st = gl_FragCoord.xy / u_size * 2.0 - 1.0;
    float sc = st.x, tc = st.y;
    vec3 d;
    if (u_face == 0) d = vec3(1.0, -tc, -sc);
    else if (u_face == 1) d = vec3(-1.0, -tc, sc);
    else if (u_face == 2) d = vec3(sc, 1.0, tc);
    else if (u_face == 3) d = vec3(sc, -1.0, -tc);
    else if (u_face == 4) d = vec3(sc, -tc, 1.0);
    else d = vec3(-sc, -tc, -1.0);
    d = normalize(d);
    // The panorama's mapping (nightsky.frag.glsl's reference path, milkyWayTexCoord()).
    vec2 uv = vec2(fract((0.5 * kPi - atan(d.y, d.x)) / (2.0 * kPi)), acos(clamp(d.z, -1.0, 1.0)) / kPi);
    if (u_part == 1) {
        o_rgba = vec4(u_zodi * textureLod(u_zodiTex, uv, 0.0).r, 1.0);
        return;
    }
    vec3 L = u_mwFloor;
    // The panorama's level of detail for this texel's angular size (2 / N at the face centre,
    // 1 / (1 + s^2 + t^2) of it radially towards the corners), as the per-pixel path does for a
    // pixel: the cube's mips then filter further.
    float lod = max(log2(u_texelsPerRad * 2.0 / u_size / (1.0 + dot(st, st))), 0.0);
    if (u_mwScale > 0.0) L += u_mwScale * textureLod(u_mwTex, uv, lod).rgb;
    o_rgba = vec4(L, 1.0);
}
