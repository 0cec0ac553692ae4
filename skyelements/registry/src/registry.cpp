#include <welkin/elements/grid.hpp>
#include <welkin/elements/sky.hpp>
#include <welkin/elements/registry.hpp>
#include <welkin/error.hpp>

#include <functional>
#include <utility>

namespace welkin::elements {

namespace {
using Factory = std::function<std::unique_ptr<SkyElement>()>;
// Recommended compositing order: farthest first.
const std::vector<std::pair<std::string, Factory>>& factories() {
    static const std::vector<std::pair<std::string, Factory>> f = {
        {"sky", [] { return std::make_unique<Sky>(); }},
        {"grid", [] { return std::make_unique<Grid>(); }},
    };
    return f;
}
}  // namespace

std::vector<std::string> knownElements() {
    std::vector<std::string> n;
    for (auto& [name, f] : factories()) n.push_back(name);
    return n;
}

std::vector<std::string> defaultElements() {
    std::vector<std::string> n;
    for (auto& [name, f] : factories())
        if (name != "grid") n.push_back(name);
    if (n.empty()) n.push_back("grid");
    return n;
}

std::unique_ptr<SkyElement> makeElement(std::string_view name) {
    for (auto& [n, f] : factories())
        if (n == name) return f();
    std::string known;
    for (auto& k : knownElements()) known += (known.empty() ? "" : ", ") + k;
    throw Error("unknown element '" + std::string(name) + "' (known: " + known + ")");
}

std::vector<std::string> parseElementList(std::string_view list) {
    std::vector<std::string> out;
    size_t start = 0;
    while (start <= list.size()) {
        size_t end = list.find(',', start);
        if (end == std::string_view::npos) end = list.size();
        std::string item(list.substr(start, end - start));
        auto b = item.find_first_not_of(" \t"), e = item.find_last_not_of(" \t");
        if (b == std::string::npos) throw Error("element list '" + std::string(list) + "' has an empty item");
        out.push_back(item.substr(b, e - b + 1));
        start = end + 1;
    }
    return out;
}

}  // namespace welkin::elements
