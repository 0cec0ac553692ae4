// The stars' scintillation amplitude, one source for GLSL (stars.vert.glsl includes it) and C++
// (stars.cpp compiles it in double: Stars' scintillationAmplitude(), which the tests read).

// Relative amplitude of a star's twinkling at apparent altitude hApp (rad; the horizon's below it)
// for the strength `strength` (stars.scintillation): 0.02 strength X^1.75, X the Kasten-Young
// (1989) air mass 1 / (sin h + 0.50572 (h + 6.07995 deg)^-1.6364), at most 0.8.
real stars_scintillationAmplitude(real hApp, real strength) {
    real hd = max(hApp, 0.0);
    real X = 1.0 / (sin(hd) + 0.50572 * pow(degrees(hd) + 6.07995, -1.6364));
    return min(strength * 0.02 * pow(X, 1.75), 0.8);
}
