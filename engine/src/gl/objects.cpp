#include <welkin/error.hpp>
#include <welkin/gl/objects.hpp>

#include <epoxy/gl.h>

#include <glm/gtc/type_ptr.hpp>

#include <array>
#include <utility>

namespace welkin::gl {

const char* errorName(GLenum error) {
    switch (error) {
        case GL_NO_ERROR: return "GL_NO_ERROR";
        case GL_INVALID_ENUM: return "GL_INVALID_ENUM";
        case GL_INVALID_VALUE: return "GL_INVALID_VALUE";
        case GL_INVALID_OPERATION: return "GL_INVALID_OPERATION";
        case GL_INVALID_FRAMEBUFFER_OPERATION: return "GL_INVALID_FRAMEBUFFER_OPERATION";
        case GL_OUT_OF_MEMORY: return "GL_OUT_OF_MEMORY";
        case GL_STACK_UNDERFLOW: return "GL_STACK_UNDERFLOW";
        case GL_STACK_OVERFLOW: return "GL_STACK_OVERFLOW";
        default: return "unknown GL error";
    }
}

void checkError(std::string_view where) {
    GLenum first = glGetError();
    if (first == GL_NO_ERROR) return;
    while (glGetError() != GL_NO_ERROR) {
    }
    throw Error(std::string(where) + ": GL error " + errorName(first));
}

// --- Texture -----------------------------------------------------------------------------------

Texture::Texture(GLenum target, GLenum internalFormat, int w, int h, int d, int levels)
    : target_(target), format_(internalFormat), w_(w), h_(h), d_(d), levels_(levels) {
    if (w <= 0 || h <= 0 || d <= 0 || levels <= 0)
        throw Error("gl::Texture: size " + std::to_string(w) + "x" + std::to_string(h) + "x" + std::to_string(d) +
                    " with " + std::to_string(levels) + " levels must be positive");
    const bool layered = target == GL_TEXTURE_3D || target == GL_TEXTURE_2D_ARRAY;
    if (!layered && target != GL_TEXTURE_1D && target != GL_TEXTURE_2D && target != GL_TEXTURE_CUBE_MAP)
        throw Error("gl::Texture: unsupported target");
    glCreateTextures(target, 1, &id_);
    if (layered)
        glTextureStorage3D(id_, levels, internalFormat, w, h, d);
    else if (target == GL_TEXTURE_1D)
        glTextureStorage1D(id_, levels, internalFormat, w);
    else
        glTextureStorage2D(id_, levels, internalFormat, w, h);
    GLenum filter = levels > 1 ? GL_LINEAR_MIPMAP_LINEAR : GL_LINEAR;
    glTextureParameteri(id_, GL_TEXTURE_MIN_FILTER, filter);
    glTextureParameteri(id_, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    setWrap(GL_CLAMP_TO_EDGE);
    checkError("gl::Texture: creating storage");
}

Texture::~Texture() { destroy(); }
void Texture::destroy() {
    if (id_) glDeleteTextures(1, &id_);
    id_ = 0;
}
Texture::Texture(Texture&& o) noexcept
    : Object(std::move(o)), target_(o.target_), format_(o.format_), w_(o.w_), h_(o.h_), d_(o.d_), levels_(o.levels_) {}
Texture& Texture::operator=(Texture&& o) noexcept {
    if (this != &o) {
        destroy();
        id_ = o.release();
        target_ = o.target_;
        format_ = o.format_;
        w_ = o.w_;
        h_ = o.h_;
        d_ = o.d_;
        levels_ = o.levels_;
    }
    return *this;
}

void Texture::setFilter(GLenum minFilter, GLenum magFilter) {
    glTextureParameteri(id_, GL_TEXTURE_MIN_FILTER, minFilter);
    glTextureParameteri(id_, GL_TEXTURE_MAG_FILTER, magFilter);
}
void Texture::setWrap(GLenum wrap) {
    glTextureParameteri(id_, GL_TEXTURE_WRAP_S, wrap);
    glTextureParameteri(id_, GL_TEXTURE_WRAP_T, wrap);
    glTextureParameteri(id_, GL_TEXTURE_WRAP_R, wrap);
}
void Texture::bind(GLuint unit) const { glBindTextureUnit(unit, id_); }
void Texture::generateMipmaps() { glGenerateTextureMipmap(id_); }

namespace {
// Client-memory transfers (upload, read back) with GL's default pixel-store parameters and no
// pixel buffer bound, whatever the host set; the host's values are put back afterwards.
class ClientTransfer {
public:
    explicit ClientTransfer(bool pack) : pack_(pack) {
        glGetIntegerv(pack ? GL_PIXEL_PACK_BUFFER_BINDING : GL_PIXEL_UNPACK_BUFFER_BINDING, &buffer_);
        for (size_t i = 0; i < params().size(); ++i) glGetIntegerv(params()[i].first, &saved_[i]);
        glBindBuffer(pack ? GL_PIXEL_PACK_BUFFER : GL_PIXEL_UNPACK_BUFFER, 0);
        for (auto [pname, value] : params()) glPixelStorei(pname, value);
    }
    ~ClientTransfer() {
        const GLuint b = buffer_ && glIsBuffer(GLuint(buffer_)) ? GLuint(buffer_) : 0;
        glBindBuffer(pack_ ? GL_PIXEL_PACK_BUFFER : GL_PIXEL_UNPACK_BUFFER, b);
        for (size_t i = 0; i < params().size(); ++i) glPixelStorei(params()[i].first, saved_[i]);
    }
    ClientTransfer(const ClientTransfer&) = delete;
    ClientTransfer& operator=(const ClientTransfer&) = delete;

private:
    using Params = std::array<std::pair<GLenum, GLint>, 6>;
    const Params& params() const {
        static constexpr Params kPack = {{{GL_PACK_ALIGNMENT, 4}, {GL_PACK_ROW_LENGTH, 0}, {GL_PACK_IMAGE_HEIGHT, 0},
                                          {GL_PACK_SKIP_ROWS, 0}, {GL_PACK_SKIP_PIXELS, 0}, {GL_PACK_SKIP_IMAGES, 0}}};
        static constexpr Params kUnpack = {{{GL_UNPACK_ALIGNMENT, 4}, {GL_UNPACK_ROW_LENGTH, 0}, {GL_UNPACK_IMAGE_HEIGHT, 0},
                                            {GL_UNPACK_SKIP_ROWS, 0}, {GL_UNPACK_SKIP_PIXELS, 0}, {GL_UNPACK_SKIP_IMAGES, 0}}};
        return pack_ ? kPack : kUnpack;
    }
    bool pack_;
    GLint buffer_ = 0;
    std::array<GLint, 6> saved_{};
};
}  // namespace

void Texture::upload(GLenum format, GLenum type, const void* data, int level) {
    ClientTransfer transfer(false);
    int w = std::max(1, w_ >> level), h = std::max(1, h_ >> level);
    if (target_ == GL_TEXTURE_1D) {
        glTextureSubImage1D(id_, level, 0, w, format, type, data);
    } else if (target_ == GL_TEXTURE_2D) {
        glTextureSubImage2D(id_, level, 0, 0, w, h, format, type, data);
    } else {
        int d = target_ == GL_TEXTURE_3D ? std::max(1, d_ >> level) : d_;
        glTextureSubImage3D(id_, level, 0, 0, 0, w, h, d, format, type, data);
    }
    checkError("gl::Texture::upload()");
}

std::vector<float> Texture::readRgbaFloat(int level) const {
    int w = std::max(1, w_ >> level), h = std::max(1, h_ >> level);
    int d = target_ == GL_TEXTURE_3D ? std::max(1, d_ >> level) : d_;
    std::vector<float> out(size_t(w) * h * d * 4);
    ClientTransfer transfer(true);
    glGetTextureImage(id_, level, GL_RGBA, GL_FLOAT, GLsizei(out.size() * sizeof(float)), out.data());
    checkError("gl::Texture::readRgbaFloat()");
    return out;
}

Texture1D::Texture1D(int w, GLenum f, int levels) : Texture(GL_TEXTURE_1D, f, w, 1, 1, levels) {}
Texture2D::Texture2D(int w, int h, GLenum f, int levels) : Texture(GL_TEXTURE_2D, f, w, h, 1, levels) {}
Texture3D::Texture3D(int w, int h, int d, GLenum f, int levels) : Texture(GL_TEXTURE_3D, f, w, h, d, levels) {}
TextureCube::TextureCube(int s, GLenum f, int levels) : Texture(GL_TEXTURE_CUBE_MAP, f, s, s, 6, levels) {}
Texture2DArray::Texture2DArray(int w, int h, int layers, GLenum f, int levels)
    : Texture(GL_TEXTURE_2D_ARRAY, f, w, h, layers, levels) {}

// --- Renderbuffer ------------------------------------------------------------------------------

Renderbuffer::Renderbuffer(int w, int h, GLenum f) {
    glCreateRenderbuffers(1, &id_);
    glNamedRenderbufferStorage(id_, f, w, h);
    checkError("gl::Renderbuffer");
}
Renderbuffer::~Renderbuffer() {
    if (id_) glDeleteRenderbuffers(1, &id_);
}
Renderbuffer& Renderbuffer::operator=(Renderbuffer&& o) noexcept {
    if (this != &o) {
        if (id_) glDeleteRenderbuffers(1, &id_);
        id_ = o.release();
    }
    return *this;
}

// --- Framebuffer -------------------------------------------------------------------------------

Framebuffer Framebuffer::create() {
    GLuint id = 0;
    glCreateFramebuffers(1, &id);
    return Framebuffer(id);
}
Framebuffer::~Framebuffer() {
    if (id_) glDeleteFramebuffers(1, &id_);
}
Framebuffer& Framebuffer::operator=(Framebuffer&& o) noexcept {
    if (this != &o) {
        if (id_) glDeleteFramebuffers(1, &id_);
        id_ = o.release();
    }
    return *this;
}
void Framebuffer::attach(GLenum attachment, const Texture& t, int level, int layer) {
    if (!id_) throw Error("gl::Framebuffer::attach(): empty framebuffer (use Framebuffer::create())");
    if (layer >= 0)
        glNamedFramebufferTextureLayer(id_, attachment, t.id(), level, layer);
    else
        glNamedFramebufferTexture(id_, attachment, t.id(), level);
}
void Framebuffer::attach(GLenum attachment, const Renderbuffer& rb) {
    glNamedFramebufferRenderbuffer(id_, attachment, GL_RENDERBUFFER, rb.id());
}
void Framebuffer::checkComplete(std::string_view owner) const {
    GLenum s = glCheckNamedFramebufferStatus(id_, GL_FRAMEBUFFER);
    if (s != GL_FRAMEBUFFER_COMPLETE) {
        char buf[32];
        std::snprintf(buf, sizeof buf, "0x%04x", s);
        throw Error(std::string(owner) + ": framebuffer incomplete (status " + buf + ")");
    }
}
void Framebuffer::bind() const { glBindFramebuffer(GL_FRAMEBUFFER, id_); }

// --- Buffer ------------------------------------------------------------------------------------

Buffer::Buffer(size_t bytes, const void* data) : size_(bytes) {
    glCreateBuffers(1, &id_);
    glNamedBufferStorage(id_, GLsizeiptr(bytes), data, GL_DYNAMIC_STORAGE_BIT);
    checkError("gl::Buffer");
}
Buffer::~Buffer() {
    if (id_) glDeleteBuffers(1, &id_);
}
Buffer& Buffer::operator=(Buffer&& o) noexcept {
    if (this != &o) {
        if (id_) glDeleteBuffers(1, &id_);
        id_ = o.release();
        size_ = std::exchange(o.size_, 0);
    }
    return *this;
}
void Buffer::update(const void* data, size_t bytes, size_t offset) {
    if (offset + bytes > size_)
        throw Error("gl::Buffer::update(): " + std::to_string(offset + bytes) + " bytes exceed size " + std::to_string(size_));
    glNamedBufferSubData(id_, GLintptr(offset), GLsizeiptr(bytes), data);
}
void Buffer::bindBase(GLenum target, GLuint index) const { glBindBufferBase(target, index, id_); }

// --- VertexArray -------------------------------------------------------------------------------

VertexArray VertexArray::create() {
    GLuint id = 0;
    glCreateVertexArrays(1, &id);
    return VertexArray(id);
}
VertexArray::~VertexArray() {
    if (id_) glDeleteVertexArrays(1, &id_);
}
VertexArray& VertexArray::operator=(VertexArray&& o) noexcept {
    if (this != &o) {
        if (id_) glDeleteVertexArrays(1, &id_);
        id_ = o.release();
    }
    return *this;
}
void VertexArray::bind() const { glBindVertexArray(id_); }

// --- Program -----------------------------------------------------------------------------------

Program::~Program() {
    if (id_) glDeleteProgram(id_);
}
Program& Program::operator=(Program&& o) noexcept {
    if (this != &o) {
        if (id_) glDeleteProgram(id_);
        id_ = o.release();
        label_ = std::move(o.label_);
    }
    return *this;
}
void Program::use() const { glUseProgram(id_); }
GLint Program::location(const char* name) const { return glGetUniformLocation(id_, name); }
void Program::set(const char* n, int v) const { glProgramUniform1i(id_, location(n), v); }
void Program::set(const char* n, float v) const { glProgramUniform1f(id_, location(n), v); }
void Program::set(const char* n, const glm::vec2& v) const { glProgramUniform2fv(id_, location(n), 1, glm::value_ptr(v)); }
void Program::set(const char* n, const glm::vec3& v) const { glProgramUniform3fv(id_, location(n), 1, glm::value_ptr(v)); }
void Program::set(const char* n, const glm::vec4& v) const { glProgramUniform4fv(id_, location(n), 1, glm::value_ptr(v)); }
void Program::set(const char* n, const glm::ivec2& v) const { glProgramUniform2iv(id_, location(n), 1, glm::value_ptr(v)); }
void Program::set(const char* n, const glm::mat3& v) const {
    glProgramUniformMatrix3fv(id_, location(n), 1, GL_FALSE, glm::value_ptr(v));
}
void Program::set(const char* n, const glm::mat4& v) const {
    glProgramUniformMatrix4fv(id_, location(n), 1, GL_FALSE, glm::value_ptr(v));
}

}  // namespace welkin::gl
