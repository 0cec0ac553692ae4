#include "state_guard.hpp"

#include <welkin/gl/bindings.hpp>

#include <epoxy/gl.h>

#include <algorithm>

namespace welkin::gl {

static_assert(GlStateGuard::kUnits > binding::kPrivateTextureUnitLast && GlStateGuard::kBufferBindings > binding::kPrivateUboLast &&
                  GlStateGuard::kSsboBindings > binding::kPrivateSsboLast && GlStateGuard::kImageUnits > binding::kPrivateImageUnitLast,
              "the GL state guard must cover the private binding ranges (elements' own units)");

namespace {
// Every texture target of GL 4.5, with its binding query (textures_[unit][i]).
constexpr std::array<std::pair<GLenum, GLenum>, 11> kTargets = {{
    {GL_TEXTURE_1D, GL_TEXTURE_BINDING_1D},
    {GL_TEXTURE_2D, GL_TEXTURE_BINDING_2D},
    {GL_TEXTURE_3D, GL_TEXTURE_BINDING_3D},
    {GL_TEXTURE_1D_ARRAY, GL_TEXTURE_BINDING_1D_ARRAY},
    {GL_TEXTURE_2D_ARRAY, GL_TEXTURE_BINDING_2D_ARRAY},
    {GL_TEXTURE_RECTANGLE, GL_TEXTURE_BINDING_RECTANGLE},
    {GL_TEXTURE_CUBE_MAP, GL_TEXTURE_BINDING_CUBE_MAP},
    {GL_TEXTURE_CUBE_MAP_ARRAY, GL_TEXTURE_BINDING_CUBE_MAP_ARRAY},
    {GL_TEXTURE_BUFFER, GL_TEXTURE_BINDING_BUFFER},
    {GL_TEXTURE_2D_MULTISAMPLE, GL_TEXTURE_BINDING_2D_MULTISAMPLE},
    {GL_TEXTURE_2D_MULTISAMPLE_ARRAY, GL_TEXTURE_BINDING_2D_MULTISAMPLE_ARRAY},
}};

// Pixel-store parameters and their defaults (GL 4.5 table 8.1, 18.1).
constexpr std::array<std::pair<GLenum, GLint>, 12> kPixelStore = {{
    {GL_UNPACK_ALIGNMENT, 4}, {GL_UNPACK_ROW_LENGTH, 0}, {GL_UNPACK_IMAGE_HEIGHT, 0},
    {GL_UNPACK_SKIP_ROWS, 0}, {GL_UNPACK_SKIP_PIXELS, 0}, {GL_UNPACK_SKIP_IMAGES, 0},
    {GL_PACK_ALIGNMENT, 4},   {GL_PACK_ROW_LENGTH, 0},   {GL_PACK_IMAGE_HEIGHT, 0},
    {GL_PACK_SKIP_ROWS, 0},   {GL_PACK_SKIP_PIXELS, 0},   {GL_PACK_SKIP_IMAGES, 0},
}};

GLint getInt(GLenum pname) {
    GLint v = 0;
    glGetIntegerv(pname, &v);
    return v;
}
GLint getInt(GLenum pname, GLuint index) {
    GLint v = 0;
    glGetIntegeri_v(pname, index, &v);
    return v;
}
long long getInt64(GLenum pname, GLuint index) {
    GLint64 v = 0;
    glGetInteger64i_v(pname, index, &v);
    return v;
}
void enable(GLenum cap, bool on) { (on ? glEnable : glDisable)(cap); }

// Names reported by bindings may belong to objects deleted since: bind only live ones.
GLuint liveTexture(GLint n) { return n && glIsTexture(GLuint(n)) ? GLuint(n) : 0; }
// ... and of the same target (a deleted name can be reused by a texture of another target).
GLuint liveTexture(GLint n, GLenum target) {
    if (!liveTexture(n)) return 0;
    GLint t = 0;
    glGetTextureParameteriv(GLuint(n), GL_TEXTURE_TARGET, &t);
    return GLenum(t) == target ? GLuint(n) : 0;
}
GLuint liveBuffer(GLint n) { return n && glIsBuffer(GLuint(n)) ? GLuint(n) : 0; }
GLuint liveFramebuffer(GLint n) { return n && glIsFramebuffer(GLuint(n)) ? GLuint(n) : 0; }
}  // namespace

GlStateGuard::GlStateGuard(std::vector<unsigned> framebuffers) {
    save(framebuffers);
    applyDefaults();
}

GlStateGuard::~GlStateGuard() { restore(); }

void GlStateGuard::save(const std::vector<unsigned>& framebuffers) {
    drawFbo_ = getInt(GL_DRAW_FRAMEBUFFER_BINDING);
    readFbo_ = getInt(GL_READ_FRAMEBUFFER_BINDING);
    program_ = getInt(GL_CURRENT_PROGRAM);
    vao_ = getInt(GL_VERTEX_ARRAY_BINDING);
    activeTexture_ = getInt(GL_ACTIVE_TEXTURE);

    viewportCount_ = std::min(getInt(GL_MAX_VIEWPORTS), 16);
    viewports_.resize(size_t(viewportCount_));
    for (int i = 0; i < viewportCount_; ++i) glGetFloati_v(GL_VIEWPORT, GLuint(i), viewports_[size_t(i)].data());

    drawBufferCount_ = std::min(getInt(GL_MAX_DRAW_BUFFERS), kDrawBuffers);
    for (int i = 0; i < drawBufferCount_; ++i) {
        Blend& b = blend_[size_t(i)];
        const GLuint u = GLuint(i);
        b.enabled = glIsEnabledi(GL_BLEND, u);
        b.srcRgb = getInt(GL_BLEND_SRC_RGB, u);
        b.dstRgb = getInt(GL_BLEND_DST_RGB, u);
        b.srcA = getInt(GL_BLEND_SRC_ALPHA, u);
        b.dstA = getInt(GL_BLEND_DST_ALPHA, u);
        b.eqRgb = getInt(GL_BLEND_EQUATION_RGB, u);
        b.eqA = getInt(GL_BLEND_EQUATION_ALPHA, u);
        glGetBooleani_v(GL_COLOR_WRITEMASK, u, b.colorMask.data());
    }
    glGetFloatv(GL_BLEND_COLOR, blendColor_.data());

    depthTest_ = glIsEnabled(GL_DEPTH_TEST);
    depthFunc_ = getInt(GL_DEPTH_FUNC);
    // Depth ranges per viewport (welkin sets glDepthRange(1, 0) for a reversed-Z host) and the
    // clip control (a host with glClipControl(..., GL_ZERO_TO_ONE) or an upper-left origin).
    depthRanges_.assign(size_t(viewportCount_), {0.0, 1.0});
    for (int i = 0; i < viewportCount_; ++i) glGetDoublei_v(GL_DEPTH_RANGE, GLuint(i), depthRanges_[size_t(i)].data());
    clipOrigin_ = getInt(GL_CLIP_ORIGIN);
    clipDepthMode_ = getInt(GL_CLIP_DEPTH_MODE);
    glGetBooleanv(GL_DEPTH_WRITEMASK, &depthMask_);
    cull_ = glIsEnabled(GL_CULL_FACE);
    cullMode_ = getInt(GL_CULL_FACE_MODE);
    frontFace_ = getInt(GL_FRONT_FACE);
    scissor_ = glIsEnabled(GL_SCISSOR_TEST);
    glGetIntegerv(GL_SCISSOR_BOX, scissorBox_.data());
    logicOpEnabled_ = glIsEnabled(GL_COLOR_LOGIC_OP);
    logicOp_ = getInt(GL_LOGIC_OP_MODE);
    discard_ = glIsEnabled(GL_RASTERIZER_DISCARD);
    glGetIntegerv(GL_POLYGON_MODE, polygonMode_.data());
    for (size_t i = 0; i < clipDistances_.size(); ++i) clipDistances_[i] = glIsEnabled(GL_CLIP_DISTANCE0 + GLenum(i));

    // Draw buffers are framebuffer state: read them with each framebuffer bound.
    for (unsigned fb : framebuffers) {
        if (std::any_of(framebufferDraws_.begin(), framebufferDraws_.end(), [&](auto& d) { return d.framebuffer == fb; })) continue;
        if (fb == 0 || !glIsFramebuffer(fb)) continue;  // welkin never changes the default framebuffer's
        glBindFramebuffer(GL_DRAW_FRAMEBUFFER, fb);
        FramebufferDraw d{fb, {}};
        for (int i = 0; i < drawBufferCount_; ++i) d.drawBuffers.push_back(GLenum(getInt(GL_DRAW_BUFFER0 + GLenum(i))));
        framebufferDraws_.push_back(std::move(d));
    }
    if (!framebufferDraws_.empty()) glBindFramebuffer(GL_DRAW_FRAMEBUFFER, GLuint(drawFbo_));

    for (int u = 0; u < kUnits; ++u) {
        glActiveTexture(GL_TEXTURE0 + GLenum(u));
        for (size_t t = 0; t < kTargets.size(); ++t) textures_[size_t(u)][t] = getInt(kTargets[t].second);
        samplers_[size_t(u)] = getInt(GL_SAMPLER_BINDING);
    }
    glActiveTexture(GLenum(activeTexture_));

    for (int i = 0; i < kBufferBindings; ++i) {
        const GLuint u = GLuint(i);
        ubos_[size_t(i)] = {getInt(GL_UNIFORM_BUFFER_BINDING, u), getInt64(GL_UNIFORM_BUFFER_START, u), getInt64(GL_UNIFORM_BUFFER_SIZE, u)};
        if (i < kSsboBindings)
            ssbos_[size_t(i)] = {getInt(GL_SHADER_STORAGE_BUFFER_BINDING, u), getInt64(GL_SHADER_STORAGE_BUFFER_START, u),
                                 getInt64(GL_SHADER_STORAGE_BUFFER_SIZE, u)};
    }
    genericUbo_ = getInt(GL_UNIFORM_BUFFER_BINDING);
    genericSsbo_ = getInt(GL_SHADER_STORAGE_BUFFER_BINDING);
    packBuffer_ = getInt(GL_PIXEL_PACK_BUFFER_BINDING);
    unpackBuffer_ = getInt(GL_PIXEL_UNPACK_BUFFER_BINDING);

    for (int i = 0; i < kImageUnits; ++i) {
        const GLuint u = GLuint(i);
        Image& im = images_[size_t(i)];
        im.name = getInt(GL_IMAGE_BINDING_NAME, u);
        im.level = getInt(GL_IMAGE_BINDING_LEVEL, u);
        im.layer = getInt(GL_IMAGE_BINDING_LAYER, u);
        im.access = getInt(GL_IMAGE_BINDING_ACCESS, u);
        im.format = getInt(GL_IMAGE_BINDING_FORMAT, u);
        glGetBooleani_v(GL_IMAGE_BINDING_LAYERED, u, &im.layered);
    }
    for (size_t i = 0; i < kPixelStore.size(); ++i) pixelStore_[i] = getInt(kPixelStore[i].first);
}

void GlStateGuard::applyDefaults() const {
    // welkin's passes assume OpenGL's defaults: a lower-left origin (images are not flipped),
    // NDC depth in [-1, 1], the full depth range.
    glClipControl(GL_LOWER_LEFT, GL_NEGATIVE_ONE_TO_ONE);
    glDepthRange(0.0, 1.0);
    glDisable(GL_SCISSOR_TEST);
    glDisable(GL_COLOR_LOGIC_OP);
    glDisable(GL_RASTERIZER_DISCARD);
    glDisable(GL_CULL_FACE);
    // Elements that clip (the Rainbow's grid) enable their planes and disable them after.
    for (GLenum i = 0; i < 8; ++i) glDisable(GL_CLIP_DISTANCE0 + i);
    glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    glPolygonMode(GL_FRONT_AND_BACK, GL_FILL);
    glBindSamplers(0, kUnits, nullptr);
    glBindBuffer(GL_PIXEL_PACK_BUFFER, 0);
    glBindBuffer(GL_PIXEL_UNPACK_BUFFER, 0);
    for (auto [pname, value] : kPixelStore) glPixelStorei(pname, value);
}

void GlStateGuard::restore() const {
    // Framebuffer draw buffers first (they need each framebuffer bound), then the bindings.
    for (auto& d : framebufferDraws_) {
        if (const GLuint fb = liveFramebuffer(GLint(d.framebuffer)))
            glNamedFramebufferDrawBuffers(fb, GLsizei(d.drawBuffers.size()), d.drawBuffers.data());
    }
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, liveFramebuffer(drawFbo_));
    glBindFramebuffer(GL_READ_FRAMEBUFFER, liveFramebuffer(readFbo_));
    glUseProgram(program_ && glIsProgram(GLuint(program_)) ? GLuint(program_) : 0);
    glBindVertexArray(vao_ && glIsVertexArray(GLuint(vao_)) ? GLuint(vao_) : 0);

    for (int i = 0; i < viewportCount_; ++i) glViewportIndexedfv(GLuint(i), viewports_[size_t(i)].data());

    for (int i = 0; i < drawBufferCount_; ++i) {
        const Blend& b = blend_[size_t(i)];
        const GLuint u = GLuint(i);
        (b.enabled ? glEnablei : glDisablei)(GL_BLEND, u);
        glBlendFuncSeparatei(u, GLenum(b.srcRgb), GLenum(b.dstRgb), GLenum(b.srcA), GLenum(b.dstA));
        glBlendEquationSeparatei(u, GLenum(b.eqRgb), GLenum(b.eqA));
        glColorMaski(u, b.colorMask[0], b.colorMask[1], b.colorMask[2], b.colorMask[3]);
    }
    glBlendColor(blendColor_[0], blendColor_[1], blendColor_[2], blendColor_[3]);

    enable(GL_DEPTH_TEST, depthTest_);
    glDepthFunc(GLenum(depthFunc_));
    for (int i = 0; i < viewportCount_; ++i) glDepthRangeIndexed(GLuint(i), depthRanges_[size_t(i)][0], depthRanges_[size_t(i)][1]);
    glClipControl(GLenum(clipOrigin_), GLenum(clipDepthMode_));
    glDepthMask(depthMask_);
    enable(GL_CULL_FACE, cull_);
    glCullFace(GLenum(cullMode_));
    glFrontFace(GLenum(frontFace_));
    enable(GL_SCISSOR_TEST, scissor_);
    glScissor(scissorBox_[0], scissorBox_[1], scissorBox_[2], scissorBox_[3]);
    enable(GL_COLOR_LOGIC_OP, logicOpEnabled_);
    glLogicOp(GLenum(logicOp_));
    enable(GL_RASTERIZER_DISCARD, discard_);
    glPolygonMode(GL_FRONT_AND_BACK, GLenum(polygonMode_[0]));
    for (size_t i = 0; i < clipDistances_.size(); ++i) enable(GL_CLIP_DISTANCE0 + GLenum(i), clipDistances_[i]);

    // Textures: the multi-bind calls (GL 4.4) restore a unit that had at most one target bound (the
    // usual case) in one batch: every target of every unit unbound, then each unit's one texture
    // bound to its own target. A unit that had several targets bound is restored target by target.
    // (Two calls instead of kUnits x 11 binds and kUnits active-unit switches: the guard runs
    // every frame, docs/hardening.md.)
    std::array<GLuint, kUnits> single{};
    std::array<GLuint, kUnits> samplers{};
    std::array<bool, kUnits> several{};
    bool anySeveral = false;
    for (int u = 0; u < kUnits; ++u) {
        int bound = 0;
        for (size_t t = 0; t < kTargets.size(); ++t) {
            const GLuint n = liveTexture(textures_[size_t(u)][t], kTargets[t].first);
            if (n) {
                single[size_t(u)] = n;
                ++bound;
            }
        }
        several[size_t(u)] = bound > 1;
        anySeveral = anySeveral || bound > 1;
        const GLint s = samplers_[size_t(u)];
        samplers[size_t(u)] = s && glIsSampler(GLuint(s)) ? GLuint(s) : 0;
    }
    glBindTextures(0, kUnits, nullptr);
    glBindTextures(0, kUnits, single.data());
    glBindSamplers(0, kUnits, samplers.data());
    if (anySeveral) {
        for (int u = 0; u < kUnits; ++u) {
            if (!several[size_t(u)]) continue;
            glActiveTexture(GL_TEXTURE0 + GLenum(u));
            for (size_t t = 0; t < kTargets.size(); ++t) glBindTexture(kTargets[t].first, liveTexture(textures_[size_t(u)][t], kTargets[t].first));
        }
    }
    glActiveTexture(GLenum(activeTexture_));

    auto rebind = [](GLenum target, GLuint index, const Indexed& b) {
        const GLuint name = liveBuffer(b.name);
        if (name != 0 && b.size > 0)
            glBindBufferRange(target, index, name, GLintptr(b.start), GLsizeiptr(b.size));
        else
            glBindBufferBase(target, index, name);
    };
    for (int i = 0; i < kBufferBindings; ++i) {
        rebind(GL_UNIFORM_BUFFER, GLuint(i), ubos_[size_t(i)]);
        if (i < kSsboBindings) rebind(GL_SHADER_STORAGE_BUFFER, GLuint(i), ssbos_[size_t(i)]);
    }
    // glBindBufferBase/Range also set the generic binding: restore it last.
    glBindBuffer(GL_UNIFORM_BUFFER, liveBuffer(genericUbo_));
    glBindBuffer(GL_SHADER_STORAGE_BUFFER, liveBuffer(genericSsbo_));
    glBindBuffer(GL_PIXEL_PACK_BUFFER, liveBuffer(packBuffer_));
    glBindBuffer(GL_PIXEL_UNPACK_BUFFER, liveBuffer(unpackBuffer_));

    for (int i = 0; i < kImageUnits; ++i) {
        const Image& im = images_[size_t(i)];
        glBindImageTexture(GLuint(i), liveTexture(im.name), im.level, im.layered, im.layer, GLenum(im.access), GLenum(im.format));
    }
    for (size_t i = 0; i < kPixelStore.size(); ++i) glPixelStorei(kPixelStore[i].first, pixelStore_[i]);
}

}  // namespace welkin::gl
