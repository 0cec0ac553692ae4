// The host's own OpenGL plumbing: move-only owners of GL names and a shader-program builder.
// A game has these already; the example keeps its own (it does not borrow welkin's internal
// wrappers) so that it reads like a host beside welkin, not a part of it.
//
//   host::GlName vbo = host::GlName::buffer();             // glCreateBuffers, freed by the destructor
//   host::GlName prog = host::buildProgram("pbr", {{GL_VERTEX_SHADER, vs}, {GL_FRAGMENT_SHADER, fs}});
//
// Every function needs a current OpenGL 4.5 core context (loaded with libepoxy) and throws
// std::runtime_error with a one-line message naming what failed.
#pragma once
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace host {

/// One GL object name and the function that deletes it. Move-only; empty when id() == 0.
class GlName {
public:
    using Deleter = void (*)(unsigned);
    GlName() = default;
    GlName(unsigned id, Deleter del) : id_(id), del_(del) {}
    GlName(GlName&& o) noexcept : id_(std::exchange(o.id_, 0)), del_(o.del_) {}
    GlName& operator=(GlName&& o) noexcept {
        if (this != &o) {
            reset();
            id_ = std::exchange(o.id_, 0);
            del_ = o.del_;
        }
        return *this;
    }
    GlName(const GlName&) = delete;
    GlName& operator=(const GlName&) = delete;
    ~GlName() { reset(); }

    unsigned id() const { return id_; }
    explicit operator bool() const { return id_ != 0; }
    void reset() {
        if (id_ && del_) del_(id_);
        id_ = 0;
    }

    static GlName buffer();
    static GlName vertexArray();
    static GlName texture(unsigned target);
    static GlName framebuffer();
    static GlName query(unsigned target);

private:
    unsigned id_ = 0;
    Deleter del_ = nullptr;
};

/// A program from its stages' sources (each a complete GLSL text, "#version 450 core" first).
/// Throws std::runtime_error("<name>: <stage> shader: <first line of the log>") on a compile
/// or link error; the whole log goes to stderr.
GlName buildProgram(std::string_view name, const std::vector<std::pair<unsigned, std::string>>& stages);

/// Throws std::runtime_error("<where>: GL error 0x....") if the GL reports an error.
void checkGl(std::string_view where);

}  // namespace host
