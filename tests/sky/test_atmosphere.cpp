// The atmosphere description: presets, derived quantities, validation, phase functions.
#include <welkin/error.hpp>
#include <welkin/generators/atmosphere.hpp>

#include <catch2/catch.hpp>

#include <numbers>

using namespace welkin;
using namespace welkin::atmosphere;

namespace {
/// Integral over the sphere of f(mu) and of mu f(mu): 2 pi int_{-1}^{1} f dmu (midpoint, 200k cells).
std::pair<double, double> sphereMoments(const std::function<double(double)>& f) {
    const int n = 200000;
    double s0 = 0.0, s1 = 0.0;
    for (int i = 0; i < n; ++i) {
        const double mu = -1.0 + (i + 0.5) * 2.0 / n;
        s0 += f(mu);
        s1 += mu * f(mu);
    }
    const double w = 2.0 * std::numbers::pi * 2.0 / n;
    return {s0 * w, s1 * w};
}
}  // namespace

TEST_CASE("atmosphere: presets are valid and match published columns", "[cpu][atmosphere]") {
    for (const Atmosphere& a : {Atmosphere::earthClear(), Atmosphere::earthHazy(), Atmosphere::earthBruneton2017(),
                                Atmosphere::earthBruneton2017Evaluation(), Atmosphere::mars()})
        CHECK_NOTHROW(a.validate());
    const Atmosphere e = Atmosphere::earthClear();
    // Rayleigh optical depth of the standard atmosphere at 550 nm: about 0.0973 (Bodhaine et al.
    // 1999; the often quoted sea-level value); 0.3% covers the rounding of the quoted value.
    CHECK(e.rayleighOpticalDepth(550.0) == Approx(0.0973).epsilon(3e-3));
    // Its spectral slope is close to lambda^-4.08 across the visible (dispersion of the
    // refractive index and of the King factor); 2% on the ratio between 440 and 680 nm.
    CHECK(e.rayleighOpticalDepth(440.0) / e.rayleighOpticalDepth(680.0) == Approx(std::pow(680.0 / 440.0, 4.08)).epsilon(0.02));
    CHECK(e.aerosolOpticalDepth(550.0) == Approx(0.1).epsilon(1e-3));
    CHECK(e.ozoneColumnDobson() == Approx(300.0).epsilon(1e-6));
    CHECK(Atmosphere::earthHazy().aerosolOpticalDepth(550.0) == Approx(0.4).epsilon(1e-3));
    // Bruneton's demo: Mie beta 5.328e-3 with alpha 0 is the aerosol optical depth at every wavelength.
    CHECK(Atmosphere::earthBruneton2017().aerosolOpticalDepth(450.0) == Approx(5.328e-3).epsilon(1e-6));
    // Bruneton's evaluation: AOD = beta lambda_um^-alpha = 0.04 * 0.55^-0.8 = 0.0645 at 550 nm;
    // Penndorf's 550 nm coefficient 12.26e-6 /m at 0 C, times 273.16 / 288.16 and 8 km.
    const Atmosphere be = Atmosphere::earthBruneton2017Evaluation();
    CHECK(be.aerosolOpticalDepth(550.0) == Approx(0.04 * std::pow(0.55, -0.8)).epsilon(1e-3));
    CHECK(be.rayleighOpticalDepth(550.0) == Approx(12.26e-6 * 273.16 / 288.16 * 8000.0).epsilon(2e-3));
    // Mars: the Sun at 1.5237 AU receives 1 / 1.5237^2 = 0.4307 of the Earth's irradiance.
    const Atmosphere m = Atmosphere::mars();
    CHECK(m.solarIrradiance[10] / e.solarIrradiance[10] == Approx(1.0 / (1.5237 * 1.5237)).epsilon(1e-9));
    CHECK(m.ozoneColumnDobson() == 0.0);
}

TEST_CASE("atmosphere: aerosol, ozone and albedo modifiers", "[cpu][atmosphere]") {
    const Atmosphere a = Atmosphere::earthClear().withAerosolOpticalDepth(0.3, 1.2);
    CHECK(a.aerosolOpticalDepth(550.0) == Approx(0.3).epsilon(1e-3));
    // Angstrom law: tau(445) = 0.3 (445 / 550)^-1.2 (445 is a grid wavelength: no interpolation error).
    CHECK(a.aerosolOpticalDepth(445.0) == Approx(0.3 * std::pow(445.0 / 550.0, -1.2)).epsilon(1e-9));
    // Single-scattering albedo kept (0.9).
    CHECK(a.mieScattering[5] / a.mieExtinction[5] == Approx(0.9).epsilon(1e-12));
    // Without alpha, the spectral shape is kept.
    const Atmosphere b = Atmosphere::earthClear().withAerosolOpticalDepth(0.2);
    CHECK(b.aerosolOpticalDepth(445.0) / b.aerosolOpticalDepth(645.0) ==
          Approx(Atmosphere::earthClear().aerosolOpticalDepth(445.0) / Atmosphere::earthClear().aerosolOpticalDepth(645.0)).epsilon(1e-12));
    CHECK(Atmosphere::earthClear().withOzoneColumn(350.0).ozoneColumnDobson() == Approx(350.0).epsilon(1e-9));
    CHECK(Atmosphere::earthClear().withGroundAlbedo(0.3).groundAlbedo[7] == 0.3);
    // Asymmetry 0.64 (AERONET, Kider's day) with Cornette-Shanks: the phase function's numeric
    // mean cosine must come out at 0.64.
    const Atmosphere g = Atmosphere::earthClear().withAerosolAsymmetry(0.64);
    const auto [norm, meanCos] = sphereMoments([&](double mu) { return miePhase(g, mu); });
    CHECK(norm == Approx(1.0).epsilon(1e-6));
    CHECK(meanCos == Approx(0.64).epsilon(1e-5));
    CHECK_THROWS_AS(Atmosphere::earthClear().withAerosolOpticalDepth(-0.1), Error);
    CHECK_THROWS_AS(Atmosphere::earthClear().withAerosolAsymmetry(0.99), Error);
}

TEST_CASE("atmosphere: validate names the member and its range", "[cpu][atmosphere]") {
    auto message = [](const Atmosphere& a) {
        try {
            a.validate();
        } catch (const Error& e) {
            return std::string(e.what());
        }
        return std::string();
    };
    Atmosphere a = Atmosphere::earthClear();
    a.mieG = 1.5;
    CHECK_THAT(message(a), Catch::Contains("mieG") && Catch::Contains("[-0.999, 0.999]"));
    a = Atmosphere::earthClear();
    a.mieScattering[3] = 2.0 * a.mieExtinction[3];
    CHECK_THAT(message(a), Catch::Contains("mieScattering[3]"));
    a = Atmosphere::earthClear();
    a.topRadiusM = a.bottomRadiusM - 1.0;
    CHECK_THAT(message(a), Catch::Contains("topRadiusM"));
    a = Atmosphere::earthClear();
    a.groundAlbedo.pop_back();
    CHECK_THAT(message(a), Catch::Contains("groundAlbedo") && Catch::Contains("46 values for 47"));
    a = Atmosphere::earthClear();
    std::swap(a.wavelengthsNm[3], a.wavelengthsNm[4]);
    CHECK_THAT(message(a), Catch::Contains("wavelengthsNm"));
    a = Atmosphere::earthClear();
    a.solarIrradiance[0] = std::nan("");
    CHECK_THAT(message(a), Catch::Contains("solarIrradiance[0]"));
}

TEST_CASE("atmosphere: phase functions are normalised", "[cpu][atmosphere]") {
    // Rayleigh: mean cosine 0 (symmetric).
    auto [n0, m0] = sphereMoments(rayleighPhase);
    CHECK(n0 == Approx(1.0).epsilon(1e-8));
    CHECK(m0 == Approx(0.0).margin(1e-8));
    for (double g : {-0.3, 0.0, 0.5, 0.8}) {
        // Midpoint rule on 200k cells: the sharpest case (g 0.8) is resolved to < 1e-6.
        auto [n1, m1] = sphereMoments([g](double mu) { return henyeyGreensteinPhase(mu, g); });
        CHECK(n1 == Approx(1.0).epsilon(1e-6));
        CHECK(m1 == Approx(g).margin(1e-6));  // HG: mean cosine = g
        auto [n2, m2] = sphereMoments([g](double mu) { return cornetteShanksPhase(mu, g); });
        CHECK(n2 == Approx(1.0).epsilon(1e-6));
        CHECK(m2 == Approx(phaseAsymmetry(MiePhaseFunction::CornetteShanks, g)).margin(1e-6));
    }
}

TEST_CASE("atmosphere: density profiles", "[cpu][atmosphere]") {
    const Atmosphere a = Atmosphere::earthClear();
    CHECK(rayleighDensity(a, 0.0) == 1.0);
    CHECK(rayleighDensity(a, 8000.0) == Approx(std::exp(-1.0)));
    CHECK(mieDensity(a, 2400.0) == Approx(std::exp(-2.0)));
    CHECK(ozoneDensity(a, 25000.0) == 1.0);
    CHECK(ozoneDensity(a, 17500.0) == Approx(0.5));
    CHECK(ozoneDensity(a, 9000.0) == 0.0);
    CHECK(ozoneDensity(a, 41000.0) == 0.0);
}

TEST_CASE("atmosphere: RGB coefficients", "[cpu][atmosphere]") {
    const Atmosphere a = Atmosphere::earthClear();
    const RgbCoefficients p = a.rgbAtWavelengths({680.0, 550.0, 440.0});
    // Point-sampled Rayleigh coefficients against Bruneton's and Hillaire's published RGB values
    // (5.802e-6, 13.558e-6, 33.1e-6 /m, from a slightly different law: 1.24062e-6 lambda_um^-4):
    // within 12%, the difference between that law and Bodhaine's optical depth.
    CHECK(p.rayleighScattering.r == Approx(5.802e-6).epsilon(0.12));
    CHECK(p.rayleighScattering.g == Approx(13.558e-6).epsilon(0.12));
    CHECK(p.rayleighScattering.b == Approx(33.1e-6).epsilon(0.12));
    const RgbCoefficients c = a.rgb();
    // Effective wavelengths keep the channel order and the coefficients their spectral order.
    CHECK(c.rayleighScattering.b > c.rayleighScattering.g);
    CHECK(c.rayleighScattering.g > c.rayleighScattering.r);
    CHECK(c.wavelengthsNm.r > c.wavelengthsNm.g);
    CHECK(c.wavelengthsNm.g > c.wavelengthsNm.b);
    // Ozone absorbs most in green-red (Chappuis band), least in blue.
    CHECK(c.ozoneAbsorption.b < 0.2 * c.ozoneAbsorption.g);
    // The Sun: luminance is its illuminance (128-134 klx) and r > g > b (warmer than D65).
    const double lux = 0.2126 * c.solarIlluminance.r + 0.7152 * c.solarIlluminance.g + 0.0722 * c.solarIlluminance.b;
    CHECK(lux > 128e3);
    CHECK(lux < 134e3);
    CHECK(c.solarIlluminance.r > c.solarIlluminance.b);
}

TEST_CASE("atmosphere: SkyVars key rebuilds on a new pointer", "[cpu][atmosphere]") {
    SkyVars vars;
    auto a = std::make_shared<const Atmosphere>(Atmosphere::earthClear());
    vars.set(kAtmosphere, a);
    const auto v0 = vars.version(kAtmosphere);
    vars.set(kAtmosphere, a);  // same pointer: no change
    CHECK(vars.version(kAtmosphere) == v0);
    vars.set(kAtmosphere, std::make_shared<const Atmosphere>(Atmosphere::earthHazy()));
    CHECK(vars.version(kAtmosphere) == v0 + 1);
    CHECK(vars.get(kAtmosphere)->name == "earth-hazy");
}
