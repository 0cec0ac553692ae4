// Sky irradiance generator (GPU pass sky_irradiance.glsl; CPU twin cpuDiffuseIrradiance in
// sky_luts_common.cpp with cpu::skyViewSample).
#include <welkin/embedded/atmosphere_shaders.hpp>
#include <welkin/generators/sky_luts.hpp>
#include <welkin/gl/shader.hpp>
#include <welkin/keys.hpp>

#include <epoxy/gl.h>

#include <algorithm>

namespace welkin::generators {

namespace {
// Workgroups of the irradiance pass: the samples shared among them, so llvmpipe's threads (and a
// GPU's units) all work; 8 x 64 invocations.
constexpr int kGroups = 8;
}  // namespace

SkyIrradiance::SkyIrradiance() : SkyGenerator("sky.irradiance") {
    input(skykeys::transmittanceLuts);
    input(skykeys::sunViewLut);
    input(skykeys::moonViewLut);
    input(lightkeys::sunIlluminance);
    input(lightkeys::moonIlluminance);
    input(skykeys::moonLit, {.optional = true});
    input(skykeys::sunCosZenith, {.tolerance = kCosZenithTolerance});
    input(skykeys::moonCosZenith, {.tolerance = kCosZenithTolerance});
    input(keys::observerHeight);
    input(skykeys::eclipseViewLut, {.optional = true});  // a solar eclipse: republished every run it is on
    input(keys::sunEclipseFraction, {.optional = true});
    output(skykeys::horizontalIlluminance);
    output(skykeys::diffuseIrradiance);
    output(skykeys::zenithLuminance);
}

void SkyIrradiance::releaseGl() {
    prog_ = {};
    eclipseProg_ = {};
    out_ = {};
    releaseCommon();
}

void SkyIrradiance::doRun(SkyVars& vars, const Logger&) {
    prepare(vars);
    if (!prog_)
        prog_ = gl::ProgramBuilder("SkyIrradiance")
                    .define("ATM_USE_TRANSMITTANCE")
                    .define("SKY_IRRADIANCE_GROUPS", kGroups)
                    .compute("generators/atmosphere.glsl", embedded::atmosphere_shaders("atmosphere.glsl"))
                    .compute("generators/sky_irradiance.glsl", embedded::atmosphere_shaders("sky_irradiance.glsl"))
                    .build();
    if (!eclipseProg_)
        eclipseProg_ = gl::ProgramBuilder("SkyIrradiance (eclipse)")
                           .define("ATM_USE_TRANSMITTANCE")
                           .define("SKY_IRRADIANCE_GROUPS", kGroups)
                           .define("SKY_IRRADIANCE_ECLIPSE")
                           .compute("generators/atmosphere.glsl", embedded::atmosphere_shaders("atmosphere.glsl"))
                           .compute("generators/sky_irradiance.glsl", embedded::atmosphere_shaders("sky_irradiance.glsl"))
                           .build();
    if (!out_) out_ = gl::Buffer(sizeof(float) * 4 * (6 + 2 * kGroups));
    const double Ht = model_.topRadius - model_.bottomRadius;
    const double h = std::clamp(vars.getOr(keys::observerHeight, 0.0), 0.0, Ht);
    const double muSun = std::clamp(vars.get(skykeys::sunCosZenith), -1.0, 1.0);
    const double muMoon = std::clamp(vars.get(skykeys::moonCosZenith), -1.0, 1.0);
    // Only the elevations matter (the quadrature runs over the azimuth from each light).
    auto dirOf = [](double mu) { return glm::vec3(float(std::sqrt(std::max(1.0 - mu * mu, 0.0))), 0.0f, float(mu)); };
    glm::dvec3 sunE = vars.getOr(lightkeys::sunIlluminance, model_.solarIlluminance);
    glm::dvec3 moonE = vars.getOr(skykeys::moonLit, true) ? vars.getOr(lightkeys::moonIlluminance, glm::dvec3(0.0)) : glm::dvec3(0.0);
    // The GPU pass gives values per lux of each light; it runs again only when a table, an
    // elevation or the height changed, not when only the lights' illuminances or the Sun's
    // visible fraction did (a partial eclipse changes it every frame: applied below, on the CPU).
    std::vector<uint64_t> gv;
    for (size_t i = 0; i < inputs().size(); ++i) {
        const std::string& name = inputs()[i].name;
        if (name != lightkeys::sunIlluminance.name() && name != lightkeys::moonIlluminance.name() && name != keys::sunEclipseFraction.name())
            gv.push_back(inputVersion(vars, i));
    }
    if (gv != gpuFor_) {
        gpuFor_ = std::move(gv);
        // A solar eclipse (EclipseSkyLut on): the Sun's part from its table over the whole circle.
        const bool eclipse = vars.has(skykeys::eclipseViewLut) && vars.get(skykeys::eclipseViewLut).id != 0;
        eclipseRun_ = eclipse;
        const gl::Program& prog = eclipse ? eclipseProg_ : prog_;
        glBindTextureUnit(gl::binding::kSunViewLut, vars.get(eclipse ? skykeys::eclipseViewLut : skykeys::sunViewLut).id);
        glBindTextureUnit(gl::binding::kSunViewMieLut, vars.get(eclipse ? skykeys::eclipseViewMieLut : skykeys::sunViewMieLut).id);
        glBindTextureUnit(gl::binding::kMoonViewLut, vars.get(skykeys::moonViewLut).id);
        glBindTextureUnit(gl::binding::kMoonViewMieLut, vars.get(skykeys::moonViewMieLut).id);
        glBindTextureUnit(gl::binding::kTransmittanceLut, vars.get(skykeys::transmittanceLut).id);
        out_.bindBase(GL_SHADER_STORAGE_BUFFER, gl::binding::kSkyIrradianceSsbo);
        prog.use();
        prog.set("u_h", float(h));
        prog.set("u_sunDir", eclipse ? glm::vec3(glm::normalize(vars.get(keys::sunDirection))) : dirOf(muSun));
        prog.set("u_moonDir", dirOf(muMoon));
        prog.set("u_sunE", glm::vec3(1.0f));
        prog.set("u_moonE", glm::vec3(1.0f));
        prog.set("u_nz", q_.irradianceZenith);
        prog.set("u_na", q_.irradianceAzimuth);
        prog.set("u_invScale", float(1.0 / kLutScale));
        glDispatchCompute(kGroups, 1, 1);
        glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
        float all[4 * (6 + 2 * kGroups)];
        glGetNamedBufferSubData(out_.id(), 0, sizeof all, all);
        std::copy(all, all + 24, perLux_);
        for (int g = 0; g < kGroups; ++g)  // the diffuse sums: the groups' partial sums
            for (int i = 0; i < 2; ++i)
                for (int c = 0; c < 3; ++c) perLux_[4 * i + c] += all[4 * (6 + 2 * g + i) + c];
    }
    // Rows 0, 2, 4 per lux of the Sun; 1, 3, 5 of the Moon.
    const float* r = perLux_;
    auto perLux = [&](int i) { return glm::max(glm::dvec3(r[4 * i], r[4 * i + 1], r[4 * i + 2]), glm::dvec3(0.0)); };
    // The direct sunlight (row 2) keeps the Sun's visible fraction while the eclipse table is used.
    const double directFraction = eclipseRun_ ? std::clamp(vars.getOr(keys::sunEclipseFraction, 1.0), 0.0, 1.0) : 1.0;
    auto v = [&](int i) {
        return i == 4 ? perLux(4) * sunE + perLux(5) * moonE : perLux(i) * (i % 2 == 0 ? sunE : moonE) * (i == 2 ? directFraction : 1.0);
    };
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
