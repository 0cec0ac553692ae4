// The frame-time overlay: lines of text drawn over the tone-mapped (display) image, with the
// glyph atlas of welkin's font service (welkin::gl::Font: FreeType, DejaVu Sans) and the host's
// own quad shader. Draws with alpha blending into the bound framebuffer and restores the blend
// state, program and vertex array it changes.
#pragma once
#include <welkin_host/gl.hpp>

#include <welkin/gl/text.hpp>

#include <string>
#include <vector>

namespace host {

class TextOverlay {
public:
    /// Loads the font (welkin::gl::Font::load(); throws welkin::Error if the font is missing).
    TextOverlay();
    /// Draws `lines` at the top-left corner of a width x height viewport, `pixelSize` px per em,
    /// white on a translucent dark box.
    void draw(const std::vector<std::string>& lines, int width, int height, float pixelSize = 15.0f);

private:
    welkin::gl::Font font_;
    GlName program_, vao_, vbo_;
};

}  // namespace host
