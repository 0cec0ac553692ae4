// Private: the image file codecs behind welkin::writeImage / welkin::readImage.
// Two builds: OpenImageIO (default; every format it knows) or the small built-in set
// (WELKIN_IMAGE_IO=builtin: PNG/JPEG/HDR through stb, uncompressed float EXR written and read
// by image_exr.cpp), for hosts that do not want OpenImageIO's dependency tree.
#pragma once
#include <welkin/image.hpp>

#include <string>

namespace welkin::detail {

/// Encodes `img` into the file `path` (a temporary name chosen by writeImage); `ext` is the
/// lower-case extension of the final target (".exr", ".png", ...). Returns an empty string on
/// success, else the reason. Must not throw for I/O failures.
std::string encodeImage(const Image& img, const std::string& path, const std::string& ext);
/// Decodes any supported file as float, top row first; 8-bit channels map k to k / 255 and
/// 16-bit ones k to k / 65535 (no colour conversion). Throws welkin::Error naming the path.
Image decodeImage(const std::string& path);

/// `text` on one line (line breaks become "; "): welkin's errors are one line.
std::string oneLine(std::string text);
/// Throws welkin::Error naming `path` unless the size is within kMaxImageEdge, kMaxImageChannels
/// and kMaxImageValues (welkin/image.hpp): checked before any decoder allocates.
void checkReadSize(const std::string& path, long long width, long long height, long long channels);

/// Uncompressed scanline OpenEXR, 32-bit float channels (1: Y, 3: RGB, 4: RGBA).
std::string writeExrUncompressed(const Image& img, const std::string& path);
/// Reads an uncompressed scanline EXR with FLOAT or HALF channels (what writeExrUncompressed
/// and most tools write with compression "none"). Throws welkin::Error naming the path.
Image readExrUncompressed(const std::string& path);

}  // namespace welkin::detail
