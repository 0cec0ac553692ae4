// SkyModelAccess: what the shared atmosphere marches call of the atmosphere, on a SkyModel and its
// transmittance LUT, in double: the CPU side of atmosphere.glsl's block wrappers (atm_bottom(),
// atm_extinction(h), distanceToTop(h, mu), transmittanceToLight(h, muS, angular), ...). Private to
// welkin_generators (not installed).
//
// A C++ twin includes a shared march (atmosphere_march.shared.glsl, atmosphere_view.shared.glsl,
// cloud_sky_shadow.shared.glsl) inside a struct derived from this one, so that the march's
// unqualified calls find these members before the namespace's functions of the same names (the
// shared file's own, with more parameters), as in docs/architecture.md, "Marches that call the
// includer":
//
//   struct SkyShadowMarch : welkin::glsl::dp::SkyModelAccess {
//       real cld_skyShadowMapAt(vec2 uv) const { ... }   // what only this march reads
//   #include "cloud_sky_shadow.shared.glsl"
//   };
//   SkyShadowMarch{{model, &transmittanceLut}}.cld_skyShadowLoss(...);
//
// Used by SkyMarch (sky_model.cpp: the LUT marches and the view-ray march) and SkyShadowMarch
// (generators/clouds/src/cloud_sky_shadow.cpp: the clouds' shadow on the sky).
#pragma once
#include <welkin/generators/sky_model.hpp>
#include <welkin/glsl_cpp.hpp>

namespace welkin::glsl::dp {

struct SkyModelAccess {
    const generators::SkyModel& m;
    const generators::Lut2D* T = nullptr;  // the transmittance LUT (transmittanceToLight(); null where no sample reads the light)

    real atm_bottom() const { return m.bottomRadius; }
    real atm_thickness() const { return m.topRadius - m.bottomRadius; }
    vec3 atm_groundAlbedoRgb() const { return m.groundAlbedo; }
    vec3 atm_extinction(real h) const { return m.extinction(h); }
    vec3 atm_scatteringRayleigh(real h) const { return m.scatteringRayleigh(h); }
    vec3 atm_scatteringMie(real h) const { return m.scatteringMie(h); }
    real distanceToTop(real h, real mu) const { return generators::cpu::distanceToTop(m, h, mu); }
    real distanceToBottom(real h, real mu) const { return generators::cpu::distanceToBottom(m, h, mu); }
    bool rayIntersectsGround(real h, real mu) const { return generators::cpu::rayIntersectsGround(m, h, mu); }
    real heightAt(real h, real mu, real t) const { return generators::cpu::heightAt(m, h, mu, t); }
    vec3 transmittanceToLight(real h, real muS, real angular) const { return generators::cpu::transmittanceToLight(m, *T, h, muS, angular); }
};

}  // namespace welkin::glsl::dp
