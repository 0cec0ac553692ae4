// Lorenz-Mie series (generators/optics/mie.hpp) against published values and physical limits.
#include <catch2/catch.hpp>

#include <welkin/error.hpp>
#include <welkin/generators/mie.hpp>

#include <cmath>
#include <complex>

using namespace welkin::generators;
using cd = std::complex<double>;

namespace {
constexpr double kDeg = M_PI / 180.0;

// Integral of the phase function over the sphere, 2 pi int p(theta) sin(theta) dtheta, by the
// composite Simpson rule on `n` (even) intervals of theta: the forward peak has a width ~ 1/x rad,
// so n >> x resolves it.
double phaseIntegral(const MieSphere& s, int n) {
    std::vector<double> mu(std::size_t(n) + 1), p;
    for (int i = 0; i <= n; ++i) mu[std::size_t(i)] = std::cos(M_PI * i / n);
    s.phases(mu, p);
    double sum = 0;
    for (int i = 0; i <= n; ++i) {
        const double w = (i == 0 || i == n) ? 1.0 : (i % 2 ? 4.0 : 2.0);
        sum += w * p[std::size_t(i)] * std::sin(M_PI * i / n);
    }
    return 2.0 * M_PI * sum * (M_PI / n) / 3.0;
}

// Descartes' minimum deviation for a ray with k internal reflections in a sphere of index n,
// returned as the scattering angle in [0, pi]: sin i = n sin r, cos^2 i = (n^2 - 1) / (k(k+2)),
// deviation D = k pi + 2 i - 2 (k + 1) r (Humphreys, "Physics of the Air", 1940; Nussenzveig 1977).
double descartesScatteringAngle(double n, int k) {
    const double i = std::acos(std::sqrt((n * n - 1.0) / (k * (k + 2.0))));
    const double r = std::asin(std::sin(i) / n);
    double D = std::fmod(k * M_PI + 2.0 * i - 2.0 * (k + 1.0) * r, 2.0 * M_PI);
    if (D > M_PI) D = 2.0 * M_PI - D;
    return D;
}

// Scattering angle of the brightest point of the phase function in [lo, hi] (step 0.01 deg),
// averaged over 9 radii spread +-4 % around x: the average (as any real shower's spread of sizes)
// removes the ripple of period ~pi/x from the interference with the external reflection, which
// would otherwise decide which 0.02-degree ripple crest is the maximum.
double bowMaximum(cd m, double x, double lo, double hi) {
    std::vector<double> mu;
    for (double t = lo; t <= hi + 1e-9; t += 0.01) mu.push_back(std::cos(t * kDeg));
    std::vector<double> sum(mu.size(), 0.0), p;
    for (int j = -4; j <= 4; ++j) {
        MieSphere s(m, x * (1.0 + 0.01 * j));
        s.phases(mu, p);
        for (std::size_t i = 0; i < mu.size(); ++i) sum[i] += p[i];
    }
    std::size_t best = 0;
    for (std::size_t i = 1; i < mu.size(); ++i)
        if (sum[i] > sum[best]) best = i;
    return lo + 0.01 * double(best);
}
}  // namespace

TEST_CASE("Mie: Bohren & Huffman's BHMIE example", "[cpu][mie]") {
    // B&H appendix A (p. 482): m = 1.55, r = 0.525 um, lambda = 0.6328 um (x = 5.213):
    // Qext = Qsca = 3.10543, Qback = 2.92534, g = 0.63314 (printed to 5 decimals: tolerance 1e-5).
    MieSphere s(cd(1.55, 0.0), 2.0 * M_PI * 0.525 / 0.6328);
    CHECK(s.qext() == Approx(3.10543).margin(1e-5));
    CHECK(s.qsca() == Approx(3.10543).margin(1e-5));
    CHECK(s.qback() == Approx(2.92534).margin(1e-5));
    CHECK(s.g() == Approx(0.63314).margin(1e-5));
}

TEST_CASE("Mie: Wiscombe's MIEV0 test cases for large size parameters", "[cpu][mie]") {
    // Wiscombe 1979 (NCAR TN-140+STR, appendix; MIEV0 test cases 'd', 'e', 'f'), printed to 7
    // significant digits: tolerance 2e-6 (their last digit). MIEV0 writes m = n - i k; here k >= 0.
    SECTION("x = 100, m = 1.33 + 1e-5 i") {
        MieSphere s(cd(1.33, 1e-5), 100.0);
        CHECK(s.qext() == Approx(2.101321).margin(2e-6));
        CHECK(s.qsca() == Approx(2.096594).margin(2e-6));
        CHECK(s.g() == Approx(0.868959).margin(2e-6));
        cd s1, s2;
        s.amplitudes(1.0, s1, s2);  // forward amplitude S1(0) = 5.253302e3 (+-) 1.243188e2 i
        CHECK(s1.real() == Approx(5253.302).margin(2e-3));
        CHECK(std::abs(s1.imag()) == Approx(124.3188).margin(2e-4));
    }
    SECTION("x = 1000, m = 0.75") {
        MieSphere s(cd(0.75, 0.0), 1000.0);
        CHECK(s.qext() == Approx(1.997908).margin(2e-6));
        CHECK(s.qsca() == Approx(1.997908).margin(2e-6));
    }
    SECTION("x = 10000, m = 1.33 + 1e-5 i") {
        MieSphere s(cd(1.33, 1e-5), 10000.0);
        CHECK(s.qext() == Approx(2.004089).margin(2e-6));
        CHECK(s.qsca() == Approx(1.723857).margin(2e-6));
        CHECK(s.g() == Approx(0.907840).margin(2e-6));
        CHECK(std::isfinite(s.qback()));
    }
}

TEST_CASE("Mie: the Rayleigh limit", "[cpu][mie]") {
    // x = 0.01: Qsca = 8/3 x^4 |(m^2-1)/(m^2+2)|^2 and p = 3 (1 + mu^2) / (16 pi) (B&H eq. 5.8,
    // 5.9); the next order is O(x^2) = 1e-4 relative: tolerance 1e-3.
    const cd m(1.33, 0.0);
    const double x = 0.01;
    MieSphere s(m, x);
    const double K = std::norm((m * m - 1.0) / (m * m + 2.0));
    CHECK(s.qsca() == Approx(8.0 / 3.0 * std::pow(x, 4) * K).epsilon(1e-3));
    for (double mu : {-1.0, -0.3, 0.0, 0.5, 1.0}) CHECK(s.phase(mu) == Approx(3.0 * (1.0 + mu * mu) / (16.0 * M_PI)).epsilon(1e-3));
    CHECK(std::abs(s.g()) < 1e-3);  // symmetric fore and back to O(x^2)
}

TEST_CASE("Mie: the phase function integrates to 1 (energy conservation)", "[cpu][mie]") {
    // The 0.1 %: the angular sum of |S1|^2 + |S2|^2 must equal the series' Qsca. Simpson
    // on 40 x intervals resolves the forward peak (width ~ 1/x): its own error is < 1e-5 here.
    for (double x : {0.5, 12.0, 300.0, 2000.0}) {
        MieSphere s(waterRefractiveIndex(550.0), x);
        CAPTURE(x);
        CHECK(phaseIntegral(s, std::max(2000, int(40 * x) / 2 * 2)) == Approx(1.0).epsilon(1e-3));
    }
}

TEST_CASE("Mie: refractive index of water", "[cpu][mie]") {
    // Handbook (CRC, 20 degC, relative to air): n_D = 1.33299 at 589.3 nm; the IAPWS fit's
    // residuals are ~1e-5 and the air index is known to 1e-7: tolerance 3e-5.
    CHECK(waterRefractiveIndex(589.3).real() == Approx(1.33299).margin(3e-5));
    // Normal dispersion: the textbook violet 1.343 and red 1.331 (Nussenzveig 1977) differ by 0.012.
    const double dn = waterRefractiveIndex(400.0).real() - waterRefractiveIndex(700.0).real();
    CHECK(dn > 0.010);
    CHECK(dn < 0.015);
    CHECK(waterRefractiveIndex(550.0).imag() == Approx(1.96e-9).epsilon(1e-6));  // Hale & Querry table entry
    CHECK_THROWS_WITH(waterRefractiveIndex(200.0), "waterRefractiveIndex(): wavelength (nm) 200 not in [300, 1000]");
    CHECK_THROWS_AS(MieSphere(cd(1.33, 0.0), -1.0), welkin::Error);
}

TEST_CASE("Mie: large drops put the bows at Descartes' angles", "[cpu][mie]") {
    // r = 1 mm at 550 nm (x = 11424): the Airy maximum lies within a few hundredths of a degree of
    // the geometric-optics minimum deviation (its shift ~ (x)^(-2/3) rad ~ 0.01 deg), so +-0.3 deg.
    const double lambda = 550e-9, n = waterRefractiveIndex(550.0).real();
    const double x = 2.0 * M_PI * 1e-3 / lambda;
    const double primary = descartesScatteringAngle(n, 1) / kDeg, secondary = descartesScatteringAngle(n, 2) / kDeg;
    // The reference itself: for n = 1.333 the textbook gives 137.9 deg (42.1 from the anti-solar
    // point) and 129.1 deg (50.9); printed to 0.1 deg.
    CHECK(descartesScatteringAngle(1.333, 1) / kDeg == Approx(137.9).margin(0.06));
    CHECK(descartesScatteringAngle(1.333, 2) / kDeg == Approx(129.1).margin(0.06));
    CHECK(bowMaximum(waterRefractiveIndex(550.0), x, 136.0, 140.0) == Approx(primary).margin(0.3));
    CHECK(bowMaximum(waterRefractiveIndex(550.0), x, 126.0, 131.0) == Approx(secondary).margin(0.3));
}
