// The reference integrator: a brute-force, double-precision CPU solution of the radiative
// transfer in an Atmosphere, with all scattering orders, used as ground truth by the tests and
// benchmarks (never by the real-time path).
//
//   using namespace welkin::atmosphere;
//   ReferenceSky sky(Atmosphere::earthClear());            // precomputes the scattering field (~s)
//   glm::dvec3 sun = glm::normalize(glm::dvec3(0.0, -0.5, 0.8));   // ENU, towards the Sun
//   glm::dvec3 L = sky.radiance(0.0, {0.0, 0.0, 1.0}, sun);        // zenith, linear sRGB, cd/m^2
//   SkyIlluminance e = sky.illuminance(0.0, sun);                   // lux: global, direct, diffuse
//   glm::dvec3 t = sky.transmittance(0.0, sun);                     // the Sun's reddening
//
// Method (see docs/sky-reference-and-measurements.md for the measured accuracy):
//  1. Column densities of the three constituents from any point to the top of the atmosphere are
//     tabulated once (they do not depend on wavelength) on a fine (r, mu) grid with Bruneton's
//     horizon-aware mapping; transmittance to the Sun is exp(-sum sigma * column), times the
//     visible fraction of the solar disk above the local horizon (a uniform disk: this gives the
//     penumbra of Earth's shadow and a continuous terminator).
//  2. Multiple scattering is solved order by order. For order n the phase-weighted incoming
//     radiance G_n(r, theta_s, theta, phi) (one table for the Rayleigh phase function, one for
//     the aerosols') is gathered at grid points (altitude r, sun zenith angle theta_s) by a
//     quadrature over incoming directions (Gauss-Legendre in mu, split at the horizon and
//     concentrated towards it; midpoint rule in azimuth, mirrored about the Sun's vertical
//     plane); each incoming radiance is a ray march through the previous order's scattering
//     density (order 1: exact single scattering) plus the ground's Lambertian reflection of the
//     previous order's irradiance. Orders are added until one contributes less than
//     `convergence` of the total (or maxOrders).
//  3. A view ray is marched from the observer (or from where it enters the atmosphere, when the
//     observer is above it), split at the lowest point and at Earth's shadow boundary, with
//     exact single scattering at every step and the tabulated higher orders; a ray that hits
//     the ground adds the ground's reflection of the direct and diffuse irradiance.
// The Sun's disk itself is not part of radiance(): see sunDiskRadiance().
// Spectral mode runs on `spectralSamples` wavelengths with unit solar irradiance; the resulting
// transfer spectrum (radiance / irradiance, smooth in wavelength) is interpolated linearly onto
// the atmosphere's own wavelengths, multiplied by its solar spectrum and integrated against the
// CIE 1931 observer (683 lm/W). RGB mode uses Atmosphere::rgb() directly.
#pragma once
#include <welkin/generators/atmosphere.hpp>

#include <glm/glm.hpp>

#include <memory>
#include <optional>
#include <vector>

namespace welkin::atmosphere {

enum class SpectralMode {
    Rgb,       ///< three channels from Atmosphere::rgb() (what the real-time path computes)
    Spectral,  ///< spectralSamples wavelengths through the CIE 1931 observer
};

/// Resolution and convergence settings. The defaults give a reference whose numerical error is
/// documented in docs/sky-reference-and-measurements.md (0.2% RMS by day, ~1% RMS and <= 2.7%
/// at the horizon around sunset, 2-3% RMS in deep twilight; 40-110 s of precomputation in RGB
/// on one core of this machine); tests use ReferenceOptions::fast().
struct ReferenceOptions {
    SpectralMode mode = SpectralMode::Spectral;
    int spectralSamples = 16;  ///< wavelengths spread evenly over the atmosphere's range, [3, 64]
    /// Rgb mode only: sample the coefficients at these wavelengths (r, g, b), nm, with
    /// Atmosphere::rgbAtWavelengths() instead of the band averages of Atmosphere::rgb().
    std::optional<glm::dvec3> rgbWavelengthsNm;

    // Multiple-scattering tables (orders >= 2).
    int altitudeSamples = 16;      ///< altitude grid (uniform in sqrt(altitude)), [4, 256]
    int sunZenithSamples = 37;     ///< sun zenith grid over [0, pi], 7x denser near 95 deg, [4, 512]
    int viewZenithSamples = 33;    ///< angle from the light, gamma = pi u^2, [4, 512]
    int viewAzimuthSamples = 19;   ///< azimuth around the light from the vertical, [0, pi], [3, 512]
    int gatherZenithSamples = 12;  ///< Gauss-Legendre nodes on each side of the horizon, [2, 64]
    int gatherAzimuthSamples = 16; ///< azimuth nodes over [0, pi] (mirrored), [2, 256]
    int gatherSteps = 32;          ///< ray-march points per gathered ray, [8, 4096]
    int maxOrders = 60;            ///< scattering orders at most (1 = single scattering only), [1, 500]
    double convergence = 1e-4;     ///< stop when an order adds less than this fraction, [0, 0.1]

    // Transmittance table (column densities).
    int transmittanceRadiusSamples = 128;  ///< [16, 4096]
    int transmittanceMuSamples = 256;      ///< [16, 4096]

    int raySteps = 512;  ///< march points per view ray, [16, 65536]
    int threads = 1;     ///< worker threads for the precomputation, [1, 64]

    /// Throws welkin::Error naming the first member out of range.
    void validate() const;

    /// Coarse settings for tests of behaviour (about 1 s of precomputation in RGB): 5-10% RMS
    /// luminance error, up to ~25% at the horizon near sunset and x1.5-2 at -18 deg (measured
    /// against a refined run, see the docs). Not for accuracy figures.
    static ReferenceOptions fast() {
        ReferenceOptions o;
        o.mode = SpectralMode::Rgb;
        o.altitudeSamples = 10;
        o.sunZenithSamples = 19;
        o.viewZenithSamples = 13;
        o.viewAzimuthSamples = 7;
        o.gatherZenithSamples = 6;
        o.gatherAzimuthSamples = 6;
        o.gatherSteps = 24;
        o.transmittanceRadiusSamples = 64;
        o.transmittanceMuSamples = 128;
        o.raySteps = 128;
        return o;
    }
};

/// Horizontal illuminance at the observer, lux.
struct SkyIlluminance {
    double global = 0.0;   ///< direct + diffuse on a horizontal surface
    double direct = 0.0;   ///< from the light sources' disks (transmitted beam), horizontal surface
    double diffuse = 0.0;  ///< from the sky (all scattering orders), horizontal surface
    glm::dvec3 globalRgb{0.0};  ///< global as linear sRGB (luminance = global)
};

/// A second light source such as the Moon: its direction and its illuminance at normal
/// incidence outside the atmosphere, lux. Its spectrum is taken as the Sun's, scaled.
struct ExtraLight {
    glm::dvec3 direction{0.0, 0.0, 1.0};  ///< unit vector towards the light, ENU
    double illuminanceLux = 0.0;          ///< >= 0; the full Moon at mean distance is ~0.26 lx
};

class ReferenceSky {
public:
    /// Validates both arguments and precomputes the multiple-scattering field (the expensive
    /// part: from a fraction of a second at test settings to tens of seconds at the defaults).
    explicit ReferenceSky(const Atmosphere& atmosphere, const ReferenceOptions& options = {});
    ~ReferenceSky();
    ReferenceSky(ReferenceSky&&) noexcept;
    ReferenceSky& operator=(ReferenceSky&&) noexcept;

    /// Sky radiance seen from `heightM` above the ground (negative heights are clamped to 0) in
    /// direction `view` (unit, ENU), lit by the Sun in direction `sun` (unit, ENU) and optionally
    /// by `extra` (the Moon). Linear sRGB, cd/m^2; the solar disk itself is excluded. An observer
    /// above the atmosphere sees the part of the ray inside it (0 when the ray misses it).
    glm::dvec3 radiance(double heightM, const glm::dvec3& view, const glm::dvec3& sun,
                        const std::optional<ExtraLight>& extra = {}) const;

    /// The same in the integrator's channels: radiance per unit solar irradiance (sr^-1), at
    /// wavelengths() (Spectral mode) or for the r, g, b channels (Rgb mode).
    std::vector<double> transfer(double heightM, const glm::dvec3& view, const glm::dvec3& sun) const;
    /// Spectral radiance, W m^-2 sr^-1 nm^-1, at the atmosphere's own wavelengths (Spectral
    /// mode: the transfer interpolated and multiplied by the solar spectrum). Rgb mode throws.
    std::vector<double> spectralRadiance(double heightM, const glm::dvec3& view, const glm::dvec3& sun) const;

    /// Transmittance from the observer along `direction` to the top of the atmosphere, per
    /// channel (0 where the ray hits the ground), ignoring the solar disk's extent.
    std::vector<double> channelTransmittance(double heightM, const glm::dvec3& direction) const;
    /// The same as the ratio of linear sRGB of the transmitted to the unattenuated Sun: the
    /// colour by which the solar disk is multiplied ((1, 1, 1) outside the atmosphere).
    glm::dvec3 transmittance(double heightM, const glm::dvec3& direction) const;
    /// Radiance of the centre of the solar disk seen from `heightM` (linear sRGB, cd/m^2), a
    /// uniform disk: transmitted illuminance / solid angle of the disk. 0 below the horizon.
    glm::dvec3 sunDiskRadiance(double heightM, const glm::dvec3& sun) const;

    /// Horizontal illuminance at the observer from the Sun (and `extra`), lux. The diffuse part
    /// is a quadrature of radiance() over the upper hemisphere (`zenithNodes` Gauss-Legendre
    /// nodes in cos(zenith), 2 * `azimuthNodes` in azimuth).
    SkyIlluminance illuminance(double heightM, const glm::dvec3& sun, const std::optional<ExtraLight>& extra = {},
                               int zenithNodes = 16, int azimuthNodes = 24) const;

    /// Wavelengths of the channels, nm (Rgb mode: the rgb() effective wavelengths).
    const std::vector<double>& wavelengths() const;
    const Atmosphere& atmosphere() const;
    const ReferenceOptions& options() const;
    /// Scattering orders computed, and the fraction the last one added.
    int orders() const;
    double lastOrderFraction() const;
    /// Wall-clock seconds spent in the constructor.
    double precomputeSeconds() const;
    /// Converts a transfer vector (per unit solar irradiance) to linear sRGB for the atmosphere's
    /// Sun (cd/m^2 for radiance, lux for irradiance).
    glm::dvec3 toRgb(const std::vector<double>& transfer) const;

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

/// Unit ENU direction from azimuth (from north through east) and altitude, radians.
inline glm::dvec3 directionFromAzAlt(double azimuthRad, double altitudeRad) {
    return {std::cos(altitudeRad) * std::sin(azimuthRad), std::cos(altitudeRad) * std::cos(azimuthRad), std::sin(altitudeRad)};
}

}  // namespace welkin::atmosphere
