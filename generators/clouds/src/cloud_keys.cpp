#include <welkin/error.hpp>
#include <welkin/generators/cloud_keys.hpp>

#include <cstdio>
#include <string>

namespace welkin::generators {

namespace {
std::string fmt(double v) {
    char b[32];
    std::snprintf(b, sizeof b, "%g", v);
    return b;
}
}  // namespace

void validateCloudLayer(const SkyVars& vars) {
    const double bottom = vars.getOr(cloudkeys::bottom, 2000.0);
    const double top = vars.getOr(cloudkeys::top, 3000.0);
    const double cirrus = vars.getOr(cloudkeys::cirrusHeight, 9000.0);
    // A layer thinner than 100 m has no room for the height profile (and the ray march's steps
    // would be shorter than the detail noise's cells).
    if (top < bottom + 100.0)
        throw Error(cloudkeys::top.name() + " " + fmt(top) + " must be at least " + cloudkeys::bottom.name() + " + 100 m (" +
                    fmt(bottom + 100.0) + ")");
    if (cirrus <= top)
        throw Error(cloudkeys::cirrusHeight.name() + " " + fmt(cirrus) + " must be above " + cloudkeys::top.name() + " (" + fmt(top) +
                    ")");
}

}  // namespace welkin::generators
