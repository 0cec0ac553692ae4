// Shader assembly in an explicit order, with compile errors that name the source file and line.
//
//   auto program = welkin::gl::ProgramBuilder("Grid")
//       .define("GRID_STEP_DEG", 10)                                    // generated header
//       .bindings(bindings())                                           // the element's own units
//       .fullscreenVertex()                                             // engine/fullscreen.vert.glsl
//       .fragment("engine/camera.glsl", engineShader("camera.glsl"))    // shared chunks first
//       .fragment("engine/composite.glsl", engineShader("composite.glsl"))
//       .fragment("grid/grid.frag.glsl", gridText)                      // then the owner's code
//       .build();                                                      // throws welkin::Error
//
// Each stage is assembled as: a generated header (`#version 450 core`; the stage's macro,
// WELKIN_VERTEX_SHADER, WELKIN_FRAGMENT_SHADER or WELKIN_COMPUTE_SHADER; every binding of
// <welkin/gl/bindings.hpp> as `#define WELKIN_BINDING_<NAME> <value>`; then the private bindings
// given to bindings(), the same way; then every define in the order given; then the shared-maths
// dialect of <welkin/glsl_cpp.hpp>: `real` as float, IN(T)/OUT(T)/INOUT(T) as in/out/inout T),
// then each chunk in the order added, each preceded by `#line <n*100000+first line>` so
// that the driver's messages can be mapped back whatever the driver: "grid/grid.frag.glsl:12: error: ...".
// A file that an embedded shader `#include`s (EmbedShaders.cmake expands it between marker
// comments) becomes a chunk of its own named after it in the includer's folder
// ("generators/cloud_noise.shared.glsl:40: error: ..."), and the includer resumes after it.
#pragma once
#include <welkin/gl/bindings.hpp>  // the table whose names every generated header defines
#include <welkin/gl/objects.hpp>
#include <welkin/gl/private_bindings.hpp>

#include <string>
#include <string_view>
#include <vector>

namespace welkin::gl {

/// Text of one of the engine's embedded GLSL chunks (`engine/shaders/<path>`).
std::string_view engineShader(std::string_view path);

class ProgramBuilder {
public:
    explicit ProgramBuilder(std::string label) : label_(std::move(label)) {}

    ProgramBuilder& define(const std::string& name, const std::string& value = "1");
    ProgramBuilder& define(const std::string& name, int value);
    ProgramBuilder& define(const std::string& name, double value);
    /// Defines `WELKIN_BINDING_<NAME> <value>` for every binding `b` has assigned so far (an
    /// element's own units: SkyElement::bindings()); ask for them before building. Throws
    /// welkin::Error if a name was already given another value by an earlier call.
    ProgramBuilder& bindings(const PrivateBindings& b);
    /// A chunk of the vertex stage (e.g. engine/camera.glsl, then your own main() that sets
    /// gl_Position = welkin_clipFromDirection(dir)); or fullscreenVertex().
    ProgramBuilder& vertex(std::string name, std::string_view text);
    ProgramBuilder& fragment(std::string name, std::string_view text);
    ProgramBuilder& compute(std::string name, std::string_view text);
    /// Adds the engine's fullscreen-triangle vertex shader (draw 3 vertices, no attributes).
    ProgramBuilder& fullscreenVertex();

    /// The assembled source of a stage (GL_VERTEX_SHADER, ...), as the driver sees it.
    std::string assembled(unsigned stage) const;
    /// Compiles and links. Throws welkin::Error whose message names the label, file and line.
    Program build() const;

private:
    struct Chunk {
        std::string name;
        std::string text;
        int firstLine = 1;  ///< the line of `name` that text starts at
    };
    static std::vector<Chunk> split(const std::string& name, std::string_view text);
    std::string label_;
    std::vector<std::pair<std::string, std::string>> defines_;
    std::vector<std::pair<std::string, int>> privateBindings_;
    std::vector<Chunk> vertex_, fragment_, compute_;

    std::string header(unsigned stage) const;
    std::vector<std::string> sources(unsigned stage, const std::vector<Chunk>& chunks) const;
    unsigned compileStage(unsigned stage, const std::vector<Chunk>& chunks) const;
    std::string mapLog(const std::string& log, const std::vector<Chunk>& chunks) const;
};

}  // namespace welkin::gl
