// Element-private GL bindings (welkin/gl/private_bindings.hpp): assigned by name from the private
// ranges of welkin/gl/bindings.hpp, refused with one line past a range's end, defined in every
// stage by ProgramBuilder::bindings(), and used by an element written here that never touches
// the shared table.
#include <catch2/catch.hpp>

#include "gl_test_context.hpp"

#include <welkin/element.hpp>
#include <welkin/error.hpp>
#include <welkin/gl/objects.hpp>
#include <welkin/gl/private_bindings.hpp>
#include <welkin/gl/shader.hpp>
#include <welkin/processor.hpp>

#include <epoxy/gl.h>

#include <algorithm>
#include <functional>
#include <string>

using namespace welkin;
namespace binding = gl::binding;

namespace {
// The largest value of a kind in the shared table (-1 if none).
int largestShared(binding::Kind kind) {
    int m = -1;
    for (const auto& e : binding::kTable)
        if (e.kind == kind) m = std::max(m, e.value);
    return m;
}

std::string thrownBy(const std::function<void()>& f) {
    try {
        f();
    } catch (const Error& e) {
        return e.what();
    }
    return "";
}
}  // namespace

TEST_CASE("PrivateBindings: consecutive values per kind from the private ranges, by name", "[cpu][bindings]") {
    gl::PrivateBindings b("element 'probe'");
    // Texture units number from the first private unit in the order asked; asking again for a
    // name returns its value and assigns nothing.
    CHECK(b.textureUnit("PROBE_A") == binding::kPrivateTextureUnitFirst);
    CHECK(b.textureUnit("PROBE_B") == binding::kPrivateTextureUnitFirst + 1);
    CHECK(b.textureUnit("PROBE_A") == binding::kPrivateTextureUnitFirst);
    // The other kinds are separate name spaces, each from its own first value.
    CHECK(b.imageUnit("PROBE_IMAGE") == binding::kPrivateImageUnitFirst);
    CHECK(b.uniformBuffer("PROBE_UBO") == binding::kPrivateUboFirst);
    CHECK(b.storageBuffer("PROBE_SSBO") == binding::kPrivateSsboFirst);
    CHECK(b.storageBuffer("PROBE_SSBO_2") == binding::kPrivateSsboFirst + 1);
    REQUIRE(b.assigned().size() == 6);
    CHECK(b.assigned()[0].glslName == "WELKIN_BINDING_PROBE_A");
    CHECK(b.assigned()[1].glslName == "WELKIN_BINDING_PROBE_B");
    CHECK(b.assigned()[2].kind == binding::Kind::ImageUnit);

    // Deterministic: another owner asking the same names in the same order gets the same values
    // (elements render one at a time, so each numbers from the same first value).
    gl::PrivateBindings c("element 'other'");
    CHECK(c.textureUnit("PROBE_A") == b.textureUnit("PROBE_A"));
    CHECK(c.textureUnit("OTHER_NAME") == b.textureUnit("PROBE_B"));

    // A private value never equals a shared one of its kind, which the same pass may also sample
    // (the ranges start above the whole table), and each range lies inside the state guard's
    // (checked at compile time in state_guard.cpp) and GL 4.5's guaranteed limits (the [gl] test
    // of the bindings table).
    for (auto kind : {binding::Kind::TextureUnit, binding::Kind::ImageUnit, binding::Kind::UniformBuffer, binding::Kind::StorageBuffer}) {
        const auto r = gl::PrivateBindings::range(kind);
        CHECK(r.first > largestShared(kind));
        CHECK(r.last >= r.first);
    }
    // The former names of the ranges still build and mean the same.
    CHECK(binding::kUserTextureUnitFirst == binding::kPrivateTextureUnitFirst);
    CHECK(binding::kUserSsboLast == binding::kPrivateSsboLast);
}

TEST_CASE("PrivateBindings: a full range, a bad name or a shared name is refused in one line", "[cpu][bindings]") {
    gl::PrivateBindings b("element 'greedy'");
    const auto tex = gl::PrivateBindings::range(binding::Kind::TextureUnit);
    for (int i = tex.first; i <= tex.last; ++i) CHECK(b.textureUnit("UNIT_" + std::to_string(i)) == i);
    const std::string full = thrownBy([&] { b.textureUnit("ONE_TOO_MANY"); });
    INFO(full);
    CHECK_THAT(full, Catch::Contains("element 'greedy'"));
    CHECK_THAT(full, Catch::Contains("ONE_TOO_MANY"));
    CHECK_THAT(full, Catch::Contains(std::to_string(tex.first) + ".." + std::to_string(tex.last)));
    CHECK(full.find('\n') == std::string::npos);
    // A name already assigned is still answered when the range is full.
    CHECK(b.textureUnit("UNIT_" + std::to_string(tex.first)) == tex.first);

    const auto img = gl::PrivateBindings::range(binding::Kind::ImageUnit);
    for (int i = img.first; i <= img.last; ++i) b.imageUnit("IMAGE_" + std::to_string(i));
    CHECK_THAT(thrownBy([&] { b.imageUnit("IMAGE_EXTRA"); }), Catch::Contains(std::to_string(img.first) + ".." + std::to_string(img.last)));

    // Names: the define's suffix, so upper case, digits and '_' only, not a shared name, one kind.
    CHECK_THAT(thrownBy([&] { b.storageBuffer("lower_case"); }), Catch::Contains("upper-case"));
    CHECK_THAT(thrownBy([&] { b.storageBuffer(""); }), Catch::Contains("upper-case"));
    CHECK_THAT(thrownBy([&] { b.storageBuffer("9LIVES"); }), Catch::Contains("upper-case"));
    CHECK_THAT(thrownBy([&] { b.uniformBuffer("CAMERA_UBO"); }), Catch::Contains("shared binding"));
    CHECK_THAT(thrownBy([&] { b.storageBuffer("UNIT_" + std::to_string(tex.first)); }), Catch::Contains("already asked for as a texture unit"));
}

TEST_CASE("An element of the test's own gets private units: its shaders see them and it renders", "[gl][bindings][processor]") {
    // A user element that samples a texture and reads a storage buffer, each at a binding it asks
    // for by name: nothing of it is in welkin/gl/bindings.hpp.
    struct Patch final : SkyElement {
        Patch() : SkyElement("patch") {}
        int unit = -1, ssbo = -1;
        gl::Program program;
        gl::Texture2D texture;
        gl::Buffer buffer;
        std::string fragmentSource;
        void doInit(InitContext&) override {
            unit = textureUnit("PATCH_TEXTURE");
            ssbo = storageBuffer("PATCH_SCALE");
            auto builder = gl::ProgramBuilder("Patch")
                               .bindings(bindings())
                               .fullscreenVertex()
                               .fragment("engine/composite.glsl", gl::engineShader("composite.glsl"))
                               .fragment("patch.frag.glsl",
                                         "layout(binding = WELKIN_BINDING_PATCH_TEXTURE) uniform sampler2D u_patch;\n"
                                         "layout(std430, binding = WELKIN_BINDING_PATCH_SCALE) readonly buffer Scale { float u_scale; };\n"
                                         "void main() { welkin_output(texelFetch(u_patch, ivec2(0), 0).rgb * u_scale, vec3(0.0)); }\n");
            fragmentSource = builder.assembled(GL_FRAGMENT_SHADER);
            program = builder.build();
            texture = gl::Texture2D(1, 1, GL_RGBA32F);
            const float rgba[4] = {1.0f, 2.0f, 4.0f, 1.0f};  // cd/m^2 before the scale
            texture.upload(GL_RGBA, GL_FLOAT, rgba);
            const float scale = 250.0f;
            buffer = gl::Buffer(sizeof scale, &scale);
        }
        void doRender(const FrameContext& ctx) override {
            program.use();
            texture.bind(unsigned(unit));
            buffer.bindBase(GL_SHADER_STORAGE_BUFFER, unsigned(ssbo));
            ctx.drawFullscreen();
        }
        void doRelease() override { program = {}; }
    };
    test::glContext();
    SkyProcessor p(SkyVars::earth(), Logger(), ProcessorOptions{.astronomy = false});
    Camera cam;
    cam.width = cam.height = 4;
    p.setCamera(cam);
    auto& patch = static_cast<Patch&>(p.add(std::make_unique<Patch>()));
    p.renderFrame();

    // The framework's numbers, in the generated header of the stage and in the linked program.
    CHECK(patch.unit == binding::kPrivateTextureUnitFirst);
    CHECK(patch.ssbo == binding::kPrivateSsboFirst);
    CHECK_THAT(patch.fragmentSource, Catch::Contains("#define WELKIN_BINDING_PATCH_TEXTURE " + std::to_string(patch.unit) + "\n"));
    CHECK_THAT(patch.fragmentSource, Catch::Contains("#define WELKIN_BINDING_PATCH_SCALE " + std::to_string(patch.ssbo) + "\n"));
    GLint samplerUnit = -1;
    glGetUniformiv(patch.program.id(), patch.program.location("u_patch"), &samplerUnit);
    CHECK(samplerUnit == patch.unit);
    REQUIRE(patch.bindings().assigned().size() == 2);
    CHECK(patch.bindings().owner() == "element 'patch'");

    // Rendered: texel x scale on every pixel, exactly (small integers are exact in float).
    const Image hdr = p.readHdr();
    for (int y = 0; y < hdr.height; ++y)
        for (int x = 0; x < hdr.width; ++x) {
            CHECK(hdr.at(x, y, 0) == 250.0f);
            CHECK(hdr.at(x, y, 1) == 500.0f);
            CHECK(hdr.at(x, y, 2) == 1000.0f);
        }

    // Two sets that give one name two values cannot both reach a program.
    gl::PrivateBindings one("element 'one'"), two("element 'two'");
    one.textureUnit("SAME_NAME");
    two.textureUnit("FIRST");
    two.textureUnit("SAME_NAME");
    gl::ProgramBuilder builder("clash");
    builder.bindings(one);
    CHECK_THROWS_WITH(builder.bindings(two), Catch::Contains("WELKIN_BINDING_SAME_NAME"));
}
