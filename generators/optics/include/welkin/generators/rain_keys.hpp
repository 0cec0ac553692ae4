// Rain and fog drops for the optics generators and the Rainbow element: the keys and the
// generator that turns them into phase tables (GL textures) and bulk coefficients.
//
//   vars.set(welkin::generators::rainkeys::rate, 5.0);             // mm/h (0: no rain)
//   vars.set(welkin::generators::rainkeys::dropRadius, 0.5e-3);    // effective radius, m
//   auto gen = std::make_shared<welkin::generators::MiePhaseGenerator>();  // element's addGenerator
//   // after it ran: rain.phase_lut (1-D, RGBA32F, rgb = phase per channel in 1/sr, by
//   // welkin_mieUFromAngle(theta)), rain.scattering_per_m / rain.extinction_per_m (1/m per channel)
//
// The 2-D table (rain.phase_table: x = angle texel, y = radius, log-spaced 5 um .. 2 mm; rgb the
// phase per channel, a unused) is the one-time exact-Mie build of MieTable::cached (on disk after
// the first run); the 1-D table is its integral over the distribution (a few ms): it is rebuilt
// only when a drop key changes. The rain rate only scales the coefficients.
#pragma once
#include <welkin/element.hpp>
#include <welkin/generators/mie_tables.hpp>
#include <welkin/gl/objects.hpp>

#include <memory>

namespace welkin::generators {

namespace rainkeys {
inline const Key<double> rate{"rain.rate_mm_h", Range{0, 200}, "rain rate of the user's rain curtain (0: no rain); sets the water content 0.0889 R^0.84 g/m^3", "mm/h"};
inline const Key<double> dropRadius{"rain.drop_radius_m", Range{5e-6, 2e-3}, "effective radius of the drops (gamma distribution): 10-50 um fog, 0.1-2 mm rain"};
inline const Key<double> dropVariance{"rain.drop_variance", Range{1e-3, 0.5}, "effective variance of the gamma drop-size distribution (Hansen 1971)", "1"};
inline const Key<std::string> distribution{"rain.distribution", Choices{{"gamma", "marshall_palmer"}}, "drop sizes: 'gamma' (rain.drop_radius_m, rain.drop_variance) or 'marshall_palmer' (from the rate)"};
inline const Key<std::string> tableQuality{"rain.table_quality", Choices{{"low", "default", "high"}}, "Mie table quality: low, default or high (skyelements/rainbow/README.md: build times)"};
inline const Key<TextureRef> phaseLut{"rain.phase_lut", "1-D phase LUT of the current drops: rgb phase per channel, 1/sr, by welkin_mieUFromAngle"};
inline const Key<TextureRef> phaseTable{"rain.phase_table", "2-D Mie phase table: angle texel x drop radius (5 um .. 2 mm, log), rgb 1/sr"};
inline const Key<glm::dvec3> scattering{"rain.scattering_per_m", Range{0, 1e3}, "scattering coefficient of the rain at rain.rate_mm_h", "1/m"};
inline const Key<glm::dvec3> extinction{"rain.extinction_per_m", Range{0, 1e3}, "extinction coefficient of the rain at rain.rate_mm_h", "1/m"};
}  // namespace rainkeys

/// The distribution the keys describe (throws welkin::Error naming the key on a bad value).
DropDistribution dropDistributionFromVars(const SkyVars& vars);

/// Writes rain.phase_lut, rain.phase_table, rain.scattering_per_m and rain.extinction_per_m.
class MiePhaseGenerator final : public Generator {
public:
    MiePhaseGenerator();
    /// Coefficients of the current distribution per kg/m^3 of liquid water (1/m per channel):
    /// multiply by liquidWaterContent(rate) for any rain rate (the clouds' rain).
    glm::dvec3 scatteringPerWater() const { return scaPerWater_; }
    glm::dvec3 extinctionPerWater() const { return extPerWater_; }
    const MiePhase1D& phase1D() const { return phase_; }
    /// Seconds spent in the last run on the 1-D table (integration + upload) and on obtaining the
    /// 2-D table (0 when it was in memory).
    double lastPhaseSeconds() const { return phaseSeconds_; }
    double lastTableSeconds() const { return tableSeconds_; }

private:
    void doRun(SkyVars& vars, const Logger& log) override;
    void doRelease() override;
    void doDeclare(SkyVars& vars) override;

    const MieTable* table_ = nullptr;
    gl::Texture1D lut_;
    gl::Texture2D tableTex_;
    MiePhase1D phase_;
    glm::dvec3 scaPerWater_{0.0}, extPerWater_{0.0};
    double phaseSeconds_ = 0.0, tableSeconds_ = 0.0;
};

}  // namespace welkin::generators
