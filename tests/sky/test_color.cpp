// Colour science: CIE 1931 observer, photometry, sRGB, the extraterrestrial solar spectrum.
#include <welkin/color.hpp>
#include <welkin/error.hpp>

#include <catch2/catch.hpp>

using namespace welkin;

TEST_CASE("color: XYZ to linear sRGB matrix matches IEC 61966-2-1", "[cpu][color]") {
    // The published matrix (4 decimals in the standard; 6 from the primaries and D65, as in the
    // Kider 2013 reference README). Tolerance: rounding of the 6-decimal values.
    const double expected[3][3] = {{3.240970, -1.537383, -0.498611}, {-0.969244, 1.875968, 0.041555}, {0.055630, -0.203977, 1.056972}};
    const glm::dmat3 m = color::xyzToLinearSrgbMatrix();
    for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c) CHECK(m[c][r] == Approx(expected[r][c]).margin(1e-6));
    // Round trip: both matrices are inverses to double precision.
    const glm::dvec3 xyz(0.3, 0.7, 1.2);
    const glm::dvec3 back = color::linearSrgbToXyz(color::xyzToLinearSrgb(xyz));
    for (int i = 0; i < 3; ++i) CHECK(back[i] == Approx(xyz[i]).epsilon(1e-12));
    // The luminance row of sRGB -> XYZ is (0.2126, 0.7152, 0.0722) (Rec. 709), to 4 decimals.
    const glm::dmat3 inv = color::linearSrgbToXyzMatrix();
    CHECK(inv[0][1] == Approx(0.2126).margin(5e-5));
    CHECK(inv[1][1] == Approx(0.7152).margin(5e-5));
    CHECK(inv[2][1] == Approx(0.0722).margin(5e-5));
}

TEST_CASE("color: D65 white point and u'v'", "[cpu][color]") {
    const glm::dvec2 xy = color::chromaticity(color::linearSrgbToXyz(glm::dvec3(1.0)));
    CHECK(xy.x == Approx(0.3127).margin(1e-6));
    CHECK(xy.y == Approx(0.3290).margin(1e-6));
    // D65 in CIE 1976 u'v': (0.1978, 0.4683) (published, 4 decimals).
    const glm::dvec2 uv = color::uvPrime(color::linearSrgbToXyz(glm::dvec3(1.0)));
    CHECK(uv.x == Approx(0.1978).margin(1e-4));
    CHECK(uv.y == Approx(0.4683).margin(1e-4));
}

TEST_CASE("color: equal-energy spectrum", "[cpu][color]") {
    // The integral of y-bar over 360-830 nm is 106.857 nm (CIE 1931, 1 nm table: 106.8566; the 5 nm
    // table with linear interpolation differs by < 0.01%), so 1 W m^-2 sr^-1 nm^-1 is 72,983 cd/m^2.
    const glm::dvec3 xyz = color::spectrumToXyz({400.0, 700.0}, {1.0, 1.0});
    CHECK(xyz.y == Approx(683.0 * 106.857).epsilon(2e-4));
    // Illuminant E has chromaticity (1/3, 1/3) by construction of the CMFs (equal integrals,
    // to 4 decimals in the CIE table).
    const glm::dvec2 xy = color::chromaticity(xyz);
    CHECK(xy.x == Approx(1.0 / 3.0).margin(2e-4));
    CHECK(xy.y == Approx(1.0 / 3.0).margin(2e-4));
}

TEST_CASE("color: narrow line at 555 nm", "[cpu][color]") {
    // A triangle of unit height and 5 nm half width at 555 nm has an area of 5 W m^-2 sr^-1:
    // Y = 683 * 5 * ybar(555) with ybar(555) = 1.0000 (the peak of the photopic curve); the
    // curvature of y-bar over +-5 nm lowers it by < 0.2%.
    const glm::dvec3 xyz = color::spectrumToXyz({550.0, 555.0, 560.0}, {0.0, 1.0, 0.0});
    CHECK(xyz.y == Approx(683.0 * 5.0).epsilon(3e-3));
    CHECK(color::cie1931(555.0).y == Approx(1.0).margin(1e-4));
    CHECK(color::cie1931(300.0) == glm::dvec3(0.0));
    CHECK_THROWS_AS(color::spectrumToXyz({500.0, 400.0}, {1.0, 1.0}), Error);
    CHECK_THROWS_AS(color::spectrumToXyz({500.0}, {1.0, 1.0}), Error);
}

TEST_CASE("color: Kider 2013 sample colour conversion", "[cpu][color]") {
    // First sample of the 09:30 scan, computed independently by the data set's Python script:
    // XYZ (3641.58, 3868.54, 6381.60) -> linear sRGB (2672.89, 3992.87, 6158.66) (2 decimals).
    const glm::dvec3 rgb = color::xyzToLinearSrgb({3641.58, 3868.54, 6381.60});
    CHECK(rgb.r == Approx(2672.89).margin(0.02));
    CHECK(rgb.g == Approx(3992.87).margin(0.02));
    CHECK(rgb.b == Approx(6158.66).margin(0.02));
    // luminance() uses the 4-decimal Rec. 709 weights: up to ~3e-5 relative from the exact Y row.
    CHECK(color::luminance(rgb) == Approx(3868.54).epsilon(3e-5));
}

TEST_CASE("color: solar illuminance at the top of the atmosphere", "[cpu][color]") {
    // Published values of the extraterrestrial solar illuminance range from 128 klx to 133.8 klx
    // (solar constant 1361-1367 W/m^2 and luminous efficacy ~ 98 lm/W).
    const glm::dvec3 sun = color::solarIlluminanceSrgb();
    CHECK(color::luminance(sun) > 128e3);
    CHECK(color::luminance(sun) < 134e3);
    // The Sun is slightly warmer than D65 (x 0.3127): ~0.322-0.325 for a 5800 K black body.
    const glm::dvec2 xy = color::chromaticity(color::linearSrgbToXyz(sun));
    CHECK(xy.x > 0.318);
    CHECK(xy.x < 0.330);
}

TEST_CASE("color: the spectral weights are kept per wavelength set and stay exact", "[cpu][color]") {
    // spectralToXyzWeights() keeps the last 8 wavelength sets it computed: a repeated call must
    // give the identical weights, and a different set (or more than 8 sets in turn) its own.
    const std::vector<double> a = {440.0, 550.0, 680.0};
    const std::vector<double> b = {440.0, 550.0, 681.0};
    const std::vector<glm::dvec3> wa = color::spectralToXyzWeights(a);
    const std::vector<glm::dvec3> wb = color::spectralToXyzWeights(b);
    CHECK(wa != wb);  // the last sample moved by 1 nm: its weight changes
    CHECK(color::spectralToXyzWeights(a) == wa);
    for (int i = 0; i < 12; ++i) (void)color::spectralToXyzWeights({400.0 + i, 500.0, 600.0});  // push a and b out
    CHECK(color::spectralToXyzWeights(a) == wa);  // recomputed: bit-identical
    CHECK(color::spectralToXyzWeights(b) == wb);
    // Bad wavelengths are still refused on every call, cached or not.
    CHECK_THROWS_AS(color::spectralToXyzWeights({550.0, 440.0}), Error);
    CHECK_THROWS_AS(color::spectralToXyzWeights({550.0, 440.0}), Error);
}
