// CloudSkyShadow: the clouds' shadow on the atmosphere's in-scattering (crepuscular rays, the
// dimmer air below a deck). For every view direction from the observer it integrates the single
// scattering of the shadowing light (the Sun, or the Moon at night: the light of
// clouds.shadow_map) that the clouds' shadow removes, and publishes it as the optional
// sky.shadow_loss_lut / sky.shadow_loss_mie_lut (generic keys of sky_luts.hpp), which the Sky
// element subtracts from that light's sky-view radiance. Without this generator the keys do not
// exist and the sky is exactly what it was (no fetch, same program).
//
//   // The Clouds element adds it with the shadow map; a host with its own clouds' shadow map:
//   processor.addGenerator(welkin::generators::CloudShadowMap::obtain(processor.vars()));
//   processor.addGenerator(welkin::generators::CloudSkyShadow::obtain(processor.vars()));
//
// Model (skyelements/clouds/README.md, "The clouds' shadow on the atmosphere's in-scattering"): along each
// direction, the segment of the ray below the cloud top (clouds.top_m) and within reach of the
// map (clouds.shadow_extent_m) is marched in kSkyShadowSteps equal steps (midpoint rule), summing
// T_view sigma_s T_light P (1 - S) ds for Rayleigh (phase applied) and Mie (phase per pixel), with
// the sky-view march's delta-M view transmittance and light transmittance
// (generators/atmosphere.glsl), and S the shadow map's transmittance of the direct light at the
// point (traced to the ground along clouds.shadow_light_direction; 1 outside the map and above the
// top; inside the layer the map's value to the power of the fraction of the layer above the
// point). A ray ending on the ground inside the map also loses the ground's direct term. Multiple
// scattering is not shadowed: it is the diffuse light of the whole sky, which a broken deck dims
// little and whose shadowing would need the clouds in the multiple-scattering LUT.
//
// Table: 2 x the sky view's width over 2 pi of azimuth (the sky view covers pi), the sky view's
// height and latitude mapping, RGBA32F (RGBA16F at SkyQuality::halfFloat). Rebuilt when the
// shadow map, its light, the lights, the observer's height, the transmittance LUT or the
// atmosphere changes, or when the wind moved the clouds by more than kSkyShadowOffsetTolerance.
#pragma once
#include <vector>
#include <welkin/generators/sky_luts.hpp>

#include <functional>
#include <memory>
#include <utility>

namespace welkin::generators {

/// March steps along the shadowed segment of each direction (<= ~40 km: ~1.2 km steps, shafts
/// of a few km stay resolved).
inline constexpr int kSkyShadowSteps = 32;
/// A wind shift (clouds.weather_offset_m) below this keeps the table, m: one default shadow-map
/// texel (156 m); the shafts then lag the clouds by less than a texel.
inline constexpr double kSkyShadowOffsetTolerance = 156.0;

/// The inputs of the last table (also what the tests reproduce).
struct SkyShadowInputs {
    double observerHeightM = 0.0;
    glm::dvec3 light{0, 0, 1};     ///< the shadowed light, unit ENU
    glm::dvec3 mapLight{0, 0, 1};  ///< clouds.shadow_light_direction
    glm::dvec2 shift{0.0};         ///< clouds.weather_offset_m - clouds.shadow_offset_m, m
    double extentM = 40e3;         ///< clouds.shadow_extent_m
    double bottomM = 2000.0, topM = 3000.0;
    bool moon = false;             ///< the light is the Moon
    int steps = kSkyShadowSteps;   ///< march steps
};

namespace cpu {
/// The double-precision twin of one texel of cloud_sky_shadow.glsl: (Rayleigh with its phase +
/// the ground's direct term, Mie without its phase) removed per lux of the light, for the unit
/// ENU view direction `dir`; `ground`: the texel's row is in the sky view's ground half. `T`: the
/// transmittance LUT (cpu::transmittanceLut); `deltaM`: the delta-M forward fraction of the sky
/// view's march (cpu::phaseMoments(m, q.shBands).forward); `angularRadius`: the light's, rad;
/// `map(uv)`: the shadow map's transmittance at map coordinates uv in [0, 1]^2.
std::pair<glm::dvec3, glm::dvec3> skyShadowLoss(const SkyModel& m, const Lut2D& T, double deltaM, const SkyShadowInputs& in,
                                                double angularRadius, glm::dvec3 dir, bool ground,
                                                const std::function<double(glm::dvec2)>& map);
}  // namespace cpu

class CloudSkyShadow final : public SkyGenerator {
public:
    CloudSkyShadow();
    /// The shared instance of `vars` (created on first request).
    static std::shared_ptr<CloudSkyShadow> obtain(SkyVars& vars);
    void releaseGl() override;
    /// The last run's table, its Mie part and the inputs it was built with (tests).
    const gl::Texture2D& table() const { return loss_; }
    const gl::Texture2D& mieTable() const { return lossMie_; }
    const SkyShadowInputs& inputs() const { return in_; }
    /// Parts of time-sliced rebuilds drawn so far (clouds.shadow_slices), for tests.
    int slicesBuilt() const { return slicesBuilt_; }

private:
    void doRun(SkyVars& vars, const Logger& log) override;
    gl::Texture2D loss_, lossMie_;
    gl::Framebuffer fbo_;
    gl::Program prog_;
    SkyShadowInputs in_;
    // Time-sliced rebuilds (clouds.shadow_slices with render.interactive): the tables being built,
    // the inputs, shadow map and light they are built with, the next row; shown when complete.
    gl::Texture2D backLoss_, backLossMie_;
    gl::Framebuffer backFbo_;
    bool slicing_ = false;
    int sliceRow_ = 0;
    SkyShadowInputs sliceIn_;
    unsigned sliceMap_ = 0;
    std::vector<double> setup_;  // what the shown tables were built with, but the lights and the map
    int slicesBuilt_ = 0;
};

}  // namespace welkin::generators
