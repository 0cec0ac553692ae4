// welkin bench cloud-doc-images --out DIR: writes the images of skyelements/clouds/README.md that are data, not
// renders (scripts/doc-images.sh runs it with --out skyelements/clouds/images): the default weather map, slices
// of the base, detail and curl noises (level 0, z = 0), and a vertical section of the density
// function (the CPU twin over the GPU-made textures). Every image is display-encoded [0, 1] data
// (a 1/2.2 power, so mid-tones show), 8-bit PNG.

#include <CLI/CLI.hpp>
#include <welkin/bench.hpp>
#include <welkin/error.hpp>
#include <welkin/generators/cloud_density.hpp>
#include <welkin/generators/cloud_keys.hpp>
#include <welkin/generators/cloud_noise.hpp>
#include <welkin/generators/weather_map.hpp>
#include <welkin/gl/context.hpp>
#include <welkin/image.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>

namespace welkin::cli {
namespace {

using namespace welkin::generators;

struct CloudDocImagesOptions {
    std::string out;  // existing directory the PNGs go to
};

// Display encoding of [0, 1] data (a 1/2.2 power, so mid-tones are visible).
float enc(double v) { return float(std::pow(std::clamp(v, 0.0, 1.0), 1.0 / 2.2)); }

cpu::Image toCpu(const gl::Texture& t) {
    cpu::Image im;
    im.w = t.width();
    im.h = t.height();
    im.d = t.depth();
    im.rgba = t.readRgbaFloat(0);
    return im;
}

// Rows of a GL-ordered (bottom-up) slice z to a top-down Image, channels mapped by `f`.
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

int run(const CloudDocImagesOptions& o) {
    if (o.out.empty() || !std::filesystem::is_directory(o.out)) throw Error("--out '" + o.out + "': not an existing directory");
    const std::filesystem::path dir(o.out);
    Logger log;
    auto ctx = gl::HeadlessContext::create({}, log);
    SkyVars vars;
    vars.declare(cloudkeys::seed, 1);
    CloudNoise noise;
    noise.run(vars, log, true);
    WeatherMap wm;
    wm.declareKeys(vars);
    wm.run(vars, log, true);
    const cpu::Image w = toCpu(wm.texture()), base = toCpu(noise.base()), detail = toCpu(noise.detail()), curl = toCpu(noise.curl());
    auto write = [&](const Image& img, const char* name) {
        writeImage(img, (dir / name).string());
        std::printf("wrote %s (%dx%d)\n", (dir / name).string().c_str(), img.width, img.height);
    };
    // Weather map: R density as grey, rain (A) tinted blue, the cloud top (B) tinted red.
    write(toDoc(w, 0, [](glm::dvec4 t) { return glm::dvec3(t.r * (0.6 + 0.4 * t.b), t.r, t.r + 0.5 * t.a); }), "clouds_weather_map.png");
    // Base noise slice z = 0: R (Perlin-Worley) and G (Worley fBm), two images.
    write(toDoc(base, 0, [](glm::dvec4 t) { return glm::dvec3(t.r); }), "clouds_noise_base_r.png");
    write(toDoc(base, 0, [](glm::dvec4 t) { return glm::dvec3(t.g); }), "clouds_noise_base_g.png");
    write(toDoc(detail, 0, [](glm::dvec4 t) { return glm::dvec3(t.r, t.g, t.b); }), "clouds_noise_detail.png");
    write(toDoc(curl, 0, [](glm::dvec4 t) { return glm::dvec3(t.r, t.g, t.b); }), "clouds_curl_noise.png");
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
    write(sec, "clouds_density_section.png");
    return 0;
}

bench::CommandBenchRegistrar reg({"cloud-doc-images", "write skyelements/clouds/README.md's weather map, noise slices and density section (--out DIR)",
                   [](CLI::App& sub) {
                       auto o = std::make_shared<CloudDocImagesOptions>();  // the action below owns it
                       sub.add_option("--out", o->out, "existing directory for the PNGs (docs/images)")->required();
                       return [o]() { return run(*o); };
                   }});

}  // namespace
}  // namespace welkin::cli
