#include "scene_edit.hpp"

#include <welkin/elements/registry.hpp>
#include <welkin/error.hpp>

#include <algorithm>

namespace welkin::cli {

std::string setElementEnabled(SkyProcessor& sky, const std::string& name, bool on) {
    try {
        if (!on) {
            if (auto e = sky.remove(name)) e->release();
            return {};
        }
        if (sky.find(name)) return {};
        std::unique_ptr<SkyElement> added = elements::makeElement(name);  // throws for an unknown name
        const std::vector<std::string> known = elements::knownElements();
        auto rank = [&](const std::string& n) { return size_t(std::find(known.begin(), known.end(), n) - known.begin()); };
        std::vector<std::string> after;
        for (auto& e : sky.elements())
            if (rank(e->name()) > rank(name)) after.push_back(e->name());
        std::vector<std::unique_ptr<SkyElement>> held;
        for (auto& n : after) held.push_back(sky.remove(n));
        sky.add(std::move(added));
        for (auto& e : held) sky.add(std::move(e));
        try {
            sky.init();  // now, so that a failure is reported here
        } catch (const Error& e) {
            if (auto el = sky.remove(name)) el->release();
            return name + ": " + e.what();
        }
        return {};
    } catch (const Error& e) {
        return name + ": " + e.what();
    }
}

}  // namespace welkin::cli
