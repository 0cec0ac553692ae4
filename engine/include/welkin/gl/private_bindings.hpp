// PrivateBindings: the texture units, image units and uniform/storage buffer bindings an element
// uses alone, asked for by name and numbered by the framework, so that no element edits the
// shared table of <welkin/gl/bindings.hpp>.
//
//   void Planet::doInit(welkin::InitContext& ctx) {
//       albedoUnit_ = textureUnit("MOON_ALBEDO");         // SkyElement's wrapper: 16, the first private unit
//       program_ = welkin::gl::ProgramBuilder("Planet")
//                      .bindings(bindings())              // #define WELKIN_BINDING_MOON_ALBEDO 16
//                      ...
//                      .build();
//   }
//   // GLSL: layout(binding = WELKIN_BINDING_MOON_ALBEDO) uniform sampler2D u_albedo;
//   // doRender(): albedoTex_.bind(albedoUnit_);
//
// Each kind (texture unit, image unit, uniform buffer, storage buffer) is numbered on its own,
// from the first value of its private range (binding::kPrivateTextureUnitFirst, ...) up, in the
// order of the requests; asking again for a name returns its value. Elements render one at a
// time, so every element numbers from the same first value; the private ranges lie above every
// shared binding of the table, so an element's own units never hide the shared ones its passes
// also sample (the sky's LUTs, the clouds' textures), and the processor's GL state guard saves and
// restores them for the host. A name is the define's suffix: upper-case letters, digits and '_',
// not a name of the shared table.
#pragma once
#include <welkin/gl/bindings.hpp>

#include <string>
#include <string_view>
#include <vector>

namespace welkin::gl {

class PrivateBindings {
public:
    /// `owner`: who asks, as the errors name it (a SkyElement's are "element 'planet'").
    explicit PrivateBindings(std::string owner) : owner_(std::move(owner)) {}

    /// The value of `name` as a texture unit (glBindTextureUnit, `layout(binding = ...)` on a
    /// sampler), assigned from binding::kPrivateTextureUnitFirst..kPrivateTextureUnitLast.
    /// Throws welkin::Error (one line naming the owner, the name and the range) when the range is
    /// full, the name is malformed or shared, or it was asked for as another kind.
    int textureUnit(std::string_view name) { return request(binding::Kind::TextureUnit, name); }
    /// An image unit (glBindImageTexture), from kPrivateImageUnitFirst..kPrivateImageUnitLast.
    int imageUnit(std::string_view name) { return request(binding::Kind::ImageUnit, name); }
    /// A uniform-buffer binding point, from kPrivateUboFirst..kPrivateUboLast.
    int uniformBuffer(std::string_view name) { return request(binding::Kind::UniformBuffer, name); }
    /// A shader-storage-buffer binding point, from kPrivateSsboFirst..kPrivateSsboLast.
    int storageBuffer(std::string_view name) { return request(binding::Kind::StorageBuffer, name); }
    /// Any of the four kinds above (not Kind::UserRange).
    int request(binding::Kind kind, std::string_view name);

    struct Assigned {
        std::string glslName;  ///< WELKIN_BINDING_<NAME>
        int value;
        binding::Kind kind;
    };
    /// Every binding assigned so far, in the order asked (what ProgramBuilder::bindings() defines).
    const std::vector<Assigned>& assigned() const { return assigned_; }
    const std::string& owner() const { return owner_; }

    /// The inclusive private range of a kind (binding::kPrivate*First, kPrivate*Last).
    struct Range {
        int first, last;
    };
    static Range range(binding::Kind kind);

private:
    std::string owner_;
    std::vector<Assigned> assigned_;
};

}  // namespace welkin::gl
