// Spectral mode of the real-time sky: wavelength triples and their conversion to linear sRGB
// (see sky_spectral.hpp).
#include <welkin/color.hpp>
#include <welkin/error.hpp>
#include <welkin/generators/sky_spectral.hpp>

#include <algorithm>

namespace welkin::generators {

void validateWavelengthCount(int n, const std::string& who) {
    if (n == 0 || n == 3 || (n >= kMinSpectralWavelengths && n <= kMaxSpectralWavelengths && n % 3 == 0)) return;
    throw Error(who + ": " + std::to_string(n) + " not 0 (the quality preset's), 3 (RGB) or a multiple of 3 in [" +
                std::to_string(kMinSpectralWavelengths) + ", " + std::to_string(kMaxSpectralWavelengths) + "]");
}

int effectiveWavelengths(int requested, const SkyQuality& q) {
    if (requested != 0) return requested;
    return q.perPixel ? kReferenceWavelengths : 3;
}

std::vector<double> spectralWavelengthsNm(int n) {
    constexpr double lo = 380.0, hi = 720.0;
    std::vector<double> nm;
    for (int i = 0; i < n; ++i) nm.push_back(lo + (hi - lo) * (i + 0.5) / n);
    return nm;
}

SkyModel skyModelFrom(const atmosphere::Atmosphere& a, const atmosphere::RgbCoefficients& c) {
    SkyModel m;
    m.bottomRadius = a.bottomRadiusM;
    m.topRadius = a.topRadiusM;
    m.rayleighScattering = c.rayleighScattering;
    m.rayleighDensity = DensityProfile::exponential(a.rayleighScaleHeightM);
    m.mieScattering = c.mieScattering;
    m.mieExtinction = glm::max(c.mieExtinction, c.mieScattering);
    m.mieDensity = DensityProfile::exponential(a.mieScaleHeightM);
    m.mieG = a.mieG;
    m.miePhase = a.miePhase == atmosphere::MiePhaseFunction::HenyeyGreenstein ? 0 : 1;
    m.absorptionExtinction = c.ozoneAbsorption;
    m.absorptionDensity = DensityProfile::tent(a.ozoneCenterAltitudeM, a.ozoneHalfWidthM);
    m.groundAlbedo = c.groundAlbedo;
    m.solarIlluminance = c.solarIlluminance;
    m.sunAngularRadius = a.sunAngularRadiusRad;
    return m;
}

SpectralSampling SpectralSampling::make(const atmosphere::Atmosphere& a, int n) {
    if (n < kMinSpectralWavelengths || n > kMaxSpectralWavelengths || n % 3 != 0)
        throw Error("SpectralSampling::make(): wavelengths " + std::to_string(n) + " not a multiple of 3 in [" +
                    std::to_string(kMinSpectralWavelengths) + ", " + std::to_string(kMaxSpectralWavelengths) + "]");
    a.validate();
    SpectralSampling s;
    s.wavelengths = n;
    s.nm = spectralWavelengthsNm(n);
    const int K = n / 3;
    // Weight of each sample wavelength: the transfer, piecewise linear between the samples and
    // constant beyond them, times the solar spectrum, integrated against the CIE observer on the
    // atmosphere's own wavelength grid (color::spectralToLinearSrgbWeights: 683 lm/W, sRGB).
    const auto& full = a.wavelengthsNm;
    const auto w = color::spectralToLinearSrgbWeights(full);
    std::vector<glm::dvec3> conv(s.nm.size(), glm::dvec3(0.0));
    for (std::size_t j = 0; j < full.size(); ++j) {
        const double l = full[j];
        const glm::dvec3 base = w[j] * a.solarIrradiance[j];
        if (l <= s.nm.front()) {
            conv.front() += base;
        } else if (l >= s.nm.back()) {
            conv.back() += base;
        } else {
            const std::size_t i = std::size_t(std::upper_bound(s.nm.begin(), s.nm.end(), l) - s.nm.begin());
            const double f = (l - s.nm[i - 1]) / (s.nm[i] - s.nm[i - 1]);
            conv[i - 1] += base * (1.0 - f);
            conv[i] += base * f;
        }
    }
    for (const auto& c : conv) s.solarIlluminance += c;
    for (int c = 0; c < 3; ++c)
        if (!(s.solarIlluminance[c] > 0.0))
            throw Error("SpectralSampling::make(): the solar spectrum has no linear-sRGB channel " + std::to_string(c) +
                        " (a black or single-coloured Sun cannot be normalised)");
    for (int k = 0; k < K; ++k) {
        glm::dvec3 tnm;
        glm::dmat3 M(0.0);
        for (int c = 0; c < 3; ++c) {
            const int i = k + (2 - c) * K;
            tnm[c] = s.nm[size_t(i)];
            M[c] = conv[size_t(i)] / s.solarIlluminance;  // column c: triple channel c -> rgb
        }
        atmosphere::RgbCoefficients rc = a.rgbAtWavelengths(tnm);
        rc.solarIlluminance = s.solarIlluminance;
        s.models.push_back(skyModelFrom(a, rc));
        s.toRgb.push_back(M);
    }
    return s;
}

glm::dvec3 SpectralSampling::combine(const std::vector<glm::dvec3>& perTriple) const {
    if (perTriple.size() != toRgb.size())
        throw Error("SpectralSampling::combine(): " + std::to_string(perTriple.size()) + " values for " +
                    std::to_string(toRgb.size()) + " triples");
    glm::dvec3 rgb(0.0);
    for (std::size_t k = 0; k < toRgb.size(); ++k) rgb += toRgb[k] * perTriple[k];
    return rgb;
}

}  // namespace welkin::generators
