// SkyModel from the shared atmosphere description (welkin::atmosphere::Atmosphere in SkyVars).
#include <welkin/generators/atmosphere.hpp>
#include <welkin/generators/sky_model.hpp>

namespace welkin::generators {

SkyModel SkyModel::fromVars(const SkyVars& vars) {
    if (!vars.has(atmosphere::kAtmosphere)) return earthClear();
    const auto& a = vars.get(atmosphere::kAtmosphere);
    if (!a) return earthClear();
    const atmosphere::RgbCoefficients c = a->rgb();
    SkyModel m;
    m.bottomRadius = a->bottomRadiusM;
    m.topRadius = a->topRadiusM;
    m.rayleighScattering = c.rayleighScattering;
    m.rayleighDensity = DensityProfile::exponential(a->rayleighScaleHeightM);
    m.mieScattering = c.mieScattering;
    m.mieExtinction = glm::max(c.mieExtinction, c.mieScattering);
    m.mieDensity = DensityProfile::exponential(a->mieScaleHeightM);
    m.mieG = a->mieG;
    m.miePhase = a->miePhase == atmosphere::MiePhaseFunction::HenyeyGreenstein ? 0 : 1;
    m.absorptionExtinction = c.ozoneAbsorption;
    m.absorptionDensity = DensityProfile::tent(a->ozoneCenterAltitudeM, a->ozoneHalfWidthM);
    m.groundAlbedo = c.groundAlbedo;
    m.solarIlluminance = c.solarIlluminance;
    m.sunAngularRadius = a->sunAngularRadiusRad;
    return m;
}

}  // namespace welkin::generators
