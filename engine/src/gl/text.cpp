// Font atlas (FreeType) and text quads; the contract is in include/welkin/gl/text.hpp.
#include <welkin/color.hpp>
#include <welkin/error.hpp>
#include <welkin/gl/bindings.hpp>
#include <welkin/gl/shader.hpp>
#include <welkin/gl/text.hpp>

#include <epoxy/gl.h>
#include <ft2build.h>
#include FT_FREETYPE_H

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>

namespace welkin::gl {

namespace {

constexpr int kAtlasWidth = 1024;  // texels; a multiple of 4 (GL's default unpack alignment)
constexpr int kLevels = 4;         // mip levels: rasterPx down to rasterPx / 8
constexpr int kPad = 1 << kLevels; // texels between glyphs, so no mip level mixes two glyphs

// The code points of the atlas: printable ASCII and Latin-1.
std::vector<char32_t> atlasCodes() {
    std::vector<char32_t> c;
    for (char32_t u = 0x20; u <= 0x7E; ++u) c.push_back(u);
    for (char32_t u = 0xA0; u <= 0xFF; ++u) c.push_back(u);
    return c;
}

// Decodes UTF-8; a malformed sequence yields U+FFFD (drawn as '?').
std::vector<char32_t> decodeUtf8(std::string_view s) {
    std::vector<char32_t> out;
    for (size_t i = 0; i < s.size();) {
        const unsigned char b = static_cast<unsigned char>(s[i]);
        const int n = b < 0x80 ? 0 : (b >> 5) == 6 ? 1 : (b >> 4) == 14 ? 2 : (b >> 3) == 30 ? 3 : -1;
        if (n < 0 || i + size_t(n) >= s.size()) {  // a stray or truncated byte
            out.push_back(0xFFFD);
            ++i;
            continue;
        }
        char32_t u = n == 0 ? b : n == 1 ? (b & 0x1F) : n == 2 ? (b & 0x0F) : (b & 0x07);
        bool ok = true;
        for (int k = 1; k <= n; ++k) {
            const unsigned char c = static_cast<unsigned char>(s[i + size_t(k)]);
            if ((c >> 6) != 2) ok = false;
            u = (u << 6) | (c & 0x3F);
        }
        out.push_back(ok ? u : 0xFFFD);
        i += ok ? size_t(n) + 1 : 1;
    }
    return out;
}

struct FtLibrary {
    FT_Library lib = nullptr;
    FT_Face face = nullptr;
    ~FtLibrary() {
        if (face) FT_Done_Face(face);
        if (lib) FT_Done_FreeType(lib);
    }
};

}  // namespace

Font Font::load(const FontOptions& options) {
    if (!(options.rasterPx >= 8 && options.rasterPx <= 256))
        throw Error("Font::load(): rasterPx " + std::to_string(options.rasterPx) + " not in [8, 256]");
    std::error_code ec;
    if (!std::filesystem::is_regular_file(options.path, ec))
        throw Error("Font::load(): cannot open font '" + options.path + "' (install fonts-dejavu-core or set FontOptions::path)");
    FtLibrary ft;
    if (FT_Init_FreeType(&ft.lib)) throw Error("Font::load(): FreeType failed to initialise");
    if (FT_New_Face(ft.lib, options.path.c_str(), 0, &ft.face))
        throw Error("Font::load(): FreeType cannot read '" + options.path + "' as a font");
    if (FT_Set_Pixel_Sizes(ft.face, 0, FT_UInt(options.rasterPx)))
        throw Error("Font::load(): '" + options.path + "' has no size " + std::to_string(options.rasterPx) + " px");

    Font f;
    f.rasterPx_ = options.rasterPx;
    f.ascender_ = float(ft.face->size->metrics.ascender) / 64.0f;
    f.descender_ = float(ft.face->size->metrics.descender) / 64.0f;
    // Rasterise every glyph, then pack them on shelves of the atlas.
    struct Bitmap {
        std::vector<unsigned char> px;
    };
    std::vector<Bitmap> bitmaps;
    for (char32_t u : atlasCodes()) {
        if (FT_Get_Char_Index(ft.face, FT_ULong(u)) == 0 && u != 0x20) continue;  // not in the font
        if (FT_Load_Char(ft.face, FT_ULong(u), FT_LOAD_RENDER)) continue;
        const FT_GlyphSlot g = ft.face->glyph;
        Glyph gl;
        gl.size = {int(g->bitmap.width), int(g->bitmap.rows)};
        gl.bearing = {g->bitmap_left, g->bitmap_top};
        gl.advance = float(g->advance.x) / 64.0f;
        Bitmap b;
        b.px.resize(size_t(gl.size.x) * size_t(gl.size.y));
        for (int y = 0; y < gl.size.y; ++y)
            for (int x = 0; x < gl.size.x; ++x) b.px[size_t(y * gl.size.x + x)] = g->bitmap.buffer[y * g->bitmap.pitch + x];
        f.codes_.push_back(u);
        f.glyphs_.push_back(gl);
        bitmaps.push_back(std::move(b));
    }
    if (std::find(f.codes_.begin(), f.codes_.end(), U'?') == f.codes_.end())
        throw Error("Font::load(): '" + options.path + "' has no glyph for '?'");
    int x = kPad, y = kPad, shelf = 0;
    for (Glyph& g : f.glyphs_) {
        if (x + g.size.x + kPad > kAtlasWidth) {
            x = kPad;
            y += shelf + kPad;
            shelf = 0;
        }
        g.atlasPos = {x, y};
        x += g.size.x + kPad;
        shelf = std::max(shelf, g.size.y);
    }
    int height = y + shelf + kPad;
    height = (height + kPad - 1) / kPad * kPad;  // whole blocks of the coarsest mip level
    std::vector<unsigned char> atlas(size_t(kAtlasWidth) * size_t(height), 0);
    for (size_t i = 0; i < f.glyphs_.size(); ++i) {
        const Glyph& g = f.glyphs_[i];
        for (int r = 0; r < g.size.y; ++r)
            std::copy_n(bitmaps[i].px.data() + size_t(r * g.size.x), g.size.x, atlas.data() + size_t((g.atlasPos.y + r) * kAtlasWidth + g.atlasPos.x));
    }
    f.atlas_ = Texture2D(kAtlasWidth, height, GL_R8, kLevels);
    f.atlas_.upload(GL_RED, GL_UNSIGNED_BYTE, atlas.data());
    f.atlas_.generateMipmaps();
    f.atlas_.setFilter(GL_LINEAR_MIPMAP_LINEAR, GL_LINEAR);
    f.atlas_.setWrap(GL_CLAMP_TO_EDGE);
    return f;
}

bool Font::has(char32_t u) const { return std::binary_search(codes_.begin(), codes_.end(), u); }

const Glyph& Font::glyph(char32_t u) const {
    auto find = [&](char32_t c) {  // codes_ is ascending (atlasCodes() order)
        auto it = std::lower_bound(codes_.begin(), codes_.end(), c);
        return it != codes_.end() && *it == c ? it : codes_.end();
    };
    auto it = find(u);
    if (it == codes_.end()) it = find(U'?');
    if (it == codes_.end()) throw Error("Font::glyph(): the font is not loaded");
    return glyphs_[size_t(it - codes_.begin())];
}

TextExtent Font::measure(std::string_view utf8, float pixelSize) const {
    if (!(pixelSize > 0.0f && pixelSize <= 1024.0f)) throw Error("Font::measure(): pixelSize " + std::to_string(pixelSize) + " not in (0, 1024]");
    if (!atlas_) throw Error("Font::measure(): the font is not loaded");
    const float s = pixelSize / float(rasterPx_);
    TextExtent e;
    e.ascender = ascender_ * s;
    e.descender = descender_ * s;
    bool any = false;
    float pen = 0;
    for (char32_t u : decodeUtf8(utf8)) {
        const Glyph& g = glyph(u);
        if (g.size.x > 0 && g.size.y > 0) {
            const glm::vec2 lo(pen + float(g.bearing.x) * s, -float(g.bearing.y) * s);
            const glm::vec2 hi = lo + glm::vec2(g.size) * s;
            e.inkMin = any ? glm::min(e.inkMin, lo) : lo;
            e.inkMax = any ? glm::max(e.inkMax, hi) : hi;
            any = true;
        }
        pen += g.advance * s;
    }
    e.advance = pen;
    return e;
}

TextBatch::~TextBatch() = default;

void TextBatch::add(const Font& font, const glm::vec4& clip, std::string_view utf8, const TextStyle& style) {
    if (!(clip.w > 0.0f) || !std::isfinite(clip.x) || !std::isfinite(clip.y)) {
        push(font, glm::vec4(0.0f), "", style);  // checks the style all the same
        return;
    }
    push(font, clip, utf8, style);
}

void TextBatch::addAt(const Font& font, const glm::vec3& d, std::string_view utf8, const TextStyle& style) {
    if (!(std::isfinite(d.x) && std::isfinite(d.y) && std::isfinite(d.z)) || glm::dot(d, d) == 0.0f)
        throw Error("TextBatch::addAt(): direction is zero or not finite");
    push(font, glm::vec4(d, 0.0f), utf8, style);  // w = 0: a direction, projected in the vertex shader
}

void TextBatch::push(const Font& font, const glm::vec4& clip, std::string_view utf8, const TextStyle& style) {
    if (!(style.pixelSize > 0.0f && style.pixelSize <= 1024.0f))
        throw Error("TextBatch::add(): pixelSize " + std::to_string(style.pixelSize) + " not in (0, 1024]");
    if (!(style.luminanceCdM2 >= 0.0f && std::isfinite(style.luminanceCdM2)))
        throw Error("TextBatch::add(): luminanceCdM2 " + std::to_string(style.luminanceCdM2) + " not >= 0");
    if (!(style.align.x >= 0.0f && style.align.x <= 1.0f && style.align.y >= 0.0f && style.align.y <= 1.0f))
        throw Error("TextBatch::add(): align not in [0, 1]^2");
    if (utf8.empty()) return;
    const TextExtent e = font.measure(utf8, style.pixelSize);
    const float s = style.pixelSize / float(font.rasterPx());
    // Radiance: the colour scaled to luminance 1, times the luminance.
    const glm::dvec3 c(style.colour);
    const double Y = color::luminance(c);
    const glm::vec3 radiance = Y > 0 ? glm::vec3(c / Y) * style.luminanceCdM2 : glm::vec3(0.0f);
    // The pen's origin on the baseline, in pixels from the anchor (y down).
    const float boxH = e.ascender - e.descender;
    // Rounded to a whole pixel (the shader snaps the anchor too): glyphs drawn at the atlas' size
    // then map texel to pixel.
    glm::vec2 pen = glm::round(glm::vec2(-style.align.x * e.advance + style.offsetPx.x, e.ascender - style.align.y * boxH + style.offsetPx.y));
    const glm::vec2 atlasSize(font.atlas().width(), font.atlas().height());
    for (char32_t u : decodeUtf8(utf8)) {
        const Glyph& g = font.glyph(u);
        if (g.size.x > 0 && g.size.y > 0) {
            // A glyph thinner than 2 px on screen along an axis (a hyphen or a minus sign at
            // 11 px) may cover no pixel centre and vanish: its quad is grown by a pixel on both
            // sides along that axis (its atlas box by the same amount, into the empty padding
            // around the glyph), so its pixels show its filtered coverage. Other glyphs are
            // drawn exactly as laid out.
            const glm::vec2 sizePx = glm::vec2(g.size) * s;
            const float grow = std::min(1.0f, 0.5f * float(kPad) * s);  // at most half the padding, in texels
            const glm::vec2 marginPx(sizePx.x < 2.0f ? grow : 0.0f, sizePx.y < 2.0f ? grow : 0.0f);
            const glm::vec2 lo = pen + glm::vec2(float(g.bearing.x), -float(g.bearing.y)) * s - marginPx;
            const glm::vec2 hi = lo + sizePx + 2.0f * marginPx;
            const glm::vec2 marginTexels = marginPx / s;
            const glm::vec2 uv0 = (glm::vec2(g.atlasPos) - marginTexels) / atlasSize,
                            uv1 = (glm::vec2(g.atlasPos + g.size) + marginTexels) / atlasSize;
            const float q[kFloatsPerQuad] = {clip.x, clip.y, clip.z, clip.w, lo.x, lo.y, hi.x, hi.y,
                                             uv0.x, uv0.y, uv1.x, uv1.y, radiance.r, radiance.g, radiance.b, 0.0f};
            vertices_.insert(vertices_.end(), q, q + kFloatsPerQuad);
        }
        pen.x += g.advance * s;
    }
}

void TextBatch::draw(const Font& font) {
    if (vertices_.empty()) return;
    if (!font) throw Error("TextBatch::draw(): the font is not loaded");
    if (!program_) {
        program_ = ProgramBuilder("Text")
                       .vertex("engine/camera.glsl", engineShader("camera.glsl"))
                       .vertex("engine/text.vert.glsl", engineShader("text.vert.glsl"))
                       .fragment("engine/camera.glsl", engineShader("camera.glsl"))
                       .fragment("engine/composite.glsl", engineShader("composite.glsl"))
                       .fragment("engine/text.frag.glsl", engineShader("text.frag.glsl"))
                       .build();
        vao_ = VertexArray::create();
        for (unsigned a = 0; a < 4; ++a) {
            glEnableVertexArrayAttrib(vao_.id(), a);
            glVertexArrayAttribFormat(vao_.id(), a, 4, GL_FLOAT, GL_FALSE, a * 4 * sizeof(float));
            glVertexArrayAttribBinding(vao_.id(), a, 0);
        }
        glVertexArrayBindingDivisor(vao_.id(), 0, 1);
    }
    const size_t bytes = vertices_.size() * sizeof(float);
    if (buffer_.size() < bytes) buffer_ = Buffer(std::max(bytes, buffer_.size() * 2));
    buffer_.update(vertices_.data(), bytes);
    glVertexArrayVertexBuffer(vao_.id(), 0, buffer_.id(), 0, GLsizei(kFloatsPerQuad * sizeof(float)));
    program_.use();
    vao_.bind();
    font.atlas().bind(binding::kTextAtlas);
    glDrawArraysInstanced(GL_TRIANGLES, 0, 6, GLsizei(quads()));
    checkError("TextBatch::draw()");
    vertices_.clear();
}

}  // namespace welkin::gl
