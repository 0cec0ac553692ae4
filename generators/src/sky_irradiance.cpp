// Sky irradiance generator (GPU pass sky_irradiance.glsl; CPU twin cpuDiffuseIrradiance in
// sky_luts_common.cpp with cpu::skyViewSample).
#include <welkin/embedded/generator_shaders.hpp>
#include <welkin/generators/sky_luts.hpp>
#include <welkin/gl/shader.hpp>
#include <welkin/keys.hpp>

#include <epoxy/gl.h>

#include <algorithm>

namespace welkin::generators {

SkyIrradiance::SkyIrradiance() : SkyGenerator("sky.irradiance") {
    input(skykeys::transmittanceLuts);
    input(skykeys::sunViewLut);
    input(skykeys::moonViewLut);
    input(lightkeys::sunIlluminance);
    input(lightkeys::moonIlluminance);
    input(keys::sunDirection);
    input(keys::moonDirection);
    input(keys::observerHeight);
    output(skykeys::horizontalIlluminance);
    output(skykeys::diffuseIrradiance);
    output(skykeys::zenithLuminance);
}

void SkyIrradiance::releaseGl() {
    prog_ = {};
    out_ = {};
    releaseCommon();
}

void SkyIrradiance::doRun(SkyVars& vars, const Logger&) {
    prepare(vars);
    if (!prog_)
        prog_ = gl::ProgramBuilder("SkyIrradiance")
                    .define("ATM_USE_TRANSMITTANCE")
                    .compute("generators/atmosphere.glsl", embedded::generator_shaders("atmosphere.glsl"))
                    .compute("generators/sky_irradiance.glsl", embedded::generator_shaders("sky_irradiance.glsl"))
                    .build();
    if (!out_) out_ = gl::Buffer(sizeof(float) * 20);
    const double Ht = model_.topRadius - model_.bottomRadius;
    const double h = std::clamp(vars.getOr(keys::observerHeight, 0.0), 0.0, Ht);
    auto unit = [](glm::dvec3 d) { return glm::length(d) > 0 ? glm::normalize(d) : glm::dvec3(0, 0, -1); };
    glm::dvec3 sun = unit(vars.getOr(keys::sunDirection, glm::dvec3(0, 0, 1)));
    glm::dvec3 moon = unit(vars.getOr(keys::moonDirection, glm::dvec3(0, 0, -1)));
    glm::dvec3 sunE = vars.getOr(lightkeys::sunIlluminance, model_.solarIlluminance);
    glm::dvec3 moonE = vars.getOr(lightkeys::moonIlluminance, glm::dvec3(0.0));
    glBindTextureUnit(gl::binding::kSunViewLut, vars.get(skykeys::sunViewLut).id);
    glBindTextureUnit(gl::binding::kSunViewMieLut, vars.get(skykeys::sunViewMieLut).id);
    glBindTextureUnit(gl::binding::kMoonViewLut, vars.get(skykeys::moonViewLut).id);
    glBindTextureUnit(gl::binding::kMoonViewMieLut, vars.get(skykeys::moonViewMieLut).id);
    glBindTextureUnit(gl::binding::kTransmittanceLut, vars.get(skykeys::transmittanceLut).id);
    out_.bindBase(GL_SHADER_STORAGE_BUFFER, gl::binding::kSkyIrradianceSsbo);
    prog_.use();
    prog_.set("u_h", float(h));
    prog_.set("u_sunDir", glm::vec3(sun));
    prog_.set("u_moonDir", glm::vec3(moon));
    prog_.set("u_sunE", glm::vec3(sunE));
    prog_.set("u_moonE", glm::vec3(moonE));
    prog_.set("u_nz", q_.irradianceZenith);
    prog_.set("u_na", q_.irradianceAzimuth);
    prog_.set("u_invScale", float(1.0 / kLutScale));
    glDispatchCompute(1, 1, 1);
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    float r[20] = {};
    glGetNamedBufferSubData(out_.id(), 0, sizeof r, r);
    auto v = [&](int i) { return glm::max(glm::dvec3(r[4 * i], r[4 * i + 1], r[4 * i + 2]), glm::dvec3(0.0)); };
    sunDiffuse_ = v(0);
    moonDiffuse_ = v(1);
    auto Y = [](glm::dvec3 c) { return 0.2126 * c.r + 0.7152 * c.g + 0.0722 * c.b; };
    glm::dvec3 diffuse = sunDiffuse_ + moonDiffuse_;
    double direct = Y(v(2)) + Y(v(3));
    vars.set(skykeys::horizontalIlluminance, glm::dvec3(direct + Y(diffuse), direct, Y(diffuse)));
    vars.set(skykeys::diffuseIrradiance, diffuse);
    vars.set(skykeys::zenithLuminance, Y(v(4)));
}

}  // namespace welkin::generators
