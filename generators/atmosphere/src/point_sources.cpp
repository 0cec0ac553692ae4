// Perceptual point sources: the per-frame uniforms of atmosphere/shaders/point_perceptual.glsl.
#include <welkin/astro/bodies.hpp>
#include <welkin/generators/lights.hpp>
#include <welkin/generators/point_sources.hpp>
#include <welkin/generators/sky_luts.hpp>
#include <welkin/generators/sky_model.hpp>
#include <welkin/gl/bindings.hpp>
#include <welkin/keys.hpp>
#include <welkin/point_source.hpp>

#include <epoxy/gl.h>

#include <algorithm>
#include <vector>

namespace welkin::generators {

double nightSkyBackgroundCdM2(const SkyVars& v) {
    if (v.has(keys::nightBackground)) return v.get(keys::nightBackground);
    // The Stars' option by name: this file is shared, the Stars' folder is theirs.
    if (const std::vector<double> floor = v.numeric("stars.background_floor_cd_m2"); floor.size() == 1) return floor[0];
    return astro::magnitude::surfaceBrightnessCdM2(astro::magnitude::kDarkSkyZenithMag);
}

bool setPerceptualPointUniforms(const gl::Program& p, const SkyVars& v, bool skyLater) {
    namespace sk = generators::skykeys;
    namespace lk = generators::lightkeys;
    const bool perceptual = pointSourceMode(v) == PointSourceMode::Perceptual;
    p.set("u_ppMode", perceptual ? 1 : 0);
    if (!perceptual) return false;
    int sky = 0;
    if (skyLater && v.has(sk::sunViewTotalLut) && v.get(sk::sunViewTotalLut).id != 0) {
        const TextureRef sun = v.get(sk::sunViewTotalLut);
        const generators::SkyModel m = generators::SkyModel::fromVars(v);
        const double h = std::clamp(v.getOr(keys::observerHeight, 0.0), 0.0, m.topRadius - m.bottomRadius);
        auto unit = [](glm::dvec3 d) { return glm::length(d) > 0 ? glm::normalize(d) : glm::dvec3(0, 0, -1); };
        p.set("u_ppSH", float(generators::skyViewHorizonS(m, h)));
        p.set("u_ppLutSize", glm::vec2(float(sun.width), float(sun.height)));
        const glm::dvec3 sunE = v.getOr(lk::sunIlluminance, m.solarIlluminance);
        p.set("u_ppSunDir", glm::vec3(unit(v.get(keys::sunDirection))));
        p.set("u_ppSunE", glm::vec3(sunE / generators::kLutScale));
        glBindTextureUnit(gl::binding::kSunViewLut, sun.id);
        sky |= 1;
        // The Moon's term as the Sky draws it: while it gives light and is above -20 deg.
        const glm::dvec3 moonE = v.getOr(sk::moonLight, true) ? v.getOr(lk::moonIlluminance, glm::dvec3(0.0)) : glm::dvec3(0.0);
        if (glm::length(moonE) > 0.0 && unit(v.get(keys::moonDirection)).z > -0.342 && v.has(sk::moonViewTotalLut) &&
            v.get(sk::moonViewTotalLut).id != 0) {
            p.set("u_ppMoonDir", glm::vec3(unit(v.get(keys::moonDirection))));
            p.set("u_ppMoonE", glm::vec3(moonE / generators::kLutScale));
            glBindTextureUnit(gl::binding::kMoonViewLut, v.get(sk::moonViewTotalLut).id);
            sky |= 2;
        }
    }
    p.set("u_ppSky", sky);
    p.set("u_ppNight", float(nightSkyBackgroundCdM2(v)));
    p.set("u_ppContrast", float(v.get(keys::pointContrast)));
    return true;
}

}  // namespace welkin::generators
