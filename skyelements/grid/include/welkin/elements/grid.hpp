// Grid: an altitude/azimuth coordinate grid with the horizon emphasised and N/E/S/W markers.
// It is also the worked example of writing an element (docs/writing-an-element.md).
//
//   welkin::elements::GridOptions opt;
//   opt.altitudeStepDeg = 15;                 // circles of equal altitude every 15 deg
//   processor.add(std::make_unique<welkin::elements::Grid>(opt));
//
// Lines are antialiased and drawn with a constant angular width: `lineWidthPx` pixels at the
// centre of the image (projections stretch them elsewhere, e.g. towards a fisheye's rim); opaque (they hide
// what lies behind) and emit `luminanceCdM2` (or, if that is 0, a luminance that the current
// manual exposure renders at 80 % of white, so the grid stays visible at any exposure).
#pragma once
#include <welkin/element.hpp>
#include <welkin/gl/objects.hpp>
#include <welkin/gl/projection_programs.hpp>

namespace welkin::elements {

struct GridOptions {
    double altitudeStepDeg = 10.0;  ///< spacing of altitude circles, degrees, [1, 90]
    double azimuthStepDeg = 10.0;   ///< spacing of azimuth lines, degrees, [1, 180]
    double lineWidthPx = 1.5;       ///< line width, pixels, [0.5, 20]
    double horizonWidthPx = 3.0;    ///< horizon line width, pixels, [0.5, 40]
    double luminanceCdM2 = 0.0;     ///< line luminance, cd/m^2, [0, 1e10]; 0 = follow exposure
    bool markers = true;            ///< draw N, E, S, W at the horizon
    /// Throws welkin::Error naming the member and its range.
    void validate() const;
};

class Grid final : public SkyElement {
public:
    explicit Grid(const GridOptions& options = {});
    const GridOptions& options() const { return options_; }
    /// Changes the options (validated); takes effect next frame.
    void setOptions(const GridOptions& options);

    /// Altitude of the centres of the cardinal markers, radians (they sit just above the horizon).
    static constexpr double kMarkerAltitudeRad = 0.1396263402;  // 8 deg

private:
    void doInit(InitContext& ctx) override;
    void doRender(const FrameContext& ctx) override;
    void doRelease() override;

    GridOptions options_;
    gl::ProjectionPrograms programs_;  // one per camera projection
};

}  // namespace welkin::elements
