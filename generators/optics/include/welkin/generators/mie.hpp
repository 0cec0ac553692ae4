// Lorenz-Mie scattering by a homogeneous sphere, double precision, on the CPU.
//
//   welkin::generators::MieSphere s(std::complex<double>(1.33, 1e-8), 2.0 * M_PI * 0.5e-3 / 550e-9);
//   double q = s.qsca();                        // scattering efficiency, dimensionless
//   double p = s.phase(std::cos(138.0 * M_PI / 180.0));   // phase function, 1/sr, integrates to 1
//   std::complex<double> n = welkin::generators::waterRefractiveIndex(550.0);  // ~1.3334 + 2e-9 i
//
// Conventions: Bohren & Huffman, "Absorption and Scattering of Light by Small Particles" (1983),
// ch. 4: time dependence exp(-i w t), so an absorbing sphere has m = n + i k with k >= 0;
// x = 2 pi r / lambda (size parameter, lambda in the surrounding medium); scattering angle theta
// between the incident and the scattered directions (0 = forward, pi = back), mu = cos(theta).
// Scheme (Wiscombe 1980, Appl. Opt. 19, 1505; BHMIE, B&H appendix A): terms n = 1..N with
// N = x + 4 x^(1/3) + 2; the logarithmic derivative D_n(mx) by downward recurrence from
// n = max(N, |m x|) + 16 |m x|^(1/3) + 15 (D = 0 there; Du 2004, Appl. Opt. 43, 1951);
// Riccati-Bessel psi_n(x), chi_n(x) by upward recurrence (stable for n <= N, no overflow:
// |psi|, |chi| stay O(1) to O(1e3) below n ~ x). Valid for
// x in (0, 1e5] and |m x| <= 1e6 (checked).
#pragma once
#include <complex>
#include <vector>

namespace welkin::generators {

/// Complex refractive index of liquid water relative to air at `wavelengthNm` in [300, 1000] nm,
/// 20 degC, 1 atm: real part from the IAPWS 1997 formulation (Harvey, Gallagher & Levelt Sengers
/// 1998, J. Phys. Chem. Ref. Data 27, 761, eq. 7 with their table 3) divided by the index of air
/// (Edlen 1966); imaginary part interpolated (log-linear) in the table of Hale & Querry 1973
/// (Appl. Opt. 12, 555).
/// Throws welkin::Error outside the range.
std::complex<double> waterRefractiveIndex(double wavelengthNm);

/// The Mie coefficients a_n, b_n of one sphere and the quantities derived from them.
class MieSphere {
public:
    /// m: relative refractive index (Im m >= 0, Re m > 0); x: size parameter in (0, 1e5].
    /// Throws welkin::Error with a one-line message otherwise.
    MieSphere(std::complex<double> m, double x);

    double x() const { return x_; }
    int terms() const { return int(a_.size()); }
    double qext() const { return qext_; }   ///< extinction efficiency C_ext / (pi r^2)
    double qsca() const { return qsca_; }   ///< scattering efficiency
    double qback() const;                   ///< backscattering efficiency |S1(pi)|^2 4 / x^2
    double g() const { return g_; }         ///< asymmetry parameter <cos theta>
    /// Amplitude functions S1(mu), S2(mu) (B&H eq. 4.74), mu in [-1, 1].
    void amplitudes(double mu, std::complex<double>& s1, std::complex<double>& s2) const;
    /// Phase function (|S1|^2 + |S2|^2) / (2 pi x^2 Qsca), 1/sr: integrates to 1 over the sphere.
    double phase(double mu) const;
    /// Phase function at many mu at once (same values as phase(); faster).
    void phases(const std::vector<double>& mu, std::vector<double>& out) const;
    /// (|S1|^2 + |S2|^2) / 2 at mu, dimensionless: phase(mu) = intensity(mu) / (pi x^2 Qsca).
    double intensity(double mu) const;

    const std::vector<std::complex<double>>& a() const { return a_; }
    const std::vector<std::complex<double>>& b() const { return b_; }

private:
    double x_;
    std::vector<std::complex<double>> a_, b_;
    double qext_ = 0, qsca_ = 0, g_ = 0;
};

}  // namespace welkin::generators
