// Float images and atomic image files (OpenImageIO, or the built-in codec: see WELKIN_IMAGE_IO).
//
//   welkin::Image img = processor.readHdr();             // RGB float, cd/m^2, top row first
//   welkin::writeImage(img, "sky.exr");                  // linear float EXR
//   welkin::writeImage(processor.readToneMapped(), "sky.png");   // 8-bit sRGB PNG
//
// Files are written to a temporary name beside the target and renamed, so a failed write never
// leaves a partial file. Errors name the path.
#pragma once
#include <string>
#include <vector>

namespace welkin {

struct Image {
    int width = 0;
    int height = 0;
    int channels = 3;
    std::vector<float> pixels;  ///< row-major, top row first, `channels` floats per pixel
    float& at(int x, int y, int c) { return pixels[(size_t(y) * width + x) * channels + c]; }
    float at(int x, int y, int c) const { return pixels[(size_t(y) * width + x) * channels + c]; }
};

/// Writes .exr (float, linear) or .png/.jpg/.tif (8-bit: values clamped to [0, 1], written as
/// they are, i.e. already encoded) atomically. Throws welkin::Error naming the path.
void writeImage(const Image& image, const std::string& path);
/// Largest image readImage() accepts: pixels a side, channels, and values (width x height x
/// channels: 2^28 floats, 1 GiB).
inline constexpr int kMaxImageEdge = 65536;
inline constexpr int kMaxImageChannels = 16;
inline constexpr long long kMaxImageValues = 1LL << 28;
/// Reads an image file as float (top row first); 8-bit channels k read as k / 255, no colour
/// conversion. The default build reads every OpenImageIO format; a WELKIN_IMAGE_IO=builtin build
/// reads PNG, JPEG, Radiance HDR and uncompressed EXR. Throws welkin::Error naming the path for
/// an unreadable file or a size outside the limits above.
Image readImage(const std::string& path);
/// Checks that `path` can be created (its directory exists and is writable) before rendering.
void checkWritable(const std::string& path);

}  // namespace welkin
