// The Rainbow's direction cache: a 2-D table of the curtain's radiance and transmittance over the
// directions around the anti-light point (the point opposite the Sun or Moon), where every bow is
// a circle. Texel x is sin(a / 2), a the angle from the anti-light point: sqrt((1 - cos a) / 2),
// which a pixel gets without an inverse cosine, nearly uniform in a where the bows and the glory
// are (2048 texels: 0.056 deg at the anti-light point, 0.060 deg at the primary, 0.066 deg at the
// secondary; coarse only towards the light itself). Texel y is the position angle psi around the
// anti-light point over 2 pi (the bows do not vary along psi: only the curtain's geometry does).
uniform vec3 u_polarA;   // unit vector to the anti-light point (-u_light), world ENU
uniform vec3 u_polarE1;  // unit vector orthogonal to u_polarA: psi = 0
uniform vec3 u_polarE2;  // cross(u_polarA, u_polarE1): psi = pi/2

const float RAINBOW_PI = 3.14159265358979;

// The direction of the cache coordinate (x, psi): 2 asin(x) from the anti-light point.
vec3 rainbow_polarDirection(float x, float psi) {
    float a = 2.0 * asin(clamp(x, 0.0, 1.0));
    return cos(a) * u_polarA + sin(a) * (cos(psi) * u_polarE1 + sin(psi) * u_polarE2);
}
