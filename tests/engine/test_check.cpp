// welkin::checkRange / checkOpenRange: the one range check behind the API's preconditions.
#include <catch2/catch.hpp>

#include <welkin/camera.hpp>
#include <welkin/check.hpp>
#include <welkin/error.hpp>
#include <welkin/processor.hpp>

#include <cmath>
#include <numbers>

using namespace welkin;

TEST_CASE("checkRange: closed bounds pass, outside and NaN throw one line naming where, what and range", "[cpu][check]") {
    CHECK_NOTHROW(checkRange("f()", "x", 1.0, 1.0, 2.0));  // both bounds are inside
    CHECK_NOTHROW(checkRange("f()", "x", 2.0, 1.0, 2.0));
    CHECK_THROWS_MATCHES(checkRange("f()", "x", 2.5, 1.0, 2.0), Error, Catch::Message("f(): x 2.5 not in [1, 2]"));
    CHECK_THROWS_MATCHES(checkRange("f()", "x", -0.5, 1.0, 2.0), Error, Catch::Message("f(): x -0.5 not in [1, 2]"));
    CHECK_THROWS_WITH(checkRange("f()", "x", std::nan(""), -1e300, 1e300), Catch::Contains("f(): x nan not in"));
}

TEST_CASE("checkOpenRange: bounds excluded, infinite bounds printed as inf", "[cpu][check]") {
    CHECK_NOTHROW(checkOpenRange("g()", "near", 1e-9, 0.0, kInfinity));
    CHECK_THROWS_MATCHES(checkOpenRange("g()", "near", 0.0, 0.0, kInfinity), Error, Catch::Message("g(): near 0 not in (0, inf)"));
    CHECK_THROWS_MATCHES(checkOpenRange("g()", "t", 1.0, 0.0, 1.0), Error, Catch::Message("g(): t 1 not in (0, 1)"));
    CHECK_THROWS_WITH(checkOpenRange("g()", "t", std::nan(""), -kInfinity, kInfinity), Catch::Contains("not in (-inf, inf)"));
}

TEST_CASE("checkRange: compared unscaled, shown scaled with the unit", "[cpu][check]") {
    constexpr double pi = std::numbers::pi;
    const Shown deg{180 / pi, " deg"};
    CHECK_NOTHROW(checkRange("Observer", "latitude", pi / 2, -pi / 2, pi / 2, deg));  // the pole itself is valid
    CHECK_THROWS_MATCHES(checkRange("Observer", "latitude", pi, -pi / 2, pi / 2, deg), Error,
                         Catch::Message("Observer: latitude 180 deg not in [-90, 90]"));
}

TEST_CASE("The API's preconditions use checkRange's message form", "[cpu][check]") {
    CHECK_THROWS_MATCHES(Observer{.latitudeRad = 2.0}.validate(), Error,
                         Catch::Message("Observer: latitude 114.592 deg not in [-90, 90]"));
    CHECK_THROWS_MATCHES(Observer{.heightMeters = 2e9}.validate(), Error, Catch::Message("Observer: height 2e+09 m not in [-10000, 1e+09]"));
    Camera c;
    c.verticalFovRad = 0;
    CHECK_THROWS_MATCHES(c.validate(), Error, Catch::Message("Camera: verticalFovRad 0 not in (0, 3.14159)"));
    SkyProcessor p;
    CHECK_THROWS_MATCHES(p.setExposure({.compensationEv = 11}), Error,
                         Catch::Message("SkyProcessor::setExposure(): compensationEv 11 not in [-10, 10]"));
}
