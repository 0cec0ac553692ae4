// Planet: the Sun's limb-darkened disk, the Moon (maps, Hapke-Lommel-Seeliger, earthshine,
// the Earth's shadow), a planet's Lambert disk, or a PSF. Needs engine/camera.glsl and
// engine/composite.glsl before it. Disks are opaque (transmittance 1 - coverage); the PSF is
// transparent. The model and its sources: skyelements/planet/include/welkin/elements/planet.hpp.
layout(binding = WELKIN_BINDING_MOON_ALBEDO_TEXTURE) uniform sampler2D u_albedo;  // R: relative albedo
layout(binding = WELKIN_BINDING_MOON_NORMAL_TEXTURE) uniform sampler2D u_normals; // tangent (east, south, up)

uniform vec3 u_centre;
uniform float u_sinRadius;
uniform int u_kind;
uniform float u_psfSigma;
flat in vec4 v_pp;  // perceptual point: peak radiance (cd/m^2), sigma (px); 0: none
uniform vec3 u_limb;          // Sun: limb-darkening exponents per channel
uniform vec3 u_light;         // Moon, planet: unit direction from the body to the Sun
uniform mat3 u_moonAxes;      // selenographic axes in ENU (lon 0, lon 90 E, north pole)
uniform mat3 u_worldToSel;    // its transpose
uniform float u_hapke;        // B(g) S(g) at the Moon's phase angle
uniform vec3 u_earthshine;    // earthshine radiance per unit albedo x Lommel-Seeliger term
uniform float u_albedoLod, u_normalLod;
uniform int u_eclipse;
uniform vec3 u_earthCentre;   // relative to the observer, 1e6 m
uniform vec3 u_sunPos;        // 1e6 m
uniform float u_moonDist, u_moonRadius, u_earthRadius, u_sunRadius;  // 1e6 m (Earth's enlarged)
uniform vec3 u_umbraColour;   // luminance 1
uniform vec2 u_umbraRefracted;  // refracted light at the umbra's centre and edge (astro/eclipses.hpp)
uniform vec3 u_coronaAxis;      // corona: the Sun's rotation axis, ENU
uniform float u_coronaSunRadius;  // corona: the Sun's apparent radius, rad
uniform float u_coronaFlattening;

uniform int u_limbOn;            // Moon: 1 while it overlaps the Sun: the limb profile (Baily's beads)
uniform float u_limbProfile[360]; // Moon: the limb's height over its radius, every degree of position angle from the north pole through east
uniform float u_limbMax;          // Moon: a bound on |u_limbProfile|
in vec2 v_offset;
flat in vec3 v_flux;
flat in float v_pixelAngle;

// The corona's radiance (Baumbach's fit): planet.cpp compiles the same text in double.
#include "planet_corona.shared.glsl"

// The sphere's normal, the normal map's and the Sun's visible fraction behind the Earth:
// planet.cpp compiles the same text in double (sphereNormal(), visibleSunFraction()).
#include "planet_sphere.shared.glsl"
#include "../../../engine/shaders/disk_overlap.shared.glsl"  // the eclipsed Sun's fraction (also astro::lensVisibleFraction)

// Sunlight reaching the lunar point at `n` (geocentric shadow geometry): the visible fraction of
// the Sun's disk past the Earth (its radius enlarged for the atmosphere), plus in the shadow the
// reddened light the atmosphere refracts into it.
vec3 planet_eclipse(vec3 n) {
    vec3 P = u_moonDist * u_centre + u_moonRadius * n - u_earthCentre;  // from the Earth's centre
    vec3 S = u_sunPos - u_earthCentre - P;                              // point -> Sun
    float dS = length(S), dE = length(P);
    vec3 s = S / dS, e = -P / dE;
    float rs = asin(min(u_sunRadius / dS, 1.0)), re = asin(min(u_earthRadius / dE, 1.0));
    float sep = atan(length(cross(s, e)), dot(s, e));
    float f = welkin_diskVisibleFraction(rs, re, sep);
    if (f >= 1.0) return vec3(1.0);
    // Refracted light: u_umbraRefracted.y of sunlight at the umbra's edge, .x at its centre
    // (astro::earthShadowLight, the same formula).
    float depth = clamp(sep / max(re - rs, 1e-6), 0.0, 1.0);
    return vec3(f) + (1.0 - f) * mix(u_umbraRefracted.x, u_umbraRefracted.y, depth * depth) * u_umbraColour;
}

vec3 planet_moon(vec3 d, vec3 n) {
    vec3 sel = u_worldToSel * n;
    float h = length(sel.xy);
    float lon = atan(sel.y, sel.x), lat = atan(sel.z, h);
    vec2 uv = vec2(0.5 + lon / (2.0 * WELKIN_PI), 0.5 - lat / WELKIN_PI);
    // The maps' rows are top (north) first as uploaded: t = 0 is the first row.
    float A = textureLod(u_albedo, uv, u_albedoLod).r;
    vec3 t = textureLod(u_normals, uv, u_normalLod).xyz;
    // East and north tangents without trigonometry: (-sin lon, cos lon, 0) and
    // (-sin lat cos lon, -sin lat sin lon, cos lat) from the selenographic normal itself.
    vec2 cs = h > 1e-6 ? sel.xy / h : vec2(1.0, 0.0);  // (cos lon, sin lon)
    vec3 tE = u_moonAxes * vec3(-cs.y, cs.x, 0.0);
    vec3 tN = u_moonAxes * vec3(-sel.z * cs, h);
    vec3 m = planet_mapNormal(t, tE, tN, n);  // the map's G points south
    float ce = max(dot(m, -d), 0.0);
    float ci = dot(m, u_light);
    vec3 L = vec3(0.0);
    if (ci > 0.0) {
        vec3 sun = vec3(v_flux * (A * u_hapke * ci / (ci + ce + 1e-6)));
        if (u_eclipse == 1) sun *= planet_eclipse(n);
        L += sun;
    }
    float cEarth = max(dot(m, -u_centre), 0.0);
    L += u_earthshine * (A * cEarth / (cEarth + ce + 1e-6));
    return L;
}

// The Moon's limb radius over its mean radius towards `d` (the profile at d's position angle).
float planet_limb(vec3 d) {
    if (u_limbOn == 0) return 1.0;
    vec3 e = d - u_centre * dot(d, u_centre);
    vec3 pole = u_moonAxes[2] - u_centre * dot(u_moonAxes[2], u_centre);
    float pa = atan(dot(e, cross(pole, u_centre)), dot(e, pole));  // from the pole through east
    float f = fract(pa / (2.0 * WELKIN_PI) + 1.0) * 360.0;
    int i0 = int(f) % 360;
    float w = fract(f);
    return 1.0 + mix(u_limbProfile[i0], u_limbProfile[(i0 + 1) % 360], w);
}
// Radiance towards `d` and whether it meets the disk (1) or not (0).
vec3 planet_sample(vec3 d, out float inside) {
    float rho;
    vec3 n = planet_normal(d, u_centre, u_sinRadius, rho);
    inside = (rho <= (u_kind == 1 ? planet_limb(d) : 1.0) && dot(d, u_centre) > 0.0) ? 1.0 : 0.0;
    if (inside == 0.0) return vec3(0.0);
    if (u_kind == 0) {
        float mu = max(dot(n, -d), 0.0);
        return v_flux * pow(vec3(mu), u_limb);
    }
    if (u_kind == 2) return v_flux * max(dot(n, u_light), 0.0);
    return planet_moon(d, n);
}

void main() {
    vec3 dir;
    if (!welkin_viewDirection(welkin_pixel(), dir)) discard;  // outside a fisheye's circle
    if (u_kind == 3) {
        float sigma = u_psfSigma;
        float w = exp(-0.5 * dot(v_offset, v_offset) / (sigma * sigma)) / (2.0 * WELKIN_PI * sigma * sigma);
        vec3 Lp = v_flux * w;
        // Perceptual point (planet.vert.glsl): where it is brighter than the physical PSF.
        if (v_pp.w > 0.0) Lp = max(Lp, v_pp.rgb * exp(-0.5 * dot(v_offset, v_offset) / (v_pp.w * v_pp.w)));
        welkin_output(Lp, vec3(1.0));
        return;
    }
    float theta = atan(length(cross(dir, u_centre)), dot(dir, u_centre));
    if (u_kind == 4) {
        // The corona (planet::coronaRelativeRadiance): v_flux is the disk's mean radiance.
        float r = theta / u_coronaSunRadius;
        if (r < 1.0 || theta > asin(min(u_sinRadius, 1.0))) discard;
        vec3 off = dir - u_centre * dot(dir, u_centre);
        vec3 ax = u_coronaAxis - u_centre * dot(u_coronaAxis, u_centre);
        float sinLat = (length(off) > 0.0 && length(ax) > 0.0) ? dot(normalize(off), normalize(ax)) : 0.0;
        float k = planet_coronaRelativeRadiance(r, u_coronaFlattening, sinLat);  // planet_corona.shared.glsl
        welkin_output(v_flux * k, vec3(1.0));
        return;
    }
    float alpha = asin(min(u_sinRadius, 1.0));
    float band = 1.5 * v_pixelAngle + (u_kind == 1 && u_limbOn == 1 ? u_limbMax * alpha : 0.0);
    if (theta > alpha + band) discard;
    vec3 L = vec3(0.0);
    float coverage = 0.0;
    if (theta > alpha - band) {
        // Near the limb: 4 x 4 samples over the pixel's footprint.
        vec2 px = welkin_pixel();
        for (int j = 0; j < 4; ++j)
            for (int i = 0; i < 4; ++i) {
                vec3 d;
                if (!welkin_viewDirection(px + (vec2(i, j) - 1.5) * 0.25, d)) continue;
                float in1;
                L += planet_sample(d, in1);
                coverage += in1;
            }
        L /= 16.0;
        coverage /= 16.0;
    } else {
        L = planet_sample(dir, coverage);
    }
    if (coverage <= 0.0) discard;
    welkin_output(L, vec3(1.0 - coverage));
}
