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
        throw Error("writeImage('" + path + "'): " + err);
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
