// Writes the images of docs/clouds.md (hidden: `welkin_tests "[docimages]"` from the source tree
// regenerates them): the default weather map, slices of the noises, and a vertical section of
// the density function (CPU twin over the GPU-made textures).
#include <catch2/catch.hpp>

#include "clouds/cloud_test_util.hpp"
#include "gl_test_context.hpp"

#include <welkin/generators/cloud_density.hpp>
#include <welkin/generators/cloud_keys.hpp>
#include <welkin/generators/cloud_noise.hpp>
#include <welkin/generators/weather_map.hpp>
#include <welkin/image.hpp>

#include <cmath>
#include <string>

using namespace welkin;
using namespace welkin::generators;

namespace {
const std::string kDir = std::string(WELKIN_SOURCE_DIR) + "/docs/images/";

// Display encoding of [0, 1] data (sRGB-like 1/2.2 gamma, so mid-tones are visible).
float enc(double v) { return float(std::pow(std::clamp(v, 0.0, 1.0), 1.0 / 2.2)); }

// Rows of a GL-ordered (bottom-up) image to a top-down Image, channels mapped by `f`.
template <class F>
Image toDoc(const cpu::Image& im, int z, F f) {
    Image out{.width = im.w, .height = im.h, .channels = 3, .pixels = {}};
    out.pixels.resize(size_t(im.w) * size_t(im.h) * 3);
    for (int y = 0; y < im.h; ++y)
        for (int x = 0; x < im.w; ++x) {
            const glm::dvec3 c = f(im.texel(x, im.h - 1 - y, z));
            for (int k = 0; k < 3; ++k) out.at(x, y, k) = enc(c[k]);
        }
    return out;
}
}  // namespace

TEST_CASE("Cloud docs images", "[.][docimages]") {
    test::glContext();
    SkyVars vars;
    vars.declare(cloudkeys::seed, 1);
    CloudNoise noise;
    noise.run(vars, test::testLogger(), true);
    WeatherMap wm;
    wm.declareKeys(vars);
    wm.run(vars, test::testLogger(), true);
    const cpu::Image w = test::toImage(wm.texture()), base = test::toImage(noise.base()), detail = test::toImage(noise.detail()),
                     curl = test::toImage(noise.curl());
    // Weather map: R density as grey, rain (A) tinted blue, the cloud top (B) tinted red.
    writeImage(toDoc(w, 0, [](glm::dvec4 t) { return glm::dvec3(t.r * (0.6 + 0.4 * t.b), t.r, t.r + 0.5 * t.a); }),
               kDir + "clouds_weather_map.png");
    // Base noise slice z = 0: R (Perlin-Worley) left half, G (Worley fBm) right: two images.
    writeImage(toDoc(base, 0, [](glm::dvec4 t) { return glm::dvec3(t.r); }), kDir + "clouds_noise_base_r.png");
    writeImage(toDoc(base, 0, [](glm::dvec4 t) { return glm::dvec3(t.g); }), kDir + "clouds_noise_base_g.png");
    writeImage(toDoc(detail, 0, [](glm::dvec4 t) { return glm::dvec3(t.r, t.g, t.b); }), kDir + "clouds_noise_detail.png");
    writeImage(toDoc(curl, 0, [](glm::dvec4 t) { return glm::dvec3(t.r, t.g, t.b); }), kDir + "clouds_curl_noise.png");
    // Vertical section of the density (full LOD) along the map's cloudiest row, z from 3100 m down
    // to 1900 m around the layer 2-3 km, coverage 0.75 (the fair preset), cumulus.
    int bestRow = 0;
    double bestSum = -1;
    for (int j = 0; j < w.h; ++j) {
        double sum = 0;
        for (int i = 0; i < w.w; ++i) sum += w.texel(i, j).r;
        if (sum > bestSum) bestSum = sum, bestRow = j;
    }
    const double rowY = (bestRow + 0.5) / w.h * kDefaultWeatherExtentM;
    int bestCol = 0;
    for (int i = 0; i < w.w; ++i)
        if (w.texel(i, bestRow).r > w.texel(bestCol, bestRow).r) bestCol = i;
    const double x0 = (bestCol + 0.5) / w.w * kDefaultWeatherExtentM - 5000.0;
    const CloudLayerBlock b = CloudLayerBlock::make(6360e3, 2000.0, 3000.0, 0.75, 1.0, 0.05, 9000.0, 0.3, kDefaultWeatherExtentM,
                                                    {0.0, 0.0}, {0.0, 0.0, 0.0});
    const cpu::CloudTextures t{w, base, detail, curl};
    // 10 km around the row's densest point, vertical exaggeration x2: 1024 px for 10 km, 246 px
    // for 1.2 km.
    Image sec{.width = 1024, .height = 246, .channels = 3, .pixels = std::vector<float>(1024 * 246 * 3)};
    for (int y = 0; y < sec.height; ++y)
        for (int x = 0; x < sec.width; ++x) {
            const glm::dvec3 p(x0 + 10000.0 * (x + 0.5) / sec.width, rowY, 3100.0 - 1200.0 * (y + 0.5) / sec.height);
            const double d = cpu::cloudDensity(b, t, p, CloudLod::Full);
            for (int k = 0; k < 3; ++k) sec.at(x, y, k) = enc(k == 2 ? std::max(d, 0.25) : d);
        }
    writeImage(sec, kDir + "clouds_density_section.png");
}
