// Grid: an altitude/azimuth coordinate grid with the horizon emphasised and N/E/S/W markers,
// and/or an equatorial (right ascension / declination, J2000) grid (grid.frame).
// It is also the worked example of writing an element (docs/writing-an-element.md).
//
//   welkin::elements::GridOptions opt;
//   opt.altitudeStepDeg = 15;                 // circles of equal altitude every 15 deg
//   processor.add(std::make_unique<welkin::elements::Grid>(opt));
//   processor.vars().set(welkin::elements::gridkeys::azimuthStep, 0.5);   // later: any option, rad
//   // command line: welkin render --elements sky,grid --var grid.altitude_step_rad=15deg
//   //               welkin render --elements grid --var grid.frame=both --var grid.ra_step_rad=30deg
//               welkin render --elements grid --var grid.ecliptic=true      // + the ecliptic
//
// Options are keys (gridkeys below): GridOptions gives their values when the element is added.
// Lines are antialiased and drawn with a constant angular width: `lineWidthPx` pixels at the
// centre of the image (projections stretch them elsewhere, e.g. towards a fisheye's rim); opaque (they hide
// what lies behind) and emit `luminanceCdM2` (or, if that is 0, a luminance that the current
// manual exposure renders at 80 % of white, so the grid stays visible at any exposure).
// The equatorial grid (grid.frame equatorial or both) draws circles of equal declination every
// grid.dec_step_rad and hour circles every grid.ra_step_rad (15 deg = 1 h) in the ICRS/J2000
// frame of the star catalogues, placed by the astronomy's stars.frame_icrs_to_enu rotation (so its
// lines pass through the stars' J2000 coordinates; the pole of date is ~0.36 deg from the J2000
// pole in 2026) and lifted by the same refraction as the stars (astro::refraction at the
// astronomy's pressure and temperature). Hour circles stop at the last declination circle before
// each pole. Without the astronomy (no stars.frame_icrs_to_enu) ICRS is taken as ENU.
// The ecliptic (grid.ecliptic) is the great circle of the J2000 mean ecliptic, pole at ICRS
// (0, -sin e, cos e), e = 23 deg 26' 21.406" (IAU 2006), placed and refracted like the equatorial
// lines, golden, 1.5 x their width and twice their luminance. The ecliptic of date is within 50" of it for
// 1900-2100 (it tilts by ~47" a century): the Sun's apparent place (ecliptic latitude < 1") lies on
// the drawn line to well under a pixel at any ordinary field of view.
// Cost: the lines' shader runs only on the 4x4-pixel tiles the lines can reach, traced on the CPU
// each frame (skyelements/constellations/README.md, "Grid: cost in proportion to its lines"); the image is the
// same as a fullscreen pass's (setTiled(false)).
#pragma once
#include <welkin/element.hpp>
#include <welkin/gl/objects.hpp>
#include <welkin/gl/projection_programs.hpp>

#include <string>
#include <vector>

namespace welkin::elements {

namespace gridkeys {
inline constexpr double kDeg = 0.017453292519943295;
inline const Key<double> altitudeStep{"grid.altitude_step_rad", Range{1 * kDeg, 90 * kDeg}, "spacing of altitude circles"};
inline const Key<double> azimuthStep{"grid.azimuth_step_rad", Range{1 * kDeg, 180 * kDeg}, "spacing of azimuth lines"};
inline const Key<double> lineWidth{"grid.line_width_px", Range{0.5, 20}, "line width at the image centre", "px"};
inline const Key<double> horizonWidth{"grid.horizon_width_px", Range{0.5, 40}, "horizon line width", "px"};
inline const Key<double> luminance{"grid.luminance_cd_m2", Range{0, 1e10}, "line luminance; 0 = 80 % of white at the manual exposure"};
inline const Key<bool> markers{"grid.markers", "draw N, E, S, W at the horizon"};
inline const Key<std::string> frame{"grid.frame", Choices{{"horizontal", "equatorial", "both"}}, "which grid: horizontal (altitude/azimuth), equatorial (RA/Dec, J2000) or both"};
inline const Key<double> raStep{"grid.ra_step_rad", Range{1 * kDeg, 180 * kDeg}, "spacing of hour circles (equatorial; 15 deg = 1 h)"};
inline const Key<double> decStep{"grid.dec_step_rad", Range{1 * kDeg, 90 * kDeg}, "spacing of declination circles (equatorial)"};
/// The ecliptic (J2000 mean ecliptic, obliquity 23 deg 26' 21.406"), in any grid.frame.
inline const Key<bool> tiled{"grid.tiled", "the lines' shader runs only on the tiles near the lines (false: on every pixel, a fullscreen pass; the same image, its cost before 2026-11-26)"};
inline const Key<bool> ecliptic{"grid.ecliptic", "draw the ecliptic (J2000), the Sun's yearly path, where the planets wander"};
}  // namespace gridkeys

struct GridOptions {
    double altitudeStepDeg = 10.0;  ///< spacing of altitude circles, degrees, [1, 90]
    double azimuthStepDeg = 10.0;   ///< spacing of azimuth lines, degrees, [1, 180]
    double lineWidthPx = 1.5;       ///< line width, pixels, [0.5, 20]
    double horizonWidthPx = 3.0;    ///< horizon line width, pixels, [0.5, 40]
    double luminanceCdM2 = 0.0;     ///< line luminance, cd/m^2, [0, 1e10]; 0 = follow exposure
    bool markers = true;            ///< draw N, E, S, W at the horizon
    std::string frame = "horizontal";  ///< "horizontal", "equatorial" or "both"
    double raStepDeg = 15.0;        ///< spacing of hour circles, degrees, [1, 180] (15 = 1 h)
    double decStepDeg = 10.0;       ///< spacing of declination circles, degrees, [1, 90]
    bool ecliptic = false;          ///< draw the ecliptic (J2000) as a line of its own colour
    /// Throws welkin::Error naming the member and its range.
    void validate() const;
};

class Grid final : public SkyElement {
public:
    /// The option keys with GridOptions{}'s defaults (values already in the SkyVars are kept).
    Grid();
    /// The option keys set to `options` (validated) when the element is added.
    explicit Grid(const GridOptions& options);

    /// Altitude of the centres of the cardinal markers, radians (they sit just above the horizon).
    static constexpr double kMarkerAltitudeRad = 0.1396263402;  // 8 deg

    /// true (the default): the lines' shader runs only on the 4x4-pixel tiles that the lines, their
    /// antialiasing and the markers can reach (cost in proportion to the lines' pixels); false:
    /// on every pixel, as a fullscreen pass (the reference the tests compare the tiles with; the
    /// image is the same). The key grid.tiled (default true) does the same by name; the lines are
    /// tiled when both are true.
    void setTiled(bool tiled) { tiled_ = tiled; }
    /// Pixels the lines' shader ran on in the last render() (the image's size when not tiled).
    long long lastShadedPixels() const { return shadedPixels_; }

private:
    Grid(const GridOptions& options, bool force);
    void doInit(InitContext& ctx) override;
    void doRender(const FrameContext& ctx) override;
    void doRelease() override;
    void drawRuns(const std::vector<float>& rects);  // rects: x0, y0, x1, y1 per run (pixels); vao_ bound
    void doValidateOptions(const SkyVars& vars) const override;

    gl::ProjectionPrograms programs_;  // one per camera projection
    gl::VertexArray vao_;              // one vec4 per instance: a run of tiles near the lines (pixels)
    gl::Buffer buffer_;                // the runs of this frame (grows as needed)
    bool tiled_ = true;
    long long shadedPixels_ = 0;
};

}  // namespace welkin::elements
