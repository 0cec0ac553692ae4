#include <welkin/astro/astro_keys.hpp>
#include <welkin/astro/eclipses.hpp>
#include <welkin/astro/stars.hpp>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

namespace welkin::astro {

namespace keys {
namespace {
struct PlanetKeys {
    std::vector<Key<glm::dvec3>> direction;
    std::vector<Key<double>> magnitude, diameter;
    PlanetKeys() {
        // Indexed by Body (Sun and Moon entries exist but are not written).
        for (Body b : kAllBodies) {
            const std::string base = std::string("planet.") + bodyName(b) + ".";
            direction.emplace_back(base + "direction", Range{-1, 1}, "unit vector to the planet (refracted), ENU");
            magnitude.emplace_back(base + "magnitude", Range{-30, 30}, "visual magnitude");
            diameter.emplace_back(base + "angular_diameter_rad", Range{0, 0.01}, "apparent angular diameter, rad");
        }
    }
};
const PlanetKeys& planetKeys() {
    static const PlanetKeys k;
    return k;
}
}  // namespace

const Key<glm::dvec3>& planetDirection(Body planet) { return planetKeys().direction[static_cast<int>(planet)]; }
const Key<double>& planetMagnitude(Body planet) { return planetKeys().magnitude[static_cast<int>(planet)]; }
const Key<double>& planetAngularDiameter(Body planet) { return planetKeys().diameter[static_cast<int>(planet)]; }
}  // namespace keys

double eclipseVisibleFraction(double rs, double ro, double d, double u, int bandNodes) {
    if (!(rs > 0.0)) return 1.0;
    const double R = std::max(ro, 0.0) / rs, D = std::abs(d) / rs;
    if (D >= 1.0 + R) return 1.0;  // no overlap
    if (R >= D + 1.0) return 0.0;  // covered
    constexpr double kPi = welkin::keys::kPi;
    // The limb-darkened flux inside radius a (0..1) of the source, per 2 pi (intensity 1 at the
    // centre): the integral of (1 - u (1 - sqrt(1 - r^2))) r dr from 0 to a.
    auto fluxInside = [u](double a) {
        const double c = std::max(1.0 - a * a, 0.0);
        return (1.0 - u) * 0.5 * a * a + u * (1.0 - c * std::sqrt(c)) / 3.0;
    };
    // Rings of radius r (units of rs) are wholly visible for r < D - R and r > R + D, wholly
    // hidden for r < R - D, and cut by the occulter's limb only for r in [|R - D|, min(1, R + D)]:
    // the whole rings in closed form, the cut ones with the nodes spread over that band alone
    // (r = lo + (hi - lo)(1 - cos(pi s)) / 2, s by the midpoint rule: the substitution removes the
    // square-root ends of the cut arc), so a thin crescent near the contacts gets every node.
    const double lo = std::abs(R - D), hi = std::min(1.0, R + D);
    double visible = fluxInside(std::clamp(D - R, 0.0, 1.0)) + fluxInside(1.0) - fluxInside(hi);
    const int n = std::max(bandNodes, 1);
    if (D > 1e-12 && hi > lo) {
        const double half = 0.5 * (hi - lo);
        double band = 0.0;
        for (int i = 0; i < n; ++i) {
            const double s = kPi * (i + 0.5) / n;
            const double r = lo + half * (1.0 - std::cos(s));
            const double w = (1.0 - u * (1.0 - std::sqrt(std::max(1.0 - r * r, 0.0)))) * r;
            // The hidden half-angle of the ring, acos((r^2 + D^2 - R^2) / (2 r D)), written with
            // the factors of 1 -+ that cosine: exact near 0 and pi (thin crescents; float on the GPU).
            const double a = std::max(R + D - r, 0.0) * std::max(R - D + r, 0.0), b = std::max(r + D - R, 0.0) * (r + D + R);
            band += w * (1.0 - 2.0 * std::atan2(std::sqrt(a), std::sqrt(b)) / kPi) * std::sin(s);
        }
        visible += band * half * kPi / n;
    }
    return std::clamp(visible / fluxInside(1.0), 0.0, 1.0);
}

void updateSkyVars(SkyVars& vars, Ephemeris* ephemeris) {
    vars.declare(keys::precise, false);
    vars.declare(keys::refractionPressure, 1013.25);
    vars.declare(keys::refractionTemperature, 10.0);
    vars.declare(keys::eclipses, true);
    const glm::dvec2 jd = vars.get(welkin::keys::timeJdUtc);
    Site site;
    site.latitudeRad = vars.get(welkin::keys::observerLatitude);
    site.longitudeRad = vars.get(welkin::keys::observerLongitude);
    // observer.height_m allows up to 1e9 m; the astronomy's site model stops at 1e8 m (beyond it
    // "topocentric" loses meaning for the Moon): clamp rather than fail a frame.
    site.heightMeters = std::min(vars.get(welkin::keys::observerHeight), 1e8);
    site.pressureHpa = vars.get(keys::refractionPressure);
    site.temperatureC = vars.get(keys::refractionTemperature);
    const Path path = vars.get(keys::precise) ? Path::Precise : Path::Fast;
    Ephemeris fresh;
    Ephemeris& eph = ephemeris ? *ephemeris : fresh;
    const ObserverFrame frame = observerFrame(site, timeScales(JulianDate{jd.x, jd.y}.normalized()), path, &eph.earthSeries());
    eph.update(frame);

    const StarFrame sf = starFrame(frame);
    vars.set(keys::starFrameRotation, sf.icrsToEnu);
    vars.set(keys::starFrameAberration, sf.aberration);
    vars.set(keys::starFrameEpochYears, sf.yearsSinceJ2000);

    const BodyState& sun = eph[Body::Sun];
    const BodyState& moon = eph[Body::Moon];
    vars.set(welkin::keys::sunDirection, sun.topo.enu);
    vars.set(welkin::keys::moonDirection, moon.topo.enu);
    vars.set(keys::sunDistance, sun.topo.distanceMeters);
    vars.set(keys::sunAngularRadius, 0.5 * sun.angularDiameterRad);
    vars.set(keys::sunAzimuth, sun.topo.azimuthRad);
    vars.set(keys::sunAltitude, sun.topo.altitudeRad);
    vars.set(keys::moonDistance, moon.topo.distanceMeters);
    vars.set(keys::moonAngularRadius, 0.5 * moon.angularDiameterRad);
    vars.set(keys::moonAzimuth, moon.topo.azimuthRad);
    vars.set(keys::moonAltitude, moon.topo.altitudeRad);
    vars.set(keys::moonPhaseAngle, moon.phaseAngleRad);
    vars.set(keys::moonIlluminatedFraction, moon.illuminatedFraction);
    vars.set(keys::moonBrightLimbAngle, moon.brightLimbAngleRad);
    vars.set(keys::moonLibrationLon, moon.librationLonRad);
    vars.set(keys::moonLibrationLat, moon.librationLatRad);
    vars.set(keys::moonAxisAngle, moon.axisAngleRad);
    vars.set(keys::moonMagnitude, moon.magnitude);
    // Eclipses. Solar: the Moon's disk over the Sun's, from the observer (topocentric, airless).
    const double sunRadius = 0.5 * sun.angularDiameterRad, moonRadius = 0.5 * moon.angularDiameterRad;
    const double solarSeparation = std::acos(std::clamp(glm::dot(sun.topo.enuGeometric, moon.topo.enuGeometric), -1.0, 1.0));
    const bool eclipses = vars.get(keys::eclipses);
    vars.set(welkin::keys::sunEclipseFraction, eclipses ? eclipseVisibleFraction(sunRadius, moonRadius, solarSeparation) : 1.0);
    {
        // The Moon's position in the apparent Sun's frame: the airless position turned by the
        // rotation taking the Sun's airless direction onto its refracted one (Rodrigues).
        const glm::dvec3 a = sun.topo.enuGeometric, b = sun.topo.enu, axis = glm::cross(a, b);
        const double s = glm::length(axis), c = glm::dot(a, b);
        glm::dvec3 m = moon.topo.enuGeometric;
        if (s > 1e-15) {
            const glm::dvec3 k = axis / s;
            m = m * c + glm::cross(k, m) * s + k * glm::dot(k, m) * (1.0 - c);
        }
        vars.set(keys::moonPosition, m * moon.topo.distanceMeters);
    }
    // Lunar: the sunlight reaching the Moon's disk past the Earth's shadow (geocentric positions;
    // one model with the Planet element's per-pixel shadow: astro/eclipses.hpp).
    {
        const ShadowLight l = moonShadowLight(moon.directionIcrs * moon.distanceMeters, sun.directionIcrs * sun.distanceMeters);
        vars.set(welkin::keys::moonEclipseFactor, eclipses ? std::clamp(l.direct + l.refracted, 0.0, 1.0) : 1.0);
        vars.set(keys::moonEclipseRefracted, eclipses ? std::clamp(l.refracted, 0.0, 1.0) : 0.0);
    }
    // Parallactic angle from the topocentric hour angle: tan q = sin H / (tan phi cos d - sin d cos H).
    const double H = frame.lastRad - moon.topo.raTopocentricRad, d = moon.topo.decTopocentricRad, phi = site.latitudeRad;
    vars.set(keys::moonParallacticAngle, std::atan2(std::sin(H), std::tan(phi) * std::cos(d) - std::sin(d) * std::cos(H)));
    for (Body b : kAllBodies) {
        if (b == Body::Sun || b == Body::Moon) continue;
        const BodyState& p = eph[b];
        vars.set(keys::planetDirection(b), p.topo.enu);
        vars.set(keys::planetMagnitude(b), p.magnitude);
        vars.set(keys::planetAngularDiameter(b), p.angularDiameterRad);
    }
}

AstronomyGenerator::AstronomyGenerator() : Generator("astronomy") {
    input(welkin::keys::timeJdUtc);
    input(welkin::keys::observerLatitude);
    input(welkin::keys::observerLongitude);
    input(welkin::keys::observerHeight);
    input(keys::precise);
    input(keys::refractionPressure);
    input(keys::refractionTemperature);
    input(keys::eclipses);
    output(welkin::keys::sunDirection);
    output(keys::moonPosition);
    output(welkin::keys::moonDirection);
    output(welkin::keys::sunEclipseFraction);
    output(welkin::keys::moonEclipseFactor);
    output(keys::moonEclipseRefracted);
    for (auto* k : {&keys::sunDistance, &keys::sunAngularRadius, &keys::sunAzimuth, &keys::sunAltitude, &keys::moonDistance,
                    &keys::moonAngularRadius, &keys::moonAzimuth, &keys::moonAltitude, &keys::moonPhaseAngle,
                    &keys::moonIlluminatedFraction, &keys::moonBrightLimbAngle, &keys::moonLibrationLon, &keys::moonLibrationLat,
                    &keys::moonAxisAngle, &keys::moonMagnitude, &keys::moonParallacticAngle, &keys::starFrameEpochYears})
        output(*k);
    output(keys::starFrameRotation);
    output(keys::starFrameAberration);
    for (Body b : kAllBodies) {
        if (b == Body::Sun || b == Body::Moon) continue;
        output(keys::planetDirection(b));
        output(keys::planetMagnitude(b));
        output(keys::planetAngularDiameter(b));
    }
}

void AstronomyGenerator::doDeclare(SkyVars& vars) {
    vars.declare(keys::precise, false);
    vars.declare(keys::refractionPressure, 1013.25);
    vars.declare(keys::refractionTemperature, 10.0);
    vars.declare(keys::eclipses, true);
}

void AstronomyGenerator::doRun(SkyVars& vars, const Logger&) {
    updateSkyVars(vars, &ephemeris_);
    sunAz_ = vars.get(keys::sunAzimuth);
    sunAlt_ = vars.get(keys::sunAltitude);
    moonAz_ = vars.get(keys::moonAzimuth);
    moonAlt_ = vars.get(keys::moonAltitude);
    moonPhase_ = vars.get(keys::moonPhaseAngle);
    moonFraction_ = vars.get(keys::moonIlluminatedFraction);
    precise_ = vars.get(keys::precise);
    sunEclipse_ = vars.get(welkin::keys::sunEclipseFraction);
    moonEclipse_ = vars.get(welkin::keys::moonEclipseFactor);
    ran_ = true;
}

void AstronomyGenerator::doStats(nlohmann::json& root) const {
    if (!ran_) return;
    constexpr double deg = 180.0 / welkin::keys::kPi;
    root["sun"]["az_deg"] = sunAz_ * deg;
    root["sun"]["alt_deg"] = sunAlt_ * deg;
    root["moon"]["az_deg"] = moonAz_ * deg;
    root["moon"]["alt_deg"] = moonAlt_ * deg;
    root["moon"]["phase_angle_deg"] = moonPhase_ * deg;
    root["moon"]["illuminated_fraction"] = moonFraction_;
    root["sun"]["eclipse_fraction"] = sunEclipse_;
    root["moon"]["eclipse_factor"] = moonEclipse_;
    root["astronomy"]["path"] = precise_ ? "precise" : "fast";
    root["astronomy"]["last_ms"] = timing().lastMs;
}

}  // namespace welkin::astro
