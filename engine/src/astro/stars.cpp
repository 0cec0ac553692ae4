// Star frame for the GPU: one rotation, the aberration vector, years since J2000.
#include <welkin/astro/stars.hpp>

#include <cmath>
#include <numbers>

namespace welkin::astro {

namespace {
constexpr double kMasToRad = std::numbers::pi / (180.0 * 3600.0 * 1000.0);
}

glm::dvec3 starDirectionJ2000(const Star& s) { return directionFromRaDec(s.raJ2000Rad, s.decJ2000Rad); }

glm::dvec3 starProperMotion(const Star& s) {
    // Tangent basis at the star: east (increasing RA) and north (increasing Dec).
    const double sa = std::sin(s.raJ2000Rad), ca = std::cos(s.raJ2000Rad);
    const double sd = std::sin(s.decJ2000Rad), cd = std::cos(s.decJ2000Rad);
    const glm::dvec3 east(-sa, ca, 0.0), north(-sd * ca, -sd * sa, cd);
    return (double(s.pmRaMasPerYear) * east + double(s.pmDecMasPerYear) * north) * kMasToRad;
}

StarFrame starFrame(const ObserverFrame& f) {
    StarFrame s;
    s.icrsToEnu = f.icrsToEnu;
    s.aberration = f.observerVelocityIcrs;
    s.yearsSinceJ2000 = f.time.yearsTT();
    return s;
}

StarFrame starFrame(const Site& site, const TimeScales& ts, Path path) { return starFrame(observerFrame(site, ts, path)); }

glm::dmat3 starMatrix(const Site& site, const TimeScales& ts, Path path) { return observerFrame(site, ts, path).icrsToEnu; }

glm::dvec3 starEnu(const StarFrame& f, const glm::dvec3& p0, const glm::dvec3& pm) {
    glm::dvec3 p = glm::normalize(p0 + f.yearsSinceJ2000 * pm);
    p = glm::normalize(p + f.aberration);
    return f.icrsToEnu * p;
}

}  // namespace welkin::astro
