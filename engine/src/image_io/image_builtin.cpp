// The built-in codec (WELKIN_IMAGE_IO=builtin): PNG, JPEG and Radiance HDR through stb (Debian
// libstb), OpenEXR uncompressed float through image_exr.cpp. No TIFF, no compressed EXR: those
// need the OpenImageIO build, and the error says so.
#include "../image_codec.hpp"

#include <welkin/error.hpp>

#include <stb/stb_image.h>
#include <stb/stb_image_write.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>

namespace welkin::detail {

std::string encodeImage(const Image& img, const std::string& path, const std::string& ext) {
    if (ext == ".exr") return writeExrUncompressed(img, path);
    if (img.channels < 1 || img.channels > 4) return std::to_string(img.channels) + " channels (accepted: 1 to 4)";
    std::vector<unsigned char> bytes(img.pixels.size());
    for (size_t i = 0; i < bytes.size(); ++i)
        bytes[i] = (unsigned char)std::lround(std::clamp(img.pixels[i], 0.0f, 1.0f) * 255.0f);
    int ok = 0;
    if (ext == ".png") ok = stbi_write_png(path.c_str(), img.width, img.height, img.channels, bytes.data(), img.width * img.channels);
    else if (ext == ".jpg" || ext == ".jpeg") ok = stbi_write_jpg(path.c_str(), img.width, img.height, img.channels, bytes.data(), 95);
    else return "no writer for '" + ext + "' in this build (WELKIN_IMAGE_IO=builtin writes .exr, .png, .jpg)";
    return ok ? std::string() : std::string("write failed");
}

Image decodeImage(const std::string& path) {
    {
        std::FILE* f = std::fopen(path.c_str(), "rb");
        if (!f) throw Error("readImage('" + path + "'): cannot open the file");
        unsigned char magic[4] = {0, 0, 0, 0};
        size_t n = std::fread(magic, 1, 4, f);
        std::fclose(f);
        if (n == 4 && magic[0] == 0x76 && magic[1] == 0x2f && magic[2] == 0x31 && magic[3] == 0x01)
            return readExrUncompressed(path);
    }
    int w = 0, h = 0, c = 0;
    if (!stbi_info(path.c_str(), &w, &h, &c))
        throw Error("readImage('" + path + "'): " + stbi_failure_reason() +
                    " (this build reads PNG, JPEG, HDR and uncompressed EXR; others need WELKIN_IMAGE_IO=OpenImageIO)");
    checkReadSize(path, w, h, c);
    Image img;
    auto fill = [&](auto* data, float scale) {
        img.width = w;
        img.height = h;
        img.channels = c;
        img.pixels.resize(size_t(w) * h * c);
        for (size_t i = 0; i < img.pixels.size(); ++i) img.pixels[i] = float(data[i]) * scale;
    };
    if (stbi_is_hdr(path.c_str())) {
        std::unique_ptr<float, void (*)(void*)> d(stbi_loadf(path.c_str(), &w, &h, &c, 0), stbi_image_free);
        if (!d) throw Error("readImage('" + path + "'): " + stbi_failure_reason());
        fill(d.get(), 1.0f);
    } else if (stbi_is_16_bit(path.c_str())) {
        std::unique_ptr<stbi_us, void (*)(void*)> d(stbi_load_16(path.c_str(), &w, &h, &c, 0), stbi_image_free);
        if (!d) throw Error("readImage('" + path + "'): " + stbi_failure_reason());
        fill(d.get(), 1.0f / 65535.0f);
    } else {
        std::unique_ptr<stbi_uc, void (*)(void*)> d(stbi_load(path.c_str(), &w, &h, &c, 0), stbi_image_free);
        if (!d)
            throw Error("readImage('" + path + "'): " + stbi_failure_reason() +
                        " (this build reads PNG, JPEG, HDR and uncompressed EXR; others need WELKIN_IMAGE_IO=OpenImageIO)");
        fill(d.get(), 1.0f / 255.0f);
    }
    return img;
}

}  // namespace welkin::detail
