// The Sky's azimuth for its tables over absolute azimuth (the eclipse's sky view, the clouds'
// shadow loss), one source for GLSL (sky.frag.glsl includes it) and C++ (the Sky's tests compile
// it in double against std::atan2).
//
// atan(y, x) in [-pi, pi] without the builtin: Abramowitz & Stegun (1964) 4.4.49's polynomial for
// atan on [0, 1] (stated |error| <= 1e-5 rad; 1.15e-5 with its 7-digit coefficients, the Sky's
// test) after the reduction to the first octant. 1.2e-5 rad is 1.9e-6 of the table's turn, ~1e-3
// of a texel of the eclipse table's 2 x 192 texels at medium quality (2 x 256 at high). The
// builtin (Mesa's NIR lowering: a wider reduction, scaling for huge arguments) cost llvmpipe
// ~0.8 of a trivial fullscreen pass, this ~0.4 (`welkin bench frame`, skyelements/sky/README.md
// "Cost"). 0 at x = y = 0 (the zenith and nadir, where u does not matter).
real skyAtan2(real y, real x) {
    real ax = abs(x);
    real ay = abs(y);
    real a = min(ax, ay) / max(max(ax, ay), 1e-30);
    real s = a * a;
    real r = a * (0.9998660 + s * (-0.3302995 + s * (0.1801410 + s * (-0.0851330 + s * 0.0208351))));
    r = ay > ax ? 1.5707963267948966 - r : r;
    r = x < 0.0 ? 3.141592653589793 - r : r;
    return y < 0.0 ? -r : r;
}
