#include <atomic>
#include <welkin/vars.hpp>

#include <algorithm>
#include <cmath>
#include <cctype>
#include <cstdio>
#include <cstdlib>
#include <cstring>

namespace welkin {

void SkyVars::failScalar(const std::string& name, const std::optional<Range>& range, double v) {
    char buf[96];
    if (!std::isfinite(v)) {
        std::snprintf(buf, sizeof buf, "%g", v);
        throw Error("SkyVars: key '" + name + "': " + buf + " is not finite");
    }
    std::snprintf(buf, sizeof buf, "%g not in [%g, %g]", v, range ? range->min : 0.0, range ? range->max : 0.0);
    throw Error("SkyVars: key '" + name + "': " + buf);
}

void SkyVars::checkName(const std::string& name, const std::vector<std::string>& choices, const std::string& value) {
    if (choices.empty()) return;
    for (const std::string& c : choices)
        if (c == value) return;
    std::string list;
    for (const std::string& c : choices) list += (list.empty() ? "" : ", ") + c;
    throw Error("key '" + name + "': '" + value + "' is not one of " + list);
}

uint64_t detail::nextKeySerial() {
    static std::atomic<uint64_t> next{1};  // process-wide; 0 marks an empty cache line
    return next.fetch_add(1, std::memory_order_relaxed);
}

uint64_t SkyVars::newIdentity() {
    static std::atomic<uint64_t> next{1};  // process-wide: identities are never reused
    return next.fetch_add(1, std::memory_order_relaxed);
}

std::vector<std::string> SkyVars::names() const {
    std::vector<std::string> out;
    out.reserve(entries_.size());
    for (const auto& [name, e] : entries_) out.push_back(name);
    std::sort(out.begin(), out.end());
    return out;
}

std::string SkyVars::typeName(std::string_view name) const {
    auto it = entries_.find(name);
    return it == entries_.end() ? std::string() : std::string(it->second.typeName);
}

}  // namespace welkin

namespace welkin {

namespace {
std::string rangeText(const std::optional<Range>& r) {
    if (!r) return "any value";
    char buf[96];
    std::snprintf(buf, sizeof buf, "[%g, %g]", r->min, r->max);
    return buf;
}
std::string describeDecl(const char* type, const std::optional<Range>& r, const std::string& unit) {
    return std::string(type) + " in " + rangeText(r) + (unit.empty() ? "" : " " + unit);
}
std::string trim(std::string_view t) {
    size_t b = t.find_first_not_of(" \t"), e = t.find_last_not_of(" \t");
    return b == std::string_view::npos ? std::string() : std::string(t.substr(b, e - b + 1));
}
std::string formatDouble(double v) {
    char buf[40];
    std::snprintf(buf, sizeof buf, "%.17g", v);
    // Shortest form that reads back to the same double ("10", not "1e+01").
    std::string best = buf;
    for (int p = 1; p <= 17; ++p) {
        char b2[40];
        std::snprintf(b2, sizeof b2, "%.*g", p, v);
        if (std::strtod(b2, nullptr) == v && std::strlen(b2) < best.size()) best = b2;
    }
    return best;
}
}  // namespace

std::string unitFromKeyName(std::string_view name) {
    static const std::pair<const char*, const char*> kSuffixes[] = {
        {"_cd_m2", "cd/m^2"}, {"_lux", "lx"}, {"_rad", "rad"}, {"_deg", "deg"}, {"_km", "km"}, {"_m", "m"},
        {"_s", "s"},          {"_ms", "ms"},  {"_hpa", "hPa"}, {"_c", "degC"},  {"_nm", "nm"}, {"_mm_h", "mm/h"},
        {"_m_s", "m/s"},      {"_k", "K"},    {"_jd", "d"},    {"_ev100", "EV"}};
    std::string best;
    size_t bestLen = 0;
    for (auto& [suf, unit] : kSuffixes) {
        std::string_view s(suf);
        if (name.size() > s.size() && name.substr(name.size() - s.size()) == s && s.size() > bestLen) {
            best = unit;
            bestLen = s.size();
        }
    }
    return best;
}

void SkyVars::checkCompatible(Entry& e, const KeyInfo& k) const {
    bool typeOk = e.type == k.type;
    bool rangeOk = !e.range || !k.range || *e.range == *k.range;
    bool unitOk = e.unit.empty() || k.unit.empty() || e.unit == k.unit;
    bool choicesOk = e.choices.empty() || k.choices.empty() || e.choices == k.choices;
    if (!choicesOk)
        throw Error("SkyVars: key '" + k.name + "' declared by '" + e.declarer + "' and by '" + declarer_ + "' with different names of its values");
    if (!typeOk || !rangeOk || !unitOk)
        throw Error("SkyVars: key '" + k.name + "' declared by '" + e.declarer + "' as " + describeDecl(e.typeName, e.range, e.unit) +
                    " and by '" + declarer_ + "' as " + describeDecl(k.typeName, k.range, k.unit));
    if (!e.range && k.range) e.range = k.range;
    if (e.choices.empty()) e.choices = k.choices;
    if (e.unit.empty()) e.unit = k.unit;
    if (e.description.empty()) e.description = k.description;
}

void SkyVars::touch(std::string_view name) {
    auto it = entries_.find(name);
    if (it == entries_.end()) throw Error("SkyVars::touch(): key '" + std::string(name) + "' is not declared");
    ++it->second.version;
}

std::optional<KeyInfo> SkyVars::info(std::string_view name) const {
    auto it = entries_.find(name);
    if (it == entries_.end()) return std::nullopt;
    const Entry& e = it->second;
    return KeyInfo{it->first, e.type, e.typeName, e.range, e.description, e.unit, e.choices};
}

std::vector<double> SkyVars::numeric(std::string_view name) const {
    auto it = entries_.find(name);
    if (it == entries_.end() || !it->second.isSet) return {};
    const std::any& a = it->second.value;
    if (auto* b = std::any_cast<bool>(&a)) return {*b ? 1.0 : 0.0};
    if (auto* i = std::any_cast<int>(&a)) return {double(*i)};
    if (auto* d = std::any_cast<double>(&a)) return {*d};
    if (auto* v = std::any_cast<glm::dvec2>(&a)) return {v->x, v->y};
    if (auto* v = std::any_cast<glm::dvec3>(&a)) return {v->x, v->y, v->z};
    if (auto* v = std::any_cast<glm::dvec4>(&a)) return {v->x, v->y, v->z, v->w};
    if (auto* m = std::any_cast<glm::dmat3>(&a)) {
        std::vector<double> out;
        for (int c = 0; c < 3; ++c)
            for (int r = 0; r < 3; ++r) out.push_back((*m)[c][r]);
        return out;
    }
    if (auto* m = std::any_cast<glm::dmat4>(&a)) {
        std::vector<double> out;
        for (int c = 0; c < 4; ++c)
            for (int r = 0; r < 4; ++r) out.push_back((*m)[c][r]);
        return out;
    }
    return {};
}

std::string SkyVars::valueString(std::string_view name) const {
    auto it = entries_.find(name);
    if (it == entries_.end() || !it->second.isSet) return {};
    const std::any& a = it->second.value;
    if (auto* b = std::any_cast<bool>(&a)) return *b ? "true" : "false";
    if (auto* s = std::any_cast<std::string>(&a)) return *s;
    if (auto* i = std::any_cast<int>(&a)) return std::to_string(*i);
    if (it->second.type == typeid(glm::dmat3) || it->second.type == typeid(glm::dmat4)) return {};
    std::vector<double> v = numeric(name);
    std::string out;
    for (size_t k = 0; k < v.size(); ++k) out += (k ? "," : "") + formatDouble(v[k]);
    return out;
}

void SkyVars::setFromString(std::string_view name, std::string_view text) {
    auto it = entries_.find(name);
    if (it == entries_.end()) throw Error("unknown key '" + std::string(name) + "' (`welkin vars` lists the keys)");
    Entry& e = it->second;
    const std::string key(name);
    const std::string t = trim(text);
    auto fail = [&](const std::string& why) { throw Error("key '" + key + "' (" + describeDecl(e.typeName, e.range, e.unit) + "): '" + t + "' " + why); };
    auto parseNumber = [&](std::string part) -> double {
        part = trim(part);
        double scale = 1.0;
        if (e.unit == "rad" && part.size() > 3 && part.compare(part.size() - 3, 3, "deg") == 0) {
            part = trim(part.substr(0, part.size() - 3));
            scale = 3.14159265358979323846 / 180.0;
        }
        char* end = nullptr;
        double v = std::strtod(part.c_str(), &end);
        if (part.empty() || end != part.c_str() + part.size()) fail("is not a number");
        return v * scale;
    };
    auto components = [&](int n) {
        std::vector<double> out;
        size_t start = 0;
        while (true) {
            size_t comma = t.find(',', start);
            out.push_back(parseNumber(t.substr(start, comma == std::string::npos ? std::string::npos : comma - start)));
            if (comma == std::string::npos) break;
            start = comma + 1;
        }
        if (int(out.size()) != n) fail("needs " + std::to_string(n) + " comma-separated numbers");
        return out;
    };
    auto store = [&](auto value) {
        using T = decltype(value);
        try {
            validate(key, e.range, value);
        } catch (const Error&) {
            fail("not in " + rangeText(e.range));
        }
        if (e.isSet && std::any_cast<const T&>(e.value) == value) return;
        e.value = std::move(value);
        e.isSet = true;
        ++e.version;
    };
    if (e.type == typeid(bool)) {
        std::string l = t;
        for (auto& c : l) c = char(std::tolower(static_cast<unsigned char>(c)));
        if (l == "true" || l == "on" || l == "1" || l == "yes") store(true);
        else if (l == "false" || l == "off" || l == "0" || l == "no") store(false);
        else fail("is not a bool (true/false, on/off, 1/0)");
    } else if (e.type == typeid(int)) {
        char* end = nullptr;
        long v = std::strtol(t.c_str(), &end, 10);
        if (t.empty() || end != t.c_str() + t.size() || v < -2147483647L || v > 2147483647L) fail("is not an integer");
        store(int(v));
    } else if (e.type == typeid(double)) {
        store(parseNumber(t));
    } else if (e.type == typeid(glm::dvec2)) {
        auto c = components(2);
        store(glm::dvec2(c[0], c[1]));
    } else if (e.type == typeid(glm::dvec3)) {
        auto c = components(3);
        store(glm::dvec3(c[0], c[1], c[2]));
    } else if (e.type == typeid(glm::dvec4)) {
        auto c = components(4);
        store(glm::dvec4(c[0], c[1], c[2], c[3]));
    } else if (e.type == typeid(std::string)) {
        checkName(key, e.choices, t);
        store(t);
    } else {
        throw Error("key '" + key + "' holds " + e.typeName + ", which cannot be set from text");
    }
}

std::vector<KeyDescription> SkyVars::describe() const {
    std::vector<KeyDescription> out;
    for (const auto& [name, e] : entries_)
        out.push_back({KeyInfo{name, e.type, e.typeName, e.range, e.description, e.unit, e.choices}, e.declarer, valueString(name), e.isSet});
    std::sort(out.begin(), out.end(), [](const KeyDescription& a, const KeyDescription& b) { return a.info.name < b.info.name; });
    return out;
}

}  // namespace welkin
