// The clouds' reference: a Monte Carlo volumetric path tracer on the CPU (double precision, all
// scattering orders, deterministic per seed), ground truth for the real-time clouds' tests and
// benchmarks (never used by the real-time path), and an independent adding-doubling solver for
// plane-parallel slabs that checks it.
//
//   using namespace welkin::cloudref;
//   SlabMedium slab(0.0, 1000.0, 10.0 / 1000.0);          // z in [0, 1000] m, tau = 10
//   HenyeyGreenstein hg(0.85);
//   Scene s{&slab, &hg};                                    // conservative scattering, no ground
//   s.lights.sunDirection = {0, 0, 1};                      // towards the Sun, unit
//   s.lights.sunIrradiance = glm::dvec3(1.0);               // at normal incidence, per channel
//   SlabFluxes f = slabFluxes(s, {0, 0, -1}, 20000, 7);     // photons entering at the top
//   // f.transmission, f.reflection (+- f.transmissionSigma, ...), fractions of the incident flux
//   glm::dvec3 L = radiance(s, {0, 0, -10}, {0, 0, 1}, 256, 7).mean;  // camera below, looking up
//   SlabSolution ad = addingDoubling(10.0, 1.0, hgMoments(0.85, 64), 1.0);  // independent check
//
// Method: free paths by delta tracking against the medium's majorant (Woodcock; exact for any
// density under the majorant), real collisions scatter with probability the single-scattering
// albedo (the photon estimator's analog absorption; the radiance estimator multiplies its
// throughput by the albedo instead). Radiance: at every real collision and every ground hit, next-
// event estimation towards the Sun with the transmittance by ratio tracking (the Sun is a delta
// light: a path that escapes adds only the sky's radiance, never the Sun's); the phase function
// (or the Lambertian ground's cosine) samples the next direction. No Russian roulette and no cap
// that matters (`maxScatterings`, default 1e6): with albedo 1 every order is kept.
// Units: metres, extinction 1/m, the lights' units are the output's (lux in, cd/m^2 out; or unit
// irradiance in, sr^-1 out). Directions: any right-handed frame with z up (ENU for the clouds).
// Determinism: each path's random numbers come from (seed, pixel or photon index) alone, so
// results do not depend on the thread count.
#pragma once
#include <welkin/generators/cloud_density.hpp>

#include <glm/glm.hpp>

#include <cstdint>
#include <functional>
#include <vector>

namespace welkin::cloudref {

/// Random numbers: PCG32 (O'Neill 2014) seeded from (seed, stream); uniform doubles in [0, 1).
class Rng {
public:
    Rng(uint64_t seed, uint64_t stream);
    double uniform();
private:
    uint64_t state_ = 0, inc_ = 1;
    uint32_t next();
};

/// A ray's parameter interval [t0, t1] (m) inside a medium's support.
struct Interval {
    double t0 = 0.0, t1 = 0.0;
};

/// A participating medium: its extinction coefficient and single-scattering albedo, an upper
/// bound of the extinction (the majorant of delta tracking) and its support (where it may be
/// non-zero) as ray intervals.
class Medium {
public:
    virtual ~Medium() = default;
    /// Extinction coefficient at p, 1/m, in [0, majorantPerM()].
    virtual double extinctionPerM(const glm::dvec3& p) const = 0;
    /// Upper bound of extinctionPerM() everywhere, 1/m, > 0.
    virtual double majorantPerM() const = 0;
    /// Single-scattering albedo at p, [0, 1]; default 1 (conservative scattering).
    virtual double albedo(const glm::dvec3& /*p*/) const { return albedo_; }
    /// The sub-intervals of [0, tMax] where the ray o + t d (d unit) may meet the medium, in
    /// increasing order, written to out (at most 4); returns their number.
    virtual int support(const glm::dvec3& o, const glm::dvec3& d, double tMax, Interval out[4]) const = 0;
    void setAlbedo(double a) { albedo_ = a; }
protected:
    double albedo_ = 1.0;
};

/// A homogeneous plane-parallel slab between heights z0 < z1 (m), infinite in x and y.
class SlabMedium final : public Medium {
public:
    SlabMedium(double z0, double z1, double extinctionPerM);
    double extinctionPerM(const glm::dvec3& p) const override;
    double majorantPerM() const override { return sigma_; }
    int support(const glm::dvec3& o, const glm::dvec3& d, double tMax, Interval out[4]) const override;
    double z0() const { return z0_; }
    double z1() const { return z1_; }
private:
    double z0_, z1_, sigma_;
};

/// An axis-aligned box [lo, hi] (m) whose extinction is sigmaMax * density(p), density in [0, 1]
/// (a heterogeneous test medium; an empty density function: uniform 1).
class BoxMedium final : public Medium {
public:
    BoxMedium(glm::dvec3 lo, glm::dvec3 hi, double sigmaMaxPerM, std::function<double(const glm::dvec3&)> density = {});
    double extinctionPerM(const glm::dvec3& p) const override;
    double majorantPerM() const override { return sigma_; }
    int support(const glm::dvec3& o, const glm::dvec3& d, double tMax, Interval out[4]) const override;
    /// True if p is inside the closed box.
    bool contains(const glm::dvec3& p) const;
private:
    glm::dvec3 lo_, hi_;
    double sigma_;
    std::function<double(const glm::dvec3&)> density_;
};

/// The real-time clouds' density field (generators::cpu::cloudDensity, CloudLod::Full, the same
/// function and textures as the GPU's) in the spherical shell [R + bottom, R + top]; extinction
/// = density x clouds.scattering_per_m; albedo 0.99999 (liquid water in the visible).
class CloudFieldMedium final : public Medium {
public:
    /// The textures must outlive the medium.
    CloudFieldMedium(const generators::CloudLayerBlock& block, const generators::cpu::CloudTextures& textures,
                     generators::CloudLod lod = generators::CloudLod::Full);
    double extinctionPerM(const glm::dvec3& p) const override;
    double majorantPerM() const override { return sigma_; }
    int support(const glm::dvec3& o, const glm::dvec3& d, double tMax, Interval out[4]) const override;
    double planetRadiusM() const { return R_; }
    double bottomM() const { return rb_ - R_; }  ///< the layer's bottom above the ground, m
    double topM() const { return rt_ - R_; }     ///< its top, m
private:
    generators::CloudLayerBlock block_;
    generators::cpu::CloudTextures tex_;
    generators::CloudLod lod_;
    double R_, rb_, rt_, sigma_;
};

/// A phase function (1/sr, integrating to 1 over the sphere) of the scattering angle's cosine,
/// with exact importance sampling.
class PhaseFunction {
public:
    virtual ~PhaseFunction() = default;
    virtual double eval(double cosTheta) const = 0;
    /// cos(theta) drawn with density eval(cos) * 2 pi (per unit cos) from u in [0, 1).
    virtual double sampleCos(double u) const = 0;
    /// Asymmetry parameter g, the mean cosine of the scattering angle.
    virtual double g() const = 0;
};

/// Henyey-Greenstein, g in (-1, 1).
class HenyeyGreenstein final : public PhaseFunction {
public:
    explicit HenyeyGreenstein(double g);
    double eval(double cosTheta) const override;
    double sampleCos(double u) const override;
    double g() const override { return g_; }
private:
    double g_;
};

/// A tabulated phase function: piecewise constant in cos(theta) between the given angles (the
/// mean of the tabulated values over each interval, renormalised to 1), so that eval() and
/// sampleCos() (by the cumulative distribution) agree exactly.
class TabulatedPhase final : public PhaseFunction {
public:
    /// thetaRad increasing from 0 to pi (>= 2 values), phase >= 0 at those angles (any scale).
    TabulatedPhase(const std::vector<double>& thetaRad, const std::vector<double>& phase);
    double eval(double cosTheta) const override;
    double sampleCos(double u) const override;
    double g() const override { return g_; }
private:
    std::vector<double> cosEdges_;  // decreasing cos from 1 to -1
    std::vector<double> value_;     // per interval, 1/sr
    std::vector<double> cdf_;       // cumulative probability at each edge
    double g_ = 0.0;
};

/// The Lorenz-Mie phase function of cloud droplets (generators::MieSphere, liquid water at
/// `wavelengthNm`) averaged over a gamma size distribution of effective radius rEffM and effective
/// variance vEff (Hansen 1971; weights n(r) pi r^2 Qsca), on `angles` angles denser towards the
/// forward peak and the glory. Defaults: a fair-weather cumulus (r_eff 10 um, v_eff 0.1, 550 nm;
/// asymmetry ~0.86). About 0.1-1 s.
TabulatedPhase cloudDropletPhase(double rEffM = 10e-6, double vEff = 0.1, double wavelengthNm = 550.0, int radii = 48,
                                 int angles = 3000);

/// A phase function with its forward peak truncated (the delta-M idea for Monte Carlo: Iwabuchi
/// 2006): the phase clipped to its value at thetaCutRad inside that cone, renormalised, and the
/// fraction f of the scattering that the clip removed (the light scattered by less than the cut,
/// treated as unscattered). Scale the medium's extinction by 1 - f with it: fluxes and radiances
/// away from the light's direction keep their values (to the truncation's error), the variance of
/// next-event estimation towards a delta light drops with the peak. thetaCutRad in (0, pi/2);
/// tabulated on `angles` angles (>= 100), denser near 0.
struct TruncatedPhase {
    TabulatedPhase phase;
    double removedFraction = 0.0;  ///< f in [0, 1)
};
TruncatedPhase truncatePhase(const PhaseFunction& phase, double thetaCutRad, int angles = 3000);

/// The ground: none, a plane z = height, or the planet's sphere (centre (0, 0, -radius)); a
/// Lambertian reflector of albedo [0, 1].
struct Ground {
    enum class Kind { None, Plane, Sphere };
    Kind kind = Kind::None;
    double heightM = 0.0;   ///< Plane: its height, m
    double radiusM = 6360e3;  ///< Sphere: the planet's radius, m
    double albedo = 0.0;    ///< [0, 1]
};

/// The lights: the Sun's direct beam (a delta: its irradiance at normal incidence where it enters
/// the medium, per channel) and the sky's radiance arriving from each direction (none: black).
struct Lights {
    glm::dvec3 sunDirection{0.0, 0.0, 1.0};  ///< unit, towards the Sun
    glm::dvec3 sunIrradiance{0.0};           ///< at normal incidence, per channel (e.g. lux)
    /// Radiance arriving along -dir from direction dir (dir unit, pointing away from the scene),
    /// per channel (e.g. cd/m^2); empty: no sky light.
    std::function<glm::dvec3(const glm::dvec3& dir)> sky;
};

/// What a path sees: a medium, its phase function, the ground and the lights.
struct Scene {
    const Medium* medium = nullptr;
    const PhaseFunction* phase = nullptr;
    Ground ground;
    Lights lights;
    /// Real collisions per path at most (1: single scattering only, exactly); the default is a
    /// safety cap never reached in practice.
    long maxScatterings = 1000000;
};

/// An estimate with its standard error (of the mean, per channel).
struct Estimate {
    glm::dvec3 mean{0.0};
    glm::dvec3 sigma{0.0};
};

/// Radiance arriving at `origin` from direction -`dir` (dir unit: the camera ray), the mean of
/// `paths` paths with seed (seed, stream). The Sun's disk itself is not included.
Estimate radiance(const Scene& scene, const glm::dvec3& origin, const glm::dvec3& dir, int paths, uint64_t seed,
                  uint64_t stream = 0);

/// A pinhole image: rows x cols rays of the camera at `origin` (m) looking along `forward` with
/// `up` roughly up and a vertical field of view fovYRad; row 0 at the top. Deterministic for any
/// thread count.
struct ImageRequest {
    glm::dvec3 origin{0.0}, forward{0.0, 1.0, 0.0}, up{0.0, 0.0, 1.0};
    double fovYRad = 1.0;
    int width = 64, height = 36;
    int pathsPerPixel = 16;
    uint64_t seed = 1;
    int threads = 1;
};
struct Image {
    int width = 0, height = 0;
    std::vector<glm::dvec3> radiance;        ///< per pixel, row major
    std::vector<double> luminanceSigma;      ///< standard error of the luminance per pixel
    std::vector<double> transmittance;       ///< the camera ray's transmittance through the medium
};
Image render(const Scene& scene, const ImageRequest& request);
/// The ray of pixel (x, y) (through its centre) of the request.
glm::dvec3 pixelDirection(const ImageRequest& request, double x, double y);

/// Photons launched at the top of a slab (or into a box from above): where their energy goes.
/// Fractions of the incident flux, with standard errors.
struct SlabFluxes {
    double reflection = 0.0, transmission = 0.0, absorbed = 0.0;  ///< absorbed: collision estimator
    double reflectionSigma = 0.0, transmissionSigma = 0.0, absorbedSigma = 0.0;
    double directTransmission = 0.0;  ///< unscattered fraction (analog)
    double meanScatterings = 0.0;
};
/// Analog photon tracking of `photons` photons entering the medium travelling along `dir` (unit,
/// dir.z < 0), from the medium's top at x = y = 0 (a SlabMedium; a BoxMedium: the centre of its
/// top face; a CloudFieldMedium: its top above the origin, reflection and transmission by the
/// shell's outer and inner boundary). Reflection counts photons leaving upwards (dir.z > 0) and transmission downwards;
/// `absorbed` is the expected absorption tallied at every tentative collision (sigma_a / majorant,
/// an estimator independent of the escape counts: reflection + transmission + absorbed = 1 within
/// the errors tests energy conservation). The scene's ground and lights are ignored.
SlabFluxes slabFluxes(const Scene& scene, const glm::dvec3& dir, long photons, uint64_t seed);

/// Transmittance exp(-integral of extinction) from o along d (unit) over [0, tMax], by ratio
/// tracking (unbiased; one estimate).
double ratioTrackingTransmittance(const Medium& m, const glm::dvec3& o, const glm::dvec3& d, double tMax, Rng& rng);

// ---- The independent check: adding-doubling for a plane-parallel slab -------------------------

/// Legendre moments chi_l (l = 0..n-1, chi_0 = 1) of Henyey-Greenstein: g^l.
std::vector<double> hgMoments(double g, int n);

/// Reflection and transmission (direct + diffuse) of a homogeneous slab lit by a collimated beam,
/// fractions of the incident flux, azimuthally integrated (the m = 0 Fourier term).
struct SlabSolution {
    double reflection = 0.0, transmission = 0.0, directTransmission = 0.0;
    /// The azimuth-averaged diffuse radiance leaving the slab (1/sr per unit irradiance normal to
    /// the beam) at the Gauss-Legendre cosines `mu` (increasing, in (0, 1)): reflected from the lit
    /// side, transmitted from the other. The delta-M peak is in the direct beam, not here.
    std::vector<double> mu, reflectedRadiance, transmittedRadiance;
};
/// The azimuth-averaged diffuse radiance inside the same slab at optical depth `depth` in
/// [0, tau] from the lit top (1/sr per unit irradiance normal to the beam), at the Gauss-Legendre
/// cosines `mu`: `down` travelling downwards (away from the lit side), `up` upwards. The adding
/// equations between the layers above and below the depth, each doubled as addingDoubling().
/// At depth tau, `down` is addingDoubling()'s transmitted radiance; at 0, `up` its reflected.
struct SlabInternal {
    std::vector<double> mu, down, up;
};
SlabInternal addingDoublingInternal(double tau, double albedo, const std::vector<double>& moments, double mu0, double depth, int streams = 32);
/// Legendre moments chi_l (l = 0..n-1, chi_0 = 1) of any phase function, by the midpoint rule in
/// cos(theta) over `steps` intervals (4e5 resolve the droplets' diffraction peak).
std::vector<double> phaseMoments(const PhaseFunction& phase, int n, int steps = 400000);
/// Adding-doubling (van de Hulst 1980; Hansen & Travis 1974 §3.3): `streams` Gauss-Legendre
/// nodes per hemisphere (double Gauss), the phase function's Legendre expansion truncated at
/// 2 x streams with the delta-M scaling (Wiscombe 1977), a first-order thin layer of optical depth
/// <= 1e-9 doubled up to tau; beam at cos(zenith) mu0 in (0, 1]; black ground. Double precision,
/// milliseconds. tau in [0, 1e4], albedo [0, 1], streams [2, 128].
SlabSolution addingDoubling(double tau, double albedo, const std::vector<double>& moments, double mu0, int streams = 32);

}  // namespace welkin::cloudref
