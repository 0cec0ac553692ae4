// Night sky: the diffuse light of a moonless night behind the stars: the Milky Way (the
// stellarium-data panorama, calibrated in cd/m^2), airglow, zodiacal light and light pollution
// (Bortle class), which also hides faint stars.
//
//   processor.add(welkin::elements::makeElement("nightsky"));   // Background, before the stars
//   processor.add(welkin::elements::makeElement("stars"));      // reads nightsky.background_cd_m2
//   processor.add(welkin::elements::makeElement("sky"));        // its transmittance dims them all
//   processor.vars().set(welkin::elements::nightkeys::bortle, 7);          // a suburban sky
//   // command line: welkin render --var nightsky.bortle=9 --var nightsky.airglow_zenith_mag_arcsec2=21.5
//
// Model (skyelements/nightsky/README.md has the sources, the numbers and the measured cost). Every term is a
// luminance in cd/m^2 (linear sRGB whose Y is the luminance) above the air, then attenuated once:
// by the Sky composited later (FrameContext::attenuatedLater), or here by the atmosphere's
// transmittance towards each altitude when nothing attenuates it later.
//  - Surface brightness m (V mag/arcsec^2) -> luminance: L = E0 / (1 arcsec^2 in sr) x 10^(-0.4 m)
//    = 1.0807e5 cd/m^2 x 10^(-0.4 m), E0 = 2.54e-6 lx the illuminance of V = 0
//    (astro::magnitude::illuminanceLux): surfaceBrightnessCdM2().
//  - Milky Way: the panorama /usr/share/stellarium/textures/milkyway.png is in J2000 equatorial
//    coordinates (not galactic): column u = frac((90 deg - RA) / 360 deg), row from the top
//    v = (90 deg - Dec) / 180 deg (milkyWayTexCoord()). sRGB -> linear, luminance Y; calibrated
//    L = k Y^0.5 + L_floor (the exponent a judgement: the panorama is contrast-stretched), L(mean over the Large Sagittarius Star Cloud) = 20.5 mag/arcsec^2 and
//    L_floor = 23.0 mag/arcsec^2 (the diffuse galactic light and faint starlight at the galactic
//    poles, where the texture is black). ENU -> ICRS by the transpose of stars.frame_icrs_to_enu.
//  - Airglow: a thin emitting shell at nightsky.airglow_height_m (90 km); zenith brightness
//    nightsky.airglow_zenith_mag_arcsec2 (22.38 = 145 S10, the airglow share of the dark-sky budget
//    of Leinert et al. 1998, solar minimum), times van Rhijn's factor
//    1 / sqrt(1 - (R / (R + h))^2 sin^2 z) (vanRhijn()); greenish (OI 557.7 nm and a continuum).
//  - Zodiacal light: Leinert et al. 1998 Table 17 (1e-8 W m^-2 sr^-1 um^-1 at 500 nm) over
//    (|ecliptic longitude - the Sun's|, |ecliptic latitude|), bilinear; J2000 ecliptic
//    (obliquity 23.4392911 deg); the Sun's colour (zodiacalTable(), zodiacalUnitCdM2()); baked on
//    the CPU into a 256 x 128 texture over the panorama's mapping when the Sun's longitude moves.
//  - Light pollution: nightsky.bortle 1..9 sets the total zenith brightness of the class
//    (bortleZenithMag()); the artificial part is that minus the dark-sky reference
//    kDarkSkyZenithMag, brighter towards the horizon by van Rhijn's factor for an 8 km layer
//    (the air's scale height), in the colour of a 3000 K black body (sodium and warm LEDs).
//  - Cost: by default the panorama is looked up per pixel (an atan and an acos). With
//    setDirectLookup(false) the terms fixed to the stars are read from cube maps over ICRS directions (RGBA16F),
//    built on the GPU from the panorama and the baked zodiacal texture: the Milky Way and its
//    floor (kNightCubeSize texels a face, mipmapped) once and when its keys change, the
//    zodiacal light (kNightZodiCubeSize, smooth) when the Sun's ecliptic longitude moved
//    > 0.1 deg (nightCubeStale()). Per pixel: a 3x3 rotation ENU -> ICRS, two cube fetches, two
//    van Rhijn factors, no inverse trigonometry. The per-pixel panorama lookup (an atan and an
//    acos) is the reference the tests compare the cubes with. Measured on llvmpipe (2 cores) the
//    cube path cost 8.8x a trivial pass against the direct lookup's 8.2x, and adds a 64 MB cube
//    and its build to the first frame, so the direct lookup is the default.
//  - Cost: the pass is skipped when a Sky's zenith luminance exceeds 1e5 x the night sky's (its
//    pixels would change by < 1e-5 relative).
//  - Cost: in displayed frames (render.interactive) the pass is also skipped where the previous
//    frame's exposure (keys::exposurePrevious) cannot show it: eye::displaySlopeBound() x exposure
//    x 2 x radianceBound() under half an 8-bit code (twilight; nightsky.skip_invisible, README).
//  - Cost: in displayed frames (render.interactive) the pass's image, drawn first over the
//    processor's black target, is kept (one target-size RGBA32F texture) and copied back with
//    glCopyImageSubData in later frames whose inputs are the same byte for byte (camera, keys,
//    uniforms, program variant, the folded panorama's version) and whose sky rotation moved no
//    screen direction by nightsky.reuse_tolerance_px (0.05 px: at 1280x720 and 60 deg a redraw
//    every ~0.46 s of real time); nightsky.reuse false turns it off (README "Reusing the image").
//  - Published: nightsky.background_cd_m2, the zenith luminance of all four terms; Stars adds it
//    to the Sky's zenith luminance for its limiting magnitude (instead of its own floor).
#pragma once
#include <welkin/astro/bodies.hpp>
#include <welkin/element.hpp>
#include <welkin/keys.hpp>
#include <welkin/gl/objects.hpp>
#include <welkin/gl/projection_programs.hpp>

#include <glm/glm.hpp>

#include <cmath>
#include <optional>
#include <string>
#include <vector>

namespace welkin::elements {

namespace nightkeys {
/// The dark-sky reference, V mag/arcsec^2 at the zenith (astro::magnitude::kDarkSkyZenithMag: the
/// natural night sky of a dark site at solar minimum, Leinert et al. 1998: ~220 S10 = 21.9; Benn &
/// Ellison 1998, La Palma: 21.9): Stars' default background floor and Bortle class 1.
inline constexpr double kDarkSkyZenithMag = astro::magnitude::kDarkSkyZenithMag;
inline const Key<std::string> milkyWayTexture{"nightsky.milky_way_texture", "Milky Way panorama (stellarium-data milkyway.png, J2000 equirectangular); missing: the Milky Way is only its uniform floor"};
inline const Key<double> milkyWayScale{"nightsky.milky_way_scale", Range{0, 100}, "factor on the calibrated Milky Way (0 off)", "1"};
inline const Key<double> airglowZenithMag{"nightsky.airglow_zenith_mag_arcsec2", Range{14, 30}, "airglow surface brightness at the zenith, V (22.4 solar minimum, ~21.7 maximum)", "mag/arcsec2"};
inline const Key<double> airglowHeight{"nightsky.airglow_height_m", Range{1e4, 5e5}, "height of the airglow's emitting layer (van Rhijn's factor)"};
inline const Key<double> zodiacalScale{"nightsky.zodiacal_scale", Range{0, 100}, "factor on the zodiacal light of Leinert 1998 Table 17 (0 off)", "1"};
inline const Key<int> bortle{"nightsky.bortle", Range{1, 9}, "light pollution, Bortle class (1 a pristine sky, 9 an inner city)"};
/// Skip the pass where the previous frame's exposure cannot show it (keys::exposurePrevious; README
/// "Twilight: the pass skipped where it cannot show"); false: drawn whenever the Sky's zenith allows.
inline const Key<bool> skipInvisible{"nightsky.skip_invisible", "skip the pass where the previous frame's exposure shows none of it (under half an 8-bit code at every pixel)"};
/// Reuse the pass's image in displayed frames (render.interactive) whose inputs did not change
/// enough to change it (README "Reusing the image"): the first pass over the processor's black
/// target keeps its HDR output in a texture of the target's size and format (one more target:
/// 14.7 MB at 1280x720, 33 MB at 1920x1080), copied back (glCopyImageSubData) in place of the draw.
inline const Key<bool> reuse{"nightsky.reuse", "reuse the pass's kept image in displayed frames (render.interactive) while its inputs are unchanged and the sky turned by less than nightsky.reuse_tolerance_px"};
/// How far the sky's rotation (time) may have moved any screen direction since the kept image,
/// pixels, for the image to be reused; 0: only when the rotation is identical. Other inputs
/// (camera, keys, exposure skip, the folded panorama's version) must be identical.
inline const Key<double> reuseTolerancePx{"nightsky.reuse_tolerance_px", Range{0, 2}, "the sky's rotation since the kept image, in pixels at the screen's largest scale, under which the kept image is reused (0: identical rotation only)", "px"};
/// Written by the element every frame (not an option): the engine's shared key.
inline const Key<double>& background = welkin::keys::nightBackground;
}  // namespace nightkeys

/// V surface brightness <-> luminance: the engine's (astro::magnitude, welkin/astro/bodies.hpp).
using astro::magnitude::surfaceBrightnessCdM2;
using astro::magnitude::surfaceBrightnessMag;
/// Van Rhijn's factor: brightness of a thin emitting shell at height h (m, > 0) seen at zenith
/// angle z (rad, [0, pi/2]) over its zenith brightness, Earth radius 6371 km.
double vanRhijn(double zenithAngleRad, double layerHeightM);
/// Total zenith brightness of a Bortle class (1..9), V mag/arcsec^2 (the table in skyelements/nightsky/README.md).
double bortleZenithMag(int bortleClass);
/// Zodiacal light, Leinert et al. 1998 Table 17 (bilinear), in 1e-8 W m^-2 sr^-1 um^-1 at 500 nm:
/// `dLambdaRad` the ecliptic longitude from the Sun (any value; folded to [0, pi]), `betaRad` the
/// ecliptic latitude ([-pi/2, pi/2]). Cells the paper leaves empty (within 15 deg of the Sun)
/// take the nearest tabulated latitude.
double zodiacalTable(double dLambdaRad, double betaRad);
/// Luminance (cd/m^2) of one Table 17 unit of sunlight-coloured light (from the ASTM G-173 solar
/// spectrum: 683 lm/W x integral S(l) y(l) dl / S(500 nm) x 1e-8 W m^-2 sr^-1 um^-1).
double zodiacalUnitCdM2();
/// The largest value of zodiacalTable() (Table 17 units) at any direction whose angle from the Sun
/// is at least `minElongationRad` (<= 0: the whole sky): the largest corner of every bilinear cell
/// that reaches that elongation (cos elongation = cos dLambda cos beta; a bilinear cell's largest
/// value is at a corner).
double zodiacalMaxBeyond(double minElongationRad);
/// ICRS (J2000) -> galactic rotation (IAU 1958 system in ICRS axes: Hipparcos Catalogue, ESA 1997,
/// vol. 1, sect. 1.5.3, eq. 1.5.11). Rows are the galactic x (to the centre), y (l = 90), z (NGP).
glm::dmat3 icrsToGalactic();
/// ICRS -> J2000 ecliptic (rotation by the obliquity 23.4392911 deg about x).
glm::dmat3 icrsToEcliptic();
/// Texture coordinate in the Milky Way panorama (u right, v down from the top row, [0, 1)) of an
/// ICRS unit direction.
glm::dvec2 milkyWayTexCoord(const glm::dvec3& icrs);

/// Face size of the night sky's Milky Way cube map, texels: the panorama's 2048 columns are 326
/// texels per radian, a face's centre N / 2 = 512 (a face spans 2 units of tangent over 90 deg),
/// its corners 3x more: the cube oversamples the panorama everywhere (64 MB with its mips).
/// The folded texture's rebuild budget, texels per frame (NightSky::setFoldBudget): 2048 x 64,
/// 1/16 of the panorama's level 0, so a rebuild of its 2.8 M texels over all levels takes 23
/// frames (under a second at 30 fps; at 1440x the Sun moves 0.1 deg in 6 s).
inline constexpr int kNightFoldTexelsPerFrame = 2048 * 64;
inline constexpr int kNightCubeSize = 1024;
/// Face size of the zodiacal light's cube map: 1.4 deg texels at a face's centre, as the baked
/// 256 x 128 texture it is resampled from (Table 17's grid is 5-15 deg).
inline constexpr int kNightZodiCubeSize = 64;
/// The zodiacal cube is rebuilt when the Sun's ecliptic longitude moved more than this (rad):
/// 0.1 deg, 2.4 h of the Sun's motion; 0.07 of a texel of the baked zodiacal light (1.4 deg) and
/// 1/50 of Table 17's finest step (5 deg), where the table changes by < 1 % (its steepest:
/// 11500 -> 6400 over 5 deg at 15 deg from the Sun, i.e. 0.1 deg moves it 1 %; 0.1 % at 90 deg).
/// Nothing else of time or place enters the cubes: the Earth's rotation, the observer's place and
/// precession are the per-pixel rotation stars.frame_icrs_to_enu.
inline constexpr double kNightCubeSunToleranceRad = 0.1 * 3.14159265358979323846 / 180.0;
/// What the night sky's cube maps were built for.
struct NightCubeInputs {
    double sunEclipticLongitudeRad = std::nan("");  ///< the Sun's J2000 ecliptic longitude; NaN: never built
    double milkyWayScale = std::nan("");            ///< nightsky.milky_way_scale; NaN: never built
    double zodiacalScale = 0;                       ///< nightsky.zodiacal_scale
    std::string milkyWayPath;                       ///< the panorama's file ("" or missing: only the floor)
    bool milkyWayLoaded = false;
};
/// Which cube a change of inputs makes stale.
struct NightCubeStale {
    bool milkyWay = false;  ///< never built, or the Milky Way's scale or panorama changed at all
    bool zodiacal = false;  ///< never built, the Sun's ecliptic longitude moved more than
                            ///< kNightCubeSunToleranceRad (either way, across +-pi too), or its scale changed
};
NightCubeStale nightCubeStale(const NightCubeInputs& built, const NightCubeInputs& now);

class NightSky final : public SkyElement {
public:
    NightSky();

    /// true (default): the per-pixel panorama lookup (an atan and an acos per pixel, the reference
    /// the cube map is checked against); false: the ICRS cube maps. Call before init().
    void setDirectLookup(bool direct) { direct_ = direct; }
    bool directLookup() const { return direct_; }
    /// true (default): the frame's cheaper programs where they give the same pixels: a pinhole
    /// camera whose pixels are all smaller than the panorama's texels (the level of detail is
    /// then 0 everywhere) uses a program with the level fixed at 0, and the first pass over the
    /// processor's black target (FrameContext::nothingBehind) writes without blending. false: the
    /// general program and the blend always (the reference the tests compare with).
    void setFastPaths(bool fast) { fast_ = fast; }
    /// Whether the last frame's pass fixed the level of detail at 0, and wrote without blending.
    bool lastLevelFixed() const { return lastLevelFixed_; }
    bool lastUnblended() const { return lastUnblended_; }
    /// How many times the Milky Way's cube (6 faces and the mips) and the zodiacal light's were
    /// built since init.
    int cubeBuilds() const { return cubeBuilds_; }
    int zodiCubeBuilds() const { return zodiCubeBuilds_; }

    /// The per-pixel path samples one folded texture (README "Cost", 2026-11-27): the panorama's
    /// Milky Way with its floor and the zodiacal light summed over its J2000 equirectangular
    /// mapping and mips, cd/m^2 x 1e4, RGBA32F. It is rebuilt when the Sun's ecliptic longitude
    /// moved 0.1 deg. With render.interactive (welkin view, a game loop) the rebuild goes into a
    /// second texture, at most `texels` texels of it a frame (whole rows of a level; the
    /// zodiacal table's CPU bake takes a frame of its own), while the old one is drawn; the new
    /// one is drawn from the frame after its last row. Without it (welkin render, a timelapse:
    /// every frame complete), or with 0, the whole rebuild in the frame that needs it. The first build and a change of the Milky Way's or the zodiacal
    /// light's scale or panorama are always whole. Default kNightFoldTexelsPerFrame.
    void setFoldBudget(int texels) { foldBudget_ = texels < 0 ? 0 : texels; }
    /// Completed rebuilds of the folded texture since init (the first build counts); a rebuild
    /// in progress (spread over frames); the Sun's ecliptic longitude (rad) the displayed one is
    /// for, NaN before the first frame.
    int foldBuilds() const { return foldBuilds_; }
    bool foldInProgress() const { return foldStage_ >= 0; }
    double foldedSunLongitude() const { return foldLon_[foldFront_]; }
    /// The displayed folded texture's level (RGBA floats, bottom row first as GL stores them,
    /// which is the panorama's top row: its t = 0), and the panorama's own (the calibrated
    /// Milky Way x 1e4 before the floor and scale), for the tests. Need the element's context.
    std::vector<float> readFolded(int level) const { return fold_[foldFront_].readRgbaFloat(level); }
    std::vector<float> readPanorama(int level) const { return mwTexture_.readRgbaFloat(level); }
    /// The baked zodiacal table the displayed folded texture was built from (Table 17 units,
    /// 256 x 128, row 0 the panorama's top), its size, and the terms' scales (x 1e4) the fold
    /// applied: zodiacal colour x unit x scale, and the floor per channel.
    const std::vector<float>& foldedZodiacalTable() const { return zodiBaked_[foldFront_]; }
    static constexpr int zodiacalTableWidth() { return 256; }
    static constexpr int zodiacalTableHeight() { return 128; }
    glm::vec3 foldZodiacalFactor() const { return foldZodi_; }
    glm::vec3 foldFloor() const { return foldFloor_; }
    float foldMilkyWayScale() const { return foldMwScale_; }

    /// Image reuse (nightsky.reuse, README "Reusing the image"): whether the last frame copied
    /// the kept image instead of drawing; frames that copied, frames whose drawn image was kept
    /// (since init); the kept texture's bytes (0 when none is held).
    bool lastReused() const { return lastReused_; }
    int reuseHits() const { return reuseHits_; }
    int reuseKeeps() const { return reuseKeeps_; }
    size_t reuseBytes() const;
    /// The angle (rad) by which the rotation `a` -> `b` (ICRS -> ENU) moves a direction at most,
    /// and the most pixels one radian moves a direction anywhere in the camera's image (a pinhole:
    /// at a corner; a fisheye: along the horizon; +inf where unbounded: equirect, cube faces).
    static double rotationAngle(const glm::dmat3& a, const glm::dmat3& b);
    static double maxPixelsPerRadian(const Camera& camera);

    /// The Milky Way panorama was found and loaded (after init).
    bool milkyWayLoaded() const { return mwLoaded_; }
    /// The calibration: cd/m^2 = gain x Y^0.5 + floor (Y the texture's linear luminance).
    double milkyWayGain() const { return mwGain_; }
    double milkyWayFloorCdM2() const;
    /// Zenith luminance of each term above the air in the last update, cd/m^2.
    struct Zenith { double airglow = 0, zodiacal = 0, milkyWay = 0, lightPollution = 0; };
    const Zenith& zenith() const { return zenith_; }
    /// The last frame drew the pass (false when a Sky's zenith is over 1e5 x brighter: daylight).
    bool drawn() const { return drawn_; }
    /// The last frame skipped the pass because the previous frame's exposure could not show it
    /// (nightsky.skip_invisible), and that bound: the largest change the pass could have made to a
    /// displayed pixel, in 8-bit codes (0 when unknown: no exposure published).
    bool lastSkippedInvisible() const { return skippedInvisible_; }
    double lastInvisibleBoundCodes() const { return invisibleBoundCodes_; }
    /// An upper bound of the pass's radiance (cd/m^2, any channel, before the air's transmittance)
    /// over the directions within `coneHalfAngleRad` of `axisEnu` (>= pi: the whole sky), from the
    /// last update's terms: airglow and light pollution at the horizon (van Rhijn's largest), the
    /// brightest panorama texel plus the floor, and the zodiacal light beyond the cone's smallest
    /// elongation from the Sun (less 3 deg: the folded texture's zodiacal texels, refraction, its lag).
    double radianceBound(const glm::dvec3& axisEnu, double coneHalfAngleRad, const SkyVars& vars) const;

private:
    void doInit(InitContext& ctx) override;
    void doUpdate(const FrameContext& ctx) override;
    void doRender(const FrameContext& ctx) override;
    void doRelease() override;
    void doStats(nlohmann::json& root) const override;
    void loadMilkyWay(const std::string& path, const Logger& log);
    void updateExtinction(const SkyVars& v);
    void bakeZodiacal(double sunEclipticLongitudeRad);
    NightCubeInputs cubeInputs(const SkyVars& v) const;
    void buildCube(const FrameContext& ctx, const NightCubeInputs& in, bool zodiacal);
    void uploadZodiacal(const std::vector<float>& table);
    void foldUpdate(const FrameContext& ctx);
    void foldAllocate(int slot);
    static constexpr long kFoldWhole = 1L << 40;  // a budget no texture reaches
    bool foldStep(const FrameContext& ctx, long budget);  // true when the back texture is complete

    // [extinction][level fixed]: [1][.] with the element's own extinction (NIGHT_EXTINCTION),
    // [.][1] with the level of detail fixed at 0 (NIGHT_LOD0, pinhole cameras only).
    gl::ProjectionPrograms programs_[2][2];
    bool fast_ = true, lastLevelFixed_ = false, lastUnblended_ = false;
    bool direct_ = true;  // the per-pixel lookup by default: on llvmpipe the cubes measured no cheaper (skyelements/nightsky/README.md)
    gl::Program cubeProgram_;
    gl::TextureCube cube_, zodiCube_;
    gl::Framebuffer cubeFbo_;
    NightCubeInputs cubeBuiltFor_;
    int cubeBuilds_ = 0, zodiCubeBuilds_ = 0;
    double cubeBuildMs_ = 0, zodiCubeBuildMs_ = 0;  // CPU wall time of the last builds (no glFinish), ms
    gl::Texture2D mwTexture_;
    gl::Texture2D zodiTexture_;  // Table 17 units over the panorama's mapping
    // The folded texture (setFoldBudget): [foldFront_] drawn, the other built. foldStage_: -1 no
    // rebuild in progress, 0 the zodiacal table to bake for foldTargetLon_, 1 + the rows drawn
    // so far (foldLevel_, foldRow_).
    gl::Texture2D fold_[2];
    gl::Framebuffer foldFbo_;
    gl::Program foldProgram_;
    int foldFront_ = 0, foldStage_ = -1, foldLevel_ = 0, foldRow_ = 0, foldBuilds_ = 0;
    long foldBudget_ = kNightFoldTexelsPerFrame;
    double foldLon_[2] = {std::nan(""), std::nan("")};
    double foldTargetLon_ = std::nan("");
    double sunLon_ = std::nan("");
    std::vector<float> zodiBaked_[2];  // the baked table of each folded texture
    NightCubeInputs foldInputs_;  // the keys the front texture was built with (whole rebuild on change)
    glm::vec3 foldZodi_{0.f}, foldFloor_{0.f};
    float foldMwScale_ = 0.f;
    int milkyWayUnit_ = 0, zodiacalUnit_ = 0;  // private texture units (SkyElement::textureUnit)
    double zodiLon_ = std::nan("");  // the Sun's ecliptic longitude it was baked for, rad
    std::string mwPath_;
    bool mwLoaded_ = false;
    double mwGain_ = 0;
    std::vector<float> mwCpu_;  // calibrated luminance (before the floor), CPU twin of the texture
    int mwW_ = 0, mwH_ = 0;
    glm::dvec3 mwColour_{1.0};  // mean colour of the panorama, luminance 1 (the floor's colour)
    std::vector<float> extinction_;
    const void* extinctionAtm_ = nullptr;
    double extinctionHeight_ = -1;
    Zenith zenith_;
    bool drawn_ = false;
    glm::dvec3 mwMax_{0.0};  // the brightest panorama texel per channel, cd/m^2 (before the floor and scale)
    bool skippedInvisible_ = false;
    double invisibleBoundCodes_ = 0.0;
    // Image reuse: the inputs (every uniform, texture and camera value the pass reads, as bytes,
    // and the sky's rotation) of the kept image and of the last frame's pass.
    struct ReuseInputs {
        std::vector<unsigned char> bytes;
        glm::dmat3 rotation{1.0};
        bool valid = false;
    };
    ReuseInputs kept_, last_;
    gl::Texture2D keptImage_;
    bool lastReused_ = false;
    int reuseHits_ = 0, reuseKeeps_ = 0;
    void reuseForget();
};

}  // namespace welkin::elements
