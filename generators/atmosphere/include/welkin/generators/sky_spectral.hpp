// Spectral mode of the real-time sky: N = 3K wavelengths run through the unchanged 3-channel LUT
// chain as K "wavelength triples", each triple's result converted to linear sRGB by a 3x3 matrix
// and summed into the one RGB LUT the Sky element reads.
//
//   using namespace welkin::generators;
//   auto a = welkin::atmosphere::Atmosphere::earthClear();
//   SpectralSampling s = SpectralSampling::make(a, 15);     // 5 triples
//   // s.models[k]: the SkyModel of triple k (its 3 channels = 3 wavelengths);
//   // per-lux transfer of triple k (any LUT value) -> linear sRGB per lux of the Sun:
//   glm::dvec3 rgbPerLux = s.toRgb[k] * transferOfTripleK;   // summed over k
//   vars.set(skykeys::wavelengths, 15);                        // the generators switch to it
//
// Method. The wavelengths are the centres of N equal bins over [380, 720] nm (outside it the CIE
// 1931 colour-matching functions are below 0.4 % of their peaks: z-bar at 380 nm, x-bar at
// 720 nm); the transfer, radiance per unit irradiance, is smooth in wavelength, so N = 12..15
// samples suffice (measured in skyelements/sky/README.md, "Spectral mode"). As in the reference integrator's spectral mode
// (reference_sky.hpp), the transfer at these wavelengths is taken as piecewise linear in
// wavelength (constant beyond the ends), evaluated at the atmosphere's own wavelengths (47 for
// the Earth presets), multiplied by its solar spectrum and integrated against the CIE 1931
// observer at 683 lm/W and converted to linear sRGB. That is linear in the N transfers:
// rgb = sum_i c_i t_i with c_i (one linear-sRGB triple per wavelength) computed once. The LUTs
// store radiance per lux of the light's illuminance per channel, as in RGB mode, so the matrices
// are normalised by S = sum_i c_i (the exact linear sRGB of the solar spectrum = the light's
// colour, sky.sun_illuminance at 1 AU): toRgb[k] column c = c_(index of triple k channel c) / S,
// per output row. A spectrally flat transfer t therefore gives exactly t in every channel.
//
// Transmittance (stars and planets behind the sky, the Sun's disk) uses the same weights: the
// transmitted linear sRGB of the solar spectrum divided by the unattenuated one, per channel,
// sum_k toRgb[k] T_k: the colour by which a sunlit (solar-coloured) object behind the atmosphere
// is multiplied. Exact for the Sun; for stars of other colours a close approximation.
//
// Triples are interleaved: triple k holds wavelengths (i = k + 2K, k + K, k) as its (r, g, b)
// channels (the longest in r), so each triple is itself roughly an RGB sampling.
#pragma once
#include <welkin/generators/atmosphere.hpp>
#include <welkin/generators/sky_model.hpp>

#include <glm/glm.hpp>

#include <string>
#include <vector>

namespace welkin::generators {

namespace skykeys {
/// Wavelengths of the real-time sky: 0 = the quality preset's (kReferenceWavelengths at
/// `reference`, else 3); 3 = RGB (Atmosphere::rgb(), one pass per LUT); a multiple of 3 in
/// [6, 24] = spectral (that many wavelengths through the CIE 1931 observer; each LUT pass runs
/// N/3 times). Set by the Sky element from SkyOptions::wavelengths or by the host.
inline const Key<int> wavelengths{"sky.wavelengths", Range{0, 24},
                                  "real-time sky wavelengths: 0 = preset's, 3 = RGB, 6..24 (multiple of 3) = spectral"};
}  // namespace skykeys

/// Smallest and largest spectral wavelength counts (and 3 = RGB).
inline constexpr int kMinSpectralWavelengths = 6;
inline constexpr int kMaxSpectralWavelengths = 24;
/// Wavelengths of the `reference` quality preset (the only preset that is spectral by default:
/// 12 and 15 measured alike, 15 kept as Bruneton 2017's spectral setting).
inline constexpr int kReferenceWavelengths = 15;

/// Throws welkin::Error "`who`: N not 0 (the quality preset's), 3 (RGB) or a multiple of 3 in
/// [6, 24]" unless n is valid.
void validateWavelengthCount(int n, const std::string& who);
/// The count in use: `requested` unless 0, else the preset's (kReferenceWavelengths when the
/// preset ray-marches every pixel, i.e. `reference`; else 3).
int effectiveWavelengths(int requested, const SkyQuality& q);

/// The real-time sky's N wavelengths, nm: centres of N equal bins over [380, 720] nm.
std::vector<double> spectralWavelengthsNm(int n);

/// The SkyModel of an atmosphere with the given 3-channel coefficients (geometry, profiles and
/// phase from `a`; coefficients, albedo and solar illuminance from `c`).
SkyModel skyModelFrom(const atmosphere::Atmosphere& a, const atmosphere::RgbCoefficients& c);

/// Wavelength triples and their conversion matrices (see the header comment).
struct SpectralSampling {
    int wavelengths = 0;               ///< N
    std::vector<double> nm;            ///< the N wavelengths, increasing
    std::vector<SkyModel> models;      ///< one per triple; channel c of triple k = nm[tripleIndex(k, c)]
    std::vector<glm::dmat3> toRgb;     ///< rgb per lux = toRgb[k] * (transfer of triple k), summed over k
    glm::dvec3 solarIlluminance{0.0};  ///< S: linear sRGB of the solar spectrum, lux (Y = illuminance)

    /// Validates n (validateWavelengthCount) and the atmosphere.
    static SpectralSampling make(const atmosphere::Atmosphere& a, int n);
    int triples() const { return int(models.size()); }
    /// Index into nm of channel c (0 r, 1 g, 2 b) of triple k.
    int tripleIndex(int k, int c) const { return k + (2 - c) * triples(); }
    /// sum_k toRgb[k] * perTriple[k].
    glm::dvec3 combine(const std::vector<glm::dvec3>& perTriple) const;
};

}  // namespace welkin::generators
