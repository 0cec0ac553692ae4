// The cloud-path LUT (SevenSky's C(alpha, r), Papp 2018 sec. 5.3): where a view ray enters and
// leaves the cloud shell [clouds.bottom_m, clouds.top_m], by view zenith and observer altitude,
// so the ray march starts at the layer without solving two quadratics per pixel. RG32F:
//   R entry distance (m, 0 inside the layer), G exit distance (m); both -1 where the ray does not
//   cross the layer (below it looking into the ground, above it looking up or past it).
// The first crossing only (cloudShellIntersect() in cloud_density.hpp, whose twin it is).
//
//   auto lut = welkin::generators::CloudPathLut::obtain(vars);    // one per SkyVars
//   element.addGenerator(lut);                                     // publishes clouds.path_lut
//   // GLSL (after cloud_density.glsl, then cloud_path.glsl):
//   //   vec2 seg = cloudPathLookup(altitude_m, cos_zenith);       // (entry, exit) m
//
// Mapping (shared by C++ and GLSL, texel-centred: coordinate 0 and 1 fall on the first and last
// texel centres):
//   x = 0.5 + 0.5 sign(mu) sqrt(|mu|)      view zenith: half the texels where |mu| < 0.25 (within
//                                          14.5 deg of the horizon), where the path changes fastest
//   y: three equal thirds, linear in altitude h: [0, bottom] below, [bottom, top] inside,
//      [top, top + kCloudPathAboveM] above (clamped beyond)
// Filtering across a miss (-1) and a hit blends them: readers treat exit <= entry as no crossing;
// the exact crossing is cloudShellIntersect().
#pragma once
#include <welkin/element.hpp>
#include <welkin/gl/objects.hpp>

#include <memory>

namespace welkin::generators {

/// Altitude span of the LUT's upper third above the layer's top, m (an aircraft or a high
/// camera; above it the LUT clamps: use cloudShellIntersect()).
inline constexpr double kCloudPathAboveM = 50000.0;

/// LUT coordinate (texel-centred, [0, 1]) of cos(view zenith) mu in [-1, 1] and back.
double cloudPathX(double mu);
double cloudPathMu(double x);
/// LUT coordinate of altitude h (m) for a layer [bottom, top] and back.
double cloudPathY(double h, double bottom, double top);
double cloudPathAltitude(double y, double bottom, double top);

class CloudPathLut : public Generator {
public:
    /// Texels: `width` in view zenith, `height` in altitude (each >= 3).
    explicit CloudPathLut(int width = 256, int height = 96);
    static std::shared_ptr<CloudPathLut> obtain(SkyVars& vars);
    const gl::Texture2D& texture() const { return tex_; }

private:
    void doRun(SkyVars& vars, const Logger& log) override;
    void doRelease() override;
    int w_, h_;
    gl::Texture2D tex_;
    gl::Program prog_;
};

namespace cpu {
/// The LUT's texel (i, j): (entry, exit) m, by the analytic ray-sphere crossing in double.
glm::dvec2 cloudPathTexel(int i, int j, int width, int height, double planetRadius, double bottom, double top);
}  // namespace cpu

}  // namespace welkin::generators
