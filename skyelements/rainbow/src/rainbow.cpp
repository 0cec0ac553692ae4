#include <welkin/elements/rainbow.hpp>
#include <welkin/embedded/optics_shaders.hpp>
#include <welkin/embedded/rainbow_shaders.hpp>
#include <welkin/error.hpp>
#include <welkin/generators/cloud_keys.hpp>
#include <welkin/generators/cloud_shadow.hpp>
#include <welkin/generators/lights.hpp>
#include <welkin/generators/sky_luts.hpp>
#include <welkin/gl/bindings.hpp>
#include <welkin/gl/shader.hpp>
#include <welkin/keys.hpp>

#include <epoxy/gl.h>

#include <cmath>

namespace welkin::elements {

using generators::cloudkeys::weatherMap;
namespace rk = generators::rainkeys;
namespace lk = generators::lightkeys;
namespace ck = generators::cloudkeys;

Rainbow::Rainbow() : SkyElement("rainbow") {
    option(rk::rate, 0.0);
    option(rk::dropRadius, 0.5e-3);
    option(rk::dropVariance, 0.02);
    option(rk::distribution, std::string("gamma"));
    option(rk::tableQuality, std::string("default"));
    option(rainbowkeys::distance, 2000.0);
    option(rainbowkeys::depth, 1000.0);
    option(rainbowkeys::height, 1500.0);
    option(rainbowkeys::halfWidth, 90.0 * rainbowkeys::kDeg);
    reads(keys::sunDirection);
    reads(keys::moonDirection);
    reads(keys::observerHeight);
    reads(lk::sunIlluminance);
    reads(lk::sunTransmittance);
    reads(lk::moonIlluminance);
    reads(lk::moonTransmittance);
    reads(rk::phaseLut);
    reads(rk::scattering);
    reads(rk::extinction);
    reads(generators::skykeys::diffuseIrradiance);
}

bool Rainbow::bowPossible(double lightElevation, double observerHeightM, double curtainDistanceM) {
    const double lowest = -std::atan2(std::max(observerHeightM, 0.0), std::max(curtainDistanceM, 0.0));
    return 54.0 * rainbowkeys::kDeg - lightElevation >= lowest;
}

void Rainbow::doValidateOptions(const SkyVars& vars) const {
    // Before any GL work: the string keys' values (one-line errors naming the key).
    (void)generators::dropDistributionFromVars(vars);
    const std::string q = vars.get(rk::tableQuality);
    if (q != "low" && q != "default" && q != "high")
        throw Error("rain.table_quality: '" + q + "' is not one of low, default, high");
}

void Rainbow::doInit(InitContext& ctx) {
    declareOptions(ctx.vars);
    addGenerator(generators::AtmosphereLights::obtain(ctx.vars));
    mie_ = std::make_shared<generators::MiePhaseGenerator>();
    addGenerator(mie_);
    // The clouds' shadow on the light reaching the rain (clouds.shadow_map): shared with the host
    // and any element; every cloud input of it is optional, and without a weather map it is a
    // map of 1 built once per 0.03 deg of the light's motion (a trivial pass).
    addGenerator(generators::CloudShadowMap::obtain(ctx.vars));
    auto recipe = [](bool clouds) {
        gl::ProgramBuilder b("Rainbow");
        b.fullscreenVertex();
        if (clouds) b.define("WELKIN_RAINBOW_CLOUDS");
        b.fragment("engine/camera.glsl", gl::engineShader("camera.glsl"))
            .fragment("engine/composite.glsl", gl::engineShader("composite.glsl"))
            .fragment("generators/clouds/cloud_shadow.glsl", std::string(generators::CloudShadowMap::hostGlsl()))
            .fragment("optics/mie_angle.glsl", embedded::optics_shaders("mie_angle.glsl"))
            .fragment("rainbow/rainbow.frag.glsl", embedded::rainbow_shaders("rainbow.frag.glsl"));
        return b;
    };
    programs_ = gl::ProjectionPrograms(recipe(false));
    cloudPrograms_ = gl::ProjectionPrograms(recipe(true));
    programs_.get(Projection::Perspective);  // shader errors surface in init()
}

void Rainbow::doRender(const FrameContext& ctx) {
    drew_ = false;
    const SkyVars& v = ctx.vars;
    // The light: the Sun, or the Moon when the Sun gives no light at the observer (moonbows).
    glm::dvec3 E = v.get(lk::sunIlluminance) * v.get(lk::sunTransmittance);
    glm::dvec3 L = v.get(keys::sunDirection);
    if (E == glm::dvec3(0.0) || L.z < 0.0) {
        E = v.has(lk::moonIlluminance) ? v.get(lk::moonIlluminance) * v.get(lk::moonTransmittance) : glm::dvec3(0.0);
        L = v.get(keys::moonDirection);
    }
    if (E == glm::dvec3(0.0) || L.z < 0.0) return;  // no light
    L = glm::normalize(L);
    const double h0 = v.has(keys::observerHeight) ? v.get(keys::observerHeight) : 0.0;
    const double dist = v.get(rainbowkeys::distance);
    if (!bowPossible(std::asin(std::clamp(L.z, -1.0, 1.0)), h0, dist)) return;
    const double rate = v.get(rk::rate);
    const bool clouds = v.has(weatherMap) && v.has(ck::rainDensity) && v.get(ck::rainDensity) > 0.0 &&
                        v.get(weatherMap).id != 0;
    if (rate <= 0.0 && !clouds) return;  // no rain: nothing drawn, nothing bound

    const gl::Program& p = (clouds ? cloudPrograms_ : programs_).get(ctx.camera.projection);
    p.use();
    const TextureRef lut = v.get(rk::phaseLut);
    glBindTextureUnit(gl::binding::kMiePhaseLut, lut.id);
    p.set("u_light", glm::vec3(L));
    p.set("u_E", glm::vec3(E));
    p.set("u_sca", glm::vec3(v.get(rk::scattering)));
    // Grey extinction (rainbow.frag.glsl): the luminance-weighted mean of the channels.
    const glm::dvec3 ext = v.get(rk::extinction);
    p.set("u_ext", float(0.2126 * ext.r + 0.7152 * ext.g + 0.0722 * ext.b));
    p.set("u_dist", float(dist));
    p.set("u_depth", float(v.get(rainbowkeys::depth)));
    p.set("u_height", float(v.get(rainbowkeys::height)));
    glm::dvec2 axis(-L.x, -L.y);
    axis = glm::length(axis) > 1e-9 ? glm::normalize(axis) : glm::dvec2(0.0, 1.0);
    p.set("u_axis", glm::vec2(axis));
    p.set("u_cosHalfWidth", float(std::cos(v.get(rainbowkeys::halfWidth))));
    p.set("u_obsHeight", float(h0));
    // The Sky's diffuse illuminance when a Sky runs (optional: 0 otherwise).
    const glm::dvec3 skyE = v.has(generators::skykeys::diffuseIrradiance) ? v.get(generators::skykeys::diffuseIrradiance) : glm::dvec3(0.0);
    p.set("u_skyE", glm::vec3(skyE));
    // The clouds' shadow, once its map exists (before, and without clouds: no shadow).
    const bool shadow = v.has(generators::cloudkeys::shadowMap) && v.get(generators::cloudkeys::shadowMap).id != 0;
    p.set("u_shadow", shadow ? 1 : 0);
    if (shadow) generators::CloudShadowMap::bindForHost(v, p.id());
    if (clouds) {
        const TextureRef w = v.get(weatherMap);
        glBindTextureUnit(gl::binding::kCloudWeatherMap, w.id);
        p.set("u_weatherExtent", float(v.get(ck::weatherExtent)));
        p.set("u_weatherOffset", glm::vec2(v.get(ck::weatherOffset)));
        p.set("u_cloudBottom", float(v.get(ck::bottom)));
        p.set("u_cloudTop", float(v.get(ck::top)));
        p.set("u_rainRateScale", float(v.get(ck::rainDensity) * generators::kRainRateAtFullDensityMmH));
        p.set("u_scaPerWater", glm::vec3(mie_->scatteringPerWater()));
        p.set("u_extPerWater", glm::vec3(mie_->extinctionPerWater()));
        p.set("u_marchMax", 20000.0f);
    }
    ctx.drawFullscreen();
    drew_ = true;
}

void Rainbow::doRelease() {
    programs_.releasePrograms();
    cloudPrograms_.releasePrograms();
    mie_.reset();
}

}  // namespace welkin::elements

WELKIN_ELEMENT_DESCRIPTOR(rainbow) {
    static const welkin::ElementDescriptor d{"rainbow", "rainbows, fogbows and the glory from exact Mie tables where rain is (docs/rainbow.md)",
                                             welkin::Layer::Foreground, false,
                                             [] { return std::make_unique<welkin::elements::Rainbow>(); }};
    return d;
}
