// Stars: the star catalogue on the GPU, at its apparent places for the processor's time and
// observer, with its brightness, colour, twinkling and the sky's limiting magnitude.
//
//   processor.add(welkin::elements::makeElement("stars"));            // before the Sky (farthest first)
//   processor.add(welkin::elements::makeElement("sky"));              // its transmittance dims them
//   processor.vars().set(welkin::elements::starkeys::magnitudeLimit, 4.0);    // hard cap, mag
//   // command line: welkin render --var stars.catalogue=/path/hygdata_v3.csv --var stars.seed=7
//   // a host's own catalogue: std::make_unique<welkin::elements::Stars>(std::move(myStars))
//
// Model (skyelements/stars/README.md has the sources and the measured cost):
//  - Catalogue: kstars-data stars.dat by default (125,982 stars to V ~ 9; B-V, proper motion);
//    BSC5 (`catalog`, or a name containing "bsc") or HYG (`*.csv`) by stars.catalogue. Uploaded
//    once, sorted by magnitude, as one storage buffer: J2000 direction, proper motion, V, colour.
//  - Place: per frame one rotation (the astronomy's stars.frame_icrs_to_enu), the aberration and
//    the epoch for proper motion (astro::starEnu is the CPU twin), then refraction from a table of
//    astro::refraction() at the astronomy's pressure and temperature.
//  - Brightness: illuminance E = 2.54e-6 lx x 10^(-0.4 V) above the air
//    (astro::magnitude::illuminanceLux). With an element composited after the stars that attenuates
//    what is behind it (the Sky; FrameContext::attenuatedLater) it attenuates them, once; without one, the
//    element applies the atmosphere's transmittance towards each star itself (a table of
//    altitude, RGB, from the CPU transmittance of the shared atmosphere model; 0 below the ground).
//  - Colour: B-V -> effective temperature (Ballesteros 2012, EPL 97, 34008) -> Planck spectrum ->
//    CIE 1931 XYZ -> linear sRGB, scaled to luminance E.
//  - PSF: a Gaussian in pixel space of FWHM max(stars.psf_fwhm_rad x pixels per radian,
//    stars.psf_min_px) (never under sqrt(2) px, so a moving star neither flickers nor aliases),
//    normalised so that its integral over the image is E: radiance = E w(px) / (solid angle of a
//    pixel). Stars brighter than stars.glare_magnitude put stars.glare of their flux in a wide
//    Moffat (beta = 2) halo, 6 core FWHM wide (the integral stays E).
//  - Scintillation: flux x (1 + a n(t)), n a smooth deterministic noise of (star, stars.seed,
//    time.jd_utc) at ~10 Hz, a = stars.scintillation x 0.02 X^1.75 (X the Kasten-Young airmass;
//    Young's X^1.75 growth), capped at 0.8.
//  - Limiting magnitude: Schaefer (1990, PASP 102, 212; after Hecht 1947) threshold illuminance
//    I = C1 (1 + sqrt(C2 B))^2 ft-cd for the background B (nL) = sky.zenith_luminance (if a Sky
//    publishes it) + the night sky: nightsky.background_cd_m2 (if the NightSky element publishes
//    it: airglow, zodiacal light, Milky Way, light pollution) or else stars.background_floor_cd_m2
//    (default the dark-sky reference astro::magnitude::kDarkSkyZenithMag), m = -16.57 - 2.5 log10 I;
//    capped by stars.magnitude_limit. Stars fainter than it are not drawn: the catalogue is sorted
//    by magnitude and only the prefix brighter than the limit is instanced (cost nothing).
//  - render.point_sources = perceptual (displayed images; welkin/point_source.hpp): each star's
//    illuminance at the eye against the threshold for the sky behind it (point_perceptual.glsl);
//    under it the star is not drawn, over it also as a Gaussian sized and brightened with log10
//    of the ratio (the brighter of it and the PSF per pixel).
#pragma once
#include <welkin/astro/stars.hpp>
#include <welkin/color.hpp>
#include <welkin/element.hpp>
#include <welkin/elements/star_labels.hpp>
#include <welkin/gl/objects.hpp>
#include <welkin/gl/projection_programs.hpp>

#include <glm/glm.hpp>

#include <memory>
#include <string>
#include <vector>

namespace welkin::elements {

namespace starkeys {
inline constexpr double kArcmin = 2.908882086657216e-4;  // rad
inline const Key<std::string> catalogue{"stars.catalogue", "star catalogue file: kstars stars.dat, BSC5 catalog (name 'catalog' or containing 'bsc'), or HYG *.csv"};
inline const Key<double> magnitudeLimit{"stars.magnitude_limit", Range{-30, 30}, "hard cap on the faintest magnitude drawn (the sky's limit applies too)", "mag"};
inline const Key<bool> adaptiveLimit{"stars.adaptive_limit", "the limiting magnitude follows the sky background (false: only stars.magnitude_limit)"};
inline const Key<double> backgroundFloor{"stars.background_floor_cd_m2", Range{0, 1}, "natural night-sky luminance added to the Sky's zenith luminance for the limiting magnitude when no NightSky element publishes nightsky.background_cd_m2"};
inline const Key<double> psfFwhm{"stars.psf_fwhm_rad", Range{0, 0.01}, "angular FWHM of the stars' point-spread function (seeing, the eye's acuity)"};
inline const Key<double> psfMinPx{"stars.psf_min_px", Range{1.41421356, 64}, "smallest FWHM of a star on the screen (anti-aliasing)", "px"};
inline const Key<double> glare{"stars.glare", Range{0, 0.5}, "fraction of a bright star's flux in its glare halo", "1"};
inline const Key<double> glareMagnitude{"stars.glare_magnitude", Range{-30, 30}, "stars brighter than this get a glare halo", "mag"};
inline const Key<double> scintillation{"stars.scintillation", Range{0, 20}, "scintillation strength (0 off, 1 typical)", "1"};
inline const Key<int> seed{"stars.seed", Range{0, 1 << 30}, "seed of the scintillation noise"};
}  // namespace starkeys

// A star's colour from B-V is the engine's colour science (welkin/color.hpp).
using color::blackBodyLinearSrgb;
using color::starColourFromBV;
using color::starTemperatureFromBV;
/// Naked-eye limiting magnitude against a background luminance (cd/m^2, >= 0): Schaefer 1990.
double limitingMagnitude(double backgroundCdM2);
/// Scintillation amplitude (relative flux, [0, 0.8]) at an apparent altitude (rad) for strength s.
double scintillationAmplitude(double altitudeRad, double strength);

class Stars final : public SkyElement {
public:
    /// The catalogue named by stars.catalogue (default astro::kKStarsCatalogue), loaded at init.
    Stars();
    /// A host's own catalogue (stars.catalogue is then ignored).
    explicit Stars(std::vector<astro::Star> stars);

    /// Stars drawn by the last frame (in the perceptual mode, render.point_sources: instanced;
    /// those under the eye's threshold over the sky behind them are then culled on the GPU), and
    /// the limiting magnitude it used.
    int drawn() const { return drawn_; }
    double limitingMagnitudeUsed() const { return limit_; }
    /// Catalogue size (after init).
    int catalogueSize() const { return int(mags_.size()); }
    /// false (default): one indexed draw of 4 vertices (6 indices) per star; true: the instanced draw of before
    /// 2026-11-27 (an instance per star: on llvmpipe its per-instance cost, README "Cost"), kept
    /// as the reference the tests compare with. Call before init().
    void setInstancedDraw(bool instanced) { instanced_ = instanced; }

private:
    void doInit(InitContext& ctx) override;
    void doRender(const FrameContext& ctx) override;
    void doRelease() override;
    void doStats(nlohmann::json& root) const override;
    void upload(std::vector<astro::Star> stars);
    void updateExtinction(const SkyVars& v);

    bool own_ = false;                 // constructed with a catalogue
    bool instanced_ = false;           // setInstancedDraw
    std::vector<astro::Star> given_;   // until uploaded
    std::string loadedPath_;
    std::vector<float> mags_;          // sorted, brightest first
    gl::Buffer buffer_;
    gl::Buffer indices_;     // 6 per star and copy (two triangles over 4 vertices), for the single draw
    gl::VertexArray vao_;    // holds indices_ as its element buffer
    int indexedStars_ = 0;   // star copies indices_ covers
    int starsSsbo_ = 0;  // its private storage-buffer binding (SkyElement::storageBuffer)
    gl::ProjectionPrograms programs_;
    std::vector<float> extinction_;    // RGB per altitude sample, no Sky
    double extinctionKey_[2] = {-1, -1};
    const void* extinctionAtm_ = nullptr;
    int drawn_ = 0;
    double limit_ = 0;
    bool perceptual_ = false;  // render.point_sources of the last frame
    StarLabels labels_;  // stars.labels (star_labels.hpp)
};

}  // namespace welkin::elements
