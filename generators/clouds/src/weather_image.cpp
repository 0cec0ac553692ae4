// The weather map's image inputs (clouds.weather_map_file, clouds.flow_file): what is checked
// and converted after OpenImageIO has read them, and the flow field's sampling. CPU only (no
// GL): the fuzz target tests/fuzz/fuzz_image_load.cpp builds this file alone.
#include <welkin/error.hpp>
#include <welkin/generators/cloud_keys.hpp>
#include <welkin/generators/weather_map.hpp>

#include <algorithm>
#include <cmath>

namespace welkin::generators::cpu {

namespace {
double wrapMod(double v, double p) {
    double m = std::fmod(v, p);
    return m < 0 ? m + p : m;
}
// Throws naming `key`, the file and the first non-finite value among the first `channels`.
void checkFinite(const Image& im, int channels, const std::string& key, const std::string& path) {
    for (int y = 0; y < im.height; ++y)
        for (int x = 0; x < im.width; ++x)
            for (int c = 0; c < channels; ++c)
                if (!std::isfinite(im.at(x, y, c)))
                    throw Error(key + ": '" + path + "' has a non-finite value at pixel (" + std::to_string(x) + ", " + std::to_string(y) +
                                ") channel " + std::to_string(c) + " (values must be finite numbers)");
}
void checkShape(const Image& im, const std::string& key, const std::string& path) {
    if (im.width < 1 || im.height < 1 || im.channels < 1 || im.pixels.size() != size_t(im.width) * size_t(im.height) * size_t(im.channels))
        throw Error(key + ": '" + path + "' is an empty or inconsistent image");
}
}  // namespace

std::vector<float> weatherMapTexels(const Image& im, const std::string& path) {
    const std::string key = cloudkeys::weatherFile.name();
    checkShape(im, key, path);
    if (im.channels < 3)
        throw Error(key + ": '" + path + "' has " + std::to_string(im.channels) + " channel(s), needs 3 or 4 (R density, G base, B top, A rain)");
    const int used = std::min(im.channels, 4);
    checkFinite(im, used, key, path);
    // GL rows run south to north (v = y / extent); the image's top row is the map's north edge.
    std::vector<float> px(size_t(im.width) * size_t(im.height) * 4);
    for (int y = 0; y < im.height; ++y)
        for (int x = 0; x < im.width; ++x)
            for (int c = 0; c < 4; ++c)
                px[(size_t(y) * size_t(im.width) + size_t(x)) * 4 + size_t(c)] =
                    c < used ? std::clamp(im.at(x, im.height - 1 - y, c), 0.0f, 1.0f) : 0.0f;
    return px;
}

void checkFlowImage(const Image& im, const std::string& path) {
    const std::string key = cloudkeys::flowFile.name();
    checkShape(im, key, path);
    if (im.channels < 2) throw Error(key + ": '" + path + "' has 1 channel, needs 2 (R east, G north)");
    checkFinite(im, 2, key, path);
}

glm::dvec2 flowAt(const Image& flow, double scale, glm::dvec2 m, double extent) {
    // Bilinear, repeat; image x east, rows top (north) to bottom.
    const double fx = wrapMod(m.x / extent, 1.0) * flow.width - 0.5, fy = (1.0 - wrapMod(m.y / extent, 1.0)) * flow.height - 0.5;
    if (!std::isfinite(fx) || !std::isfinite(fy) || flow.width < 1 || flow.height < 1 || flow.channels < 2) return glm::dvec2(0.0);
    const int x0 = int(std::floor(fx)), y0 = int(std::floor(fy));
    const double ax = fx - x0, ay = fy - y0;
    auto at = [&](int x, int y, int c) {
        x = ((x % flow.width) + flow.width) % flow.width;
        y = ((y % flow.height) + flow.height) % flow.height;
        return double(flow.at(x, y, c));
    };
    glm::dvec2 v;
    for (int c = 0; c < 2; ++c) {
        const double top = at(x0, y0, c) * (1 - ax) + at(x0 + 1, y0, c) * ax;
        const double bot = at(x0, y0 + 1, c) * (1 - ax) + at(x0 + 1, y0 + 1, c) * ax;
        v[c] = (2.0 * (top * (1 - ay) + bot * ay) - 1.0) * scale;
    }
    return v;
}

}  // namespace welkin::generators::cpu
