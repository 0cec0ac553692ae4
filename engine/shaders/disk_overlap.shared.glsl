// The visible fraction of one disk behind another (the GLSL subset: compiled by the shaders and,
// in double through welkin/glsl_cpp.hpp, by the astronomy's eclipses.cpp: one text for the
// Planet's eclipsed Sun, the eclipses' obscuration and the Earth's shadow light on the Moon).
// The includer defines WELKIN_PI (the shaders: camera_projection.shared.glsl; C++: a constant).
//
// rs: the covered disk's angular radius (the Sun's), rad, > 0; re: the covering disk's (the Moon's
// or the Earth's shadow's), rad, >= 0; d: the centres' separation, rad, >= 0. Returns 1 minus the
// two circles' lens over the covered disk's area, in [0, 1]: 1 apart, 0 wholly covered,
// 1 - (re/rs)^2 for an annulus.
real welkin_diskVisibleFraction(real rs, real re, real d) {
    if (d >= rs + re) return 1.0;
    if (d <= re - rs) return 0.0;
    if (d <= rs - re) return 1.0 - (re * re) / (rs * rs);
    real a1 = acos(clamp((d * d + rs * rs - re * re) / (2.0 * d * rs), -1.0, 1.0));
    real a2 = acos(clamp((d * d + re * re - rs * rs) / (2.0 * d * re), -1.0, 1.0));
    real lens = rs * rs * (a1 - 0.5 * sin(2.0 * a1)) + re * re * (a2 - 0.5 * sin(2.0 * a2));
    return clamp(1.0 - lens / (WELKIN_PI * rs * rs), 0.0, 1.0);
}
