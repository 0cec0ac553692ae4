// Shared parts of the sky generators: the atmosphere block, quality resolution, the shared
// instances in SkyVars, and the CPU twin of the irradiance quadrature.
#include <welkin/embedded/atmosphere_shaders.hpp>
#include <welkin/error.hpp>
#include <welkin/generators/atmosphere.hpp>
#include <welkin/generators/sky_luts.hpp>
#include <welkin/gl/shader.hpp>
#include <welkin/glsl_cpp.hpp>
#include <welkin/keys.hpp>

#include <epoxy/gl.h>

#include <algorithm>
#include <cmath>
#include <numbers>

// The sky-irradiance sum's samples and weight (atm_irradianceSample(), atm_cosViewLight(),
// atm_irradianceWeight()): the pass's text (sky_irradiance.glsl) in double.
namespace welkin::glsl::dp::irradiance_shared {
#define ATM_SEGMENT_LINEAR 1e-7  // atm_segmentFactor()'s linear limit in double (as sky_model.cpp; unused here)
#include "atmosphere.shared.glsl"
}  // namespace welkin::glsl::dp::irradiance_shared

namespace welkin::generators {

int effectiveQuality(const SkyVars& vars) {
    const int q = skykeys::quality.valueOr(vars, -1);
    return q >= 0 ? q : keys::quality.valueOr(vars, 1);
}

AtmosphereBlock AtmosphereBlock::from(const SkyModel& m, int shBands) {
    AtmosphereBlock b{};
    b.radii = glm::vec4(float(m.bottomRadius), float(m.topRadius), float(m.topRadius - m.bottomRadius), float(m.miePhase));
    b.rayleigh = glm::vec4(glm::vec3(m.rayleighScattering), float(m.mieG));
    b.mieScattering = glm::vec4(glm::vec3(m.mieScattering), 0.0f);
    b.mieExtinction = glm::vec4(glm::vec3(m.mieExtinction), 0.0f);
    b.absorption = glm::vec4(glm::vec3(m.absorptionExtinction), 0.0f);
    b.groundAlbedo = glm::vec4(glm::vec3(m.groundAlbedo), 0.0f);
    b.solarIlluminance = glm::vec4(glm::vec3(m.solarIlluminance), float(m.sunAngularRadius));
    const cpu::PhaseMoments pm = cpu::phaseMoments(m, shBands);
    b.shFactors = glm::vec4(float(pm.mie[1]), float(pm.mie[2]), float(pm.rayleigh[2]), float(pm.forward));
    b.shFactors2 = glm::vec4(float(pm.mie[3]), float(pm.mie[4]), float(pm.mie[5]), float(pm.mie[6]));
    const DensityProfile* p[3] = {&m.rayleighDensity, &m.mieDensity, &m.absorptionDensity};
    for (int i = 0; i < 3; ++i) {
        const DensityLayer &a = p[i]->layers[0], &c = p[i]->layers[1];
        b.profiles[3 * i] = glm::vec4(float(a.width), float(a.expTerm), float(a.expScale), float(a.linearTerm));
        b.profiles[3 * i + 1] = glm::vec4(float(a.constantTerm), float(c.expTerm), float(c.expScale), float(c.linearTerm));
        b.profiles[3 * i + 2] = glm::vec4(float(c.constantTerm), 0.0f, 0.0f, 0.0f);
    }
    return b;
}

SkyGenerator::SkyGenerator(std::string name) : Generator(std::move(name)) {
    input(atmosphere::kAtmosphere);
    input(skykeys::quality);
    input(keys::quality);
    input(skykeys::wavelengths);
}

void SkyGenerator::doDeclare(SkyVars& vars) {
    if (!vars.has(atmosphere::kAtmosphere))
        vars.set(atmosphere::kAtmosphere, std::make_shared<const atmosphere::Atmosphere>(atmosphere::Atmosphere::earthClear()));
    vars.declare(skykeys::quality, -1);
    vars.declare(keys::quality, 1);
    vars.declare(skykeys::wavelengths, 0);
    vars.declare(skykeys::keyframeBudget, kKeyframeBudgetDefault);
    vars.declare(skykeys::keyframeCache, true);
}

void SkyGenerator::prepare(SkyVars& vars) {
    {
        std::shared_ptr<const atmosphere::Atmosphere> a;
        if (vars.has(atmosphere::kAtmosphere)) a = vars.get(atmosphere::kAtmosphere);
        if (!a ? !modelDefault_ : a != modelFor_) {
            model_ = SkyModel::fromVars(vars);
            model_.validate();
            modelFor_ = a;
            modelDefault_ = !a;
        }
    }
    int preset = effectiveQuality(vars);
    q_ = fixed_ ? *fixed_ : SkyQuality::preset(preset);
    validateWavelengthCount(vars.getOr(skykeys::wavelengths, 0), "sky.wavelengths");
    const int n = effectiveWavelengths(vars.getOr(skykeys::wavelengths, 0), q_);
    if (n == 3) {
        spectral_.reset();
        spectralFor_.reset();
    } else {
        std::shared_ptr<const atmosphere::Atmosphere> a;
        if (vars.has(atmosphere::kAtmosphere)) a = vars.get(atmosphere::kAtmosphere);
        if (!a) a = std::make_shared<const atmosphere::Atmosphere>(atmosphere::Atmosphere::earthClear());
        if (!spectral_ || spectral_->wavelengths != n || spectralFor_ != a) {
            spectral_ = std::make_shared<const SpectralSampling>(SpectralSampling::make(*a, n));
            spectralFor_ = a;
        }
    }
    if (!ubo_) ubo_ = gl::Buffer(sizeof(AtmosphereBlock));
    if (!vao_) vao_ = gl::VertexArray::create();
    AtmosphereBlock block = AtmosphereBlock::from(spectral_ ? spectral_->models[0] : model_, q_.shBands);
    ubo_.update(&block, sizeof block);
    ubo_.bindBase(GL_UNIFORM_BUFFER, gl::binding::kAtmosphereUbo);
}

void SkyGenerator::useTriple(int k) {
    if (!spectral_) return;
    AtmosphereBlock block = AtmosphereBlock::from(spectral_->models.at(size_t(k)), q_.shBands);
    ubo_.update(&block, sizeof block);
    ubo_.bindBase(GL_UNIFORM_BUFFER, gl::binding::kAtmosphereUbo);
}

void SkyGenerator::combine(const gl::Texture& src, const gl::Texture& dst, int k) {
    if (!spectral_) throw Error("SkyGenerator::combine(): RGB mode has nothing to combine");
    const bool is3D = dst.target() == GL_TEXTURE_3D;
    const bool half = dst.internalFormat() == GL_RGBA16F;
    if (is3D && half) throw Error("SkyGenerator::combine(): rgba16f volumes not supported");
    gl::Program& p = is3D ? combine3D32_ : half ? combine2D16_ : combine2D32_;
    if (!p) {
        gl::ProgramBuilder b(std::string("SpectralCombine") + (is3D ? "3D" : "2D") + (half ? "16" : "32"));
        if (is3D) b.define("COMBINE_3D");
        b.define("COMBINE_FORMAT", half ? "rgba16f" : "rgba32f");
        p = b.compute("generators/spectral_combine.glsl", embedded::atmosphere_shaders("spectral_combine.glsl")).build();
    }
    // Image stores of the previous triple (or the pass's own image writes) before these reads.
    glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT | GL_TEXTURE_FETCH_BARRIER_BIT);
    glBindTextureUnit(gl::binding::kCombineSource, src.id());
    glBindImageTexture(gl::binding::kLutImage, dst.id(), 0, is3D ? GL_TRUE : GL_FALSE, 0, GL_READ_WRITE, half ? GL_RGBA16F : GL_RGBA32F);
    p.use();
    p.set("u_toRgb", glm::mat3(spectral_->toRgb.at(size_t(k))));
    p.set("u_accumulate", k > 0 ? 1 : 0);
    p.set("u_last", k + 1 == triples() ? 1 : 0);
    const glm::ivec3 size(dst.width(), dst.height(), std::max(dst.depth(), 1));
    glUniform3i(glGetUniformLocation(p.id(), "u_size"), size.x, size.y, size.z);
    glDispatchCompute(GLuint((size.x + 7) / 8), GLuint((size.y + 7) / 8), GLuint(size.z));
    glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT | GL_TEXTURE_FETCH_BARRIER_BIT | GL_FRAMEBUFFER_BARRIER_BIT);
}

void SkyGenerator::fullscreen() const {
    vao_.bind();
    // A dual-source blend function left by the compositor makes multi-target draws invalid
    // even with blending disabled (Mesa): reset it.
    glBlendFunc(GL_ONE, GL_ZERO);
    glDisable(GL_BLEND);
    glDisable(GL_DEPTH_TEST);
    glDrawArrays(GL_TRIANGLES, 0, 3);
}

namespace {
const Key<std::shared_ptr<TransmittanceLut>> kGenTransmittance{"sky.gen.transmittance"};
const Key<std::shared_ptr<MultiScatteringLut>> kGenMultiScattering{"sky.gen.multiscattering"};
const Key<std::shared_ptr<ShLut>> kGenSh{"sky.gen.sh"};
const Key<std::shared_ptr<SkyViewLut>> kGenSunView{"sky.gen.sun_view"};
const Key<std::shared_ptr<SkyViewLut>> kGenMoonView{"sky.gen.moon_view"};
const Key<std::shared_ptr<AerialPerspectiveLut>> kGenAerial{"sky.gen.aerial"};
const Key<std::shared_ptr<SkyIrradiance>> kGenIrradiance{"sky.gen.irradiance"};
const Key<std::shared_ptr<LightZenith>> kGenLightZenith{"sky.gen.light_zenith"};
const Key<std::shared_ptr<EclipseSkyLut>> kGenEclipse{"sky.gen.eclipse_view"};
}  // namespace

SkyLuts SkyLuts::obtain(SkyVars& vars) {
    SkyLuts l;
    l.transmittance = vars.obtain<TransmittanceLut>(kGenTransmittance, [] { return std::make_shared<TransmittanceLut>(); });
    l.multiScattering = vars.obtain<MultiScatteringLut>(kGenMultiScattering, [] { return std::make_shared<MultiScatteringLut>(); });
    l.sh = vars.obtain<ShLut>(kGenSh, [] { return std::make_shared<ShLut>(); });
    l.sunView = vars.obtain<SkyViewLut>(kGenSunView, [] { return std::make_shared<SkyViewLut>(Light::Sun); });
    l.moonView = vars.obtain<SkyViewLut>(kGenMoonView, [] { return std::make_shared<SkyViewLut>(Light::Moon); });
    l.aerial = vars.obtain<AerialPerspectiveLut>(kGenAerial, [] { return std::make_shared<AerialPerspectiveLut>(); });
    l.irradiance = vars.obtain<SkyIrradiance>(kGenIrradiance, [] { return std::make_shared<SkyIrradiance>(); });
    l.lightZenith = LightZenith::obtain(vars);
    l.eclipse = vars.obtain<EclipseSkyLut>(kGenEclipse, [] { return std::make_shared<EclipseSkyLut>(); });
    return l;
}

void SkyLuts::releaseGl() {
    for (SkyGenerator* g : std::initializer_list<SkyGenerator*>{transmittance.get(), multiScattering.get(), sh.get(), sunView.get(),
                                                                moonView.get(), aerial.get(), irradiance.get(), eclipse.get()})
        if (g) g->releaseGl();
}

LightZenith::LightZenith() : Generator("sky.light_zenith") {
    input(keys::sunDirection);
    input(keys::moonDirection);
    input(lightkeys::moonIlluminance);
    input(skykeys::moonLight, {.optional = true});  // the Sky's option: false = Sun only
    output(skykeys::sunCosZenith);
    output(skykeys::moonCosZenith);
    output(skykeys::moonLit);
}

std::shared_ptr<LightZenith> LightZenith::obtain(SkyVars& vars) {
    return vars.obtain<LightZenith>(kGenLightZenith, [] { return std::make_shared<LightZenith>(); });
}

void LightZenith::doRun(SkyVars& vars, const Logger&) {
    auto cosZenith = [](glm::dvec3 d, double fallback) {
        double l = glm::length(d);
        return l > 0 ? std::clamp(d.z / l, -1.0, 1.0) : fallback;
    };
    vars.set(skykeys::sunCosZenith, cosZenith(vars.get(keys::sunDirection), 1.0));
    vars.set(skykeys::moonCosZenith, cosZenith(vars.get(keys::moonDirection), -1.0));
    // The Moon lights the sky only while it gives light and the Sky's sky.moon option is on
    // (off: its sky-view table is not built, its light is left out of the irradiance).
    vars.set(skykeys::moonLit, vars.getOr(skykeys::moonLight, true) && glm::length(vars.get(lightkeys::moonIlluminance)) > 0.0);
}

namespace shared = glsl::dp::irradiance_shared;

glm::dvec3 cpuDiffuseIrradiance(const SkyModel& m, const SkyQuality& q, double h, double muS,
                                const std::function<glm::dvec3(double mu, double az, double nu)>& radiancePerLux) {
    // Midpoint rule in (cos^2 zenith, azimuth): E = int L cos(theta) dOmega over the upper
    // hemisphere; with x = cos^2(theta), cos(theta) dOmega = 0.5 dx dphi. Azimuth symmetric about
    // the light: integrate [0, pi] and double. Rays just below the geometric horizon of an
    // elevated observer are not counted (a horizontal surface does not see them). The samples,
    // their cosine to the light and their weight are the pass's text (atmosphere.shared.glsl);
    // only the order of the sum differs (the pass: 64 x SKY_IRRADIANCE_GROUPS strided partial
    // sums in float, added on the CPU; here one loop in double).
    (void)m;
    (void)h;
    const int nz = q.irradianceZenith, na = q.irradianceAzimuth;
    const double sinS = std::sqrt(std::max(0.0, 1.0 - muS * muS));
    glm::dvec3 E(0.0);
    for (int i = 0; i < nz; ++i)
        for (int j = 0; j < na; ++j) {
            const glm::dvec3 s = shared::atm_irradianceSample(i, j, nz, na);  // (mu, sin zenith, azimuth)
            E += radiancePerLux(s.x, s.z, shared::atm_cosViewLight(s.x, s.y, s.z, muS, sinS));
        }
    return E * shared::atm_irradianceWeight(nz, na);
}

}  // namespace welkin::generators
