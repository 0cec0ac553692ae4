// The Rainbow's direction cache: a 2-D table of the curtain's radiance and transmittance over the
// directions around the anti-light point (the point opposite the Sun or Moon), where every bow is
// a circle. Texel x is sin(a / 2), a the angle from the anti-light point: sqrt((1 - cos a) / 2),
// which a pixel gets without an inverse cosine, nearly uniform in a where the bows and the glory
// are (2048 texels: 0.056 deg at the anti-light point, 0.060 deg at the primary, 0.066 deg at the
// secondary; coarse only towards the light itself). Texel y is a pseudo-angle of the position
// angle psi around the anti-light point (the bows do not vary along psi: only the curtain's
// geometry does): with (c, s) = (cos psi, sin psi) and t = c / (|c| + |s|), y = (1 - t) / 4 for
// s >= 0 and (3 + t) / 4 for s < 0, which runs from 0 to 1 once round, continuously, with no
// inverse tangent for a pixel to evaluate (an atan cost the display half of its budget on
// llvmpipe). Within each quarter, f = 4 y - quarter gives psi = quarter pi/2 + atan2(f, 1 - f): a
// texel spans 0.9 deg (on the axes) to 1.8 deg (on the diagonals) of psi with 256 texels.
uniform vec3 u_polarA;   // unit vector to the anti-light point (-u_light), world ENU
uniform vec3 u_polarE1;  // unit vector orthogonal to u_polarA: psi = 0
uniform vec3 u_polarE2;  // cross(u_polarA, u_polarE1): psi = pi/2

const float RAINBOW_PI = 3.14159265358979;

// The position angle of the pseudo-angle y in [0, 1) (above).
float rainbow_psiFromY(float y) {
    float q = floor(4.0 * y), f = 4.0 * y - q;
    return q * (0.5 * RAINBOW_PI) + atan(f, 1.0 - f);
}

// The pseudo-angle y (above, not reduced to [0, 1)) of a direction whose components on
// (u_polarE1, u_polarE2) are (c, s), any length.
float rainbow_yFromComponents(float c, float s) {
    float t = c / max(abs(c) + abs(s), 1e-30);
    return 0.25 * (s >= 0.0 ? 1.0 - t : 3.0 + t);
}

// The direction of the cache coordinate (x, psi): 2 asin(x) from the anti-light point.
vec3 rainbow_polarDirection(float x, float psi) {
    float a = 2.0 * asin(clamp(x, 0.0, 1.0));
    return cos(a) * u_polarA + sin(a) * (cos(psi) * u_polarE1 + sin(psi) * u_polarE2);
}
