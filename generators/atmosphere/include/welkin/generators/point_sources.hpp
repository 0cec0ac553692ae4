// The perceptual point sources' per-frame uniforms (atmosphere/point_perceptual.glsl), shared
// by the Stars and the Planet elements (here, beside the sky-view LUTs they read, so that neither
// element's folder needs the other's); the model is welkin/point_source.hpp.
//
//   // in an element's doRender(), after program.use():
//   const bool perceptual = welkin::generators::setPerceptualPointUniforms(program, ctx.vars, ctx.attenuatedLater);
//   // a program that includes point_perceptual.glsl then calls pp_background(dir), pp_point(...)
#pragma once
#include <welkin/gl/objects.hpp>
#include <welkin/vars.hpp>

namespace welkin::generators {

/// The night sky's own luminance (cd/m^2) that the threshold adds to the sky's: the NightSky
/// element's nightsky.background_cd_m2 when it runs, else stars.background_floor_cd_m2 when
/// declared (the Stars' option, read by name), else the dark-sky reference (22.0 mag/arcsec^2, 1.7e-4 cd/m^2).
double nightSkyBackgroundCdM2(const SkyVars& vars);

/// Sets u_ppMode and, in perceptual mode, the background's uniforms and binds the Sun's and the
/// Moon's sky-view LUTs (texture units 0 and 2, as the Sky does after it) when the sky is drawn
/// over the points (`skyLater`: FrameContext::attenuatedLater) and the LUTs exist. Returns
/// whether the mode is perceptual. Throws welkin::Error for an unknown render.point_sources.
bool setPerceptualPointUniforms(const gl::Program& program, const SkyVars& vars, bool skyLater);

}  // namespace welkin::generators
