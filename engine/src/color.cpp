// Colour science: CIE 1931 observer, photometry, linear sRGB, the extraterrestrial solar spectrum.
#include <welkin/color.hpp>
#include <welkin/error.hpp>

#include <algorithm>
#include <mutex>
#include <utility>
#include <array>
#include <cmath>
#include <string>
#include <vector>

namespace welkin::color {
namespace {

// CIE 1931 2-degree colour matching functions (x-bar, y-bar, z-bar), 360..830 nm every 5 nm:
// the CVRL "ciexyz31" table, as tabulated in shared/reference/kider2013/cie1931_2deg_5nm.csv.
constexpr std::array<std::array<double, 3>, kCmfCount> kCmf = {{
    {0.0001299, 3.917e-06, 0.0006061},  // 360
    {0.0002321, 6.965e-06, 0.001086},  // 365
    {0.0004149, 1.239e-05, 0.001946},  // 370
    {0.0007416, 2.202e-05, 0.003486},  // 375
    {0.001368, 3.9e-05, 0.006450001},  // 380
    {0.002236, 6.4e-05, 0.01054999},  // 385
    {0.004243, 0.00012, 0.02005001},  // 390
    {0.00765, 0.000217, 0.03621},  // 395
    {0.01431, 0.000396, 0.06785001},  // 400
    {0.02319, 0.00064, 0.1102},  // 405
    {0.04351, 0.00121, 0.2074},  // 410
    {0.07763, 0.00218, 0.3713},  // 415
    {0.13438, 0.004, 0.6456},  // 420
    {0.21477, 0.0073, 1.0390501},  // 425
    {0.2839, 0.0116, 1.3856},  // 430
    {0.3285, 0.01684, 1.62296},  // 435
    {0.34828, 0.023, 1.74706},  // 440
    {0.34806, 0.0298, 1.7826},  // 445
    {0.3362, 0.038, 1.77211},  // 450
    {0.3187, 0.048, 1.7441},  // 455
    {0.2908, 0.06, 1.6692},  // 460
    {0.2511, 0.0739, 1.5281},  // 465
    {0.19536, 0.09098, 1.28764},  // 470
    {0.1421, 0.1126, 1.0419},  // 475
    {0.09564, 0.13902, 0.8129501},  // 480
    {0.05795001, 0.1693, 0.6162},  // 485
    {0.03201, 0.20802, 0.46518},  // 490
    {0.0147, 0.2586, 0.3533},  // 495
    {0.0049, 0.323, 0.272},  // 500
    {0.0024, 0.4073, 0.2123},  // 505
    {0.0093, 0.503, 0.1582},  // 510
    {0.0291, 0.6082, 0.1117},  // 515
    {0.06327, 0.71, 0.07824999},  // 520
    {0.1096, 0.7932, 0.05725001},  // 525
    {0.1655, 0.862, 0.04216},  // 530
    {0.2257499, 0.9148501, 0.02984},  // 535
    {0.2904, 0.954, 0.0203},  // 540
    {0.3597, 0.9803, 0.0134},  // 545
    {0.4334499, 0.9949501, 0.008749999},  // 550
    {0.5120501, 1, 0.005749999},  // 555
    {0.5945, 0.995, 0.0039},  // 560
    {0.6784, 0.9786, 0.002749999},  // 565
    {0.7621, 0.952, 0.0021},  // 570
    {0.8425, 0.9154, 0.0018},  // 575
    {0.9163, 0.87, 0.001650001},  // 580
    {0.9786, 0.8163, 0.0014},  // 585
    {1.0263, 0.757, 0.0011},  // 590
    {1.0567, 0.6949, 0.001},  // 595
    {1.0622, 0.631, 0.0008},  // 600
    {1.0456, 0.5668, 0.0006},  // 605
    {1.0026, 0.503, 0.00034},  // 610
    {0.9384, 0.4412, 0.00024},  // 615
    {0.8544499, 0.381, 0.00019},  // 620
    {0.7514, 0.321, 0.0001},  // 625
    {0.6424, 0.265, 4.999999e-05},  // 630
    {0.5419, 0.217, 3e-05},  // 635
    {0.4479, 0.175, 2e-05},  // 640
    {0.3608, 0.1382, 1e-05},  // 645
    {0.2835, 0.107, 0},  // 650
    {0.2187, 0.0816, 0},  // 655
    {0.1649, 0.061, 0},  // 660
    {0.1212, 0.04458, 0},  // 665
    {0.0874, 0.032, 0},  // 670
    {0.0636, 0.0232, 0},  // 675
    {0.04677, 0.017, 0},  // 680
    {0.0329, 0.01192, 0},  // 685
    {0.0227, 0.00821, 0},  // 690
    {0.01584, 0.005723, 0},  // 695
    {0.01135916, 0.004102, 0},  // 700
    {0.008110916, 0.002929, 0},  // 705
    {0.005790346, 0.002091, 0},  // 710
    {0.004109457, 0.001484, 0},  // 715
    {0.002899327, 0.001047, 0},  // 720
    {0.00204919, 0.00074, 0},  // 725
    {0.001439971, 0.00052, 0},  // 730
    {0.0009999493, 0.0003611, 0},  // 735
    {0.0006900786, 0.0002492, 0},  // 740
    {0.0004760213, 0.0001719, 0},  // 745
    {0.0003323011, 0.00012, 0},  // 750
    {0.0002348261, 8.48e-05, 0},  // 755
    {0.0001661505, 6e-05, 0},  // 760
    {0.000117413, 4.24e-05, 0},  // 765
    {8.307527e-05, 3e-05, 0},  // 770
    {5.870652e-05, 2.12e-05, 0},  // 775
    {4.150994e-05, 1.499e-05, 0},  // 780
    {2.935326e-05, 1.06e-05, 0},  // 785
    {2.067383e-05, 7.4657e-06, 0},  // 790
    {1.455977e-05, 5.2578e-06, 0},  // 795
    {1.025398e-05, 3.7029e-06, 0},  // 800
    {7.221456e-06, 2.6078e-06, 0},  // 805
    {5.085868e-06, 1.8366e-06, 0},  // 810
    {3.581652e-06, 1.2934e-06, 0},  // 815
    {2.522525e-06, 9.1093e-07, 0},  // 820
    {1.776509e-06, 6.4153e-07, 0},  // 825
    {1.251141e-06, 4.5181e-07, 0},  // 830
}};

// ASTM G-173 extraterrestrial ("ETR") solar spectral irradiance, W m^-2 nm^-1, averaged over
// the 10 nm bins [360, 370), ..., [830, 840) (as tabulated in Bruneton's
// precomputed_atmospheric_scattering demo, 2017).
const std::vector<double> kSolarBins = {
    1.11776, 1.14259, 1.01249, 1.14716, 1.72765, 1.73054, 1.6887,  1.61253, 1.91198, 2.03474,
    2.02042, 2.02212, 1.93377, 1.95809, 1.91686, 1.8298,  1.8685,  1.8931,  1.85149, 1.8504,
    1.8341,  1.8345,  1.8147,  1.78158, 1.7533,  1.6965,  1.68194, 1.64654, 1.6048,  1.52143,
    1.55622, 1.5113,  1.474,   1.4482,  1.41018, 1.36775, 1.34188, 1.31429, 1.28303, 1.26758,
    1.2367,  1.2082,  1.18737, 1.14683, 1.12362, 1.1058,  1.07124, 1.04992};

glm::dmat3 computeSrgbToXyz() {
    // Columns: XYZ of each primary with Y = 1, then scaled so that (1, 1, 1) maps to D65 (Y = 1).
    auto xyzOf = [](double x, double y) { return glm::dvec3(x / y, 1.0, (1.0 - x - y) / y); };
    const glm::dmat3 p(xyzOf(0.64, 0.33), xyzOf(0.30, 0.60), xyzOf(0.15, 0.06));
    const glm::dvec3 white = xyzOf(0.3127, 0.3290);
    const glm::dvec3 s = glm::inverse(p) * white;
    return glm::dmat3(p[0] * s.x, p[1] * s.y, p[2] * s.z);
}

void checkWavelengths(const std::vector<double>& nm, const char* who) {
    if (nm.empty()) throw Error(std::string(who) + ": no wavelengths");
    for (std::size_t i = 0; i < nm.size(); ++i) {
        if (!(nm[i] >= 300.0 && nm[i] <= 1000.0))
            throw Error(std::string(who) + ": wavelength " + std::to_string(nm[i]) + " nm not in [300, 1000]");
        if (i > 0 && !(nm[i] > nm[i - 1]))
            throw Error(std::string(who) + ": wavelengths not strictly increasing at index " + std::to_string(i));
    }
}

// Value at `lambda` of the i-th "hat" basis function of piecewise-linear interpolation through
// the samples `nm`, constant beyond the ends.
double hat(const std::vector<double>& nm, std::size_t i, double lambda) {
    const std::size_t n = nm.size();
    if (n == 1) return 1.0;
    if (lambda <= nm[i]) {
        if (i == 0) return 1.0;
        if (lambda <= nm[i - 1]) return 0.0;
        return (lambda - nm[i - 1]) / (nm[i] - nm[i - 1]);
    }
    if (i == n - 1) return 1.0;
    if (lambda >= nm[i + 1]) return 0.0;
    return (nm[i + 1] - lambda) / (nm[i + 1] - nm[i]);
}

}  // namespace

glm::dvec3 cie1931Sample(int i) {
    if (i < 0 || i >= kCmfCount) throw Error("color::cie1931Sample(): index " + std::to_string(i) + " not in [0, 94]");
    return {kCmf[i][0], kCmf[i][1], kCmf[i][2]};
}

glm::dvec3 cie1931(double nm) {
    if (!(nm >= kCmfFirstNm && nm <= kCmfLastNm)) return glm::dvec3(0.0);
    const double u = (nm - kCmfFirstNm) / kCmfStepNm;
    const int i = std::min(int(u), kCmfCount - 2);
    const double f = u - i;
    return cie1931Sample(i) * (1.0 - f) + cie1931Sample(i + 1) * f;
}

namespace {
std::vector<glm::dvec3> computeSpectralToXyzWeights(const std::vector<double>& nm);
}  // namespace

std::vector<glm::dvec3> spectralToXyzWeights(const std::vector<double>& nm) {
    checkWavelengths(nm, "color::spectralToXyzWeights()");
    // The weights depend on the wavelengths alone, and a frame asks for the same few sets again
    // (the Sun's and the Moon's colour, every frame): ~0.8 million instructions per call to
    // recompute (callgrind, `welkin bench framework`: 8.4 million per frame of 8.8 million of
    // welkin's own before this cache). The last few sets are kept; same input, same output.
    static std::mutex mutex;
    static std::vector<std::pair<std::vector<double>, std::vector<glm::dvec3>>> recent;  // newest last, at most 8
    {
        std::lock_guard<std::mutex> lock(mutex);
        for (const auto& [key, weights] : recent)
            if (key == nm) return weights;
    }
    std::vector<glm::dvec3> w = computeSpectralToXyzWeights(nm);
    std::lock_guard<std::mutex> lock(mutex);
    if (recent.size() == 8) recent.erase(recent.begin());
    recent.emplace_back(nm, w);
    return w;
}

namespace {
std::vector<glm::dvec3> computeSpectralToXyzWeights(const std::vector<double>& nm) {
    // Both the spectrum (through the hats) and the CMFs are piecewise linear: integrate their
    // product with the trapezoidal rule on a 0.05 nm grid (relative error < 1e-6).
    constexpr double kStep = 0.05;
    const int steps = int(std::lround((kCmfLastNm - kCmfFirstNm) / kStep));
    std::vector<glm::dvec3> w(nm.size(), glm::dvec3(0.0));
    std::size_t seg = 0;  // first sample index whose wavelength is >= lambda - keeps the scan linear
    for (int k = 0; k <= steps; ++k) {
        const double lambda = kCmfFirstNm + k * kStep;
        const double trap = (k == 0 || k == steps) ? 0.5 : 1.0;
        const glm::dvec3 c = cie1931(lambda) * (kLuminousEfficacy * kStep * trap);
        while (seg < nm.size() && nm[seg] < lambda) ++seg;
        // Only the two samples around lambda have non-zero hats.
        const std::size_t lo = seg == 0 ? 0 : seg - 1;
        const std::size_t hi = std::min(seg, nm.size() - 1);
        w[lo] += c * hat(nm, lo, lambda);
        if (hi != lo) w[hi] += c * hat(nm, hi, lambda);
    }
    return w;
}
}  // namespace

std::vector<glm::dvec3> spectralToLinearSrgbWeights(const std::vector<double>& nm) {
    std::vector<glm::dvec3> w = spectralToXyzWeights(nm);
    const glm::dmat3 m = xyzToLinearSrgbMatrix();
    for (auto& v : w) v = m * v;
    return w;
}

glm::dvec3 spectrumToXyz(const std::vector<double>& nm, const std::vector<double>& values) {
    if (values.size() != nm.size())
        throw Error("color::spectrumToXyz(): " + std::to_string(values.size()) + " values for " +
                    std::to_string(nm.size()) + " wavelengths");
    const std::vector<glm::dvec3> w = spectralToXyzWeights(nm);
    glm::dvec3 xyz(0.0);
    for (std::size_t i = 0; i < w.size(); ++i) xyz += w[i] * values[i];
    return xyz;
}

glm::dvec3 spectrumToLinearSrgb(const std::vector<double>& nm, const std::vector<double>& values) {
    return xyzToLinearSrgb(spectrumToXyz(nm, values));
}

glm::dmat3 linearSrgbToXyzMatrix() {
    static const glm::dmat3 m = computeSrgbToXyz();
    return m;
}
glm::dmat3 xyzToLinearSrgbMatrix() {
    static const glm::dmat3 m = glm::inverse(computeSrgbToXyz());
    return m;
}
glm::dvec3 xyzToLinearSrgb(const glm::dvec3& xyz) { return xyzToLinearSrgbMatrix() * xyz; }
glm::dvec3 linearSrgbToXyz(const glm::dvec3& rgb) { return linearSrgbToXyzMatrix() * rgb; }

glm::dvec2 chromaticity(const glm::dvec3& xyz) {
    const double s = xyz.x + xyz.y + xyz.z;
    if (!(s > 0.0) || !std::isfinite(s)) return {0.3127, 0.3290};
    return {xyz.x / s, xyz.y / s};
}

glm::dvec2 uvPrime(const glm::dvec3& xyz) {
    const double d = xyz.x + 15.0 * xyz.y + 3.0 * xyz.z;
    if (!(d > 0.0) || !std::isfinite(d)) {
        const glm::dvec3 w(0.3127 / 0.3290, 1.0, (1.0 - 0.3127 - 0.3290) / 0.3290);
        return uvPrime(w);
    }
    return {4.0 * xyz.x / d, 9.0 * xyz.y / d};
}

double chromaticityDistanceUv(const glm::dvec3& a, const glm::dvec3& b) { return glm::length(uvPrime(a) - uvPrime(b)); }

const std::vector<double>& solarIrradianceAstmG173Bins() { return kSolarBins; }

double solarIrradianceAstmG173(double nm) {
    const double u = (nm - 365.0) / 10.0;
    const int last = int(kSolarBins.size()) - 1;
    if (!(u > 0.0)) return kSolarBins.front();
    if (u >= last) return kSolarBins.back();
    const int i = int(u);
    const double f = u - i;
    return kSolarBins[i] * (1.0 - f) + kSolarBins[i + 1] * f;
}

glm::dvec3 solarIlluminanceSrgb() {
    static const glm::dvec3 rgb = [] {
        std::vector<double> nm;
        for (std::size_t i = 0; i < kSolarBins.size(); ++i) nm.push_back(365.0 + 10.0 * double(i));
        return spectrumToLinearSrgb(nm, kSolarBins);
    }();
    return rgb;
}

double starTemperatureFromBV(double bv) {
    bv = std::clamp(bv, -0.4, 2.0);
    return 4600.0 * (1.0 / (0.92 * bv + 1.7) + 1.0 / (0.92 * bv + 0.62));
}

glm::dvec3 blackBodyLinearSrgb(double kelvin) {
    if (!(kelvin >= 500.0 && kelvin <= 1e6)) throw Error("blackBodyLinearSrgb(): temperature not in [500, 1e6] K");
    // Planck's law up to a constant factor (normalised below): lambda^-5 / (exp(hc / lambda k T) - 1).
    constexpr double c2 = 1.438776877e-2;  // hc / k, m K
    std::vector<double> nm, value;
    for (int i = 0; i < kCmfCount; ++i) {
        const double l = kCmfFirstNm + i * kCmfStepNm;
        const double lm = l * 1e-9;
        nm.push_back(l);
        value.push_back(1.0 / (std::pow(l / 500.0, 5.0) * std::expm1(c2 / (lm * kelvin))));
    }
    glm::dvec3 rgb = glm::max(spectrumToLinearSrgb(nm, value), glm::dvec3(0.0));  // out of gamut: clip
    return rgb / luminance(rgb);
}

glm::dvec3 starColourFromBV(double bv) { return blackBodyLinearSrgb(starTemperatureFromBV(bv)); }

}  // namespace welkin::color
