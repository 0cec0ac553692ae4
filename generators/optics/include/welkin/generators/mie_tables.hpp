// Phase-function tables of water drops from the exact Lorenz-Mie series (mie.hpp): a 2-D table
// (scattering angle x drop radius, linear sRGB per unit irradiance) built once per quality and
// cached on disk, and the 1-D table of a drop-size distribution (rain or fog) derived from it.
//
//   using namespace welkin::generators;
//   const MieTable& t = MieTable::cached(MieTable::quality("default"));   // built or read from disk
//   DropDistribution d = DropDistribution::gamma(0.5e-3, 0.02, 5.0);       // r_eff, v_eff, mm/h
//   MiePhase1D p = integrate(t, d, SunDisk::Uniform);
//   // radiance of a thin slab of rain of depth s (m) lit by the Sun (lux per channel E):
//   //   L_c = E_c * p.scatteringPerM[c] * s * p.phaseAt(theta)[c]          cd/m^2
//
// Spectral model: 32+ wavelengths in [380, 780] nm; at each, the phase function and the
// scattering and extinction cross sections of a sphere of water (waterRefractiveIndex). Channel c
// of the table is the spectral quantity weighted by w_c(lambda) S(lambda), with w_c the CIE 1931
// -> linear sRGB weights (color::spectralToLinearSrgbWeights) and S the ASTM G-173 extraterrestrial
// solar spectrum (color::solarIrradianceAstmG173, what generators/atmosphere uses):
//   Csca_c(r)       = sum w_c S Csca(r, l) / sum w_c S                       m^2 per drop
//   phase_c(r, th)  = sum w_c S Csca(r, l) p(r, l, th) / sum w_c S Csca(r, l)  1/sr
// so that a distribution's bulk phase per channel is the Csca-weighted mean over the radii (exact:
// all sums are linear). Multiplying phase_c by the Sun's illuminance in channel c (lux) and the
// scattering coefficient gives radiance in cd/m^2. Rainbow colours lie outside the sRGB gamut:
// negative channels are clipped to 0 in the 1-D table (the 2-D table keeps them).
//
// Angles: theta = scattering angle in [0, pi] (pi - theta = angle from the anti-solar point);
// the table's texels are spaced non-uniformly (mieAngleFromU below; the same function is in
// shaders/mie_angle.glsl): dense over 120-150 deg (the bows, Alexander's band, supernumeraries)
// and 175-180 deg (the glory).
#pragma once
#include <glm/glm.hpp>

#include <cstdint>
#include <string>
#include <vector>

namespace welkin::generators {

/// The table's angle mapping: u in [0, 1] (texture coordinate) -> scattering angle, radians.
/// Piecewise linear through (u, theta deg) = (0, 0), (0.25, 120), (0.70, 150), (0.80, 175), (1, 180).
double mieAngleFromU(double u);
/// Its inverse, theta in [0, pi] (clamped).
double mieUFromAngle(double theta);

/// Angular model of the Sun for the convolution of the 1-D table.
enum class SunDisk {
    Point,    ///< no convolution (tests of the bare Mie result)
    Uniform,  ///< a uniform disk of angular radius 0.2666 deg (mean apparent diameter 0.533 deg)
};

/// A drop-size distribution with its concentration (from a rain rate).
struct DropDistribution {
    enum class Kind { Gamma, MarshallPalmer };
    Kind kind = Kind::Gamma;
    double effectiveRadiusM = 0.5e-3;  ///< r_eff = <r^3> / <r^2>, m, [5e-6, 2e-3] (Gamma)
    double effectiveVariance = 0.02;   ///< v_eff (Hansen 1971), [1e-3, 0.5] (Gamma)
    double rateMmH = 5.0;              ///< rain rate, mm/h, [0, 200]

    /// Hansen's (1971, J. Atmos. Sci. 28, 1400) gamma distribution
    /// n(r) ~ r^((1 - 3 v) / v) exp(-r / (r_eff v)), its liquid water content from the rate.
    static DropDistribution gamma(double rEffM, double vEff, double rateMmH);
    /// Marshall & Palmer (1948, J. Meteor. 5, 165): N(D) = N0 exp(-Lambda D), N0 = 8000 m^-3 mm^-1,
    /// Lambda = 4.1 R^-0.21 mm^-1 (r_eff = 1.5 / Lambda).
    static DropDistribution marshallPalmer(double rateMmH);
    /// Throws welkin::Error naming the parameter and its range.
    void validate() const;
    /// Effective radius, m (Marshall-Palmer: from the rate).
    double rEff() const;
    /// Number of drops per m^3 in the bin of each radius (log-spaced bins of ratio `ratio`),
    /// normalised to the liquid water content of the rate.
    std::vector<double> binConcentrations(const std::vector<double>& radiiM, double ratio) const;
};

/// Liquid water content of rain of rate R (mm/h), kg/m^3: the Marshall-Palmer integral
/// W = pi rho_w N0 / Lambda^4 = 0.0889 R^0.84 g/m^3 (same constants as above). Used for all
/// distributions (fog of "rate" R holds the same water: 5 mm/h -> 0.34 g/m^3, a dense fog).
double liquidWaterContent(double rateMmH);

/// The 2-D table on the CPU.
struct MieTable {
    struct Quality {
        std::string name;
        int wavelengths = 32;  ///< in [380, 780] nm, >= 30 for the issue's spectral resolution
        int radii = 48;        ///< log-spaced over [rMin, rMax]
        int angles = 512;      ///< texels of the angle mapping
        int subRadii = 1;      ///< radii per bin averaged (at least; up to 16 for small drops, see build())
        double rMinM = 5e-6, rMaxM = 2e-3;
    };
    /// "low" (32 wavelengths, 24 radii, 256 angles), "default" (32, 48, 512), "high" (40, 96 with 2
    /// sub-radii, 1024);
    /// throws welkin::Error for another name.
    static Quality quality(const std::string& name);

    Quality q;
    std::vector<double> radiiM;          ///< bin centres, m
    std::vector<glm::vec3> phase;        ///< [radius * angles + angle], 1/sr per channel
    std::vector<glm::dvec3> csca, cext;  ///< per radius, m^2 per drop, channel-weighted
    double buildSeconds = 0.0;           ///< wall time of the build (0 when read from the cache)
    bool fromCache = false;

    double radiusRatio() const { return radiiM.size() > 1 ? radiiM[1] / radiiM[0] : 1.0; }
    /// Exact Mie for every (wavelength, sub-radius) with `threads` threads (0: all cores).
    static MieTable build(const Quality& q, int threads = 0);
    /// The table from the disk cache ($XDG_CACHE_HOME/welkin, else ~/.cache/welkin, file
    /// `mie-<hash>.bin`, the hash of the quality and the code version), else built and written there
    /// atomically (temporary file + rename; a failed write only logs nothing and returns the table).
    /// Kept in memory per quality for the process.
    static const MieTable& cached(const Quality& q);
    static std::string cachePath(const Quality& q);
    uint64_t hash() const;
};

/// The 1-D table of a distribution (the table's angle mapping and size).
struct MiePhase1D {
    std::vector<glm::vec3> phase;     ///< per angle texel, 1/sr per channel, >= 0
    glm::dvec3 scatteringPerM{0.0};   ///< bulk scattering coefficient, 1/m per channel
    glm::dvec3 extinctionPerM{0.0};   ///< bulk extinction coefficient, 1/m per channel
    double rEffM = 0.0;
    /// Linear interpolation at scattering angle theta (rad).
    glm::dvec3 phaseAt(double theta) const;
};

/// Integrates the table over the distribution and convolves with the Sun's disk.
MiePhase1D integrate(const MieTable& table, const DropDistribution& d, SunDisk sun);

}  // namespace welkin::generators
