#include <welkin_host/overlay.hpp>

#include <epoxy/gl.h>

#include <algorithm>

namespace host {

namespace {
const char* kVertex = R"(#version 450 core
layout(location = 0) in vec4 a_posUv;   // pixel position (x right, y down), atlas uv
layout(location = 1) in vec4 a_color;   // premultiplied? no: straight colour and alpha
uniform vec2 u_viewport;
out vec2 v_uv;
out vec4 v_color;
void main() {
    v_uv = a_posUv.zw;
    v_color = a_color;
    gl_Position = vec4(a_posUv.x / u_viewport.x * 2.0 - 1.0, 1.0 - a_posUv.y / u_viewport.y * 2.0, 0.0, 1.0);
}
)";
const char* kFragment = R"(#version 450 core
layout(binding = 0) uniform sampler2D u_atlas;
in vec2 v_uv;
in vec4 v_color;
out vec4 o_color;
void main() {
    float coverage = v_uv.x < 0.0 ? 1.0 : texture(u_atlas, v_uv).r;   // u < 0: a solid box
    o_color = vec4(v_color.rgb, v_color.a * coverage);
}
)";
struct QuadVertex {
    float x, y, u, v;
    float r, g, b, a;
};
}  // namespace

TextOverlay::TextOverlay() : font_(welkin::gl::Font::load()) {
    program_ = buildProgram("host overlay", {{GL_VERTEX_SHADER, kVertex}, {GL_FRAGMENT_SHADER, kFragment}});
    vao_ = GlName::vertexArray();
    vbo_ = GlName::buffer();
    glVertexArrayVertexBuffer(vao_.id(), 0, vbo_.id(), 0, sizeof(QuadVertex));
    for (GLuint a = 0; a < 2; ++a) {
        glEnableVertexArrayAttrib(vao_.id(), a);
        glVertexArrayAttribFormat(vao_.id(), a, 4, GL_FLOAT, GL_FALSE, a * 4 * sizeof(float));
        glVertexArrayAttribBinding(vao_.id(), a, 0);
    }
}

void TextOverlay::draw(const std::vector<std::string>& lines, int width, int height, float pixelSize) {
    std::vector<QuadVertex> verts;
    auto quad = [&](float x0, float y0, float x1, float y1, float u0, float v0, float u1, float v1, float r, float g, float b, float a) {
        const QuadVertex q[6] = {{x0, y0, u0, v0, r, g, b, a}, {x1, y0, u1, v0, r, g, b, a}, {x1, y1, u1, v1, r, g, b, a},
                                 {x0, y0, u0, v0, r, g, b, a}, {x1, y1, u1, v1, r, g, b, a}, {x0, y1, u0, v1, r, g, b, a}};
        verts.insert(verts.end(), q, q + 6);
    };
    const float scale = pixelSize / float(font_.rasterPx());
    const float lineHeight = std::round(pixelSize * 1.3f);
    const float margin = 6.0f;
    float widest = 0.0f;
    for (const auto& l : lines) widest = std::max(widest, font_.measure(l, pixelSize).advance);
    quad(0, 0, widest + 2 * margin, lines.size() * lineHeight + 2 * margin, -1, -1, -1, -1, 0, 0, 0, 0.55f);
    const float aw = float(font_.atlas().width()), ah = float(font_.atlas().height());
    float penY = margin + std::round(font_.ascender() * scale);
    for (const auto& line : lines) {
        float penX = margin;
        for (unsigned char ch : line) {  // the overlay's text is ASCII
            const welkin::gl::Glyph& g = font_.glyph(char32_t(ch));
            if (g.size.x > 0 && g.size.y > 0) {
                const float x0 = std::round(penX) + g.bearing.x * scale, y0 = penY - g.bearing.y * scale;
                const float x1 = x0 + g.size.x * scale, y1 = y0 + g.size.y * scale;
                quad(x0, y0, x1, y1, g.atlasPos.x / aw, g.atlasPos.y / ah, (g.atlasPos.x + g.size.x) / aw,
                     (g.atlasPos.y + g.size.y) / ah, 1, 1, 1, 1);
            }
            penX += g.advance * scale;
        }
        penY += lineHeight;
    }
    glNamedBufferData(vbo_.id(), GLsizeiptr(verts.size() * sizeof(QuadVertex)), verts.data(), GL_STREAM_DRAW);

    GLboolean blend = glIsEnabled(GL_BLEND), depth = glIsEnabled(GL_DEPTH_TEST);
    GLint src = 0, dst = 0, srcA = 0, dstA = 0, prog = 0, vao = 0;
    glGetIntegerv(GL_BLEND_SRC_RGB, &src);
    glGetIntegerv(GL_BLEND_DST_RGB, &dst);
    glGetIntegerv(GL_BLEND_SRC_ALPHA, &srcA);
    glGetIntegerv(GL_BLEND_DST_ALPHA, &dstA);
    glGetIntegerv(GL_CURRENT_PROGRAM, &prog);
    glGetIntegerv(GL_VERTEX_ARRAY_BINDING, &vao);
    glEnable(GL_BLEND);
    glDisable(GL_DEPTH_TEST);
    glBlendFuncSeparate(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA, GL_ZERO, GL_ONE);
    glUseProgram(program_.id());
    glUniform2f(glGetUniformLocation(program_.id(), "u_viewport"), float(width), float(height));
    glBindTextureUnit(0, font_.atlas().id());
    glBindVertexArray(vao_.id());
    glDrawArrays(GL_TRIANGLES, 0, GLsizei(verts.size()));
    glBindVertexArray(GLuint(vao));
    glUseProgram(GLuint(prog));
    glBlendFuncSeparate(GLenum(src), GLenum(dst), GLenum(srcA), GLenum(dstA));
    if (!blend) glDisable(GL_BLEND);
    if (depth) glEnable(GL_DEPTH_TEST);
}

}  // namespace host
