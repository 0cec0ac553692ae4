// AtmosphereLights: the Sun's and the Moon's light for every element, as one shared generator.
//
//   auto lights = welkin::generators::AtmosphereLights::obtain(vars);  // one per SkyVars
//   element.addGenerator(lights);                        // in doInit(); the processor runs it
//   glm::dvec3 E = vars.get(welkin::generators::lightkeys::sunIlluminance);   // lux, above the air
//   glm::dvec3 T = vars.get(welkin::generators::lightkeys::sunTransmittance); // observer -> Sun
//   glm::dvec3 L = vars.get(welkin::generators::lightkeys::sunDiskRadiance);  // cd/m^2, unreddened
//
// Published separately (illuminance outside the atmosphere, transmittance to the observer, the
// disk's unreddened mean radiance) so that an element drawn behind the Sky (a Sun disk, a star)
// is reddened exactly once: by the Sky's per-pixel transmittance when the Sky is composited over
// it, or by the *_transmittance keys when it is drawn without a Sky. Per linear-sRGB channel; Y
// is the photometric quantity (lux, cd/m^2).
//
// The Sun: the atmosphere's solar spectrum (Atmosphere::solarIrradiance through CIE 1931) at
// 1 AU, scaled by (1 AU / sun.distance_m)^2; the disk's mean radiance E / (pi alpha^2) with alpha
// = sun.angular_radius_rad (or the atmosphere's).
//
// The Moon (one law for every element): the illuminance of its visual magnitude m (the astronomy's
// moon.magnitude: Allen's law 0.21 + 5 log10(r delta) + 0.026 |i| + 4e-9 i^4, i the phase angle in
// degrees; or the same law from moon.phase_angle_rad and moon.distance_m when no astronomy runs),
// E = 2.54e-6 lux x 10^(-0.4 m) (astro::magnitude::illuminanceLux), with the colour of sunlight
// reflected by the lunar regolith: the solar spectrum times a reflectance rising linearly with
// wavelength, R(lambda) ~ 1 + 0.0020 (lambda - 550 nm), chosen to reproduce the Moon's colour
// index B-V = 0.92 against the Sun's 0.65 (Allen's Astrophysical Quantities, 4th ed., 12.2 and
// 14.7), times moon.eclipse_factor (the fraction of sunlight reaching the Moon: a lunar eclipse,
// written by the astronomy; 1 without it). Disk radiance: E / (pi alpha_moon^2) averaged over the whole disk (lit and dark parts).
//
// One planet radius: planet.radius_m is published from the atmosphere (Atmosphere::bottomRadiusM).
#pragma once
#include <welkin/element.hpp>
#include <welkin/generators/atmosphere.hpp>
#include <welkin/generators/sky_model.hpp>
#include <welkin/keys.hpp>

#include <memory>
#include <optional>

namespace welkin::generators {

namespace lightkeys {
// The Sun's and Moon's light keys are shared world state, defined by the engine (welkin/keys.hpp);
// these names stay for the code that used them here.
inline const Key<glm::dvec3>& sunIlluminance = welkin::keys::sunIlluminance;
inline const Key<glm::dvec3>& sunTransmittance = welkin::keys::sunTransmittance;
inline const Key<glm::dvec3>& sunDiskRadiance = welkin::keys::sunDiskRadiance;
inline const Key<glm::dvec3>& moonIlluminance = welkin::keys::moonIlluminance;
inline const Key<glm::dvec3>& moonTransmittance = welkin::keys::moonTransmittance;
inline const Key<glm::dvec3>& moonDiskRadiance = welkin::keys::moonDiskRadiance;
/// The Moon's illuminance above the atmosphere as if no lunar eclipse were on (lights.moon_illuminance
/// / moon.eclipse_factor): what the Planet element calibrates its disk to, drawing the eclipse per pixel.
inline const Key<glm::dvec3> moonIlluminanceUneclipsed{"lights.moon_illuminance_uneclipsed", Range{0, 1e6}, "Moon's illuminance above the atmosphere without a lunar eclipse (the Planet element's calibration)", "lx"};
/// The planet's radius, m: the atmosphere's ground sphere (the one radius every element uses).
inline const Key<double> planetRadius{"planet.radius_m", Range{1e3, 1e9}, "planet (ground sphere) radius", "m"};
}  // namespace lightkeys

/// Linear sRGB of sunlight reflected by the Moon for a solar spectrum given at `wavelengthsNm`,
/// normalised to luminance 1 (multiply by the Moon's illuminance in lux).
glm::dvec3 moonlightColour(const std::vector<double>& wavelengthsNm, const std::vector<double>& solarIrradiance);
/// The lunar reflectance relative to 550 nm (see the header comment), >= 0.1.
double moonRelativeReflectance(double wavelengthNm);

class AtmosphereLights final : public Generator {
public:
    AtmosphereLights();
    /// The shared instance of `vars` (created on first request).
    static std::shared_ptr<AtmosphereLights> obtain(SkyVars& vars);
    /// false: the Moon gives no light (moon.* illuminance and radiance 0).
    void setMoonEnabled(bool on) { moon_ = on; }

private:
    void doRun(SkyVars& vars, const Logger& log) override;
    void doDeclare(SkyVars& vars) override;
    bool moon_ = true;
    // What depends on the atmosphere alone, kept while `atmosphere.model` holds the same object
    // (held here, so its address cannot be reused by another): its RGB model (validated spectra,
    // coefficients at three wavelengths) and the moonlight's colour. This generator runs every
    // frame while time runs; rebuilding them was ~11,000 instructions a frame (docs/hardening.md).
    std::shared_ptr<const atmosphere::Atmosphere> modelOf_;
    std::optional<SkyModel> model_;
    glm::dvec3 moonColour_{0.0};
};

}  // namespace welkin::generators
