// Point sources as people see them, one source for the shader (generators/atmosphere/shaders/
// point_perceptual.glsl includes it) and C++ (welkin::pointThresholdFootCandles(),
// perceptualPoint() in engine/src/point_source.cpp compile it in double, welkin/glsl_cpp.hpp).
//
// Lux per foot-candle (1 lm/ft^2 = 1 / 0.3048^2 lm/m^2), to the digits the shaders use.
#define WELKIN_LUX_PER_FOOT_CANDLE 10.76391
// A Gaussian's full width at half maximum over its standard deviation, 2 sqrt(2 ln 2), to 6
// digits: the drawn points' FWHM (the Stars' and the Planet's PSF, the perceptual point below) to
// the sigma their Gaussian is spread with (stars.vert.glsl, planet.vert.glsl; planet.cpp, which
// sizes the quads with it, includes this file too).
#define WELKIN_GAUSSIAN_FWHM_PER_SIGMA 2.35482

// Schaefer's (1990) threshold illuminance of a point for the eye (after Hecht 1947), in
// foot-candles (WELKIN_LUX_PER_FOOT_CANDLE lx each), against a background of B cd/m^2 (B >= 0):
// the night (scotopic) branch below 1479 nL, the day branch above (1 nL = 1e-5 / pi cd/m^2).
real welkin_pointThresholdFootCandles(real B) {
    real nL = B / 3.183098862e-6;
    bool night = nL < 1479.0;
    real c1 = night ? 1.5848931924611e-10 : 4.4668359215096e-9;  // 10^-9.8, 10^-8.35 ft-cd
    real c2 = night ? 1.2589254117942e-2 : 1.2589254117942e-6;   // 10^-1.9, 10^-5.9 per nL
    real s = 1.0 + sqrt(c2 * nL);
    return c1 * s * s;
}

// The drawn size and contrast of a point seen at R = illuminance / threshold (R >= 1): its FWHM
// grows by half of f0 per decade above the threshold (at most 8 f0) and its Weber contrast from
// c0 by twice c0 per decade. Returns (FWHM in the unit of f0, contrast).
vec2 welkin_pointSizeContrast(real R, real f0, real c0) {
    real decades = log(R) * 0.43429448190325;  // log10
    return vec2(f0 * min(1.0 + 0.5 * decades, 8.0), c0 * (1.0 + 2.0 * decades));
}
