// Aerial perspective volume generator (GPU pass aerial_perspective.glsl; CPU twin
// cpu::aerialTexel below).
#include <welkin/embedded/generator_shaders.hpp>
#include <welkin/error.hpp>
#include <welkin/generators/sky_luts.hpp>
#include <welkin/gl/shader.hpp>
#include <welkin/keys.hpp>

#include <epoxy/gl.h>

#include <algorithm>
#include <cmath>

namespace welkin::generators {

AerialPerspectiveLut::AerialPerspectiveLut() : SkyGenerator("sky.aerial_perspective") {
    input(skykeys::transmittanceLuts);
    input(skykeys::multiScatteringLuts);
    input(skykeys::shLuts);
    input(keys::observerHeight);
    input(keys::sunDirection);
    output(skykeys::aerialInscatter);
    output(skykeys::aerialTransmittance);
}

void AerialPerspectiveLut::releaseGl() {
    inscatter_ = {};
    transmittance_ = {};
    inscatterK_ = {};
    transmittanceK_ = {};
    prog_ = {};
    releaseCommon();
}

void AerialPerspectiveLut::doRun(SkyVars& vars, const Logger&) {
    prepare(vars);
    const int n = q_.aerialSize;
    if (!inscatter_ || inscatter_.width() != n) {
        inscatter_ = gl::Texture3D(n, n, n, GL_RGBA32F);
        transmittance_ = gl::Texture3D(n, n, n, GL_RGBA32F);
        for (gl::Texture3D* t : {&inscatter_, &transmittance_}) {
            t->setFilter(GL_LINEAR);
            t->setWrap(GL_CLAMP_TO_EDGE);
        }
    }
    if (!prog_ || progBands_ != q_.shBands) {
        progBands_ = q_.shBands;
        prog_ = gl::ProgramBuilder("AerialPerspectiveLut")
                    .define("ATM_USE_TRANSMITTANCE")
                    .define("ATM_USE_MULTISCATTERING")
                    .define("ATM_MS_DIRECTIONAL")
                    .define("ATM_SH_BANDS", q_.shBands)
                    .compute("generators/atmosphere.glsl", embedded::generator_shaders("atmosphere.glsl"))
                    .compute("generators/aerial_perspective.glsl", embedded::generator_shaders("aerial_perspective.glsl"))
                    .build();
    }
    const double Ht = model_.topRadius - model_.bottomRadius;
    const double h = std::clamp(vars.getOr(keys::observerHeight, 0.0), 0.0, Ht);
    glm::dvec3 dir = vars.getOr(keys::sunDirection, glm::dvec3(0, 0, 1));
    const double muS = std::clamp(dir.z / std::max(glm::length(dir), 1e-12), -1.0, 1.0);
    if (spectral_ && (!inscatterK_ || inscatterK_.width() != n)) {
        inscatterK_ = gl::Texture3D(n, n, n, GL_RGBA32F);
        transmittanceK_ = gl::Texture3D(n, n, n, GL_RGBA32F);
    }
    const skykeys::TextureList T = vars.get(skykeys::transmittanceLuts), MS = vars.get(skykeys::multiScatteringLuts),
                               SH = vars.get(skykeys::shLuts);
    const int K = triples();
    if (int(T->size()) != K || int(MS->size()) != K || int(SH->size()) != K)
        throw Error("AerialPerspectiveLut: input LUTs for " + std::to_string(T->size()) + " triples, expected " + std::to_string(K));
    for (int k = 0; k < K; ++k) {
        // Spectral mode: the triple's volumes go to the scratch pair, then are added to the RGB
        // pair through its matrix (transmittance too: the solar-weighted transmittance).
        const gl::Texture3D& in = spectral_ ? inscatterK_ : inscatter_;
        const gl::Texture3D& tr = spectral_ ? transmittanceK_ : transmittance_;
        useTriple(k);
        glBindTextureUnit(gl::binding::kTransmittanceLut, (*T)[size_t(k)].id);
        glBindTextureUnit(gl::binding::kMultiScatteringLut, (*MS)[size_t(k)].id);
        glBindTextureUnit(gl::binding::kShLut, (*SH)[size_t(k)].id);
        glBindImageTexture(gl::binding::kLutImage, in.id(), 0, GL_TRUE, 0, GL_WRITE_ONLY, GL_RGBA32F);
        glBindImageTexture(gl::binding::kSecondLutImage, tr.id(), 0, GL_TRUE, 0, GL_WRITE_ONLY, GL_RGBA32F);
        prog_.use();
        prog_.set("u_h", float(h));
        prog_.set("u_muS", float(muS));
        prog_.set("u_size", n);
        prog_.set("u_substeps", q_.aerialSteps);
        prog_.set("u_maxDistance", float(q_.aerialMaxDistance));
        prog_.set("u_scale", float(kLutScale));
        prog_.set("u_angular", float(model_.sunAngularRadius));
        glDispatchCompute((n + 7) / 8, (n + 7) / 8, 1);
        glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
        if (spectral_) {
            combine(inscatterK_, inscatter_, k);
            combine(transmittanceK_, transmittance_, k);
        }
    }
    vars.publish(skykeys::aerialInscatter, inscatter_.ref());
    vars.publish(skykeys::aerialTransmittance, transmittance_.ref());
}

namespace cpu {
AerialTexel aerialTexel(const SkyModel& m, const SkyQuality& q, const Lut2D& T, const MsField& MS, double h, double muS, int i,
                        int j, int k) {
    const int n = q.aerialSize;
    glm::dvec2 ma = skyViewMuAz(m, h, {(i + 0.5) / n, (j + 0.5) / n}, n, n);
    double mu = ma.x, az = ma.y;
    double sinV = std::sqrt(std::max(1.0 - mu * mu, 0.0)), sinS = std::sqrt(std::max(1.0 - muS * muS, 0.0));
    double nu = std::clamp(sinV * sinS * std::cos(az) + mu * muS, -1.0, 1.0);
    bool ground = j < n / 2;
    double dEnd = ground ? distanceToBottom(m, h, mu) : distanceToTop(m, h, mu);
    double r = m.bottomRadius + h;
    double phaseR = rayleighPhase(nu), phaseM = miePhase(nu, m.mieG, m.miePhase);
    const PhaseMoments moments = phaseMoments(m, MS.bands);
    glm::dvec3 L(0.0), thr(1.0), thrD(1.0);
    double t0 = 0.0;
    for (int kk = 0; kk <= k; ++kk) {
        double f = double(kk + 1) / n;
        double t1 = std::min(q.aerialMaxDistance * f * f, dEnd);
        double dt = (t1 - t0) / q.aerialSteps;
        for (int s = 0; s < q.aerialSteps && dt > 0.0; ++s) {
            double t = t0 + (s + 0.5) * dt;
            double hp = heightAt(m, h, mu, t);
            double rp = m.bottomRadius + hp;
            double muSp = std::clamp((r * muS + t * nu) / rp, -1.0, 1.0);
            glm::dvec3 sR = m.scatteringRayleigh(hp), sM = m.scatteringMie(hp), sigmaT = m.extinction(hp);
            glm::dvec3 sigmaD = sigmaT - moments.forward * sM;
            glm::dvec3 seg;
            for (int c = 0; c < 3; ++c) seg[c] = sigmaD[c] * dt > 1e-7 ? (1.0 - std::exp(-sigmaD[c] * dt)) / sigmaD[c] : dt;
            glm::dvec3 Tl = transmittanceToLight(m, T, hp, muSp, m.sunAngularRadius);
            double muP = std::clamp((r * mu + t) / rp, -1.0, 1.0);
            glm::dvec3 ms = msInscatter(m, MS, moments, hp, muP, muSp, nu, sR, sM);
            L += thrD * ((sR * phaseR + sM * phaseM) * Tl + ms) * seg;
            thr *= glm::exp(-sigmaT * dt);
            thrD *= glm::exp(-sigmaD * dt);
        }
        t0 = std::max(t0, t1);
    }
    return {L, thr};
}
}  // namespace cpu

}  // namespace welkin::generators
