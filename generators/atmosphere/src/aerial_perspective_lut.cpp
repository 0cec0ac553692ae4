// Aerial perspective volume generator (GPU pass aerial_perspective.glsl; CPU twin
// cpu::aerialTexel below).
#include <welkin/embedded/atmosphere_shaders.hpp>
#include <welkin/error.hpp>
#include <welkin/generators/sky_luts.hpp>
#include <welkin/generators/sky_model.hpp>
#include <welkin/gl/shader.hpp>
#include <welkin/glsl_cpp.hpp>
#include <welkin/keys.hpp>

#include <epoxy/gl.h>

#include <algorithm>
#include <cmath>

// skyViewTexelViewS() (a texel's view): the pass's text (atmosphere.shared.glsl) in double.
namespace welkin::glsl::dp::aerial_shared {
#define ATM_SEGMENT_LINEAR 1e-7  // atm_segmentFactor()'s linear limit in double (as sky_model.cpp; unused here)
#include "atmosphere.shared.glsl"
}  // namespace welkin::glsl::dp::aerial_shared

namespace welkin::generators {

AerialPerspectiveLut::AerialPerspectiveLut() : SkyGenerator("sky.aerial_perspective") {
    input(skykeys::transmittanceLuts);
    input(skykeys::multiScatteringLuts);
    input(skykeys::shLuts);
    input(skykeys::keyframeBudget, {.optional = true});  // the background prefill's parts per frame
    input(keys::observerHeight);
    input(skykeys::sunCosZenith, {.tolerance = kCosZenithTolerance});  // the volume's azimuth is from the Sun
    input(skykeys::aerialVolume, {.optional = true});  // the Sky's option: nothing is built while false
    input(keys::hostScene, {.optional = true});        // ... or while no host asks for its scene's aerial perspective
    output(skykeys::aerialInscatter);
    output(skykeys::aerialTransmittance);
}

void AerialPerspectiveLut::releaseGl() {
    inscatter_ = {};
    transmittance_ = {};
    inscatterK_ = {};
    transmittanceK_ = {};
    prog_ = {};
    slots_.clear();
    blendProg_ = {};
    toLogProg_ = {};
    keyframes_.reset();
    shownOnce_ = false;
    releaseCommon();
}

void AerialPerspectiveLut::doRun(SkyVars& vars, const Logger&) {
    // Pay only for what is used: no volume unless asked for (a host's geometry to fog).
    if (!vars.getOr(skykeys::aerialVolume, false) && !vars.getOr(keys::hostScene, false)) return;
    prepare(vars);
    const int n = q_.aerialSize;
    auto make = [n](gl::Texture3D& t) {
        t = gl::Texture3D(n, n, n, GL_RGBA32F);
        t.setFilter(GL_LINEAR);
        t.setWrap(GL_CLAMP_TO_EDGE);
    };
    // Keyframes as in SkyViewLut (light_keyframes.hpp): the same options and elevations, so both
    // follow the same schedule. A keyframe holds the in-scattering only: the transmittance along
    // the view rays does not depend on the light, and every build writes it into the shown one
    // (the same values whatever the elevation; after a reset the first build is whole).
    LightKeyframes::Options ko{.stepRad = q_.keyframeStepRad, .coarseStepRad = q_.keyframeCoarseStepRad, .chunks = spectral_ ? 1 : std::max(1, q_.keyframeChunks),
                               .slots = keyframeSlots(q_, &keyframes_), .stillMuS = kCosZenithTolerance, .stillRuns = kKeyframeStillRuns,
                               .prefill = q_.keyframePrefill,
                               .prefillChunksPerRun = q_.keyframePrefill ? vars.getOr(skykeys::keyframeBudget, kKeyframeBudgetDefault) : 0};
    keyframes_.setOptions(ko);
    const bool resized = !inscatter_ || inscatter_.width() != n;
    if (resized) {
        make(inscatter_);
        make(transmittance_);
        slots_.clear();
        keyframes_.reset();
    }
    if (!prog_ || progBands_ != q_.shBands) {
        progBands_ = q_.shBands;
        prog_ = gl::ProgramBuilder("AerialPerspectiveLut")
                    .define("ATM_USE_TRANSMITTANCE")
                    .define("ATM_USE_MULTISCATTERING")
                    .define("ATM_MS_DIRECTIONAL")
                    .define("ATM_SH_BANDS", q_.shBands)
                    .compute("generators/atmosphere.glsl", embedded::atmosphere_shaders("atmosphere.glsl"))
                    .compute("generators/aerial_perspective.glsl", embedded::atmosphere_shaders("aerial_perspective.glsl"))
                    .build();
    }
    if (!blendProg_)
        blendProg_ = gl::ProgramBuilder("AerialPerspectiveLut blend")
                         .define("AERIAL_BLEND")
                         .compute("generators/atmosphere.glsl", embedded::atmosphere_shaders("atmosphere.glsl"))
                         .compute("generators/light_blend.glsl", embedded::atmosphere_shaders("light_blend.glsl"))
                         .build();
    const double Ht = model_.topRadius - model_.bottomRadius;
    const double h = std::clamp(vars.getOr(keys::observerHeight, 0.0), 0.0, Ht);
    const double muS = std::clamp(vars.get(skykeys::sunCosZenith), -1.0, 1.0);
    {
        std::vector<uint64_t> v;
        for (const KeyInfo& k : inputs())
            if (k.name != skykeys::sunCosZenith.name()) v.push_back(vars.version(k.name));
        v.push_back(uint64_t(q_.aerialSteps));
        v.push_back(uint64_t(std::llround(q_.aerialMaxDistance)));
        v.push_back(uint64_t(std::llround(q_.keyframeStepRad * 1e9)));
        v.push_back(uint64_t(std::llround(q_.keyframeCoarseStepRad * 1e9)));
        if (v != validFor_ || resized) keyframes_.reset();
        validFor_ = std::move(v);
    }
    if (spectral_ && (!inscatterK_ || inscatterK_.width() != n)) {
        inscatterK_ = gl::Texture3D(n, n, n, GL_RGBA32F);
        transmittanceK_ = gl::Texture3D(n, n, n, GL_RGBA32F);
    }
    plan_ = keyframes_.plan(muS);
    auto allocateSlots = [&] {
        while (int(slots_.size()) < keyframes_.slotCount()) {
            make(slots_.emplace_back());
            slots_.back().setFilter(GL_NEAREST);
        }
    };
    // Work groups [g0, g1) of the (n/8)^2 that make slot `s`'s table at cos zenith `muS`;
    // `complete`: the table is whole now, converted in place to log radiance for the blend.
    auto buildGroups = [&](int s, double buildMuS, int g0, int g1, bool complete) {
        const skykeys::TextureList T = vars.get(skykeys::transmittanceLuts), MS = vars.get(skykeys::multiScatteringLuts),
                                   SH = vars.get(skykeys::shLuts);
        const int K = triples();
        if (int(T->size()) != K || int(MS->size()) != K || int(SH->size()) != K)
            throw Error("AerialPerspectiveLut: input LUTs for " + std::to_string(T->size()) + " triples, expected " + std::to_string(K));
        auto& sl = slots_[size_t(s)];
        const int gx = (n + 7) / 8;
        for (int k = 0; k < K && g1 > g0; ++k) {
            // Spectral mode: the triple's volumes go to the scratch pair, then are added to the
            // slot's pair through its matrix (transmittance too: the solar-weighted transmittance).
            const gl::Texture3D& in = spectral_ ? inscatterK_ : sl;
            const gl::Texture3D& tr = spectral_ ? transmittanceK_ : transmittance_;
            useTriple(k);
            glBindTextureUnit(gl::binding::kTransmittanceLut, (*T)[size_t(k)].id);
            glBindTextureUnit(gl::binding::kMultiScatteringLut, (*MS)[size_t(k)].id);
            glBindTextureUnit(gl::binding::kShLut, (*SH)[size_t(k)].id);
            glBindImageTexture(gl::binding::kLutImage, in.id(), 0, GL_TRUE, 0, GL_WRITE_ONLY, GL_RGBA32F);
            glBindImageTexture(gl::binding::kSecondLutImage, tr.id(), 0, GL_TRUE, 0, GL_WRITE_ONLY, GL_RGBA32F);
            prog_.use();
            prog_.set("u_h", float(h));
            prog_.set("u_muS", float(buildMuS));
            prog_.set("u_size", n);
            prog_.set("u_substeps", q_.aerialSteps);
            prog_.set("u_maxDistance", float(q_.aerialMaxDistance));
            prog_.set("u_scale", float(kLutScale));
            prog_.set("u_angular", float(model_.sunAngularRadius));
            prog_.set("u_groupOffset", g0);
            prog_.set("u_groupsX", gx);
            glDispatchCompute(GLuint(g1 - g0), 1, 1);
            glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
            if (spectral_) {
                combine(inscatterK_, sl, k);
                combine(transmittanceK_, transmittance_, k);
            }
        }
        if (complete) {
            if (!toLogProg_)
                toLogProg_ = gl::ProgramBuilder("AerialPerspectiveLut keyframe to log")
                                 .define("KEYFRAME_TO_LOG")
                                 .define("KEYFRAME_3D")
                                 .compute("generators/light_blend.glsl", embedded::atmosphere_shaders("light_blend.glsl"))
                                 .build();
            glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
            toLogProg_.use();
            glUniform3i(glGetUniformLocation(toLogProg_.id(), "u_size"), n, n, n);
            glBindImageTexture(gl::binding::kLutImage, sl.id(), 0, GL_TRUE, 0, GL_READ_WRITE, GL_RGBA32F);
            glDispatchCompute(GLuint((n + 7) / 8), GLuint((n + 7) / 8), GLuint(n));
            glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
        }
    };
    allocateSlots();
    const int G = ((n + 7) / 8) * ((n + 7) / 8);
    if (plan_.build >= 0) {
        // This run's work groups: chunk c of m covers groups [c G / m, (c + 1) G / m).
        const int m = ko.chunks;
        buildGroups(plan_.build, plan_.buildMuS, plan_.chunkBegin * G / m, plan_.chunkEnd * G / m, plan_.chunkEnd == m);
    }
    // Prefill (SkyQuality::keyframePrefill) with sky.keyframe_budget 0: the grid tables queued
    // when the light first moved, built whole now (else plan() spreads them).
    for (LightKeyframes::Prefill pf = keyframes_.nextPrefill(); pf.slot >= 0; pf = keyframes_.nextPrefill()) {
        allocateSlots();
        buildGroups(pf.slot, pf.muS, 0, G, true);
    }
    // Unchanged since the last mix (a run that only counts the light's rest): kept as it is.
    if (plan_.unchanged && shownOnce_) {
        if (keyframes_.pending()) runAgain();
        return;
    }
    shownOnce_ = true;
    // The shown volume from complete slots only (unused inputs repeat the first, weight 0).
    const int units[4] = {gl::binding::kBlendA, gl::binding::kBlendAerialB, gl::binding::kBlendAerialC, gl::binding::kBlendAerialD};
    glm::vec4 w(0.0f);
    for (int i = 0; i < 4; ++i) {
        glBindTextureUnit(GLuint(units[i]), slots_[size_t(i < plan_.count ? plan_.slot[size_t(i)] : plan_.slot[0])].id());
        w[i] = i < plan_.count ? float(plan_.weight[size_t(i)]) : 0.0f;
    }
    glBindImageTexture(gl::binding::kLutImage, inscatter_.id(), 0, GL_TRUE, 0, GL_WRITE_ONLY, GL_RGBA32F);
    blendProg_.use();
    blendProg_.set("u_w", w);
    blendProg_.set("u_muS", float(muS));
    blendProg_.set("u_size", n);
    glDispatchCompute(GLuint((n + 7) / 8), GLuint((n + 7) / 8), GLuint(n));
    glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
    if (keyframes_.pending()) runAgain();
    vars.publish(skykeys::aerialInscatter, inscatter_.ref());
    vars.publish(skykeys::aerialTransmittance, transmittance_.ref());
}

namespace cpu {
AerialTexel aerialTexel(const SkyModel& m, const SkyQuality& q, const Lut2D& T, const MsField& MS, double h, double muS, int i,
                        int j, int k) {
    const int n = q.aerialSize;
    const glm::dvec3 view = glsl::dp::aerial_shared::skyViewTexelViewS(skyViewHorizonS(m, h), {(i + 0.5) / n, (j + 0.5) / n},
                                                                       glm::dvec2(n), muS);  // the pass's text
    const double mu = view.x, nu = view.z;
    // Ground rays run on through air no lower than the ground (the host's terrain stops them:
    // atmosphere.glsl's atm_raySampleAir).
    bool ground = j < n / 2;
    double dEnd = ground ? q.aerialMaxDistance : distanceToTop(m, h, mu);
    glm::dvec3 L(0.0), thr(1.0), thrD(1.0);
    double t0 = 0.0;
    for (int kk = 0; kk <= k; ++kk) {
        double f = double(kk + 1) / n;
        double t1 = std::min(q.aerialMaxDistance * f * f, dEnd);
        aerialSlice(m, T, MS, h, mu, muS, nu, t0, t1, q.aerialSteps, ground, L, thr, thrD);  // the pass's slice (atm_aerialSlice)
        t0 = std::max(t0, t1);
    }
    return {L, thr};
}
}  // namespace cpu

}  // namespace welkin::generators
