// Where a label's ink must be, and where it is: for the tests of the planets' and the stars'
// labels (text anchored at a body, welkin/gl/text.hpp).
//
//   Box want = expectedInk(font, "Mars -2.2", 11, *cam.pixelOf(dir), 1 + 0.4 * 11);
//   Box got = inkIn(on, off, want.grown(6), 0.05);   // label pixels: labels on minus off
//   CHECK(got.within(want, 2));
#pragma once
#include <welkin/gl/text.hpp>
#include <welkin/image.hpp>

#include <glm/glm.hpp>

#include <algorithm>
#include <climits>
#include <cmath>
#include <sstream>
#include <string>

namespace welkin::test {

/// An inclusive pixel box (x right, y down).
struct Box {
    int x0 = INT_MAX, y0 = INT_MAX, x1 = INT_MIN, y1 = INT_MIN;
    bool empty() const { return x1 < x0 || y1 < y0; }
    void add(int x, int y) {
        x0 = std::min(x0, x), y0 = std::min(y0, y), x1 = std::max(x1, x), y1 = std::max(y1, y);
    }
    Box grown(int d) const { return {x0 - d, y0 - d, x1 + d, y1 + d}; }
    bool contains(int x, int y) const { return x >= x0 && x <= x1 && y >= y0 && y <= y1; }
    /// Every edge within `d` px of `o`'s.
    bool within(const Box& o, int d) const {
        return !empty() && !o.empty() && std::abs(x0 - o.x0) <= d && std::abs(x1 - o.x1) <= d && std::abs(y0 - o.y0) <= d && std::abs(y1 - o.y1) <= d;
    }
    std::string str() const {
        std::ostringstream s;
        s << "[" << x0 << ".." << x1 << "] x [" << y0 << ".." << y1 << "]";
        return s.str();
    }
};

/// The pixels a label's glyphs cover when its box (advance wide, ascender..descender high) starts
/// `offsetX` px right of the anchor `anchorPx` (continuous pixel coordinates, Camera::pixelOf)
/// and is vertically centred on it (TextStyle align (0, 0.5)): the anchor is snapped to the
/// nearest pixel corner and the pen to a whole pixel, as documented in welkin/gl/text.hpp; the
/// ink is Font::measure()'s bitmap box.
inline Box expectedInk(const gl::Font& font, const std::string& text, float emPx, glm::dvec2 anchorPx, double offsetX) {
    const gl::TextExtent e = font.measure(text, emPx);
    const glm::dvec2 pen = glm::round(glm::dvec2(offsetX, e.ascender - 0.5 * (e.ascender - e.descender)));
    const glm::dvec2 a = glm::floor(anchorPx + 0.5);
    const glm::dvec2 lo = a + pen + glm::dvec2(e.inkMin), hi = a + pen + glm::dvec2(e.inkMax);
    return {int(std::floor(lo.x)), int(std::floor(lo.y)), int(std::ceil(hi.x)) - 1, int(std::ceil(hi.y)) - 1};
}

inline double luminanceAt(const Image& img, int x, int y) {
    return 0.2126 * img.at(x, y, 0) + 0.7152 * img.at(x, y, 1) + 0.0722 * img.at(x, y, 2);
}

/// Bounding box of the pixels inside `window` where `on` is brighter than `off` by more than
/// `threshold` (cd/m^2): a label's ink when the two frames differ only by the labels.
inline Box inkIn(const Image& on, const Image& off, const Box& window, double threshold) {
    Box b;
    for (int y = std::max(window.y0, 0); y <= std::min(window.y1, on.height - 1); ++y)
        for (int x = std::max(window.x0, 0); x <= std::min(window.x1, on.width - 1); ++x)
            if (luminanceAt(on, x, y) - luminanceAt(off, x, y) > threshold) b.add(x, y);
    return b;
}

}  // namespace welkin::test
