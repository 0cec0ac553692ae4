#include <welkin/error.hpp>
#include <welkin/image.hpp>

#include "image_codec.hpp"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <random>
#include <unistd.h>

namespace welkin {

namespace fs = std::filesystem;

namespace detail {
// OpenImageIO's messages can span lines (one per failing layer): welkin's errors are one line.
std::string oneLine(std::string text) {
    while (!text.empty() && (text.back() == '\n' || text.back() == '\r')) text.pop_back();
    std::string out;
    for (char c : text) {
        if (c == '\n' || c == '\r') {
            if (!out.empty() && out.back() != ' ') out += "; ";
        } else {
            out += c;
        }
    }
    return out;
}

void checkReadSize(const std::string& path, long long width, long long height, long long channels) {
    // A header can claim any size: refuse the absurd before allocating (the limits are far above
    // any texture welkin reads: an 8k x 4k panorama is 2^25 pixels).
    if (width < 1 || height < 1 || channels < 1 || width > kMaxImageEdge || height > kMaxImageEdge || channels > kMaxImageChannels ||
        double(width) * double(height) * double(channels) > double(kMaxImageValues))
        throw Error("readImage('" + path + "'): " + std::to_string(width) + " x " + std::to_string(height) + " x " + std::to_string(channels) +
                    " is not a supported size (1 to " + std::to_string(kMaxImageEdge) + " pixels a side, 1 to " +
                    std::to_string(kMaxImageChannels) + " channels, at most " + std::to_string(kMaxImageValues) + " values)");
}
}  // namespace detail

namespace {
std::string lowerExt(const std::string& path) {
    std::string e = fs::path(path).extension().string();
    std::transform(e.begin(), e.end(), e.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    return e;
}
}  // namespace

void checkWritable(const std::string& path) {
    if (path.empty()) throw Error("output path is empty");
    std::string ext = lowerExt(path);
    if (ext != ".exr" && ext != ".png" && ext != ".jpg" && ext != ".jpeg" && ext != ".tif" && ext != ".tiff")
        throw Error("output '" + path + "': unsupported extension (accepted: .exr, .png, .jpg, .tif)");
    fs::path dir = fs::path(path).parent_path();
    if (dir.empty()) dir = ".";
    std::error_code ec;
    if (!fs::is_directory(dir, ec)) throw Error("output '" + path + "': directory '" + dir.string() + "' does not exist");
    if (::access(dir.c_str(), W_OK) != 0) throw Error("output '" + path + "': directory '" + dir.string() + "' is not writable");
    if (fs::is_directory(path, ec)) throw Error("output '" + path + "' is a directory");
    if (fs::exists(path, ec) && ::access(path.c_str(), W_OK) != 0) throw Error("output '" + path + "' exists and is not writable");
}

void writeImage(const Image& img, const std::string& path) {
    checkWritable(path);
    if (img.width <= 0 || img.height <= 0 || img.pixels.size() != size_t(img.width) * img.height * img.channels)
        throw Error("writeImage('" + path + "'): image is empty or inconsistent");
    std::string ext = lowerExt(path);
    // Temporary file beside the target, then rename: never a half-written output.
    fs::path target(path);
    std::string tmp = (target.parent_path() / ("." + target.filename().string() + ".tmp" + std::to_string(::getpid()))).string();
    tmp += ext;
    std::string err = detail::encodeImage(img, tmp, ext);
    bool ok = err.empty();
    std::error_code ec, ignored;
    if (!ok) {
        fs::remove(tmp, ignored);
        throw Error("writeImage('" + path + "'): " + detail::oneLine(err));
    }
    fs::rename(tmp, target, ec);
    if (ec) {
        std::string why = ec.message();
        fs::remove(tmp, ignored);
        throw Error("writeImage('" + path + "'): cannot rename the temporary file (" + why + ")");
    }
}

Image readImage(const std::string& path) { return detail::decodeImage(path); }

}  // namespace welkin
