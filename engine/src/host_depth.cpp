#include <welkin/check.hpp>
#include <welkin/error.hpp>
#include <welkin/host_depth.hpp>

#include <string>

namespace welkin {

void HostDepth::validate(const char* where) const {
    const std::string w = std::string(where) + ": HostDepth";
    if (depthTexture == 0) throw Error(w + " depthTexture is 0 (no texture)");
    checkOpenRange(w.c_str(), "nearM", nearM, 0, kInfinity);
    // farM may be +inf (an infinite far plane); checkRange's closed end lets inf in, NaN never.
    if (farM != kInfinity) checkOpenRange(w.c_str(), "farM", farM, nearM, kInfinity);
    checkOpenRange(w.c_str(), "metresPerUnit", metresPerUnit, 0, kInfinity);
}

}  // namespace welkin
