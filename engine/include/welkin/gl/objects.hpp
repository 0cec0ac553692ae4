// Move-only RAII wrappers for OpenGL 4.5 objects (direct state access). Each has an empty state
// (id() == 0), is not copyable, frees its GL name in the destructor, and release() gives the name
// up without deleting it.
//
//   welkin::gl::Texture2D lut(256, 64, GL_RGBA32F);            // immutable storage, 1 level
//   lut.setFilter(GL_LINEAR); lut.setWrap(GL_CLAMP_TO_EDGE);
//   auto fb = welkin::gl::Framebuffer::create();
//   fb.attach(GL_COLOR_ATTACHMENT0, lut);
//   fb.checkComplete("TransmittanceLut");                         // throws naming the owner
//   std::vector<float> px = lut.readRgbaFloat();                  // for tests and CPU twins
//
// All constructors need a current GL 4.5 context. The header includes no GL loader (GL enums
// and names are `unsigned`, as GLenum and GLuint are): a host using glad, GLEW or its own loader
// can include it; the GL_* constants in the example come from the caller's loader.
#pragma once
#include <welkin/vars.hpp>

#include <string>
#include <string_view>
#include <type_traits>
#include <utility>
#include <vector>

namespace welkin::gl {

/// Throws welkin::Error("<where>: GL error <name>") if glGetError() reports anything.
void checkError(std::string_view where);
/// Symbolic name of a GL error code ("GL_INVALID_OPERATION").
const char* errorName(unsigned error);

/// Base of the owning wrappers: holds the GL name and how to delete it.
class Object {
public:
    Object() = default;
    Object(const Object&) = delete;
    Object& operator=(const Object&) = delete;
    Object(Object&& o) noexcept : id_(std::exchange(o.id_, 0)) {}
    Object& operator=(Object&& o) noexcept = delete;  // each derived class implements move-assign

    unsigned id() const { return id_; }
    explicit operator bool() const { return id_ != 0; }
    /// Gives up ownership: returns the name, leaves this object empty, deletes nothing.
    unsigned release() { return std::exchange(id_, 0); }

protected:
    explicit Object(unsigned id) : id_(id) {}
    unsigned id_ = 0;
};

/// A texture of any target with immutable storage.
class Texture : public Object {
public:
    Texture() = default;
    ~Texture();
    Texture(Texture&& o) noexcept;
    Texture& operator=(Texture&& o) noexcept;

    unsigned target() const { return target_; }
    unsigned internalFormat() const { return format_; }
    int width() const { return w_; }
    int height() const { return h_; }
    /// Depth for 3-D textures, layers for arrays, 6 for cube maps, 1 otherwise.
    int depth() const { return d_; }
    int levels() const { return levels_; }
    /// Non-owning handle to publish in SkyVars.
    TextureRef ref() const { return {id_, target_, w_, h_, d_}; }

    void setFilter(unsigned minFilter, unsigned magFilter);
    void setFilter(unsigned filter) { setFilter(filter, filter); }
    void setWrap(unsigned wrap);
    void bind(unsigned unit) const;
    void generateMipmaps();
    /// Uploads level `level` (whole image) from client memory (tightly packed rows: the
    /// caller's pixel-store parameters and unpack buffer are set aside for the call).
    void upload(unsigned format, unsigned type, const void* data, int level = 0);
    /// Reads level `level` back as RGBA float (4 floats per texel, rows bottom-up as GL stores;
    /// the caller's pixel-store parameters and pack buffer are set aside for the call).
    std::vector<float> readRgbaFloat(int level = 0) const;

protected:
    Texture(unsigned target, unsigned internalFormat, int w, int h, int d, int levels);
    void destroy();
    unsigned target_ = 0, format_ = 0;
    int w_ = 0, h_ = 0, d_ = 0, levels_ = 0;
};

/// A 1-D texture (height and depth 1): a linear fetch reads 2 texels instead of 4, about half
/// the cost of a 2-D fetch on llvmpipe.
class Texture1D : public Texture {
public:
    Texture1D() = default;
    Texture1D(int width, unsigned internalFormat, int levels = 1);
};
class Texture2D : public Texture {
public:
    Texture2D() = default;
    Texture2D(int width, int height, unsigned internalFormat, int levels = 1);
};
class Texture3D : public Texture {
public:
    Texture3D() = default;
    Texture3D(int width, int height, int depth, unsigned internalFormat, int levels = 1);
};
class TextureCube : public Texture {
public:
    TextureCube() = default;
    TextureCube(int size, unsigned internalFormat, int levels = 1);
};
class Texture2DArray : public Texture {
public:
    Texture2DArray() = default;
    Texture2DArray(int width, int height, int layers, unsigned internalFormat, int levels = 1);
};

/// A renderbuffer (depth or colour storage that is never sampled).
class Renderbuffer : public Object {
public:
    Renderbuffer() = default;
    Renderbuffer(int width, int height, unsigned internalFormat);
    ~Renderbuffer();
    Renderbuffer(Renderbuffer&& o) noexcept = default;
    Renderbuffer& operator=(Renderbuffer&& o) noexcept;
};

class Framebuffer : public Object {
public:
    /// Creates a framebuffer object (needs a context).
    static Framebuffer create();
    Framebuffer() = default;
    ~Framebuffer();
    Framebuffer(Framebuffer&& o) noexcept = default;
    Framebuffer& operator=(Framebuffer&& o) noexcept;

    /// Attaches `level` of a texture; `layer` >= 0 selects one layer/face/slice.
    void attach(unsigned attachment, const Texture& texture, int level = 0, int layer = -1);
    void attach(unsigned attachment, const Renderbuffer& rb);
    /// Throws welkin::Error("<owner>: framebuffer incomplete (<status>)").
    void checkComplete(std::string_view owner) const;
    void bind() const;

private:
    explicit Framebuffer(unsigned id) : Object(id) {}
};

class Buffer : public Object {
public:
    /// A buffer of `bytes` bytes, initialised from `data` (may be null), GL_DYNAMIC_STORAGE_BIT.
    Buffer(size_t bytes, const void* data = nullptr);
    Buffer() = default;
    ~Buffer();
    Buffer(Buffer&& o) noexcept : Object(std::move(o)), size_(std::exchange(o.size_, 0)) {}
    Buffer& operator=(Buffer&& o) noexcept;

    size_t size() const { return size_; }
    void update(const void* data, size_t bytes, size_t offset = 0);
    void bindBase(unsigned target, unsigned index) const;

private:
    size_t size_ = 0;
};

class VertexArray : public Object {
public:
    static VertexArray create();
    VertexArray() = default;
    ~VertexArray();
    VertexArray(VertexArray&& o) noexcept = default;
    VertexArray& operator=(VertexArray&& o) noexcept;
    void bind() const;

private:
    explicit VertexArray(unsigned id) : Object(id) {}
};

/// A linked program. Build one with welkin::gl::ProgramBuilder (<welkin/gl/shader.hpp>).
class Program : public Object {
public:
    Program() = default;
    explicit Program(unsigned linkedProgram, std::string label) : Object(linkedProgram), label_(std::move(label)) {}
    ~Program();
    Program(Program&& o) noexcept = default;
    Program& operator=(Program&& o) noexcept;

    const std::string& label() const { return label_; }
    void use() const;
    /// Uniform location, -1 if the uniform is absent or optimised away.
    int location(const char* name) const;
    void set(const char* name, int v) const;
    void set(const char* name, float v) const;
    void set(const char* name, const glm::vec2& v) const;
    void set(const char* name, const glm::vec3& v) const;
    void set(const char* name, const glm::vec4& v) const;
    void set(const char* name, const glm::ivec2& v) const;
    void set(const char* name, const glm::mat3& v) const;
    void set(const char* name, const glm::mat4& v) const;

private:
    std::string label_;
};

static_assert(!std::is_copy_constructible_v<Texture2D> && std::is_nothrow_move_constructible_v<Texture2D>);
static_assert(!std::is_copy_constructible_v<Framebuffer> && std::is_nothrow_move_constructible_v<Framebuffer>);
static_assert(!std::is_copy_constructible_v<Buffer> && std::is_nothrow_move_constructible_v<Buffer>);
static_assert(!std::is_copy_constructible_v<Program> && std::is_nothrow_move_constructible_v<Program>);
static_assert(!std::is_copy_constructible_v<VertexArray> && std::is_nothrow_move_constructible_v<VertexArray>);

}  // namespace welkin::gl
