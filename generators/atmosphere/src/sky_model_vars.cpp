// SkyModel from the shared atmosphere description (welkin::atmosphere::Atmosphere in SkyVars).
#include <welkin/generators/atmosphere.hpp>
#include <welkin/generators/sky_model.hpp>
#include <welkin/generators/sky_spectral.hpp>

namespace welkin::generators {

SkyModel SkyModel::fromVars(const SkyVars& vars) {
    if (!vars.has(atmosphere::kAtmosphere)) return earthClear();
    const auto& a = vars.get(atmosphere::kAtmosphere);
    if (!a) return earthClear();
    return skyModelFrom(*a, a->rgb());
}

}  // namespace welkin::generators
