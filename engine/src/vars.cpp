#include <welkin/vars.hpp>

#include <cmath>
#include <cstdio>

namespace welkin {

void SkyVars::checkScalar(const std::string& name, const std::optional<Range>& range, double v) {
    char buf[96];
    if (!std::isfinite(v)) {
        std::snprintf(buf, sizeof buf, "%g", v);
        throw Error("SkyVars: key '" + name + "': " + buf + " is not finite");
    }
    if (range && !(v >= range->min && v <= range->max)) {
        std::snprintf(buf, sizeof buf, "%g not in [%g, %g]", v, range->min, range->max);
        throw Error("SkyVars: key '" + name + "': " + buf);
    }
}

std::vector<std::string> SkyVars::names() const {
    std::vector<std::string> out;
    out.reserve(entries_.size());
    for (const auto& [name, e] : entries_) out.push_back(name);
    return out;
}

std::string SkyVars::typeName(std::string_view name) const {
    auto it = entries_.find(name);
    return it == entries_.end() ? std::string() : std::string(it->second.typeName);
}

}  // namespace welkin
