// NightSky's folded panorama: one level of the texture the per-pixel pass samples once, the terms
// fixed to the stars summed over the panorama's J2000 equirectangular mapping, cd/m^2 x 1e4
// (RGBA32F): the calibrated Milky Way (the panorama's own level u_level, texel for texel: its
// mips are the panorama's), its uniform floor and the zodiacal light (the baked 256 x 128 table,
// bilinear at this level's texel centre). Drawn in horizontal bands, a few per frame, when the
// Sun's ecliptic longitude moved (src/nightsky.cpp: NightSky::foldStep).
layout(binding = WELKIN_BINDING_MILKY_WAY_TEXTURE) uniform sampler2D u_mwTex;  // calibrated x 1e4
layout(binding = WELKIN_BINDING_ZODIACAL_TEXTURE) uniform sampler2D u_zodiTex; // Table 17 units
uniform int u_level;       // the level drawn (the panorama's level it copies)
uniform vec2 u_size;       // that level's width and height, texels
uniform vec3 u_zodi;       // colour x cd/m^2 per Table 17 unit x nightsky.zodiacal_scale x 1e4
uniform vec3 u_mwFloor;    // uniform Milky Way floor, cd/m^2 per channel x 1e4
uniform float u_mwScale;   // nightsky.milky_way_scale (0: off, or no panorama)
layout(location = 0) out vec4 o_rgba;

void main() {
    // Framebuffer row j is texture row j (the panorama's top row first): t = (j + 0.5) / H is the
    // texel centre's coordinate, as the per-pixel pass computes it.
    vec3 L = u_mwFloor + u_zodi * textureLod(u_zodiTex, gl_FragCoord.xy / u_size, 0.0).r;
    if (u_mwScale > 0.0) L += u_mwScale * texelFetch(u_mwTex, ivec2(gl_FragCoord.xy), u_level).rgb;
    o_rgba = vec4(L, 1.0);
}
