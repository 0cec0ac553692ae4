// Point sources as people see them: the threshold and the perceptual size and contrast
// (welkin/point_source.hpp; shaders: generators/atmosphere/shaders/point_perceptual.glsl).
#include <welkin/error.hpp>
#include <welkin/point_source.hpp>

#include <algorithm>
#include <cmath>

namespace welkin {

PointSourceMode parsePointSourceMode(std::string_view text) {
    if (text == "physical") return PointSourceMode::Physical;
    if (text == "perceptual") return PointSourceMode::Perceptual;
    throw Error("render.point_sources '" + std::string(text) + "' unknown (accepted: physical, perceptual)");
}

PointSourceMode pointSourceMode(const SkyVars& vars) {
    return vars.has(keys::pointSources) ? parsePointSourceMode(vars.get(keys::pointSources)) : PointSourceMode::Physical;
}

void declarePointSourceKeys(SkyVars& vars) {
    vars.declare(keys::pointSources, std::string("physical"));
    vars.declare(keys::pointContrast, 0.5);
}

double pointThresholdFootCandles(double backgroundCdM2) {
    if (!(backgroundCdM2 >= 0.0)) throw Error("pointThresholdFootCandles(): background luminance not >= 0 cd/m^2");
    const double B = backgroundCdM2 / 3.183098862e-6;  // nanolamberts (1 nL = 1e-5 / pi cd/m^2)
    // Schaefer 1990 (Hecht 1947): night (scotopic) branch below 1479 nL, day above.
    const bool night = B < 1479.0;
    const double c1 = night ? std::pow(10.0, -9.8) : std::pow(10.0, -8.35);
    const double c2 = night ? std::pow(10.0, -1.9) : std::pow(10.0, -5.9);
    const double s = 1.0 + std::sqrt(c2 * B);
    return c1 * s * s;
}

double pointThresholdLux(double backgroundCdM2) { return pointThresholdFootCandles(backgroundCdM2) * 10.76391; }

PerceptualPoint perceptualPoint(double illuminanceLux, double backgroundCdM2, double contrastAtThreshold, double fwhmAtThresholdPx) {
    PerceptualPoint p;
    p.ratio = std::max(illuminanceLux, 0.0) / pointThresholdLux(backgroundCdM2);
    p.visible = p.ratio >= 1.0;
    if (!p.visible) return p;
    const double decades = std::log10(p.ratio);
    p.fwhmPx = fwhmAtThresholdPx * std::min(1.0 + 0.5 * decades, 8.0);
    p.contrast = contrastAtThreshold * (1.0 + 2.0 * decades);
    return p;
}

}  // namespace welkin
