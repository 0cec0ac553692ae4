#include <welkin/embedded/engine_shaders.hpp>
#include <welkin/error.hpp>
#include <welkin/gl/bindings.hpp>
#include <welkin/gl/shader.hpp>

#include "shader_log.hpp"

#include <epoxy/gl.h>

#include <cstdio>
#include <regex>
#include <sstream>

namespace welkin::gl {

namespace {
constexpr size_t kChunkLines = 100000;  // no chunk is that long
}

std::string_view engineShader(std::string_view path) { return embedded::engine_shaders(path); }

ProgramBuilder& ProgramBuilder::define(const std::string& name, const std::string& value) {
    defines_.emplace_back(name, value);
    return *this;
}
ProgramBuilder& ProgramBuilder::define(const std::string& name, int value) { return define(name, std::to_string(value)); }
ProgramBuilder& ProgramBuilder::define(const std::string& name, double value) {
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.9g", value);
    std::string s = buf;
    if (s.find_first_of(".eE") == std::string::npos) s += ".0";
    return define(name, s);
}
ProgramBuilder& ProgramBuilder::bindings(const PrivateBindings& b) {
    for (const auto& a : b.assigned()) {
        bool known = false;
        for (const auto& [n, v] : privateBindings_) {
            if (n != a.glslName) continue;
            if (v != a.value)
                throw Error(label_ + ": " + a.glslName + " is " + std::to_string(v) + " in one set of private bindings and " +
                            std::to_string(a.value) + " in " + b.owner() + "'s");
            known = true;
        }
        if (!known) privateBindings_.emplace_back(a.glslName, a.value);
    }
    return *this;
}
namespace {
// The marker lines around a file that EmbedShaders.cmake expanded in place of `#include "f"`.
constexpr std::string_view kIncludeBegin = "//@welkin-include-begin ";
constexpr std::string_view kIncludeEnd = "//@welkin-include-end";
}  // namespace

std::vector<ProgramBuilder::Chunk> ProgramBuilder::split(const std::string& name, std::string_view text) {
    // An expanded include becomes a chunk of its own, named after the included file (in the
    // including chunk's folder), and the including file resumes as a chunk at the line after its
    // #include: the driver's line numbers map back to each file's own lines.
    struct Open {
        std::string name;
        std::string text;
        int firstLine;
        int line;  // the line being read, in this file's numbering
    };
    std::vector<Chunk> out;
    std::vector<Open> stack{{name, {}, 1, 1}};
    auto flush = [&](Open& o) {
        if (!o.text.empty()) out.push_back({o.name, std::move(o.text), o.firstLine});
        o.text.clear();
    };
    size_t pos = 0;
    while (pos < text.size()) {
        size_t eol = text.find('\n', pos);
        if (eol == std::string_view::npos) eol = text.size();
        const std::string_view line = text.substr(pos, eol - pos);
        pos = eol + 1;
        if (line.substr(0, kIncludeBegin.size()) == kIncludeBegin) {
            Open& cur = stack.back();
            flush(cur);
            const std::string file(line.substr(kIncludeBegin.size()));
            const size_t slash = cur.name.rfind('/');
            stack.push_back({(slash == std::string::npos ? "" : cur.name.substr(0, slash + 1)) + file, {}, 1, 1});
            continue;
        }
        if (line == kIncludeEnd && stack.size() > 1) {
            flush(stack.back());
            stack.pop_back();
            Open& cur = stack.back();
            cur.firstLine = ++cur.line;  // past the #include line
            continue;
        }
        Open& cur = stack.back();
        cur.text.append(line).push_back('\n');
        ++cur.line;
    }
    for (auto& o : stack) flush(o);
    return out;
}

ProgramBuilder& ProgramBuilder::vertex(std::string name, std::string_view text) {
    for (auto& c : split(name, text)) vertex_.push_back(std::move(c));
    return *this;
}
ProgramBuilder& ProgramBuilder::fragment(std::string name, std::string_view text) {
    for (auto& c : split(name, text)) fragment_.push_back(std::move(c));
    return *this;
}
ProgramBuilder& ProgramBuilder::compute(std::string name, std::string_view text) {
    for (auto& c : split(name, text)) compute_.push_back(std::move(c));
    return *this;
}
ProgramBuilder& ProgramBuilder::fullscreenVertex() {
    return vertex("engine/fullscreen.vert.glsl", engineShader("fullscreen.vert.glsl"));
}

std::string ProgramBuilder::header(GLenum stage) const {
    std::string h = "#version 450 core\n";
    h += stage == GL_VERTEX_SHADER     ? "#define WELKIN_VERTEX_SHADER 1\n"
         : stage == GL_FRAGMENT_SHADER ? "#define WELKIN_FRAGMENT_SHADER 1\n"
                                       : "#define WELKIN_COMPUTE_SHADER 1\n";
    // One table for C++ and GLSL (welkin/gl/bindings.hpp).
    for (const auto& e : binding::kTable) h += "#define " + std::string(e.glslName) + " " + std::to_string(e.value) + "\n";
    // The element's own (welkin/gl/private_bindings.hpp).
    for (const auto& [n, v] : privateBindings_) h += "#define " + n + " " + std::to_string(v) + "\n";
    for (const auto& [n, v] : defines_) h += "#define " + n + " " + v + "\n";
    // The shared-maths dialect (welkin/glsl_cpp.hpp defines the same names for C++).
    h += "#define real float\n#define IN(T) in T\n#define OUT(T) out T\n#define INOUT(T) inout T\n";
    h += "#define ARRAY_OF(T, N) T[N](\n#define END_ARRAY )\n";  // const T a[N] = ARRAY_OF(T, N) x, y END_ARRAY;
    return h;
}

std::vector<std::string> ProgramBuilder::sources(GLenum stage, const std::vector<Chunk>& chunks) const {
    std::vector<std::string> out{header(stage)};
    for (size_t i = 0; i < chunks.size(); ++i) {
        // The chunk index is encoded in the line number itself (chunk k starts at line
        // k * kChunkLines + 1): drivers differ in whether they report the source-string number
        // of `#line L S`, but all report line numbers.
        out.push_back("#line " + std::to_string((i + 1) * kChunkLines + size_t(chunks[i].firstLine)) + "\n" + chunks[i].text + "\n");
    }
    return out;
}

std::string ProgramBuilder::assembled(GLenum stage) const {
    const auto& chunks = stage == GL_VERTEX_SHADER ? vertex_ : stage == GL_FRAGMENT_SHADER ? fragment_ : compute_;
    std::string all;
    for (const auto& s : sources(stage, chunks)) all += s;
    return all;
}

std::string ProgramBuilder::mapLog(const std::string& log, const std::vector<Chunk>& chunks) const {
    std::vector<std::string> names;
    for (const Chunk& c : chunks) names.push_back(c.name);
    return detail::mapShaderLog(log, names, kChunkLines);
}

namespace detail {
std::string mapShaderLog(const std::string& log, const std::vector<std::string>& chunkNames, size_t chunkLines) {
    // Mesa writes "0:300012(5): error: ..."; NVIDIA "0(300012) : error C1503: ..."; others
    // "ERROR: 0:300012: ...". Decode the line number into the chunk's file name and its own line.
    static const std::regex nvidia(R"(^\s*(\d+)\((\d+)\))");
    static const std::regex re(R"((\d+):(\d+)(\(\d+\))?)");
    std::string out;
    std::istringstream in(log);
    std::string line;
    while (std::getline(in, line)) {
        if (line.empty()) continue;
        std::smatch m;
        if (std::regex_search(line, m, nvidia) || std::regex_search(line, m, re)) {
            size_t encoded = std::stoul(m[2]);
            size_t idx = encoded / chunkLines, local = encoded % chunkLines;
            std::string file = idx == 0 ? "<generated header>" : idx <= chunkNames.size() ? chunkNames[idx - 1] : "?";
            line = m.prefix().str() + file + ":" + std::to_string(local) + m.suffix().str();
        }
        if (!out.empty()) out += " | ";
        out += line;
    }
    return out;
}
}  // namespace detail

GLuint ProgramBuilder::compileStage(GLenum stage, const std::vector<Chunk>& chunks) const {
    auto srcs = sources(stage, chunks);
    std::vector<const char*> ptrs;
    for (const auto& s : srcs) ptrs.push_back(s.c_str());
    GLuint sh = glCreateShader(stage);
    glShaderSource(sh, GLsizei(ptrs.size()), ptrs.data(), nullptr);
    glCompileShader(sh);
    GLint ok = 0;
    glGetShaderiv(sh, GL_COMPILE_STATUS, &ok);
    if (!ok) {
        GLint len = 0;
        glGetShaderiv(sh, GL_INFO_LOG_LENGTH, &len);
        std::string log(size_t(std::max(len, 1)), '\0');
        glGetShaderInfoLog(sh, len, nullptr, log.data());
        glDeleteShader(sh);
        const char* kind = stage == GL_VERTEX_SHADER ? "vertex" : stage == GL_FRAGMENT_SHADER ? "fragment" : "compute";
        throw Error(label_ + ": " + kind + " shader failed to compile: " + mapLog(log.c_str(), chunks));
    }
    return sh;
}

Program ProgramBuilder::build() const {
    if (compute_.empty() && (vertex_.empty() || fragment_.empty()))
        throw Error(label_ + ": a program needs a vertex and a fragment stage, or a compute stage");
    std::vector<GLuint> shaders;
    try {
        if (!compute_.empty()) {
            shaders.push_back(compileStage(GL_COMPUTE_SHADER, compute_));
        } else {
            shaders.push_back(compileStage(GL_VERTEX_SHADER, vertex_));
            shaders.push_back(compileStage(GL_FRAGMENT_SHADER, fragment_));
        }
    } catch (...) {
        for (GLuint s : shaders) glDeleteShader(s);
        throw;
    }
    GLuint p = glCreateProgram();
    for (GLuint s : shaders) glAttachShader(p, s);
    glLinkProgram(p);
    for (GLuint s : shaders) {
        glDetachShader(p, s);
        glDeleteShader(s);
    }
    GLint ok = 0;
    glGetProgramiv(p, GL_LINK_STATUS, &ok);
    if (!ok) {
        GLint len = 0;
        glGetProgramiv(p, GL_INFO_LOG_LENGTH, &len);
        std::string log(size_t(std::max(len, 1)), '\0');
        glGetProgramInfoLog(p, len, nullptr, log.data());
        glDeleteProgram(p);
        // Link messages may concern either stage, so file:line mapping would guess; keep them
        // as the driver wrote them, on one line.
        std::string oneLine;
        for (char ch : std::string(log.c_str())) oneLine += (ch == '\n') ? ' ' : ch;
        throw Error(label_ + ": program failed to link: " + oneLine);
    }
    glObjectLabel(GL_PROGRAM, p, GLsizei(label_.size()), label_.c_str());
    return Program(p, label_);
}

}  // namespace welkin::gl
