#include <welkin/astro/astro_keys.hpp>

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

void updateSkyVars(SkyVars& vars) {
    vars.declare(keys::precise, false);
    vars.declare(keys::refractionPressure, 1013.25);
    vars.declare(keys::refractionTemperature, 10.0);
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
    const ObserverFrame frame = observerFrame(site, timeScales(JulianDate{jd.x, jd.y}.normalized()), path);
    Ephemeris eph;
    eph.update(frame);

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

}  // namespace welkin::astro
