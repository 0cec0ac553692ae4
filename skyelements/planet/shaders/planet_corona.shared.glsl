// The solar corona's radiance, one source for GLSL (planet.frag.glsl includes it) and C++
// (planet.cpp compiles it in double: planet::coronaRelativeRadiance()).

// The K+F corona's radiance over the mean radiance of the solar disk at r solar radii (>= 1) from
// the Sun's centre, r stretched towards the poles by 1 + flattening sin^2(position angle from the
// solar equator) (re below):
// - re <= 6: Baumbach's (1937) fit as given in Allen's Astrophysical Quantities (4th ed., 14.5),
//   1e-6 (0.0532 r^-2.5 + 1.425 r^-7 + 2.565 r^-17) (the range it was fitted to);
// - re > 6: the F corona's (the dust's, which dominates there) power law in elongation measured by
//   LASCO-C2/C3 out to 30 solar radii and joining the zodiacal light (Lamy, Gilardy and Llebaria
//   2022, "Observations of the solar F-corona from space", arXiv:2202.11533): exponent -2.33 along
//   the equator, -2.55 towards the poles (here 2.33 cos^2 + 2.55 sin^2 of the position angle),
//   scaled to Baumbach's value at 6, so the radiance is continuous there;
// - faded to 0 between re = 20 and 30 (1 - smoothstep; planet.hpp's kCoronaExtentSolarRadii = 30,
//   the drawn quad's radius): at 20 the profile is 3.7e-11 of the disk's radiance, below the
//   totality sky near the Sun (docs/eclipse.md, "The corona's edge").
real planet_coronaRelativeRadiance(real r, real flattening, real sinFromEquator) {
    real s2 = sinFromEquator * sinFromEquator;
    real re = r * (1.0 + flattening * s2);
    real rb = min(re, 6.0);
    real b = 1e-6 * (0.0532 * pow(rb, -2.5) + 1.425 * pow(rb, -7.0) + 2.565 * pow(rb, -17.0));
    if (re <= 6.0) return b;
    real n = 2.33 + (2.55 - 2.33) * s2;
    return b * pow(re / 6.0, -n) * (1.0 - smoothstep(20.0, 30.0, re));
}
