// AtmosphereLights: Sun and Moon light above the atmosphere, transmittance to the observer and
// unreddened disk radiance (CPU, double precision; a few hundred microseconds per run).
#include <welkin/astro/astro_keys.hpp>
#include <welkin/astro/bodies.hpp>
#include <welkin/astro/eclipses.hpp>
#include <welkin/color.hpp>
#include <welkin/error.hpp>
#include <welkin/generators/lights.hpp>
#include <welkin/generators/sky_luts.hpp>
#include <welkin/generators/sky_model.hpp>
#include <welkin/generators/sky_spectral.hpp>
#include <welkin/glsl_cpp.hpp>
#include <welkin/keys.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <optional>

// atm_entryFromSpace() (an observer above the air: where a ray enters it): the sky shader's text
// (atmosphere.shared.glsl) in double.
namespace welkin::glsl::dp::lights_shared {
#define ATM_SEGMENT_LINEAR 1e-7  // atm_segmentFactor()'s linear limit in double (as sky_model.cpp; unused here)
#include "atmosphere.shared.glsl"
}  // namespace welkin::glsl::dp::lights_shared

namespace welkin::generators {

namespace {
constexpr double kPi = std::numbers::pi;
constexpr double kAu = 1.495978707e11;          // m
constexpr double kMoonMeanDistance = 384400e3;  // m
constexpr double kMoonRadius = 1737.4e3;        // m (IAU mean radius)
constexpr int kLightTransmittanceSteps = 64;     // quadrature steps of the lights' transmittance

// Transmittance from the observer (any height) towards a direction, CPU double precision; 0 if the
// planet is in the way.
glm::dvec3 transmittanceTowards(const SkyModel& m, double h, const glm::dvec3& dir) {
    const double R = m.bottomRadius, Ht = m.topRadius - R;
    double mu = std::clamp(dir.z, -1.0, 1.0);
    h = std::max(h, 0.0);
    if (h > Ht) {
        const double t = glsl::dp::lights_shared::atm_entryFromSpace(R, Ht, h, mu);  // the sky shader's text
        if (t < 0.0) return glm::dvec3(1.0);
        const double r = R + h;
        mu = std::clamp((r * mu + t) / m.topRadius, -1.0, 1.0);
        h = Ht;
    }
    if (cpu::rayIntersectsGround(m, h, mu)) return glm::dvec3(0.0);
    // 64 warped midpoint steps: within 4.1e-3 of the converged integral (relative; 1.4e-4
    // absolute) at every altitude down to the dipped horizon, observer 0-30 km, the worst case a
    // grazing ray (tested in [lights]); the sky LUTs' own interpolation error near the horizon is
    // ~1e-2. Each doubling of the steps divides the error by 4 and doubles the cost, paid every
    // frame while time runs: 64 steps keep the framework under 200,000 instructions per frame
    // (docs/hardening.md).
    return cpu::transmittanceToTop(m, h, mu, kLightTransmittanceSteps);
}

glm::dvec3 unit(const glm::dvec3& d, const glm::dvec3& fallback) { return glm::length(d) > 0 ? glm::normalize(d) : fallback; }
}  // namespace

double moonRelativeReflectance(double wavelengthNm) { return std::max(0.1, 1.0 + 0.0020 * (wavelengthNm - 550.0)); }

glm::dvec3 moonlightColour(const std::vector<double>& wavelengthsNm, const std::vector<double>& solarIrradiance) {
    if (wavelengthsNm.size() != solarIrradiance.size() || wavelengthsNm.empty())
        throw Error("moonlightColour(): wavelengths and irradiance differ in length or are empty");
    std::vector<double> reflected(solarIrradiance.size());
    for (size_t i = 0; i < reflected.size(); ++i) reflected[i] = solarIrradiance[i] * moonRelativeReflectance(wavelengthsNm[i]);
    glm::dvec3 rgb = color::spectrumToLinearSrgb(wavelengthsNm, reflected);
    const double Y = color::luminance(rgb);
    return Y > 0 ? rgb / Y : glm::dvec3(1.0);
}

AtmosphereLights::AtmosphereLights() : Generator("atmosphere.lights") {
    input(atmosphere::kAtmosphere);
    input(keys::sunDirection);
    input(keys::moonDirection);
    input(keys::observerHeight);
    input(astro::keys::sunDistance, {.optional = true});
    input(astro::keys::sunAngularRadius, {.optional = true});
    input(astro::keys::moonDistance, {.optional = true});
    input(astro::keys::moonPhaseAngle, {.optional = true});
    input(astro::keys::moonMagnitude, {.optional = true});
    input(astro::keys::moonAngularRadius, {.optional = true});
    input(keys::moonEclipseFactor, {.optional = true});
    input(astro::keys::moonEclipseRefracted, {.optional = true});
    input(skykeys::wavelengths);
    input(skykeys::quality, {.optional = true});
    input(keys::quality);
    output(lightkeys::sunIlluminance);
    output(lightkeys::sunTransmittance);
    output(lightkeys::sunDiskRadiance);
    output(lightkeys::moonIlluminance);
    output(lightkeys::moonTransmittance);
    output(lightkeys::moonIlluminanceUneclipsed);
    output(lightkeys::moonDiskRadiance);
    output(lightkeys::planetRadius);
}

std::shared_ptr<AtmosphereLights> AtmosphereLights::obtain(SkyVars& vars) {
    static const Key<std::shared_ptr<AtmosphereLights>> kShared{"generators.atmosphere_lights"};
    return vars.obtain<AtmosphereLights>(kShared, [] { return std::make_shared<AtmosphereLights>(); });
}

void AtmosphereLights::doDeclare(SkyVars& vars) {
    if (!vars.has(atmosphere::kAtmosphere))
        vars.set(atmosphere::kAtmosphere, std::make_shared<const atmosphere::Atmosphere>(atmosphere::Atmosphere::earthClear()));
    vars.declare(keys::sunDirection, directionFromAzAlt(kPi, kPi / 4));  // until the astronomy (or host) sets it
    vars.declare(keys::moonDirection, glm::dvec3(0, 0, -1));
    vars.declare(keys::observerHeight, 0.0);
    vars.declare(keys::quality, 1);
    vars.declare(skykeys::wavelengths, 0);
}

void AtmosphereLights::doRun(SkyVars& vars, const Logger& log) {
    std::shared_ptr<const atmosphere::Atmosphere> atm;
    if (vars.has(atmosphere::kAtmosphere)) atm = vars.get(atmosphere::kAtmosphere);
    const atmosphere::Atmosphere& a = atm ? *atm : atmosphere::Atmosphere::earthClear();
    if (!model_ || !atm || atm != modelOf_) {
        model_ = SkyModel::fromVars(vars);
        moonColour_ = moonlightColour(a.wavelengthsNm, a.solarIrradiance);
        modelOf_ = atm;
    }
    const SkyModel& m = *model_;
    double h = vars.getOr(keys::observerHeight, 0.0);
    if (h < 0.0) {
        char buf[160];
        std::snprintf(buf, sizeof buf, "atmosphere.lights: observer height %g m is below the ground; clamped to 0 m", h);
        log.warn(buf);
        h = 0.0;
    }
    const glm::dvec3 sun = unit(vars.getOr(keys::sunDirection, glm::dvec3(0, 0, 1)), glm::dvec3(0, 0, -1));
    const glm::dvec3 moonDir = unit(vars.getOr(keys::moonDirection, glm::dvec3(0, 0, -1)), glm::dvec3(0, 0, -1));
    const double sunDist = vars.getOr(astro::keys::sunDistance, kAu);
    const glm::dvec3 Esun = m.solarIlluminance * (kAu / sunDist) * (kAu / sunDist);
    double alpha = vars.getOr(astro::keys::sunAngularRadius, m.sunAngularRadius);
    if (alpha <= 0) alpha = m.sunAngularRadius;
    // Spectral mode: per wavelength, combined as the transmitted linear sRGB of the solar
    // spectrum over the unattenuated one (sky_spectral.hpp), like the combined LUT.
    validateWavelengthCount(vars.getOr(skykeys::wavelengths, 0), "sky.wavelengths");
    const int n = effectiveWavelengths(vars.getOr(skykeys::wavelengths, 0),
                                       SkyQuality::preset(effectiveQuality(vars)));
    std::optional<SpectralSampling> sp;
    if (n != 3) sp = SpectralSampling::make(a, n);
    auto transmittance = [&](const glm::dvec3& d) {
        if (!sp) return transmittanceTowards(m, h, d);
        std::vector<glm::dvec3> t;
        for (const SkyModel& mk : sp->models) t.push_back(transmittanceTowards(mk, h, d));
        // A deep-red setting Sun is outside the sRGB gamut: its blue (and green) channel can
        // come out slightly negative; clamped at 0 like the combined LUTs.
        return glm::max(sp->combine(t), glm::dvec3(0.0));
    };
    vars.set(lightkeys::sunIlluminance, Esun);
    vars.set(lightkeys::sunTransmittance, glm::clamp(transmittance(sun), 0.0, 1.0));
    vars.set(lightkeys::sunDiskRadiance, Esun / (kPi * alpha * alpha));

    glm::dvec3 Emoon(0.0), Lmoon(0.0), EmoonUneclipsed(0.0);
    if (moon_) {
        const double dist = vars.getOr(astro::keys::moonDistance, kMoonMeanDistance);
        double mag;
        if (vars.has(astro::keys::moonMagnitude)) {
            mag = vars.get(astro::keys::moonMagnitude);
        } else {
            // No astronomy: the same law from the phase angle (or, lacking it, the elongation:
            // the Sun is ~390x farther than the Moon, so phase ~ pi - elongation).
            const double phase = vars.has(astro::keys::moonPhaseAngle)
                                     ? vars.get(astro::keys::moonPhaseAngle)
                                     : kPi - std::acos(std::clamp(glm::dot(sun, moonDir), -1.0, 1.0));
            mag = astro::magnitude::moon(1.0, dist / kAu, phase * 180.0 / kPi);
        }
        const double E = astro::magnitude::illuminanceLux(mag);
        // A lunar eclipse: only moon.eclipse_factor of the sunlight reaches the Moon (the Earth's
        // umbra and penumbra; the astronomy writes it, 1 outside eclipses or without astronomy),
        // moon.eclipse_refracted of it the atmosphere's reddened light (astro::umbraColour()).
        const double eclipse = std::clamp(vars.getOr(keys::moonEclipseFactor, 1.0), 0.0, 1.0);
        const double refracted = std::clamp(vars.getOr(astro::keys::moonEclipseRefracted, 0.0), 0.0, eclipse);
        EmoonUneclipsed = E * moonColour_;
        Emoon = (eclipse - refracted) * EmoonUneclipsed + refracted * color::luminance(EmoonUneclipsed) * astro::umbraColour();
        double am = vars.getOr(astro::keys::moonAngularRadius, std::asin(std::min(1.0, kMoonRadius / dist)));
        if (am <= 0) am = std::asin(std::min(1.0, kMoonRadius / dist));
        Lmoon = Emoon / (kPi * am * am);
    }
    vars.set(lightkeys::moonIlluminance, Emoon);
    vars.set(lightkeys::moonIlluminanceUneclipsed, EmoonUneclipsed);
    vars.set(lightkeys::moonTransmittance, glm::clamp(transmittance(moonDir), 0.0, 1.0));
    vars.set(lightkeys::moonDiskRadiance, Lmoon);
    vars.set(lightkeys::planetRadius, m.bottomRadius);
}

}  // namespace welkin::generators
