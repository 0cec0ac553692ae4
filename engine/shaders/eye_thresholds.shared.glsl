// Threshold-versus-intensity of the eye (Ferwerda et al. 1996, "A model of visual adaptation for
// realistic image synthesis", SIGGRAPH), one source for the adaptation pass (adapt.frag.glsl
// includes it) and C++ (eye::coneThresholdLog10(), eye::rodThresholdLog10() in eye.cpp compile it
// in double, welkin/glsl_cpp.hpp): log10 of the threshold luminance at adaptation luminance La
// (photopic, cd/m^2) for the cones and Las (scotopic, scotopic cd/m^2) for the rods, La, Las > 0.
real welkin_coneThresholdLog10(real La) {
    real l = log(La) / log(10.0);
    if (l <= -2.6) return -0.72;
    if (l >= 1.9) return l - 1.255;
    return pow(0.249 * l + 0.65, 2.7) - 0.72;
}

real welkin_rodThresholdLog10(real Las) {
    real l = log(Las) / log(10.0);
    if (l <= -3.94) return -2.86;
    if (l >= -1.44) return l - 0.395;
    return pow(0.405 * l + 1.6, 2.18) - 2.86;
}
