// Point sources as people see them: the threshold and the perceptual size and contrast
// (welkin/point_source.hpp; shaders: generators/atmosphere/shaders/point_perceptual.glsl). The
// threshold and the size and contrast are point_threshold.shared.glsl, compiled here in double.
#include <welkin/error.hpp>
#include <welkin/glsl_cpp.hpp>
#include <welkin/point_source.hpp>

#include <algorithm>
#include <cmath>

namespace welkin::glsl::dp::point_shared {
#include "../shaders/point_threshold.shared.glsl"
}  // namespace welkin::glsl::dp::point_shared

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
    return glsl::dp::point_shared::welkin_pointThresholdFootCandles(backgroundCdM2);
}

double pointThresholdLux(double backgroundCdM2) { return pointThresholdFootCandles(backgroundCdM2) * WELKIN_LUX_PER_FOOT_CANDLE; }

PerceptualPoint perceptualPoint(double illuminanceLux, double backgroundCdM2, double contrastAtThreshold, double fwhmAtThresholdPx) {
    PerceptualPoint p;
    p.ratio = std::max(illuminanceLux, 0.0) / pointThresholdLux(backgroundCdM2);
    p.visible = p.ratio >= 1.0;
    if (!p.visible) return p;
    const glm::dvec2 sc = glsl::dp::point_shared::welkin_pointSizeContrast(p.ratio, fwhmAtThresholdPx, contrastAtThreshold);
    p.fwhmPx = sc.x;
    p.contrast = sc.y;
    return p;
}

}  // namespace welkin
