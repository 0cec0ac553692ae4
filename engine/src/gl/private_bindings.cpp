#include <welkin/error.hpp>
#include <welkin/gl/private_bindings.hpp>

#include <algorithm>

namespace welkin::gl {

namespace {
const char* kindName(binding::Kind kind) {
    switch (kind) {
        case binding::Kind::TextureUnit: return "texture unit";
        case binding::Kind::ImageUnit: return "image unit";
        case binding::Kind::UniformBuffer: return "uniform buffer binding";
        case binding::Kind::StorageBuffer: return "storage buffer binding";
        case binding::Kind::UserRange: break;
    }
    return "range";
}
bool validName(std::string_view name) {
    if (name.empty()) return false;
    if (name.front() >= '0' && name.front() <= '9') return false;
    return std::all_of(name.begin(), name.end(), [](char c) { return (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_'; });
}
}  // namespace

PrivateBindings::Range PrivateBindings::range(binding::Kind kind) {
    switch (kind) {
        case binding::Kind::TextureUnit: return {binding::kPrivateTextureUnitFirst, binding::kPrivateTextureUnitLast};
        case binding::Kind::ImageUnit: return {binding::kPrivateImageUnitFirst, binding::kPrivateImageUnitLast};
        case binding::Kind::UniformBuffer: return {binding::kPrivateUboFirst, binding::kPrivateUboLast};
        case binding::Kind::StorageBuffer: return {binding::kPrivateSsboFirst, binding::kPrivateSsboLast};
        case binding::Kind::UserRange: break;
    }
    throw Error("welkin::gl::PrivateBindings::range(): Kind::UserRange is not a kind of binding");
}

int PrivateBindings::request(binding::Kind kind, std::string_view name) {
    const std::string& who = owner_;
    const std::string what = std::string(kindName(kind)) + " '" + std::string(name) + "'";
    if (kind == binding::Kind::UserRange) throw Error(who + ": private binding '" + std::string(name) + "': Kind::UserRange is not a kind of binding");
    if (!validName(name))
        throw Error(who + ": private " + what + ": a name is upper-case letters, digits and '_', not starting with a digit");
    const std::string glslName = "WELKIN_BINDING_" + std::string(name);
    for (const binding::Entry& e : binding::kTable)
        if (e.glslName == glslName)
            throw Error(who + ": private " + what + ": " + glslName + " is a shared binding of welkin/gl/bindings.hpp; choose another name");
    for (const Assigned& a : assigned_) {
        if (a.glslName != glslName) continue;
        if (a.kind != kind) throw Error(who + ": private " + what + " was already asked for as a " + kindName(a.kind));
        return a.value;
    }
    const Range r = range(kind);
    const int used = int(std::count_if(assigned_.begin(), assigned_.end(), [&](const Assigned& a) { return a.kind == kind; }));
    const int value = r.first + used;
    if (value > r.last)
        throw Error(who + ": no private " + std::string(kindName(kind)) + " left for '" + std::string(name) + "': the framework assigns an element's own " + kindName(kind) + "s from " +
                    std::to_string(r.first) + ".." + std::to_string(r.last) + " and all " + std::to_string(r.last - r.first + 1) +
                    " are taken");
    assigned_.push_back({glslName, value, kind});
    return value;
}

}  // namespace welkin::gl
