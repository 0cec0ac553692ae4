// A guest in the host's GL: renderInto() (and renderFrame(), toneMapInto()) leave every piece of
// the host's OpenGL state as they found it, also when an element throws, and the host's odd state
// does not change what welkin draws. The snapshot below is the test's own (glGet* item by item),
// independent of the engine's GlStateGuard. And the host's depth reaches the elements.
#include <catch2/catch.hpp>

#include "elements_present.hpp"
#include "gl_test_context.hpp"

#include <epoxy/gl.h>
#include <nlohmann/json.hpp>

#include <welkin/elements/registry.hpp>
#include <welkin/gl/bindings.hpp>
#include <welkin/gl/objects.hpp>
#include <welkin/error.hpp>
#include <welkin/gl/shader.hpp>
#include <welkin/keys.hpp>
#include <welkin/lighting.hpp>
#include <welkin/processor.hpp>

#include <map>
#include <optional>
#include <string>
#include <vector>

using namespace welkin;

namespace {

// What the engine guards (docs/architecture.md): the shared bindings and the private ranges.
constexpr int kUnits = gl::binding::kPrivateTextureUnitLast + 1;  // texture units
constexpr int kUbos = gl::binding::kPrivateUboLast + 1;           // uniform-buffer indices
constexpr int kBindings = 8;  // SSBO indices and image units (GL 4.5's minimum; the private ranges end below)
static_assert(gl::binding::kPrivateSsboLast < kBindings && gl::binding::kPrivateImageUnitLast < kBindings);
constexpr int kDrawBufs = 8;   // GL_MAX_DRAW_BUFFERS is 8 on llvmpipe

// Every guarded item, by name ("texture unit 4 GL_TEXTURE_BINDING_3D"), as integers.
using Snapshot = std::map<std::string, std::vector<long long>>;

std::vector<long long> ints(GLenum pname, int n = 1) {
    std::vector<GLint64> v(size_t(std::max(n, 16)), 0);
    glGetInteger64v(pname, v.data());
    return {v.begin(), v.begin() + n};
}
std::vector<long long> indexed(GLenum pname, GLuint i) {
    GLint64 v = 0;
    glGetInteger64i_v(pname, i, &v);
    return {v};
}
std::vector<long long> boolsIndexed(GLenum pname, GLuint i, int n) {
    GLboolean b[4] = {};
    glGetBooleani_v(pname, i, b);
    return std::vector<long long>(b, b + n);
}
std::vector<long long> enabled(GLenum cap) { return {glIsEnabled(cap)}; }

Snapshot snapshot(const std::vector<GLuint>& framebuffers) {
    Snapshot s;
    s["GL_DRAW_FRAMEBUFFER_BINDING"] = ints(GL_DRAW_FRAMEBUFFER_BINDING);
    s["GL_READ_FRAMEBUFFER_BINDING"] = ints(GL_READ_FRAMEBUFFER_BINDING);
    s["GL_CURRENT_PROGRAM"] = ints(GL_CURRENT_PROGRAM);
    s["GL_VERTEX_ARRAY_BINDING"] = ints(GL_VERTEX_ARRAY_BINDING);
    s["GL_ACTIVE_TEXTURE"] = ints(GL_ACTIVE_TEXTURE);
    for (GLuint i = 0; i < 4; ++i) {
        GLfloat vp[4];
        glGetFloati_v(GL_VIEWPORT, i, vp);
        s["GL_VIEWPORT " + std::to_string(i)] = {(long long)vp[0], (long long)vp[1], (long long)vp[2], (long long)vp[3]};
    }
    for (GLuint i = 0; i < kDrawBufs; ++i) {
        const std::string n = " draw buffer " + std::to_string(i);
        s["GL_BLEND" + n] = {glIsEnabledi(GL_BLEND, i)};
        s["GL_BLEND_SRC_RGB" + n] = indexed(GL_BLEND_SRC_RGB, i);
        s["GL_BLEND_DST_RGB" + n] = indexed(GL_BLEND_DST_RGB, i);
        s["GL_BLEND_SRC_ALPHA" + n] = indexed(GL_BLEND_SRC_ALPHA, i);
        s["GL_BLEND_DST_ALPHA" + n] = indexed(GL_BLEND_DST_ALPHA, i);
        s["GL_BLEND_EQUATION_RGB" + n] = indexed(GL_BLEND_EQUATION_RGB, i);
        s["GL_BLEND_EQUATION_ALPHA" + n] = indexed(GL_BLEND_EQUATION_ALPHA, i);
        s["GL_COLOR_WRITEMASK" + n] = boolsIndexed(GL_COLOR_WRITEMASK, i, 4);
    }
    GLfloat bc[4];
    glGetFloatv(GL_BLEND_COLOR, bc);
    s["GL_BLEND_COLOR x1000"] = {(long long)(bc[0] * 1000), (long long)(bc[1] * 1000), (long long)(bc[2] * 1000), (long long)(bc[3] * 1000)};
    s["GL_DEPTH_TEST"] = enabled(GL_DEPTH_TEST);
    s["GL_DEPTH_FUNC"] = ints(GL_DEPTH_FUNC);
    GLboolean dm = 0;
    glGetBooleanv(GL_DEPTH_WRITEMASK, &dm);
    s["GL_DEPTH_WRITEMASK"] = {dm};
    s["GL_CULL_FACE"] = enabled(GL_CULL_FACE);
    s["GL_CULL_FACE_MODE"] = ints(GL_CULL_FACE_MODE);
    s["GL_FRONT_FACE"] = ints(GL_FRONT_FACE);
    s["GL_SCISSOR_TEST"] = enabled(GL_SCISSOR_TEST);
    s["GL_SCISSOR_BOX"] = ints(GL_SCISSOR_BOX, 4);
    s["GL_COLOR_LOGIC_OP"] = enabled(GL_COLOR_LOGIC_OP);
    s["GL_LOGIC_OP_MODE"] = ints(GL_LOGIC_OP_MODE);
    s["GL_RASTERIZER_DISCARD"] = enabled(GL_RASTERIZER_DISCARD);
    s["GL_POLYGON_MODE"] = ints(GL_POLYGON_MODE, 1);
    for (GLenum i = 0; i < 8; ++i) s["GL_CLIP_DISTANCE" + std::to_string(i)] = enabled(GL_CLIP_DISTANCE0 + i);
    const std::pair<GLenum, const char*> targets[] = {
        {GL_TEXTURE_BINDING_1D, "GL_TEXTURE_BINDING_1D"},
        {GL_TEXTURE_BINDING_2D, "GL_TEXTURE_BINDING_2D"},
        {GL_TEXTURE_BINDING_3D, "GL_TEXTURE_BINDING_3D"},
        {GL_TEXTURE_BINDING_1D_ARRAY, "GL_TEXTURE_BINDING_1D_ARRAY"},
        {GL_TEXTURE_BINDING_2D_ARRAY, "GL_TEXTURE_BINDING_2D_ARRAY"},
        {GL_TEXTURE_BINDING_RECTANGLE, "GL_TEXTURE_BINDING_RECTANGLE"},
        {GL_TEXTURE_BINDING_CUBE_MAP, "GL_TEXTURE_BINDING_CUBE_MAP"},
        {GL_TEXTURE_BINDING_CUBE_MAP_ARRAY, "GL_TEXTURE_BINDING_CUBE_MAP_ARRAY"},
        {GL_TEXTURE_BINDING_BUFFER, "GL_TEXTURE_BINDING_BUFFER"},
        {GL_TEXTURE_BINDING_2D_MULTISAMPLE, "GL_TEXTURE_BINDING_2D_MULTISAMPLE"},
        {GL_TEXTURE_BINDING_2D_MULTISAMPLE_ARRAY, "GL_TEXTURE_BINDING_2D_MULTISAMPLE_ARRAY"},
    };
    GLint active = 0;
    glGetIntegerv(GL_ACTIVE_TEXTURE, &active);
    for (int u = 0; u < kUnits; ++u) {
        glActiveTexture(GL_TEXTURE0 + GLenum(u));
        const std::string n = "texture unit " + std::to_string(u) + " ";
        for (auto [pname, name] : targets) s[n + name] = ints(pname);
        s[n + "GL_SAMPLER_BINDING"] = ints(GL_SAMPLER_BINDING);
    }
    glActiveTexture(GLenum(active));
    for (GLuint i = 0; i < kUbos; ++i) {
        const std::string n = " " + std::to_string(i);
        s["GL_UNIFORM_BUFFER_BINDING" + n] = indexed(GL_UNIFORM_BUFFER_BINDING, i);
        s["GL_UNIFORM_BUFFER_START" + n] = indexed(GL_UNIFORM_BUFFER_START, i);
        s["GL_UNIFORM_BUFFER_SIZE" + n] = indexed(GL_UNIFORM_BUFFER_SIZE, i);
    }
    for (GLuint i = 0; i < kBindings; ++i) {
        const std::string n = " " + std::to_string(i);
        s["GL_SHADER_STORAGE_BUFFER_BINDING" + n] = indexed(GL_SHADER_STORAGE_BUFFER_BINDING, i);
        s["GL_SHADER_STORAGE_BUFFER_START" + n] = indexed(GL_SHADER_STORAGE_BUFFER_START, i);
        s["GL_SHADER_STORAGE_BUFFER_SIZE" + n] = indexed(GL_SHADER_STORAGE_BUFFER_SIZE, i);
        s["GL_IMAGE_BINDING_NAME" + n] = indexed(GL_IMAGE_BINDING_NAME, i);
        s["GL_IMAGE_BINDING_LEVEL" + n] = indexed(GL_IMAGE_BINDING_LEVEL, i);
        s["GL_IMAGE_BINDING_LAYERED" + n] = boolsIndexed(GL_IMAGE_BINDING_LAYERED, i, 1);
        s["GL_IMAGE_BINDING_LAYER" + n] = indexed(GL_IMAGE_BINDING_LAYER, i);
        s["GL_IMAGE_BINDING_ACCESS" + n] = indexed(GL_IMAGE_BINDING_ACCESS, i);
        s["GL_IMAGE_BINDING_FORMAT" + n] = indexed(GL_IMAGE_BINDING_FORMAT, i);
    }
    s["GL_UNIFORM_BUFFER_BINDING (generic)"] = ints(GL_UNIFORM_BUFFER_BINDING);
    s["GL_SHADER_STORAGE_BUFFER_BINDING (generic)"] = ints(GL_SHADER_STORAGE_BUFFER_BINDING);
    s["GL_PIXEL_PACK_BUFFER_BINDING"] = ints(GL_PIXEL_PACK_BUFFER_BINDING);
    s["GL_PIXEL_UNPACK_BUFFER_BINDING"] = ints(GL_PIXEL_UNPACK_BUFFER_BINDING);
    s["GL_UNPACK_ALIGNMENT"] = ints(GL_UNPACK_ALIGNMENT);
    s["GL_UNPACK_ROW_LENGTH"] = ints(GL_UNPACK_ROW_LENGTH);
    s["GL_PACK_ALIGNMENT"] = ints(GL_PACK_ALIGNMENT);
    s["GL_PACK_ROW_LENGTH"] = ints(GL_PACK_ROW_LENGTH);
    // Draw buffers are framebuffer state: read with each framebuffer bound, then put back.
    GLint draw = 0;
    glGetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &draw);
    for (GLuint fb : framebuffers) {
        glBindFramebuffer(GL_DRAW_FRAMEBUFFER, fb);
        for (int i = 0; i < kDrawBufs; ++i)
            s["framebuffer " + std::to_string(fb) + " GL_DRAW_BUFFER" + std::to_string(i)] = ints(GL_DRAW_BUFFER0 + GLenum(i));
    }
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, GLuint(draw));
    return s;
}

void requireSame(const Snapshot& before, const Snapshot& after) {
    REQUIRE(before.size() == after.size());
    for (auto& [name, value] : before) {
        INFO(name);
        CHECK(after.at(name) == value);
    }
}

// A host's frame: its own FBO (two colour attachments, a depth texture), program, VAO,
// textures, samplers, buffers, images and unusual fixed-function state on everything welkin
// could touch. Objects live as long as the struct.
struct Host {
    int w, h;
    gl::Texture2D colour, extra, depthTex;
    gl::Framebuffer fbo, readFbo;
    gl::Program program;
    gl::VertexArray vao;
    gl::Texture1D t1d;
    gl::Texture2D t2d, t2dB;
    gl::Texture3D t3d;
    gl::Texture2DArray tArray;
    gl::TextureCube tCube;
    gl::Buffer ubo0, ubo1, ssbo, pack;
    GLuint sampler = 0;

    Host(int width, int height)
        : w(width),
          h(height),
          colour(width, height, GL_RGBA32F),
          extra(width, height, GL_RGBA8),
          depthTex(width, height, GL_DEPTH_COMPONENT32F),
          fbo(gl::Framebuffer::create()),
          readFbo(gl::Framebuffer::create()),
          vao(gl::VertexArray::create()),
          t1d(4, GL_RGBA8),
          t2d(4, 4, GL_RGBA8),
          t2dB(4, 4, GL_R32F),
          t3d(4, 4, 4, GL_RGBA8),
          tArray(4, 4, 2, GL_RGBA8),
          tCube(4, GL_RGBA8),
          ubo0(256),
          ubo1(512),
          ssbo(256),
          pack(1024) {
        fbo.attach(GL_COLOR_ATTACHMENT0, colour);
        fbo.attach(GL_COLOR_ATTACHMENT1, extra);
        fbo.attach(GL_DEPTH_ATTACHMENT, depthTex);
        fbo.checkComplete("host");
        readFbo.attach(GL_COLOR_ATTACHMENT0, extra);
        program = gl::ProgramBuilder("host").fullscreenVertex().fragment("host.frag", "out vec4 o; void main() { o = vec4(1.0); }\n").build();
        glCreateSamplers(1, &sampler);
        glSamplerParameteri(sampler, GL_TEXTURE_MIN_FILTER, GL_NEAREST);  // would change welkin's LUT lookups
        glSamplerParameteri(sampler, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
        glSamplerParameteri(sampler, GL_TEXTURE_WRAP_S, GL_REPEAT);
    }
    ~Host() { glDeleteSamplers(1, &sampler); }

    // Background and depth: 1 cd/m^2 grey, depth 1 (nothing drawn) so the sky covers every pixel.
    void clear() const {
        fbo.bind();
        const GLenum both[2] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1};
        glNamedFramebufferDrawBuffers(fbo.id(), 2, both);
        glDisable(GL_SCISSOR_TEST);
        glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
        glDepthMask(GL_TRUE);
        const float grey[4] = {1, 1, 1, 1};
        glClearBufferfv(GL_COLOR, 0, grey);
        glClearBufferfi(GL_DEPTH_STENCIL, 0, 1.0f, 0);
    }

    // Non-default values for every guarded item.
    void setOddState() const {
        glBindFramebuffer(GL_DRAW_FRAMEBUFFER, fbo.id());
        glBindFramebuffer(GL_READ_FRAMEBUFFER, readFbo.id());
        const GLenum bufs[2] = {GL_COLOR_ATTACHMENT1, GL_COLOR_ATTACHMENT0};  // swapped: welkin must put them back
        glNamedFramebufferDrawBuffers(fbo.id(), 2, bufs);
        program.use();
        vao.bind();
        glViewportIndexedf(0, 1, 2, 3, 4);
        glViewportIndexedf(1, 5, 6, 7, 8);
        glEnablei(GL_BLEND, 0);
        glDisablei(GL_BLEND, 1);
        glBlendFuncSeparatei(0, GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA, GL_ONE, GL_ZERO);
        glBlendFuncSeparatei(1, GL_DST_COLOR, GL_ZERO, GL_ZERO, GL_ONE);
        glBlendEquationSeparatei(0, GL_FUNC_SUBTRACT, GL_MAX);
        glBlendEquationSeparatei(1, GL_MIN, GL_FUNC_REVERSE_SUBTRACT);
        glBlendColor(0.25f, 0.5f, 0.75f, 1.0f);
        glColorMaski(0, GL_TRUE, GL_FALSE, GL_TRUE, GL_FALSE);
        glColorMaski(1, GL_FALSE, GL_TRUE, GL_FALSE, GL_TRUE);
        glEnable(GL_DEPTH_TEST);
        glDepthFunc(GL_GREATER);
        glDepthMask(GL_TRUE);
        glEnable(GL_CULL_FACE);
        glCullFace(GL_FRONT_AND_BACK);
        glFrontFace(GL_CW);
        glEnable(GL_SCISSOR_TEST);
        glScissor(1, 1, 2, 2);
        glEnable(GL_COLOR_LOGIC_OP);
        glLogicOp(GL_XOR);
        glPolygonMode(GL_FRONT_AND_BACK, GL_LINE);
        glEnable(GL_CLIP_DISTANCE0);  // welkin's programs write no gl_ClipDistance: must be off
        glEnable(GL_CLIP_DISTANCE5);
        glBindTextureUnit(0, t2d.id());
        glBindTextureUnit(1, t1d.id());
        glBindTextureUnit(4, t3d.id());
        glBindTextureUnit(4, t2dB.id());  // two targets on one unit
        glBindTextureUnit(8, tArray.id());
        glBindTextureUnit(9, tCube.id());
        glBindTextureUnit(10, t2d.id());
        glBindTextureUnit(15, tCube.id());
        glBindTextureUnit(16, t2d.id());   // the private range, where elements bind their own
        glBindTextureUnit(31, t3d.id());
        for (GLuint u : {0u, 4u, 5u, 9u}) glBindSampler(u, sampler);
        glActiveTexture(GL_TEXTURE3);
        glBindBufferRange(GL_UNIFORM_BUFFER, 1, ubo1.id(), 256, 128);
        glBindBufferBase(GL_UNIFORM_BUFFER, 0, ubo0.id());
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, ssbo.id());
        glBindBufferRange(GL_SHADER_STORAGE_BUFFER, 2, ubo1.id(), 0, 64);
        glBindBufferRange(GL_UNIFORM_BUFFER, 8, ubo1.id(), 0, 256);
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 4, ssbo.id());
        glBindBuffer(GL_UNIFORM_BUFFER, ubo1.id());  // generic bindings differ from the indexed ones
        glBindBuffer(GL_SHADER_STORAGE_BUFFER, ubo0.id());
        glBindBuffer(GL_PIXEL_PACK_BUFFER, pack.id());
        glBindBuffer(GL_PIXEL_UNPACK_BUFFER, pack.id());  // would make welkin's uploads read from it
        glBindImageTexture(0, t3d.id(), 0, GL_TRUE, 0, GL_READ_ONLY, GL_RGBA8);
        glBindImageTexture(1, t2d.id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA8);
        glBindImageTexture(4, t2d.id(), 0, GL_FALSE, 0, GL_READ_WRITE, GL_RGBA8);
        glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
        glPixelStorei(GL_UNPACK_ROW_LENGTH, 7);
        glPixelStorei(GL_PACK_ALIGNMENT, 8);
        glPixelStorei(GL_PACK_ROW_LENGTH, 3);
    }

    // GL defaults again (the test context is shared with the other tests).
    static void resetState() {
        glBindFramebuffer(GL_FRAMEBUFFER, 0);
        glUseProgram(0);
        glBindVertexArray(0);
        glViewport(0, 0, 1, 1);
        glDisable(GL_BLEND);
        glBlendFunc(GL_ONE, GL_ZERO);
        glBlendEquation(GL_FUNC_ADD);
        glBlendColor(0, 0, 0, 0);
        glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
        glDisable(GL_DEPTH_TEST);
        glDepthFunc(GL_LESS);
        glDepthMask(GL_TRUE);
        glDisable(GL_CULL_FACE);
        glCullFace(GL_BACK);
        glFrontFace(GL_CCW);
        glDisable(GL_SCISSOR_TEST);
        glDisable(GL_COLOR_LOGIC_OP);
        glLogicOp(GL_COPY);
        glPolygonMode(GL_FRONT_AND_BACK, GL_FILL);
        for (GLuint u = 0; u < kUnits; ++u) glBindTextureUnit(u, 0);
        glBindSamplers(0, kUnits, nullptr);
        glActiveTexture(GL_TEXTURE0);
        for (GLuint i = 0; i < kUbos; ++i) glBindBufferBase(GL_UNIFORM_BUFFER, i, 0);
        for (GLuint i = 0; i < kBindings; ++i) {
            glBindBufferBase(GL_SHADER_STORAGE_BUFFER, i, 0);
            glBindImageTexture(i, 0, 0, GL_FALSE, 0, GL_READ_ONLY, GL_R8);
        }
        glBindBuffer(GL_PIXEL_PACK_BUFFER, 0);
        glBindBuffer(GL_PIXEL_UNPACK_BUFFER, 0);
        glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
        glPixelStorei(GL_UNPACK_ROW_LENGTH, 0);
        glPixelStorei(GL_PACK_ALIGNMENT, 4);
        glPixelStorei(GL_PACK_ROW_LENGTH, 0);
    }
};

// Records the depth it is given and reads the host's depth texture at one texel in render();
// on request binds a texture, a uniform buffer and an image on shared units and on units of its
// own (SkyElement::textureUnit(), ...: the private ranges), then throws.
class DepthProbe final : public SkyElement {
public:
    DepthProbe() : SkyElement("depth probe") {}
    std::optional<HostDepth> seen;   // ctx.depth in the last render(), copied
    bool depthInUpdate = false;      // ctx.depth was set in the last update()
    float texel = -1.0f;             // depth texture at (1, 1) read in render()
    bool throwInRender = false;

private:
    void doInit(InitContext&) override {
        tex_ = gl::Texture2D(2, 2, GL_RGBA8);
        ubo_ = gl::Buffer(64);
        privateUnit_ = textureUnit("PROBE_TEXTURE");
        privateUbo_ = uniformBuffer("PROBE_UBO");
        privateSsbo_ = storageBuffer("PROBE_SSBO");
        privateImage_ = imageUnit("PROBE_IMAGE");
    }
    void doUpdate(const FrameContext& ctx) override { depthInUpdate = ctx.depth != nullptr; }
    void doRender(const FrameContext& ctx) override {
        seen = ctx.depth ? std::optional<HostDepth>(*ctx.depth) : std::nullopt;
        if (ctx.depth)
            glGetTextureSubImage(ctx.depth->depthTexture, 0, 1, 1, 0, 1, 1, 1, GL_DEPTH_COMPONENT, GL_FLOAT, sizeof texel, &texel);
        if (throwInRender) {
            glBindTextureUnit(12, tex_.id());
            ubo_.bindBase(GL_UNIFORM_BUFFER, 3);
            glBindImageTexture(2, tex_.id(), 0, GL_FALSE, 0, GL_READ_ONLY, GL_RGBA8);
            glBindTextureUnit(GLuint(privateUnit_), tex_.id());
            ubo_.bindBase(GL_UNIFORM_BUFFER, unsigned(privateUbo_));
            ubo_.bindBase(GL_SHADER_STORAGE_BUFFER, unsigned(privateSsbo_));
            glBindImageTexture(GLuint(privateImage_), tex_.id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA8);
            glEnable(GL_BLEND);
            throw Error("DepthProbe: thrown on purpose");
        }
    }
    void doRelease() override {
        tex_ = {};
        ubo_ = {};
    }
    gl::Texture2D tex_;
    gl::Buffer ubo_;
    int privateUnit_ = 0, privateUbo_ = 0, privateSsbo_ = 0, privateImage_ = 0;
};

std::unique_ptr<SkyProcessor> skyAndGrid(const Camera& cam) {
    auto p = std::make_unique<SkyProcessor>();
    p->setObserver({.latitudeRad = 0.6266, .longitudeRad = 0.2531, .heightMeters = 30});
    p->setTime(UtcInstant::parse("2026-06-21T17:30:00+02:00"));  // Sun about 20 deg up: every LUT matters
    p->setCamera(cam);
    p->setAnimationTime(0.0);
    p->add(elements::makeElement("sky"));  // by name (the registry): no element's header here
    p->vars().setFromString("sky.quality", "low");  // the cheapest generators
#ifdef WELKIN_HAS_ELEMENT_grid  // a second element, with its own programs and text (the Sky alone without it)
    p->add(elements::makeElement("grid"));
#endif
    return p;
}

}  // namespace

TEST_CASE("renderInto, renderFrame and toneMapInto leave the host's GL state as they found it", "[gl][composite][glstate]") {
    test::glContext();
    Camera cam;
    cam.width = 32;
    cam.height = 16;
    cam.altitudeRad = 0.3;
    cam.azimuthRad = 4.5;
    Host host(cam.width, cam.height);
    auto p = skyAndGrid(cam);
    const std::vector<GLuint> fbs = {host.fbo.id(), host.readFbo.id()};

    host.clear();
    host.setOddState();
    const Snapshot before = snapshot(fbs);
    // The snapshot sees what the host set (the test is not comparing defaults with defaults).
    CHECK(before.at("texture unit 4 GL_TEXTURE_BINDING_3D")[0] == host.t3d.id());
    CHECK(before.at("texture unit 4 GL_TEXTURE_BINDING_2D")[0] == host.t2dB.id());
    CHECK(before.at("framebuffer " + std::to_string(host.fbo.id()) + " GL_DRAW_BUFFER0")[0] == GL_COLOR_ATTACHMENT1);
    CHECK(before.at("GL_UNIFORM_BUFFER_START 1")[0] == 256);

    SECTION("renderInto, first frame: every generator runs") {
        p->renderInto({.framebuffer = host.fbo.id(), .width = cam.width, .height = cam.height,
                       .depth = HostDepth{.depthTexture = host.depthTex.id(), .nearM = 0.1, .farM = 1e4}});
        requireSame(before, snapshot(fbs));
        SECTION("a second frame, and an element that binds its own objects and throws") {
            p->vars().set(keys::exposureEv100, 5.0);  // input of the Grid: its update runs again
            p->renderInto({.framebuffer = host.fbo.id(), .width = cam.width, .height = cam.height});
            requireSame(before, snapshot(fbs));
            auto& probe = p->emplace<DepthProbe>();
            probe.throwInRender = true;
            CHECK_THROWS_WITH(p->renderInto({.framebuffer = host.fbo.id(), .width = cam.width, .height = cam.height}),
                              Catch::Contains("thrown on purpose"));
            requireSame(before, snapshot(fbs));
        }
    }
    SECTION("SkyLighting: the capture, its reductions and prefilter, offline and time-sliced") {
        p->setLighting(LightingOptions{.cubeSize = 8, .specularMips = 3});
        p->renderInto({.framebuffer = host.fbo.id(), .width = cam.width, .height = cam.height});
        requireSame(before, snapshot(fbs));
        REQUIRE(p->stats()["lighting"]["refreshes"].get<int>() == 1);
        p->vars().set(keys::interactive, true);
        for (int i = 0; i < 10; ++i) {  // one slice per frame: faces, reductions, mips, read-back
            p->renderInto({.framebuffer = host.fbo.id(), .width = cam.width, .height = cam.height});
            requireSame(before, snapshot(fbs));
        }
        CHECK(p->stats()["lighting"]["refreshes"].get<int>() == 2);
    }
    SECTION("init() and update() alone") {
        p->init();
        requireSame(before, snapshot(fbs));
        p->update();
        requireSame(before, snapshot(fbs));
    }
    SECTION("renderFrame and toneMapInto the host's framebuffer") {
        p->setExposure({.automatic = true});  // the meter's pass and mip chain too
        p->renderFrame();
        requireSame(before, snapshot(fbs));
        p->toneMapInto(host.fbo.id());
        requireSame(before, snapshot(fbs));
        // Reading back beside the host's pack buffer and pack row length (3): the image is the
        // frame, not rows 3 texels apart, and nothing lands in the host's buffer.
        const Image hdr = p->readHdr();
        const double ev = p->lastEv100();
        requireSame(before, snapshot(fbs));
        Host::resetState();
        const Image clean = p->readHdr();
        CHECK(hdr.pixels == clean.pixels);
        CHECK(ev == p->lastEv100());
        CHECK(ev > 5.0);  // a daylight meter: EV100 ~ 10-15 (the log-luminance mip chain was read)
    }
    Host::resetState();
}

TEST_CASE("The host's odd GL state does not change what welkin draws", "[gl][composite][glstate]") {
    test::glContext();
    Camera cam;
    cam.width = 32;
    cam.height = 16;
    cam.altitudeRad = 0.3;
    cam.azimuthRad = 4.5;
    // Two identical scenes into two identical host framebuffers: one from GL defaults, one from
    // the odd state (scissor box 2x2, colour mask without green, sampler objects with nearest
    // filtering on the LUT units, logic op XOR, line polygon mode, a bound unpack buffer ...).
    Host clean(cam.width, cam.height), odd(cam.width, cam.height);
    auto a = skyAndGrid(cam);
    auto b = skyAndGrid(cam);
    Host::resetState();
    clean.clear();
    Host::resetState();
    a->renderInto({.framebuffer = clean.fbo.id(), .width = cam.width, .height = cam.height});
    odd.clear();
    odd.setOddState();
    b->renderInto({.framebuffer = odd.fbo.id(), .width = cam.width, .height = cam.height});
    Host::resetState();
    const std::vector<float> ref = clean.colour.readRgbaFloat(), got = odd.colour.readRgbaFloat();
    REQUIRE(ref.size() == got.size());
    int differing = 0;
    for (size_t i = 0; i < ref.size(); ++i)
        if (ref[i] != got[i]) ++differing;  // same GL work on the same driver: bit-identical
    CHECK(differing == 0);
    // The sky is there (not the grey background alone): the reference frame is brighter.
    CHECK(ref[(8 * size_t(cam.width) + 16) * 4 + 2] > 1.5f);
}

TEST_CASE("Elements see the host's depth passed to renderInto, validated at the boundary", "[gl][composite][depth]") {
    test::glContext();
    const int w = 8, h = 4;
    gl::Texture2D colour(w, h, GL_RGBA32F), depthTex(w, h, GL_DEPTH_COMPONENT32F);
    auto fbo = gl::Framebuffer::create();
    fbo.attach(GL_COLOR_ATTACHMENT0, colour);
    fbo.attach(GL_DEPTH_ATTACHMENT, depthTex);
    fbo.checkComplete("host");
    fbo.bind();
    glClearBufferfi(GL_DEPTH_STENCIL, 0, 0.25f, 0);  // the host's geometry everywhere, at window depth 0.25
    glBindFramebuffer(GL_FRAMEBUFFER, 0);

    SkyProcessor p;
    Camera cam;
    cam.width = w;
    cam.height = h;
    p.setCamera(cam);
    auto& probe = p.emplace<DepthProbe>();
    const HostDepth depth{.depthTexture = depthTex.id(), .nearM = 0.5, .farM = 2000.0, .metresPerUnit = 0.01};
    p.renderInto({.framebuffer = fbo.id(), .width = w, .height = h, .depth = depth});
    REQUIRE(probe.seen.has_value());
    CHECK(probe.seen->depthTexture == depthTex.id());
    CHECK(probe.seen->nearM == 0.5);
    CHECK(probe.seen->farM == 2000.0);
    CHECK(probe.seen->metresPerUnit == 0.01);
    CHECK(probe.texel == 0.25f);       // the element read the host's depth (float32 depth: exact)
    CHECK_FALSE(probe.depthInUpdate);  // documented: render() only

    // Without a depth, and in renderFrame() (the processor's own target), elements see none.
    p.renderInto({.framebuffer = fbo.id(), .width = w, .height = h});
    CHECK_FALSE(probe.seen.has_value());
    p.renderInto({.framebuffer = fbo.id(), .width = w, .height = h, .depth = depth});
    p.renderFrame();
    CHECK_FALSE(probe.seen.has_value());

    // Validation: one line naming the member and the range.
    auto with = [&](HostDepth d) { p.renderInto({.framebuffer = fbo.id(), .width = w, .height = h, .depth = d}); };
    HostDepth d = depth;
    d.nearM = 0;
    CHECK_THROWS_WITH(with(d), "SkyProcessor::renderInto(): HostDepth: nearM 0 not in (0, inf)");
    d = depth;
    d.farM = 0.4;
    CHECK_THROWS_WITH(with(d), "SkyProcessor::renderInto(): HostDepth: farM 0.4 not in (0.5, inf)");
    d = depth;
    d.metresPerUnit = -1;
    CHECK_THROWS_WITH(with(d), "SkyProcessor::renderInto(): HostDepth: metresPerUnit -1 not in (0, inf)");
    d = depth;
    d.depthTexture = 0;
    CHECK_THROWS_WITH(with(d), Catch::Contains("depthTexture is 0"));
    gl::Texture2D small(4, 4, GL_DEPTH_COMPONENT32F);
    d.depthTexture = small.id();
    CHECK_THROWS_WITH(with(d), "SkyProcessor::renderInto(): HostDepth texture 4x4 differs from the camera's 8x4");
    d.depthTexture = 987654;
    CHECK_THROWS_WITH(with(d), "SkyProcessor::renderInto(): HostDepth depthTexture 987654 is not a texture");
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
}
