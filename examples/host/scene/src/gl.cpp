#include <welkin_host/gl.hpp>

#include <epoxy/gl.h>

#include <cstdio>
#include <stdexcept>

namespace host {

GlName GlName::buffer() {
    GLuint n = 0;
    glCreateBuffers(1, &n);
    return {n, [](unsigned id) { glDeleteBuffers(1, &id); }};
}
GlName GlName::vertexArray() {
    GLuint n = 0;
    glCreateVertexArrays(1, &n);
    return {n, [](unsigned id) { glDeleteVertexArrays(1, &id); }};
}
GlName GlName::texture(unsigned target) {
    GLuint n = 0;
    glCreateTextures(target, 1, &n);
    return {n, [](unsigned id) { glDeleteTextures(1, &id); }};
}
GlName GlName::framebuffer() {
    GLuint n = 0;
    glCreateFramebuffers(1, &n);
    return {n, [](unsigned id) { glDeleteFramebuffers(1, &id); }};
}
GlName GlName::query(unsigned target) {
    GLuint n = 0;
    glCreateQueries(target, 1, &n);
    return {n, [](unsigned id) { glDeleteQueries(1, &id); }};
}

namespace {
std::string firstLine(const std::string& s) {
    auto end = s.find('\n');
    return s.substr(0, end);
}
const char* stageName(unsigned stage) {
    switch (stage) {
    case GL_VERTEX_SHADER: return "vertex";
    case GL_FRAGMENT_SHADER: return "fragment";
    case GL_COMPUTE_SHADER: return "compute";
    default: return "other";
    }
}
}  // namespace

GlName buildProgram(std::string_view name, const std::vector<std::pair<unsigned, std::string>>& stages) {
    GlName program(glCreateProgram(), [](unsigned id) { glDeleteProgram(id); });
    std::vector<GLuint> shaders;
    for (const auto& [stage, source] : stages) {
        GLuint s = glCreateShader(stage);
        const char* text = source.c_str();
        glShaderSource(s, 1, &text, nullptr);
        glCompileShader(s);
        GLint ok = 0;
        glGetShaderiv(s, GL_COMPILE_STATUS, &ok);
        if (!ok) {
            GLint len = 0;
            glGetShaderiv(s, GL_INFO_LOG_LENGTH, &len);
            std::string log(size_t(std::max(len, 1)), '\0');
            glGetShaderInfoLog(s, len, nullptr, log.data());
            glDeleteShader(s);
            for (GLuint t : shaders) glDeleteShader(t);
            std::fprintf(stderr, "%.*s (%s shader):\n%s\n", int(name.size()), name.data(), stageName(stage), log.c_str());
            throw std::runtime_error(std::string(name) + ": " + stageName(stage) + " shader: " + firstLine(log));
        }
        glAttachShader(program.id(), s);
        shaders.push_back(s);
    }
    glLinkProgram(program.id());
    for (GLuint s : shaders) {
        glDetachShader(program.id(), s);
        glDeleteShader(s);
    }
    GLint ok = 0;
    glGetProgramiv(program.id(), GL_LINK_STATUS, &ok);
    if (!ok) {
        GLint len = 0;
        glGetProgramiv(program.id(), GL_INFO_LOG_LENGTH, &len);
        std::string log(size_t(std::max(len, 1)), '\0');
        glGetProgramInfoLog(program.id(), len, nullptr, log.data());
        std::fprintf(stderr, "%.*s (link):\n%s\n", int(name.size()), name.data(), log.c_str());
        throw std::runtime_error(std::string(name) + ": link: " + firstLine(log));
    }
    return program;
}

void checkGl(std::string_view where) {
    GLenum e = glGetError();
    if (e != GL_NO_ERROR) {
        char buf[16];
        std::snprintf(buf, sizeof buf, "0x%04X", e);
        while (glGetError() != GL_NO_ERROR) {
        }
        throw std::runtime_error(std::string(where) + ": GL error " + buf);
    }
}

}  // namespace host
