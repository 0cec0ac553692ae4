// Sky: the atmosphere's radiance (cd/m^2) for every camera projection, lit by the Sun and the
// Moon, from the noon sky to the end of astronomical twilight, seen from the ground, from an
// aircraft or from space; and the physical quantities of the sky for --stats and hosts.
//
//   welkin::elements::SkyOptions opt;
//   opt.quality = 2;                                     // high; -1 follows render.quality
//   opt.wavelengths = 15;                                // spectral (CIE 1931); 3 = RGB
//   processor.add(std::make_unique<welkin::elements::Sky>(opt));   // before stars? no: stars first,
//                                                        // the sky attenuates them (farthest first)
//   processor.renderFrame();
//   double lux = processor.vars().get(welkin::generators::skykeys::horizontalIlluminance).x;
//
// Rendering: from the sky-view LUTs (one per light, horizon-dense; generators/sky_luts.hpp)
// while the observer is inside the atmosphere; every pixel is ray-marched on the GPU (with the
// transmittance and multiple-scattering LUTs) when the observer is above the atmosphere (space:
// limb and the Earth seen from orbit) or at quality `reference`. Each pixel also outputs the
// transmittance of the atmosphere along its ray, so stars composited before the sky are
// attenuated; the ground (a Lambertian sphere lit by the Sun/Moon through the atmosphere) is
// opaque.
//
// Lights: the Sun's top-of-atmosphere illuminance follows the atmosphere's solar spectrum and the
// Sun's distance (sun.distance_m if present); the Moon's follows its phase angle and distance
// (moon.phase_angle_rad, moon.distance_m if present, else the Sun-Moon elongation) through the
// lunar magnitude law of Allen (m = -12.73 + 0.026 |i| + 4e-9 i^4, i in degrees, at the mean
// distance 384 400 km) and E = 10^(-0.4 (m + 13.99)) lux, with the Sun's colour (the Moon's
// albedo is nearly grey). Published in SkyVars: sky.sun_illuminance, sky.moon_illuminance,
// sky.sun_disk_radiance (the disk's mean radiance at the observer, reddened),
// sky.sun_transmittance, sky.moon_transmittance, sky.horizontal_illuminance (global, direct,
// diffuse lux), sky.diffuse_irradiance, sky.zenith_luminance.
//
// Shadow of the direct light: when a generator publishes sky.shadow_loss_lut (the Clouds
// element's CloudSkyShadow: crepuscular rays), the sky subtracts the single scattering it removes
// (generators/sky_luts.hpp; skyelements/clouds/README.md); without it the sky is unchanged, bit for bit.
//
// Observer heights below the ground are clamped to 0 m with a warning through the logger.
#pragma once
#include <set>
#include <utility>

#include <welkin/elements/aerial_perspective.hpp>
#include <welkin/element.hpp>
#include <welkin/generators/sky_luts.hpp>
#include <welkin/gl/objects.hpp>
#include <welkin/gl/projection_programs.hpp>

namespace welkin::elements {

/// Below this solar altitude (rad) the Sky's LUT path skips the Sun's term per pixel (the Moon's
/// stays): -21 deg. Measured (skyelements/sky/README.md, Malta 2026-08-12, fisheye, medium): the brightest pixel
/// of the Sun's sky is 7.5e-5 cd/m^2 at -19.6 deg (near the horizon under the Sun; the natural
/// night sky is 2e-4 at the zenith and ~1e-3 there), below 1e-6 at -20.25 deg and exactly 0 from
/// -20.6 deg in every pixel (multiple scattering included). The published
/// photometry (sky.zenith_luminance, ...) is unchanged.
inline constexpr double kSkySunNightAltitudeRad = -21.0 * 3.14159265358979323846 / 180.0;

/// At night without the Moon's term the Sky adds no radiance: its pass only multiplies what is
/// behind it by the transmittance (blend dst x T instead of the dual-source dst = L + T dst with
/// L = 0: the same values, ~0.1-0.25 of a trivial fullscreen pass less on llvmpipe;
/// skyelements/sky/README.md). false: the general dual-source pass (tests compare the two).
inline const Key<bool> skyNightMultiply{"sky.night_multiply",
                                        "at night without the Moon, the pass only multiplies what is behind by T (false: the general blended pass)"};

/// Build and draw once, in the first frame of each composition, every LUT-path program variant
/// the Sky can switch to while the lights move, so that no later frame compiles one (a time
/// jump that lights the Moon, nightfall; skyelements/sky/README.md). false: each variant is built
/// at its first use (the state before; benches compare the two).
inline const Key<bool> skyPrebuildPrograms{"sky.prebuild_programs",
                                           "build and draw once, in the first frame, the program variants the lights can switch to (false: at first use)"};
/// Draw the Moon's sky term while the Sun is up (its sky is then below 1e-4 of the Sun's:
/// skyelements/sky/README.md). false (default): left out by day.
inline const Key<bool> skyMoonByDay{"sky.moon_by_day", "draw the Moon's sky term while the Sun is up (false: left out, below 1e-4 of the Sun's sky)"};

struct SkyOptions {
    int quality = -1;   ///< -1: render.quality; else 0 low, 1 medium, 2 high, 3 reference
    bool moon = true;   ///< the Moon as a second light
    /// Wavelengths of the atmosphere's light transport: 0 follows sky.wavelengths, whose default
    /// 0 is the quality preset's (15 at `reference`, else 3); 3 = RGB (Atmosphere::rgb());
    /// 6..24, a multiple of 3 = spectral: that many wavelengths through the CIE 1931 observer
    /// (generators/sky_spectral.hpp). Spectral mode costs about N/3 times the LUT rebuild of RGB
    /// mode and the same per frame on the LUT path; per pixel (reference, space) the march runs
    /// N/3 times (plus a transmittance pass).
    int wavelengths = 0;
    /// Build the aerial-perspective volume (sky.aerial_volume) for the host's geometry
    /// (AerialPerspective::apply / bindResources). Off by default: the sky itself does not use
    /// it, and a scene without geometry to fog should not pay for it (about 1 ms per frame while
    /// the Sun moves at `medium` on llvmpipe, plus its keyframe builds).
    bool aerialPerspective = false;
    /// Throws welkin::Error naming the member and its range.
    void validate() const;
};


class Sky final : public SkyElement {
public:
    /// Options as keys (sky.quality, sky.moon, sky.wavelengths), declared with SkyOptions{}'s
    /// defaults: a value already in the SkyVars (another element's, the host's) is kept.
    Sky();
    /// The same keys set to `options` (validated) when the element is added.
    explicit Sky(const SkyOptions& options);
    /// The options as the last frame used them (the keys' values).
    const SkyOptions& options() const { return options_; }
    /// The shared generators (valid after init()).
    const generators::SkyLuts& luts() const { return luts_; }
    /// True if the last frame was ray-marched per pixel (space or reference quality).
    bool perPixel() const { return perPixel_; }
    /// True if the last frame subtracted a direct-light shadow (sky.shadow_loss_lut: clouds).
    bool shadowed() const { return shadowed_; }
    /// Whether the last frame drew a solar eclipse's sky (sky.eclipse_view_lut).
    bool eclipsed() const { return eclipse_; }
    /// Programs compiled and linked so far (each variant once per projection). The LUT path's
    /// variants a running sky can switch to (the Moon on and off, night, night multiply, eclipse)
    /// are all built and drawn once in the first frame for its projection and composition, so the
    /// count stays constant after it while only the lights move (skyelements/sky/README.md).
    int programBuilds() const { return programBuilds_; }

private:
    Sky(const SkyOptions& options, bool force);
    void doInit(InitContext& ctx) override;
    void doUpdate(const FrameContext& ctx) override;
    void doRender(const FrameContext& ctx) override;
    /// ScenePass::Air: the aerial perspective over the host's scene (AerialPerspective).
    void doApplyToScene(const FrameContext& ctx, ScenePass pass) override;
    void doRelease() override;
    void doStats(nlohmann::json& root) const override;
    void doValidateOptions(const SkyVars& vars) const override;
    /// shBands: SkyQuality::shBands (read by the per-pixel march only).
    /// shadow: subtract sky.shadow_loss_lut (the direct light's shadow, e.g. the clouds').
    static gl::ProgramBuilder recipe(bool perPixel, bool moon, bool transmittance, bool baked, bool spectral, int shBands, bool shadow,
                                     bool eclipse = false, bool noSun = false, bool multiply = false);

    SkyOptions options_;
    generators::SkyLuts luts_;
    // [without, with the Moon][without, with the transmittance output][separate, baked Mie phase]:
    // separate variants because llvmpipe evaluates both sides of a uniform branch; each compiled
    // per projection on first use. spectralPrograms_: per pixel, one wavelength triple per draw;
    // the per-pixel ones are (re)made for the quality's SH bands (marchBands_) on first use. The
    // last index of lutPrograms_ and marchPrograms_: [without, with] the shadow loss
    // (sky.shadow_loss_lut present: clouds in the scene).
    gl::ProjectionPrograms lutPrograms_[2][2][2][2], marchPrograms_[2][2], spectralPrograms_[2];
    // A solar eclipse (sky.eclipse_view_lut): [moon][transmittance] on the LUT path, [moon] per pixel.
    gl::ProjectionPrograms eclipsePrograms_[2][2][2], marchEclipsePrograms_[2];  // eclipse: [moon][transmittance][baked phase]
    // Night, the Sun's term skipped (SKY_NO_SUN): [moon][transmittance][baked phase], LUT path only.
    gl::ProjectionPrograms nightPrograms_[2][2][2];
    // Night without the Moon over something (sky.night_multiply): [baked phase], SKY_MULTIPLY.
    gl::ProjectionPrograms nightMultiplyPrograms_[2];
    // Every program use goes through program(): it counts the uses that find the (variant,
    // projection) not yet built (ProjectionPrograms::built()), i.e. the ones that compile and link.
    const gl::Program& program(gl::ProjectionPrograms& pp, Projection proj);
    std::set<int> warmed_;  // (projection, transmittance, baked, shadow) combinations warmed
    int programBuilds_ = 0;
    int marchBands_ = 0;
    gl::Buffer ubo_;
    AerialPerspective aerial_;  // applyToScene()'s air pass
    bool perPixel_ = false;
    bool shadowed_ = false;
    bool sunTerm_ = true;    // the last frame drew the Sun's term (false: night, kSkySunNightAltitudeRad)
    bool moonDaySkipped_ = false;  // the last frame left the Moon's term out: the Sun up (kMoonSkySunAltitudeRad)
    bool nightMultiply_ = false;  // the last frame's pass only multiplied by T (sky.night_multiply)
    bool eclipse_ = false;   // the last frame drew the eclipse's table  // the last frame subtracted sky.shadow_loss_lut
    double zenith_ = 0, global_ = 0, direct_ = 0, diffuse_ = 0;
};

}  // namespace welkin::elements
