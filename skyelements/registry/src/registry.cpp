#include <welkin/elements/registry.hpp>
#include <welkin/error.hpp>

#include <algorithm>
#include <utility>

namespace welkin::elements {

namespace detail {
std::vector<const ElementDescriptor*> generatedDescriptors();  // generated/element_registry.cpp
}

const std::vector<const ElementDescriptor*>& descriptors() {
    static const std::vector<const ElementDescriptor*> all = [] {
        std::vector<const ElementDescriptor*> d = detail::generatedDescriptors();
        std::stable_sort(d.begin(), d.end(), [](const ElementDescriptor* a, const ElementDescriptor* b) {
            return a->layer != b->layer ? a->layer < b->layer : a->name < b->name;
        });
        for (size_t i = 1; i < d.size(); ++i)
            if (d[i]->name == d[i - 1]->name) throw Error("element registry: two elements named '" + d[i]->name + "'");
        return d;
    }();
    return all;
}

const ElementDescriptor* findDescriptor(std::string_view name) {
    for (const ElementDescriptor* d : descriptors())
        if (d->name == name) return d;
    return nullptr;
}

std::vector<std::string> knownElements() {
    std::vector<std::string> n;
    for (const ElementDescriptor* d : descriptors()) n.push_back(d->name);
    return n;
}

std::vector<std::string> defaultElements() {
    std::vector<std::string> n;
    for (const ElementDescriptor* d : descriptors())
        if (d->inDefaultSet) n.push_back(d->name);
    return n;
}

std::unique_ptr<SkyElement> makeElement(std::string_view name) {
    if (const ElementDescriptor* d = findDescriptor(name)) {
        std::unique_ptr<SkyElement> e = d->make();
        if (!e || e->name() != d->name)
            throw Error("element registry: the factory of '" + d->name + "' made " + (e ? "'" + e->name() + "'" : std::string("nothing")));
        return e;
    }
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

std::vector<std::string> expandElementList(std::string_view list) {
    std::vector<std::string> out;
    for (std::string& item : parseElementList(list)) {
        if (item == "default") {
            for (std::string& n : defaultElements()) out.push_back(std::move(n));
        } else {
            makeElement(item);  // throws for an unknown name, listing the known ones
            out.push_back(std::move(item));
        }
    }
    for (size_t i = 0; i < out.size(); ++i)
        for (size_t j = i + 1; j < out.size(); ++j)
            if (out[i] == out[j]) throw Error("element list '" + std::string(list) + "' names '" + out[i] + "' twice");
    return out;
}

}  // namespace welkin::elements
