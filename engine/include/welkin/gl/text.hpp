// Text in the HDR pipeline: glyphs rasterised once by FreeType into an atlas texture, strings
// drawn as textured quads anchored at a clip-space point, emitting a luminance in cd/m^2.
//
//   welkin::gl::Font font = welkin::gl::Font::load();        // DejaVu Sans, or Font::load({.path = ...})
//   welkin::gl::TextBatch labels;
//   // in an element's doRender(ctx), anchored where a direction lands (C++ twin of welkin_clipFromDirection):
//   if (auto clip = ctx.camera.clipFromDirection(dir))
//       labels.add(font, glm::vec4(*clip), "Cygnus", {.pixelSize = 16, .luminanceCdM2 = 2e-3});
//   labels.addAt(font, glm::vec3(dir), "Vega", {});           // or: the GPU projects the direction
//   labels.draw(font);                                       // into the bound HDR target, then cleared
//
// Sizes are pixels of the output image; a string's layout (measure()) is in those pixels, x right,
// y down, from the pen's origin on the baseline; add() puts that origin on a whole pixel. The
// atlas holds printable ASCII and Latin-1 (U+0020..U+007E, U+00A0..U+00FF) rasterised at
// FontOptions::rasterPx with mipmaps; a string is
// UTF-8 and a code point outside the atlas is drawn as '?'. Quads are drawn with the camera block
// bound (the processor binds it during render()) and the composite blend of an element: radiance
// colour x luminance x coverage, transmittance 1 - coverage (a label hides what is behind it).
// Default luminance 2e-3 cd/m^2: about 10x the natural night sky at a dark site (1.7e-4 cd/m^2,
// 22 mag/arcsec^2), so a label reads against a moonless sky at the exposures that show the stars
// (EV100 -9 puts it at 85 % of the linear white point 1.2 x 2^EV cd/m^2) and, like ink on a chart, disappears against a twilight or
// day sky unless the host raises it (a label is a radiance in the HDR frame, exposed like the rest).
#pragma once
#include <welkin/gl/objects.hpp>

#include <glm/glm.hpp>

#include <string>
#include <string_view>
#include <vector>

namespace welkin::gl {

/// DejaVu Sans as Debian's fonts-dejavu-core installs it.
inline constexpr const char* kDefaultFontPath = "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf";

struct FontOptions {
    std::string path = kDefaultFontPath;  ///< a TrueType/OpenType file FreeType reads
    int rasterPx = 48;                    ///< pixel height (em) the atlas is rasterised at, [8, 256]
};

/// One glyph in the atlas, in atlas pixels at FontOptions::rasterPx.
struct Glyph {
    glm::ivec2 size{0};      ///< bitmap width, height, px (0 for a space)
    glm::ivec2 bearing{0};   ///< from the pen to the bitmap's top-left: x right, y up (FreeType's)
    float advance = 0;       ///< pen advance, px
    glm::ivec2 atlasPos{0};  ///< top-left texel of the bitmap in the atlas
};

/// A string's layout at a pixel size: pen from 0 on the baseline, x right, y down.
struct TextExtent {
    float advance = 0;          ///< total pen advance (the string's width for centring), px
    glm::vec2 inkMin{0}, inkMax{0};  ///< bounding box of the glyph bitmaps, px (empty: min = max = 0)
    float ascender = 0, descender = 0;  ///< the font's, px (descender < 0)
};

/// A font rasterised into a single-channel atlas texture (R8, mipmapped). Move-only; needs a
/// current GL 4.5 context to load.
class Font {
public:
    /// Loads the font and rasterises the atlas. Throws welkin::Error
    /// "Font::load(): cannot open font '<path>' (install fonts-dejavu-core or set FontOptions::path)"
    /// when the file is missing, or naming FreeType's error; rasterPx not in [8, 256] throws too.
    static Font load(const FontOptions& options = {});
    Font() = default;
    Font(Font&&) noexcept = default;
    Font& operator=(Font&&) noexcept = default;

    explicit operator bool() const { return bool(atlas_); }
    int rasterPx() const { return rasterPx_; }
    const Texture2D& atlas() const { return atlas_; }
    /// The glyph of a code point, or of '?' when the atlas lacks it.
    const Glyph& glyph(char32_t codePoint) const;
    bool has(char32_t codePoint) const;
    /// Font ascender/descender (descender < 0) and line height, px at rasterPx.
    float ascender() const { return ascender_; }
    float descender() const { return descender_; }
    /// Layout of a UTF-8 string at `pixelSize` (> 0) px per em, kerning not applied.
    TextExtent measure(std::string_view utf8, float pixelSize) const;

private:
    Texture2D atlas_;
    int rasterPx_ = 0;
    float ascender_ = 0, descender_ = 0;
    std::vector<char32_t> codes_;  // sorted
    std::vector<Glyph> glyphs_;    // same order
};

struct TextStyle {
    float pixelSize = 16;             ///< em height, pixels of the output image, (0, 1024]
    glm::vec3 colour{1.0f};           ///< linear sRGB, scaled to luminance 1 by the batch
    float luminanceCdM2 = 2e-3f;      ///< emitted luminance of a fully covered pixel, cd/m^2, >= 0
    /// Where the anchor sits in the string's box (width: the advance; height: ascender to
    /// descender), each in [0, 1]: x 0 left, 0.5 centre, 1 right; y 0 top, 0.5 middle, 1 bottom.
    glm::vec2 align{0.5f, 0.5f};
    glm::vec2 offsetPx{0.0f};         ///< extra offset of the anchor, pixels (x right, y down)
};

/// Strings collected for one draw. Move-only; draw() needs a current context and the camera
/// block bound (inside SkyElement::render()).
class TextBatch {
public:
    TextBatch() = default;
    TextBatch(TextBatch&&) noexcept = default;
    TextBatch& operator=(TextBatch&&) noexcept = default;
    ~TextBatch();

    /// Adds a string anchored at a clip-space position (gl_Position of the anchor: from
    /// Camera::clipFromDirection() or the GLSL welkin_clipFromDirection()); an anchor with w <= 0
    /// is skipped. Throws welkin::Error for a style out of range ("TextBatch::add(): pixelSize 0
    /// not in (0, 1024]").
    void add(const Font& font, const glm::vec4& clip, std::string_view utf8, const TextStyle& style = {});
    /// Adds a string anchored where a world (ENU) direction lands: the GPU computes the anchor with
    /// welkin_clipFromDirection() for the camera of the draw (a direction the projection does not
    /// show draws nothing). Throws like add() and for a zero or non-finite direction.
    void addAt(const Font& font, const glm::vec3& directionEnu, std::string_view utf8, const TextStyle& style = {});
    /// Glyph quads waiting to be drawn.
    int quads() const { return int(vertices_.size() / kFloatsPerQuad); }
    /// Draws every string into the bound framebuffer with the current blend state and clears the
    /// batch. The font must be the one given to add(). Leaves its own program, vertex array and
    /// atlas (unit binding::kTextAtlas) bound: an element that then draws attribute-less binds
    /// FrameContext::emptyVao again (the processor restores the host's state after the frame).
    void draw(const Font& font);
    void clear() { vertices_.clear(); }

private:
    void push(const Font& font, const glm::vec4& anchor, std::string_view utf8, const TextStyle& style);
    static constexpr size_t kFloatsPerQuad = 16;  // anchor (4), pixel box (4), uv box (4), radiance (3), pad
    std::vector<float> vertices_;
    Buffer buffer_;
    VertexArray vao_;
    Program program_;
};

}  // namespace welkin::gl
