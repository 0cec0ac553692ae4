// Colour science: the CIE 1931 standard observer, photometry and linear sRGB.
//
//   using namespace welkin::color;
//   std::vector<double> nm = {440, 550, 680};
//   glm::dvec3 xyz = spectrumToXyz(nm, {0.13, 0.075, 0.03});   // radiance W m^-2 sr^-1 nm^-1 -> XYZ, Y in cd/m^2
//   glm::dvec3 rgb = xyzToLinearSrgb(xyz);                     // linear sRGB (D65), same scale
//   glm::dvec2 c = chromaticity(xyz);                           // CIE xy
//   double lux = luminance(solarIlluminanceSrgb());             // ~1.3e5 lx at the top of the atmosphere
//   auto w = spectralToLinearSrgbWeights(nm);                   // rgb = sum_i w[i] * L(nm[i])
//
// Conventions. A spectrum is given by samples at strictly increasing wavelengths (nm) and is
// taken as piecewise linear between them and constant beyond the first and last samples (so a
// single sample means a flat spectrum); it is integrated against the colour-matching functions
// over 360-830 nm. XYZ = 683 lm/W * integral(L(lambda) cmf(lambda) dlambda), so for a spectral
// radiance (W m^-2 sr^-1 nm^-1) Y is the luminance in cd/m^2, and for a spectral irradiance
// (W m^-2 nm^-1) Y is the illuminance in lux. Linear sRGB uses the sRGB primaries and the D65
// white point (IEC 61966-2-1); its luminance is 0.2126 r + 0.7152 g + 0.0722 b = Y.
#pragma once
#include <glm/glm.hpp>

#include <vector>

namespace welkin::color {

/// Maximum luminous efficacy of radiation at 555 nm (photopic), lm/W.
inline constexpr double kLuminousEfficacy = 683.0;
/// The colour-matching function table: kCmfCount samples from kCmfFirstNm every kCmfStepNm nm.
inline constexpr double kCmfFirstNm = 360.0;
inline constexpr double kCmfStepNm = 5.0;
inline constexpr int kCmfCount = 95;  // 360..830 nm
inline constexpr double kCmfLastNm = kCmfFirstNm + kCmfStepNm * (kCmfCount - 1);

/// CIE 1931 2-degree colour matching functions (x-bar, y-bar, z-bar) at `wavelengthNm`:
/// linear interpolation of the CVRL 5 nm table; zero outside [360, 830] nm.
glm::dvec3 cie1931(double wavelengthNm);
/// The i-th entry of the 5 nm table (i in [0, kCmfCount)); throws welkin::Error otherwise.
glm::dvec3 cie1931Sample(int i);

/// Weights w (one XYZ triple per sample) such that XYZ = sum_i w[i] * L_i for the spectrum with
/// values L_i at `wavelengthsNm` (see the conventions above). Throws welkin::Error if the
/// wavelengths are empty, not strictly increasing or outside [300, 1000] nm.
std::vector<glm::dvec3> spectralToXyzWeights(const std::vector<double>& wavelengthsNm);
/// Same, to linear sRGB: rgb = sum_i w[i] * L_i.
std::vector<glm::dvec3> spectralToLinearSrgbWeights(const std::vector<double>& wavelengthsNm);

/// XYZ of a sampled spectrum (sizes must match; throws welkin::Error otherwise).
glm::dvec3 spectrumToXyz(const std::vector<double>& wavelengthsNm, const std::vector<double>& values);
/// Linear sRGB of a sampled spectrum.
glm::dvec3 spectrumToLinearSrgb(const std::vector<double>& wavelengthsNm, const std::vector<double>& values);

/// The XYZ -> linear sRGB matrix (column-major glm: rgb = m * xyz), derived from the sRGB
/// primaries and the D65 white point (x 0.3127, y 0.3290).
glm::dmat3 xyzToLinearSrgbMatrix();
/// Its inverse (linear sRGB -> XYZ).
glm::dmat3 linearSrgbToXyzMatrix();
glm::dvec3 xyzToLinearSrgb(const glm::dvec3& xyz);
glm::dvec3 linearSrgbToXyz(const glm::dvec3& rgb);

/// CIE xy chromaticity of XYZ; (0.3127, 0.3290) (D65) for black.
glm::dvec2 chromaticity(const glm::dvec3& xyz);
/// Luminance of linear sRGB: 0.2126 r + 0.7152 g + 0.0722 b (cd/m^2 or lux, as the input).
inline double luminance(const glm::dvec3& rgb) { return 0.2126 * rgb.r + 0.7152 * rgb.g + 0.0722 * rgb.b; }

/// CIE 1976 u'v' chromaticity of XYZ; D65's for black.
glm::dvec2 uvPrime(const glm::dvec3& xyz);
/// Distance between the u'v' chromaticities of two colours given as XYZ (a common, simple
/// measure of colour difference independent of luminance; 0.004 is about a just noticeable
/// difference in u'v').
double chromaticityDistanceUv(const glm::dvec3& xyzA, const glm::dvec3& xyzB);

// --- The Sun ------------------------------------------------------------------------------
/// Extraterrestrial solar spectral irradiance at 1 AU, W m^-2 nm^-1: the ASTM G-173 "ETR"
/// spectrum averaged over 10 nm bins [360, 370), ..., [830, 840) (the table of Bruneton's
/// precomputed_atmospheric_scattering demo), each value placed at its bin's centre and
/// interpolated linearly between centres (clamped to the end values outside 365..835 nm).
double solarIrradianceAstmG173(double wavelengthNm);
/// The 48 bin averages, W m^-2 nm^-1; bin i covers [360 + 10 i, 370 + 10 i) nm.
const std::vector<double>& solarIrradianceAstmG173Bins();
/// The extraterrestrial Sun (1 AU) as linear sRGB whose luminance is its illuminance, lux.
glm::dvec3 solarIlluminanceSrgb();

/// Linear sRGB of a black body at `kelvin` (Planck through CIE 1931), normalised to luminance 1;
/// out-of-gamut channels clipped at 0. Throws outside [500, 1e6] K.
glm::dvec3 blackBodyLinearSrgb(double kelvin);
/// B-V colour index -> effective temperature, K (Ballesteros 2012, EPL 97, 34008):
/// T = 4600 (1 / (0.92 bv + 1.7) + 1 / (0.92 bv + 0.62)); bv clamped to [-0.4, 2.0].
double starTemperatureFromBV(double bv);
/// Linear sRGB of a star (or planet) of colour index `bv`, luminance 1: the two functions above.
glm::dvec3 starColourFromBV(double bv);

}  // namespace welkin::color
