// The Mie phase generator (rain_keys.hpp): CPU tables uploaded as textures.
#include <welkin/error.hpp>
#include <welkin/generators/cloud_keys.hpp>
#include <welkin/generators/rain_keys.hpp>
#include <welkin/log.hpp>

#include <epoxy/gl.h>

#include <chrono>
#include <string>

namespace welkin::generators {

DropDistribution dropDistributionFromVars(const SkyVars& vars) {
    const std::string kind = vars.get(rainkeys::distribution);
    const double rate = vars.get(rainkeys::rate);
    DropDistribution d;
    d.rateMmH = rate;
    if (kind == "gamma") {
        d.kind = DropDistribution::Kind::Gamma;
        d.effectiveRadiusM = vars.get(rainkeys::dropRadius);
        d.effectiveVariance = vars.get(rainkeys::dropVariance);
    } else if (kind == "marshall_palmer") {
        d.kind = DropDistribution::Kind::MarshallPalmer;
        if (rate <= 0.0) d.rateMmH = 1.0;  // the shape needs a rate; the water content is 0 anyway
    } else {
        throw Error("rain.distribution: '" + kind + "' is not one of gamma, marshall_palmer");
    }
    d.validate();
    return d;
}

MiePhaseGenerator::MiePhaseGenerator() : Generator("optics.mie_phase") {
    input(rainkeys::rate);
    input(rainkeys::dropRadius);
    input(rainkeys::dropVariance);
    input(rainkeys::distribution);
    input(rainkeys::tableQuality);
    input(cloudkeys::rainDensity, {.optional = true});
    output(rainkeys::phaseLut);
    output(rainkeys::phaseTable);
    output(rainkeys::scattering);
    output(rainkeys::extinction);
}

void MiePhaseGenerator::doDeclare(SkyVars& vars) {
    vars.declare(rainkeys::rate, 0.0);
    vars.declare(rainkeys::dropRadius, 0.5e-3);
    vars.declare(rainkeys::dropVariance, 0.02);
    vars.declare(rainkeys::distribution, std::string("gamma"));
    vars.declare(rainkeys::tableQuality, std::string("default"));
}

void MiePhaseGenerator::doRun(SkyVars& vars, const Logger& log) {
    const auto t0 = std::chrono::steady_clock::now();
    // No rain anywhere: no table (the first build of the 2-D table costs seconds), zero coefficients.
    const bool cloudRain = vars.has(cloudkeys::rainDensity) && vars.get(cloudkeys::rainDensity) > 0.0;
    if (vars.get(rainkeys::rate) <= 0.0 && !cloudRain) {
        vars.set(rainkeys::scattering, glm::dvec3(0.0));
        vars.set(rainkeys::extinction, glm::dvec3(0.0));
        if (!vars.has(rainkeys::phaseLut)) vars.set(rainkeys::phaseLut, TextureRef{});
        if (!vars.has(rainkeys::phaseTable)) vars.set(rainkeys::phaseTable, TextureRef{});
        tableSeconds_ = phaseSeconds_ = 0.0;
        return;
    }
    const MieTable::Quality q = MieTable::quality(vars.get(rainkeys::tableQuality));
    tableSeconds_ = 0.0;
    if (!table_ || table_->hash() != [&] { MieTable t; t.q = q; return t.hash(); }() || tableTex_.id() == 0) {
        table_ = &MieTable::cached(q);
        if (!table_->fromCache && table_->buildSeconds > 0.0)
            log.info("optics.mie_phase: built the " + q.name + " Mie table in " + std::to_string(table_->buildSeconds) +
                     " s (cached in " + MieTable::cachePath(q) + ")");
        tableTex_ = gl::Texture2D(q.angles, q.radii, GL_RGBA32F);
        std::vector<float> px(std::size_t(q.angles) * std::size_t(q.radii) * 4);
        for (std::size_t i = 0; i < table_->phase.size(); ++i) {
            px[4 * i + 0] = table_->phase[i].r;
            px[4 * i + 1] = table_->phase[i].g;
            px[4 * i + 2] = table_->phase[i].b;
            px[4 * i + 3] = 1.0f;
        }
        tableTex_.upload(GL_RGBA, GL_FLOAT, px.data());
        tableTex_.setFilter(GL_LINEAR);
        tableTex_.setWrap(GL_CLAMP_TO_EDGE);
        vars.publish(rainkeys::phaseTable, tableTex_.ref());
        tableSeconds_ = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    }
    const auto t1 = std::chrono::steady_clock::now();
    const DropDistribution d = dropDistributionFromVars(vars);
    phase_ = integrate(*table_, d, SunDisk::Uniform);
    // Coefficients per unit water: the distribution at 1 mm/h, divided by its water content.
    DropDistribution unit = d;
    unit.rateMmH = 1.0;
    const MiePhase1D u = integrate(*table_, unit, SunDisk::Point);
    scaPerWater_ = u.scatteringPerM / liquidWaterContent(1.0);
    extPerWater_ = u.extinctionPerM / liquidWaterContent(1.0);
    const int A = int(phase_.phase.size());
    if (lut_.id() == 0 || lut_.width() != A) {
        lut_ = gl::Texture1D(A, GL_RGBA32F);
        lut_.setFilter(GL_LINEAR);
        lut_.setWrap(GL_CLAMP_TO_EDGE);
    }
    std::vector<float> px(std::size_t(A) * 4);
    for (int a = 0; a < A; ++a) {
        px[4 * std::size_t(a) + 0] = phase_.phase[std::size_t(a)].r;
        px[4 * std::size_t(a) + 1] = phase_.phase[std::size_t(a)].g;
        px[4 * std::size_t(a) + 2] = phase_.phase[std::size_t(a)].b;
        px[4 * std::size_t(a) + 3] = 1.0f;
    }
    lut_.upload(GL_RGBA, GL_FLOAT, px.data());
    vars.publish(rainkeys::phaseLut, lut_.ref());
    const double W = liquidWaterContent(vars.get(rainkeys::rate));
    vars.set(rainkeys::scattering, scaPerWater_ * W);
    vars.set(rainkeys::extinction, extPerWater_ * W);
    phaseSeconds_ = std::chrono::duration<double>(std::chrono::steady_clock::now() - t1).count();
}

void MiePhaseGenerator::doRelease() {
    lut_ = gl::Texture1D();
    tableTex_ = gl::Texture2D();
    table_ = nullptr;
}

}  // namespace welkin::generators
