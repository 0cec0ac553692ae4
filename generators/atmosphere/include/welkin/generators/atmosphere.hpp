// The atmosphere model shared by the real-time sky (LUT generators, GLSL) and the reference
// integrator: a spherical planet with a spherical shell of air made of three constituents.
//
//   using namespace welkin::atmosphere;
//   Atmosphere a = Atmosphere::earthClear().withAerosolOpticalDepth(0.11, 0.9);  // Kider's day
//   a.validate();                                        // throws welkin::Error naming the member
//   RgbCoefficients c = a.rgb();                         // 3-channel version for the real-time path
//   double d = rayleighDensity(a, 1500.0);               // relative density at 1.5 km, in (0, 1]
//   double p = miePhase(a, std::cos(0.1));               // phase function, 1/sr
//   vars.set(kAtmosphere, std::make_shared<const Atmosphere>(a));   // generators rebuild
//
// Model (Bruneton 2017 / Hillaire 2020, SI units throughout):
//  * The planet is a sphere of radius `bottomRadiusM`; the atmosphere ends at `topRadiusM`.
//  * Molecules (Rayleigh): scattering coefficient sigma_R(lambda) * exp(-h / rayleighScaleHeightM),
//    no absorption, phase 3 / (16 pi) (1 + mu^2).
//  * Aerosols (Mie): scattering sigma_Ms(lambda) and extinction sigma_Me(lambda) >= sigma_Ms, times
//    exp(-h / mieScaleHeightM); phase Henyey-Greenstein or Cornette-Shanks with parameter mieG.
//  * Ozone: absorption sigma_O(lambda) times a tent profile: 0 below
//    ozoneCenterAltitudeM - ozoneHalfWidthM, rising linearly to 1 at ozoneCenterAltitudeM and back
//    to 0 at ozoneCenterAltitudeM + ozoneHalfWidthM. No scattering.
//  * The ground is Lambertian with spectral albedo groundAlbedo.
//  * The Sun is a uniform disk of angular radius sunAngularRadiusRad whose irradiance at the top
//    of the atmosphere (normal incidence) is solarIrradiance(lambda), W m^-2 nm^-1.
// All coefficients are given at `wavelengthsNm` (strictly increasing, within [360, 830] nm, the
// range of the CIE observer), one value per wavelength in every spectral array. Coefficients are
// the values at density 1, in 1/m. h is the altitude above the planet's surface, metres.
//
// The spectral arrays are the source of truth: the reference integrator runs per wavelength and
// converts through the CIE 1931 observer; the real-time path uses rgb(), whose values make the
// integrated radiance come out directly as linear sRGB in cd/m^2.
#pragma once
#include <welkin/vars.hpp>

#include <glm/glm.hpp>

#include <algorithm>
#include <cmath>
#include <memory>
#include <numbers>
#include <optional>
#include <string>
#include <vector>

namespace welkin::atmosphere {

/// Aerosol phase function family.
enum class MiePhaseFunction {
    HenyeyGreenstein,  ///< (1 - g^2) / (4 pi (1 + g^2 - 2 g mu)^1.5): mean cosine = g
    CornetteShanks,    ///< 3 (1 - g^2)(1 + mu^2) / (8 pi (2 + g^2)(1 + g^2 - 2 g mu)^1.5)
};

/// The 3-channel (linear sRGB) version of an atmosphere's spectral data, for the real-time path.
/// Channel order is (r, g, b). A renderer that integrates the radiative transfer with these
/// coefficients and multiplies by `solarIlluminance` gets linear sRGB radiance with the
/// luminance (0.2126 r + 0.7152 g + 0.0722 b) in cd/m^2.
struct RgbCoefficients {
    glm::dvec3 wavelengthsNm{680.0, 550.0, 440.0};  ///< nominal wavelength of each channel (documentation)
    glm::dvec3 rayleighScattering{0.0};             ///< 1/m at density 1
    glm::dvec3 mieScattering{0.0};                  ///< 1/m at density 1
    glm::dvec3 mieExtinction{0.0};                  ///< 1/m at density 1 (>= mieScattering)
    glm::dvec3 ozoneAbsorption{0.0};                ///< 1/m at the peak of the ozone tent
    glm::dvec3 groundAlbedo{0.0};                   ///< [0, 1]
    /// The Sun at the top of the atmosphere, normal incidence, as linear sRGB whose luminance is
    /// the illuminance in lux (about 1.3e5 lx for the Earth at 1 AU).
    glm::dvec3 solarIlluminance{0.0};
};

/// A planet's atmosphere, SI units. Every member is validated by validate().
struct Atmosphere {
    std::string name = "custom";  ///< preset name, for logs and docs

    // --- Geometry --------------------------------------------------------------------------
    double bottomRadiusM = 6360e3;  ///< planet (ground) radius, m, [1e3, 1e9]
    double topRadiusM = 6420e3;     ///< top of the atmosphere, m, (bottomRadiusM, bottomRadiusM + 1e6]

    // --- Spectral sampling -----------------------------------------------------------------
    /// Wavelengths at which every spectral array is given, nm, strictly increasing, in [360, 830].
    std::vector<double> wavelengthsNm;

    // --- Molecules -------------------------------------------------------------------------
    std::vector<double> rayleighScattering;  ///< 1/m at density 1 (sea level), >= 0
    double rayleighScaleHeightM = 8000.0;    ///< m, [1, 1e6]

    // --- Aerosols --------------------------------------------------------------------------
    std::vector<double> mieScattering;  ///< 1/m at density 1, >= 0
    std::vector<double> mieExtinction;  ///< 1/m at density 1, >= mieScattering
    double mieScaleHeightM = 1200.0;    ///< m, [1, 1e6]
    MiePhaseFunction miePhase = MiePhaseFunction::CornetteShanks;
    double mieG = 0.8;  ///< phase function parameter, [-0.999, 0.999] (not the mean cosine for CS)

    // --- Absorbing layer (ozone) --------------------------------------------------------------
    std::vector<double> ozoneAbsorption;     ///< 1/m at the tent's peak (density 1), >= 0
    double ozoneCenterAltitudeM = 25000.0;   ///< altitude of the peak, m, [0, top - bottom]
    double ozoneHalfWidthM = 15000.0;        ///< half width of the tent, m, [1, 1e6]

    // --- Ground and Sun ---------------------------------------------------------------------
    std::vector<double> groundAlbedo;     ///< Lambertian reflectance, [0, 1]
    std::vector<double> solarIrradiance;  ///< W m^-2 nm^-1 at the top of the atmosphere, >= 0
    double sunAngularRadiusRad = 0.004652;  ///< rad, (0, 0.1]; Earth at 1 AU: 959.6" = 0.004652

    // --- Presets ---------------------------------------------------------------------------
    /// Earth, clear sky: 47 wavelengths (365..825 nm every 10 nm, the centres of the 10 nm bins
    /// of the tabulated solar spectrum and ozone cross sections); Rayleigh optical depth from
    /// Bodhaine et al. 1999 (0.0973 at 550 nm) with an 8 km scale height; continental aerosols
    /// with AOD 0.1 at 550 nm, Angstrom exponent 1, single-scattering albedo 0.9, 1.2 km scale
    /// height, Cornette-Shanks g 0.8; 300 DU of ozone (Serdyuchenko 2014 cross sections at
    /// 233 K, as in Bruneton 2017) in a tent from 10 to 40 km; ground albedo 0.1; ASTM G-173
    /// extraterrestrial solar spectrum.
    static Atmosphere earthClear();
    /// Earth, hazy: as earthClear() with AOD 0.4 at 550 nm, Angstrom exponent 1.3, g 0.75.
    static Atmosphere earthHazy();
    /// The atmosphere used by Bruneton's 2017 demo (precomputed_atmospheric_scattering):
    /// Rayleigh 1.24062e-6 lambda_um^-4 /m, Mie beta 5.328e-3 (AOD 0.0053), alpha 0, SSA 0.9,
    /// CS g 0.8, same ozone, ground albedo 0.1, radii 6360/6420 km.
    static Atmosphere earthBruneton2017();
    /// The atmosphere of Bruneton's 2017 evaluation of 8 clear-sky models (clear-sky-models,
    /// atmosphere/atmosphere.{h,cc}), used to compare with the Kider 2013 measurements:
    /// Rayleigh from Penndorf 1957 at 15 C, Angstrom alpha 0.8 and beta 0.04 (AOD 0.0645 at
    /// 550 nm), aerosol single-scattering albedo 0.8, Cornette-Shanks g 0.7, scale heights 8 and
    /// 1.2 km, no ozone, a grass ground albedo (Feister & Grewe 1995), radii 6360/6420 km.
    static Atmosphere earthBruneton2017Evaluation();
    /// Mars (documented in the .cpp): CO2 Rayleigh scattering, suspended dust, no ozone,
    /// 3389.5 km radius, the Sun at 1.524 AU.
    static Atmosphere mars();

    /// A copy with aerosols of optical depth `tau550` at 550 nm (vertical, whole column) and,
    /// if given, Angstrom exponent `angstromAlpha` (tau(lambda) = tau550 (lambda / 550)^-alpha);
    /// without alpha the spectral shape is kept. The single-scattering albedo per wavelength is
    /// kept. tau550 in [0, 10], alpha in [-2, 4].
    Atmosphere withAerosolOpticalDepth(double tau550, std::optional<double> angstromAlpha = {}) const;
    /// A copy with the Mie phase function set so that its mean cosine (the asymmetry parameter
    /// AERONET reports) equals `asymmetry`, in [0, 0.95].
    Atmosphere withAerosolAsymmetry(double asymmetry) const;
    /// A copy with `ozoneDobson` Dobson units of ozone (spectral shape kept), [0, 1000].
    Atmosphere withOzoneColumn(double ozoneDobson) const;
    /// A copy with a spectrally flat ground albedo, [0, 1].
    Atmosphere withGroundAlbedo(double albedo) const;
    /// A copy keeping only the given wavelengths (each interpolated linearly in wavelength from
    /// this atmosphere's arrays), e.g. to run the reference integrator on fewer wavelengths.
    Atmosphere resampled(const std::vector<double>& wavelengthsNm) const;

    /// Throws welkin::Error naming the first invalid member and its accepted range.
    void validate() const;

    /// The 3-channel version (see RgbCoefficients): the coefficients sampled at the effective
    /// wavelengths (624, 549, 456) nm, which reproduce the spectral reference's sky luminance to
    /// ~1% RMS (measured, see docs/sky-reference-and-measurements.md); solarIlluminance is the
    /// exact linear sRGB of the solar spectrum, so the Sun's colour is exact.
    RgbCoefficients rgb() const;
    /// The 3-channel version sampled at three wavelengths (r, g, b), nm, in [360, 830] (e.g.
    /// 680, 550, 440 as Bruneton's and Hillaire's RGB modes); solarIlluminance is the same as rgb()'s.
    RgbCoefficients rgbAtWavelengths(const glm::dvec3& wavelengthsNm) const;

    /// Linear interpolation of a spectral array of this atmosphere at `wavelengthNm` (clamped).
    double at(const std::vector<double>& spectrum, double wavelengthNm) const;
    /// Vertical optical depth of the whole column of aerosols at `wavelengthNm`.
    double aerosolOpticalDepth(double wavelengthNm) const;
    /// Vertical optical depth of the whole column of molecules at `wavelengthNm`.
    double rayleighOpticalDepth(double wavelengthNm) const;
    /// Ozone column, Dobson units, inferred from the absorption at 605 nm and the ozone cross
    /// section there (5.02e-25 m^2 at 233 K, the presets' table); 0 without ozone.
    double ozoneColumnDobson() const;
    /// Number of wavelengths.
    std::size_t size() const { return wavelengthsNm.size(); }
};

/// The atmosphere shared by the sky generators. Setting a new pointer bumps the version, which
/// rebuilds the transmittance and multiple-scattering LUTs. Never set a null pointer.
inline const Key<std::shared_ptr<const Atmosphere>> kAtmosphere{"sky.atmosphere", "atmosphere model (welkin::atmosphere::Atmosphere)"};

// ------------------------------------------------------------------------------------------
// Density profiles and phase functions (mirrored in GLSL by the real-time path).
// ------------------------------------------------------------------------------------------

/// exp(-h / H): relative density of an exponential layer at altitude h (m) with scale height H.
/// Not clamped below the ground (h < 0 gives > 1).
inline double exponentialDensity(double altitudeM, double scaleHeightM) { return std::exp(-altitudeM / scaleHeightM); }

/// Tent profile: max(0, 1 - |h - center| / halfWidth).
inline double tentDensity(double altitudeM, double centerM, double halfWidthM) {
    return std::max(0.0, 1.0 - std::abs(altitudeM - centerM) / halfWidthM);
}

inline double rayleighDensity(const Atmosphere& a, double altitudeM) { return exponentialDensity(altitudeM, a.rayleighScaleHeightM); }
inline double mieDensity(const Atmosphere& a, double altitudeM) { return exponentialDensity(altitudeM, a.mieScaleHeightM); }
inline double ozoneDensity(const Atmosphere& a, double altitudeM) {
    return tentDensity(altitudeM, a.ozoneCenterAltitudeM, a.ozoneHalfWidthM);
}

/// Rayleigh phase function, 1/sr; mu = cos(angle between the light's propagation direction
/// and the scattered direction), i.e. mu = dot(view, sun) for a view ray looking at the sky.
inline double rayleighPhase(double mu) { return 3.0 / (16.0 * std::numbers::pi) * (1.0 + mu * mu); }

/// Henyey-Greenstein phase function, 1/sr, normalised over the sphere; g in (-1, 1).
inline double henyeyGreensteinPhase(double mu, double g) {
    const double d = 1.0 + g * g - 2.0 * g * mu;
    return (1.0 - g * g) / (4.0 * std::numbers::pi * d * std::sqrt(d));
}

/// Cornette-Shanks phase function, 1/sr, normalised over the sphere; g in (-1, 1).
inline double cornetteShanksPhase(double mu, double g) {
    const double d = 1.0 + g * g - 2.0 * g * mu;
    return 3.0 * (1.0 - g * g) * (1.0 + mu * mu) / (8.0 * std::numbers::pi * (2.0 + g * g) * d * std::sqrt(d));
}

/// The atmosphere's aerosol phase function, 1/sr.
inline double miePhase(const Atmosphere& a, double mu) {
    return a.miePhase == MiePhaseFunction::HenyeyGreenstein ? henyeyGreensteinPhase(mu, a.mieG)
                                                            : cornetteShanksPhase(mu, a.mieG);
}

/// Mean cosine (asymmetry parameter) of a phase function family with parameter g.
inline double phaseAsymmetry(MiePhaseFunction f, double g) {
    return f == MiePhaseFunction::HenyeyGreenstein ? g : 3.0 * g * (4.0 + g * g) / (5.0 * (2.0 + g * g));
}

}  // namespace welkin::atmosphere
