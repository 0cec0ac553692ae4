#include <welkin/keys.hpp>
#include <welkin/vars.hpp>

namespace welkin {

SkyVars SkyVars::earth() {
    SkyVars v;
    v.set(keys::timeJdUtc, glm::dvec2(2451545.0 - 0.5, 0.5));  // J2000.0 (2000-01-01T12:00 UTC)
    v.set(keys::timeIso, std::string("2000-01-01T12:00:00Z"));
    v.set(keys::observerLatitude, 0.0);
    v.set(keys::observerLongitude, 0.0);
    v.set(keys::observerHeight, 0.0);
    v.set(keys::quality, 1);
    v.set(keys::interactive, false);
    v.set(keys::hostScene, false);
    v.set(keys::exposureEv100, 15.0);
    v.set(keys::exposureAuto, false);
    return v;
}

}  // namespace welkin
