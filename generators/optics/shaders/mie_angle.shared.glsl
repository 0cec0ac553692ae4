// The Mie tables' angle mapping, one source for GLSL (mie_angle.glsl includes it) and C++
// (welkin::generators::mieUFromAngle in mie_tables.cpp compiles it in double, welkin/glsl_cpp.hpp):
// scattering angle theta (rad) -> texture coordinate u, piecewise linear through the knots
// (u, theta deg) = (0, 0), (0.25, 120), (0.70, 150), (0.80, 175), (1, 180).
real welkin_mieUFromAngle(real theta) {
    real d = clamp(degrees(theta), 0.0, 180.0);
    if (d <= 120.0) return 0.25 * d / 120.0;
    if (d <= 150.0) return 0.25 + 0.45 * (d - 120.0) / 30.0;
    if (d <= 175.0) return 0.70 + 0.10 * (d - 150.0) / 25.0;
    return 0.80 + 0.20 * (d - 175.0) / 5.0;
}
