// Rainbow: the primary and secondary bows, Alexander's dark band, supernumeraries, fogbows and
// the glory, from the exact Lorenz-Mie phase function of the drops (generators/optics), where
// rain actually is: a user's rain curtain and, when the Clouds element runs, the rain under its
// clouds (the weather map's channel A). skyelements/rainbow/README.md.
//
//   processor.add(welkin::elements::makeElement("rainbow"));               // Layer Foreground
//   processor.vars().set(welkin::generators::rainkeys::rate, 5.0);           // mm/h
//   processor.vars().set(welkin::generators::rainkeys::dropRadius, 0.5e-3);  // m
//   // command line: welkin render --elements sky,rainbow --var rain.rate_mm_h=5
//   //                 --var rain.drop_radius_m=0.0005 --out bow.png
//
// The curtain: the sector of a cylindrical shell around the observer, horizontal distance
// [rain.distance_m, + rain.depth_m], height [0, rain.height_m], azimuth within
// rain.half_width_rad of the anti-solar azimuth. Radiance (cd/m^2) along the view ray: single
// scattering of the light (the Sun; the Moon when the Sun is below the horizon: moonbows) with
// the 1-D phase LUT, attenuated by the rain in front and along the light's path inside the
// curtain (closed form, skyelements/rainbow/README.md); transmittance exp(-b_ext s) of what is behind.
// Observer above the rain (observer.height_m > rain.height_m, rain.distance_m = 0): a fog layer
// below, with the glory around the anti-solar point.
// Nothing is drawn (no GL call) when no rain is declared (rain.rate_mm_h = 0 and no clouds'
// rain) or when the light is too high for any bow: see Rainbow::bowPossible().
#pragma once
#include <welkin/element.hpp>
#include <welkin/generators/rain_keys.hpp>
#include <welkin/gl/objects.hpp>
#include <welkin/gl/projection_programs.hpp>
#include <welkin/gl/shader.hpp>

#include <glm/glm.hpp>
#include <vector>

#include <memory>

namespace welkin::elements {

namespace rainbowkeys {
inline constexpr double kDeg = 0.017453292519943295;
inline const Key<double> distance{"rain.distance_m", Range{0, 1e5}, "horizontal distance from the observer to the near face of the rain curtain"};
inline const Key<double> depth{"rain.depth_m", Range{1, 1e5}, "horizontal depth of the rain curtain"};
inline const Key<double> height{"rain.height_m", Range{1, 2e4}, "top of the rain curtain above the ground (the cloud base)"};
inline const Key<double> halfWidth{"rain.half_width_rad", Range{1 * kDeg, 180 * kDeg}, "azimuthal half-width of the curtain around the anti-solar azimuth"};
inline const Key<bool> directionCache{"rain.direction_cache",
                                      "the real-time path: the curtain in a direction cache around the anti-light point (refilled when "
                                      "the light moves 0.02 deg or the rain changes) drawn by a clipped screen grid, one fetch a pixel "
                                      "(perspective projection, the curtain only); off: every pixel every frame; unset: "
                                      "on when render.interactive (welkin view)"};
/// While the light moves (time running), the direction cache is refilled over this many frames
/// (a band of its rows a frame, into a second texture; the cache filled before is drawn until the
/// new one is complete). The display places the bows around the *current* anti-light point, so
/// the bows never lag; only the curtain's light path does (measured in skyelements/rainbow/README.md). 1: the
/// whole cache in the frame the light moved past the tolerance. A jump of the light (more than
/// Rainbow::kLightJump), a change of the rain or the curtain, and the first frame fill it whole.
/// 64: 4 rows of kCachePsi a frame (32, 8 rows, until 2026-11-27 evening: a frame at 512x256 then
/// cost 1.5-1.7 still frames; skyelements/rainbow/README.md "Time running fast").
inline constexpr int kCacheSlicesDefault = 64, kCacheSlicesMax = 64;
inline const Key<int> cacheSlices{"rain.cache_slices", Range{1, kCacheSlicesMax},
                                  "frames over which the direction cache is refilled while the light moves (1: at once)"};
}  // namespace rainbowkeys

class Rainbow final : public SkyElement {
public:
    Rainbow();
    /// The drawing rule: true if any bow (or the glory) of the light at elevation `lightElevation`
    /// (rad) can fall on rain. The outer edge of the secondary bow lies 54 deg from the anti-solar
    /// point (51 deg + its width and the Sun's radius), so with the lowest rain direction at
    /// elevation -atan(h / d) (observer height h above the ground, curtain at distance d; -0 on
    /// flat ground) a bow is possible iff 54 deg - lightElevation >= that lowest elevation. On flat
    /// ground: the primary needs the light below 42 deg (the table takes care of that), any bow
    /// below 54 deg.
    static bool bowPossible(double lightElevation, double observerHeightM, double curtainDistanceM);
    /// True if the last render() issued its draw (false: skipped, nothing to see).
    bool drewLastFrame() const { return drew_; }
    /// True if the last render() drew through the direction cache (rain.direction_cache).
    bool cachedLastFrame() const { return cached_; }
    /// How many times the direction cache has been filled (tests: what triggers a refill); a
    /// refill spread over frames counts when it starts.
    int cacheFills() const { return cacheFills_; }
    /// Rows of the direction cache (of kCachePsi) filled by the last render() (work counted).
    int cacheRowsLastFrame() const { return rowsLast_; }
    /// Rows of the direction cache a frame fills while a refill is spread over `slices` frames,
    /// `slices` in [1, rainbowkeys::kCacheSlicesMax] (clamped to it, as the key's value is).
    static constexpr int rowsPerSlice(int slices) {
        const int n = slices < 1 ? 1 : (slices > rainbowkeys::kCacheSlicesMax ? rainbowkeys::kCacheSlicesMax : slices);
        return (kCachePsi + n - 1) / n;
    }
    /// A refill spread over frames is in progress.
    bool refilling() const { return backRow_ >= 0; }

    /// The direction cache's size (texels: angle from the anti-light point, position angle around
    /// it) and the display grid's cell (pixels). skyelements/rainbow/README.md gives their measured error.
    static constexpr int kCacheU = 2048, kCachePsi = 256, kGridCellPx = 64;
    /// The light's motion (rad) that refills the cache (0.02 deg: 1/27 of the Sun's diameter).
    static constexpr double kLightTolerance = 3.5e-4;
    /// The light's motion (rad) from one frame to the next beyond which the cache is refilled whole
    /// at once (a new time, not time running): 1 deg (at 1440x and 30 frames/s the Sun moves at
    /// most 0.2 deg a frame).
    static constexpr double kLightJump = 0.01745;

private:
    void doInit(InitContext& ctx) override;
    void doValidateOptions(const SkyVars& vars) const override;
    void doRender(const FrameContext& ctx) override;
    void doRelease() override;

    std::shared_ptr<generators::MiePhaseGenerator> mie_;
    gl::ProjectionPrograms programs_, cloudPrograms_, meshPrograms_;
    gl::Program cacheFill_;
    gl::Texture2D cache_;
    int cacheUnit_ = 0;                // its private texture unit (SkyElement::textureUnit)
    std::vector<double> cacheInputs_;  // what the cache was filled with (exact inputs)
    glm::dvec3 cacheLight_{0.0};       // the light's direction then
    double cacheE_ = 0, cacheSkyE_ = 0;  // the light's and the sky's luminance then, lux
    uint64_t cacheShadowVersion_ = 0;
    int cacheFills_ = 0;
    // The refill spread over frames: rows [backRow_, kCachePsi) of back_ are still to fill with
    // the inputs below (taken when it started); -1: none in progress.
    gl::Texture2D back_;
    int backRow_ = -1, rowsLast_ = 0;
    glm::dvec3 backLight_{0.0};
    double backE_ = 0, backSkyE_ = 0;
    uint64_t backShadowVersion_ = 0;
    glm::dvec3 backEColour_{0.0}, backSkyColour_{0.0};
    glm::dvec3 lastLight_{0.0};  // the light of the last frame drawn through the cache (a jump: kLightJump)
    bool drew_ = false, cached_ = false;
};

}  // namespace welkin::elements
