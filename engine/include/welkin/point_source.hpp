// Point sources as people see them: the eye's detection threshold for a star or an unresolved
// planet against the sky behind it, and the size and contrast a displayed image gives a point
// that the eye would see (docs/eye.md, "Point sources"; the Stars and Planet elements draw it).
//
//   processor.vars().set(welkin::keys::pointSources, std::string("perceptual"));   // displayed images
//   double lux = welkin::pointThresholdLux(30.0);            // civil twilight sky: ~1e-6 lx (mag ~1)
//   welkin::PerceptualPoint p = welkin::perceptualPoint(1.5e-4, 30.0);   // Venus, -4.4 mag
//   // p.visible, p.ratio (E over the threshold), p.fwhmPx, p.contrast (Weber, over the sky)
//
// Model:
//  - Threshold: Schaefer (1990, PASP 102, 212; after Hecht 1947) I = C1 (1 + sqrt(C2 B))^2 foot-
//    candles for a background B in nanolamberts, night (scotopic) branch below 1479 nL
//    (C1 = 10^-9.8, C2 = 10^-1.9), day above (10^-8.35, 10^-5.9). The Stars' limiting magnitude is
//    the magnitude of this illuminance (m = -16.57 - 2.5 log10 I).
//  - render.point_sources = physical (the library's default): a point keeps its flux, spread over
//    its PSF (right for HDR/EXR output; in a wide field a bright planet is a faint bump on one
//    pixel of a twilight sky). perceptual: a point whose illuminance at the eye E (after the
//    atmosphere's extinction) is under the threshold I(B) for the sky luminance B behind it is not
//    drawn; one above it is drawn (besides its physical PSF, whichever is brighter per pixel) as a
//    Gaussian of FWHM f0 (1 + 0.5 log10 R), at most 8 f0, whose peak is the sky plus the Weber
//    contrast C = render.point_contrast (1 + 2 log10 R), R = E / I(B) >= 1: a just-visible star is a
//    faint small dot, Venus in twilight a bright larger one, as planetarium programs draw them.
#pragma once
#include <welkin/vars.hpp>

#include <string>
#include <string_view>

namespace welkin {

namespace keys {
/// physical | perceptual (see above); the engine declares it (default physical).
inline const Key<std::string> pointSources{"render.point_sources", Choices{{"physical", "perceptual"}},
                                           "stars and unresolved planets: physical (flux per pixel, HDR/EXR output) or perceptual (drawn size "
                                           "and contrast from the eye's point-source threshold over the local sky, displayed images)"};
/// Weber contrast over the sky behind it of a point at the eye's threshold (perceptual mode).
inline const Key<double> pointContrast{"render.point_contrast", Range{0.05, 100},
                                       "perceptual point sources: Weber contrast over the sky of a point at the eye's threshold (grows "
                                       "by twice this per decade above it)",
                                       "1"};
}  // namespace keys

enum class PointSourceMode { Physical, Perceptual };

/// "physical" or "perceptual"; anything else throws welkin::Error naming the key and the values.
PointSourceMode parsePointSourceMode(std::string_view text);
/// The mode the keys ask for (render.point_sources; physical when the key is not declared).
PointSourceMode pointSourceMode(const SkyVars& vars);
/// Declares render.point_sources (physical) and render.point_contrast (0.5); the processor does.
void declarePointSourceKeys(SkyVars& vars);

/// Schaefer's (1990) point-source threshold in foot-candles for a background luminance (cd/m^2,
/// >= 0; throws otherwise).
double pointThresholdFootCandles(double backgroundCdM2);
/// The same in lux (1 ft-cd = 10.7639 lx).
double pointThresholdLux(double backgroundCdM2);

/// How the perceptual mode draws one point (the CPU twin of the shaders).
struct PerceptualPoint {
    bool visible = false;  ///< E >= the threshold
    double ratio = 0;      ///< E / threshold
    double fwhmPx = 0;     ///< drawn FWHM, px (0 when not visible)
    double contrast = 0;   ///< Weber contrast of its peak over the background (0 when not visible)
};
/// For an illuminance at the eye (lux, after extinction, >= 0) against a background (cd/m^2),
/// with contrast c0 at the threshold (render.point_contrast) and FWHM f0 there (px).
PerceptualPoint perceptualPoint(double illuminanceLux, double backgroundCdM2, double contrastAtThreshold = 0.5,
                                double fwhmAtThresholdPx = 2.0);

}  // namespace welkin
