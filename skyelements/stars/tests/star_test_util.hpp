// Helpers shared by the Stars element's tests.
#pragma once
#include <welkin/astro/stars.hpp>

#include <numbers>

namespace welkin::test {

/// A catalogue star at an ICRS direction (right ascension, declination in degrees), visual
/// magnitude and B-V colour, with no proper motion.
inline astro::Star catalogueStar(double raDeg, double decDeg, double mag, double bv) {
    constexpr double kDeg = std::numbers::pi / 180.0;
    astro::Star s;
    s.raJ2000Rad = raDeg * kDeg;
    s.decJ2000Rad = decDeg * kDeg;
    s.magnitudeV = float(mag);
    s.colorBV = float(bv);
    return s;
}

}  // namespace welkin::test
