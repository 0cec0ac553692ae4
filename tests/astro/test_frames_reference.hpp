// ERFA references shared by the astro frame and star tests.
#pragma once
#include <welkin/astro/frames.hpp>

#include <erfa.h>

#include <cmath>
#include <numbers>

namespace welkin::astro::testref {

inline constexpr double kDeg = std::numbers::pi / 180.0;
inline constexpr double kArcsec = kDeg / 3600.0;

/// Angle between two directions, radians (robust for tiny angles).
inline double angleBetween(const glm::dvec3& a, const glm::dvec3& b) {
    return std::atan2(glm::length(glm::cross(a, b)), glm::dot(a, b));
}

/// Rotation angle of m1 * m2^T (how far apart two rotation matrices are), radians.
inline double rotationDifference(const glm::dmat3& m1, const glm::dmat3& m2) {
    glm::dmat3 d = m1 * glm::transpose(m2);
    double c = (d[0][0] + d[1][1] + d[2][2] - 1.0) / 2.0;
    glm::dvec3 s(d[1][2] - d[2][1], d[2][0] - d[0][2], d[0][1] - d[1][0]);
    return std::atan2(glm::length(s) / 2.0, c);
}

/// ERFA's complete ICRS -> observed pipeline (eraAtco13) for a catalogue source, as an ENU unit
/// vector. UT1 - UTC = dut1 (s), no polar motion, as welkin assumes; dry air at 0.55 um.
inline glm::dvec3 atco13Enu(double ra, double dec, double pmRa /* dRA/dt, rad/yr */, double pmDec, const JulianDate& utc,
                            const Site& site, double pressureHpa, double dut1 = 0.0, int* status = nullptr) {
    // ERFA's "quasi-JD" UTC stretches the day of a leap second to 86401 s: convert from the
    // calendar fields so that both sides mean the same instant.
    DateTime dt = fromJulianDate(utc);
    int sec = int(dt.second);
    double u1 = 0, u2 = 0;
    eraDtf2d("UTC", dt.year, dt.month, dt.day, dt.hour, dt.minute, sec + (dt.second - sec), &u1, &u2);
    double aob, zob, hob, dob, rob, eo;
    int s = eraAtco13(ra, dec, pmRa, pmDec, 0.0, 0.0, u1, u2, dut1, site.longitudeRad, site.latitudeRad,
                      site.heightMeters, 0.0, 0.0, pressureHpa, site.temperatureC, 0.0, 0.55, &aob, &zob, &hob, &dob, &rob, &eo);
    if (status) *status = s;
    return {std::sin(aob) * std::sin(zob), std::cos(aob) * std::sin(zob), std::cos(zob)};
}

}  // namespace welkin::astro::testref
