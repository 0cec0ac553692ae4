// The solar corona's radiance, one source for GLSL (planet.frag.glsl includes it) and C++
// (planet.cpp compiles it in double: planet::coronaRelativeRadiance()).

// The K+F corona's radiance over the mean radiance of the solar disk at r solar radii (>= 1) from
// the Sun's centre: Baumbach's (1937) fit as given in Allen's Astrophysical Quantities (4th ed.,
// 14.5), 1e-6 (0.0532 r^-2.5 + 1.425 r^-7 + 2.565 r^-17), r stretched towards the poles by
// 1 + flattening sin^2(position angle from the solar equator).
real planet_coronaRelativeRadiance(real r, real flattening, real sinFromEquator) {
    real re = r * (1.0 + flattening * sinFromEquator * sinFromEquator);
    return 1e-6 * (0.0532 * pow(re, -2.5) + 1.425 * pow(re, -7.0) + 2.565 * pow(re, -17.0));
}
