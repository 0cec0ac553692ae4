// The OpenImageIO codec (WELKIN_IMAGE_IO=OpenImageIO, the default): every format OpenImageIO knows.
#include "../image_codec.hpp"

#include <welkin/error.hpp>

#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cmath>

namespace welkin::detail {

std::string encodeImage(const Image& img, const std::string& path, const std::string& ext) {
    const bool isFloat = ext == ".exr";
    auto out = OIIO::ImageOutput::create(path);
    if (!out) return "no writer for '" + ext + "'";
    OIIO::ImageSpec spec(img.width, img.height, img.channels, isFloat ? OIIO::TypeDesc::FLOAT : OIIO::TypeDesc::UINT8);
    if (isFloat) spec.attribute("compression", "zip");
    else spec.attribute("oiio:ColorSpace", "sRGB");
    bool ok = out->open(path, spec);
    if (ok) {
        if (isFloat) {
            ok = out->write_image(OIIO::TypeDesc::FLOAT, img.pixels.data());
        } else {
            std::vector<unsigned char> bytes(img.pixels.size());
            for (size_t i = 0; i < bytes.size(); ++i)
                bytes[i] = (unsigned char)std::lround(std::clamp(img.pixels[i], 0.0f, 1.0f) * 255.0f);
            ok = out->write_image(OIIO::TypeDesc::UINT8, bytes.data());
        }
        ok = out->close() && ok;
    }
    std::string err = oneLine(out->geterror());
    if (ok) return {};
    return err.empty() ? "write failed" : err;
}

Image decodeImage(const std::string& path) {
    auto in = OIIO::ImageInput::open(path);
    if (!in) throw Error("readImage('" + path + "'): " + oneLine(OIIO::geterror()));
    const OIIO::ImageSpec& spec = in->spec();
    checkReadSize(path, spec.width, spec.height, spec.nchannels);
    Image img;
    img.width = spec.width;
    img.height = spec.height;
    img.channels = spec.nchannels;
    img.pixels.resize(size_t(img.width) * img.height * img.channels);
    if (!in->read_image(0, 0, 0, img.channels, OIIO::TypeDesc::FLOAT, img.pixels.data()))
        throw Error("readImage('" + path + "'): " + oneLine(in->geterror()));
    return img;
}

}  // namespace welkin::detail
