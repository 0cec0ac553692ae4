// Grid element: the lines' shader runs only on the tiles near the lines (Grid::setTiled, grid.tiled), and the
// image is exactly the fullscreen pass's.
#include <catch2/catch.hpp>

#include "gl_test_context.hpp"

#include <welkin/elements/grid.hpp>
#include <welkin/processor.hpp>

#include <numbers>

using namespace welkin;

TEST_CASE("Grid: the tiles near the lines give the fullscreen pass's image", "[gl][grid]") {
    test::glContext();
    constexpr double kDeg = std::numbers::pi / 180.0;
    struct Case {
        const char* what;
        Projection projection;
        int w, h;
        double azDeg, altDeg, fovDeg;  // cube faces: azDeg is the face
        const char* frame;
        double stepDeg, widthPx;
        double maxShaded;  // largest fraction of the image the tiles may cover (0: not checked)
    };
    // Every projection, both grids and the ecliptic (refracted lines through the equirect seam,
    // round a fisheye's rim, past a perspective frame's edge), near the zenith and at a narrow
    // field on the horizon. The bounds on the shaded fraction: each line marks a band of at most
    // ~2-3 tiles (10 px) across at these widths (measured: 50 % of the 20-deg case with lines
    // 43 px apart, 18 % of the 4-deg field with only the horizon, the markers and the ecliptic;
    // the bounds leave 10 % to the tile rounding), so where the lines are far apart much of the
    // image is left out.
    // At the other cases' sizes the lines lie closer than a band: not checked.
    const Case cases[] = {
        {"perspective, both, ecliptic", Projection::Perspective, 192, 108, 180, 40, 60, "both", 10, 1.5, 0},
        {"perspective, horizontal, 20 deg", Projection::Perspective, 256, 144, 180, 40, 60, "horizontal", 20, 1.5, 0.55},
        {"perspective near the zenith, wide lines", Projection::Perspective, 160, 90, 30, 80, 120, "horizontal", 7, 4, 0},
        {"perspective 4 deg on the horizon", Projection::Perspective, 160, 90, 95, 1, 4, "both", 10, 1.5, 0.3},
        {"fisheye, both, ecliptic", Projection::Fisheye, 128, 128, 0, 0, 0, "both", 10, 1.5, 0},
        {"equirect, both", Projection::Equirect, 180, 90, 0, 0, 0, "both", 15, 1.5, 0},
        {"cube face up, both", Projection::CubeFace, 96, 96, 2, 0, 0, "both", 10, 1.5, 0},
        // Lines just off the face whose width reaches into it (a pinhole face: nothing beyond).
        {"cube face down, equatorial, thin", Projection::CubeFace, 96, 96, 3, 0, 0, "equatorial", 10, 0.5, 0},
    };
    int index = 0;
    for (const Case& c : cases) {
        INFO(c.what);
        // The fullscreen reference by the member (setTiled) in even cases, by the key (grid.tiled,
        // as `welkin bench frame` sets it by name) in odd ones: both must give the same image.
        const bool byKey = index++ % 2 == 1;
        INFO("fullscreen by " << (byKey ? "grid.tiled=false" : "setTiled(false)"));
        Camera cam;
        cam.projection = c.projection;
        cam.width = c.w;
        cam.height = c.h;
        cam.azimuthRad = c.azDeg * kDeg;
        cam.altitudeRad = c.altDeg * kDeg;
        if (c.fovDeg > 0) cam.verticalFovRad = c.fovDeg * kDeg;
        cam.cubeFace = c.projection == Projection::CubeFace ? int(c.azDeg) : 0;
        elements::GridOptions o;
        o.frame = c.frame;
        o.ecliptic = true;
        o.altitudeStepDeg = o.azimuthStepDeg = c.stepDeg;
        o.lineWidthPx = c.widthPx;
        o.luminanceCdM2 = 100.0;
        long long shaded[2] = {0, 0};
        Image img[2];
        for (int tiled = 0; tiled < 2; ++tiled) {
            SkyProcessor p;
            p.setTime(UtcInstant::parse("2026-01-15T22:00:00Z"));
            p.setObserver({35.9 * kDeg, 14.5 * kDeg, 0.0});
            p.setCamera(cam);
            auto grid = std::make_unique<elements::Grid>(o);
            elements::Grid* g = grid.get();
            if (!byKey) g->setTiled(tiled == 1);
            p.add(std::move(grid));
            if (byKey) p.vars().set(elements::gridkeys::tiled, tiled == 1);
            p.renderFrame();
            img[tiled] = p.readHdr();
            shaded[tiled] = g->lastShadedPixels();
        }
        CHECK(shaded[0] == (long long)c.w * c.h);
        INFO("shaded " << shaded[1] << " of " << c.w * c.h);
        CHECK(shaded[1] > 0);
        if (c.maxShaded > 0) CHECK(double(shaded[1]) <= c.maxShaded * c.w * c.h);
        // Exactly the same pixels: the same shader decides each pixel's coverage; the tiles only
        // leave out pixels it gives no coverage. A pixel left out that should have had some would
        // differ here.
        int lit = 0, differ = 0;
        for (int y = 0; y < c.h; ++y)
            for (int x = 0; x < c.w; ++x)
                for (int ch = 0; ch < 3; ++ch) {
                    if (img[0].at(x, y, ch) > 0) ++lit;
                    if (img[0].at(x, y, ch) != img[1].at(x, y, ch)) ++differ;
                }
        CHECK(lit > 100);  // the lines are there to compare
        CHECK(differ == 0);
    }
}
