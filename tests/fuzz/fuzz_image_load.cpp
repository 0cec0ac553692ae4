// Texture and weather-map loading: the bytes are written to a file (the first byte picks its
// extension: .exr .png .jpg .tif .hdr, formats OpenImageIO reads) and read with welkin::readImage
// (welkin/image.hpp: its size limits), then through the checks the clouds generator applies to
// what was loaded: the artist's weather map (cpu::weatherMapTexels: channels, non-finite values,
// clamping) and the flow field (cpu::checkFlowImage, then cpu::flowAt sampled over the tile).
// Accepted images give texels in [0, 1] and finite velocities. OpenImageIO itself is not
// instrumented: a crash inside it is reported as such (docs/fuzzing.md).
#include "fuzz_common.hpp"

#include <welkin/generators/weather_map.hpp>
#include <welkin/image.hpp>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <unistd.h>

using namespace welkin;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    if (size < 1) return 0;
    static const char* const kExt[] = {".exr", ".png", ".jpg", ".tif", ".hdr"};
    static const std::string dir = [] {
        const char* tmp = std::getenv("TMPDIR");
        std::string d = std::string(tmp && *tmp ? tmp : "/tmp") + "/welkin-fuzz-image-" + std::to_string(::getpid());
        std::filesystem::create_directories(d);
        return d;
    }();
    const std::string path = dir + "/input" + kExt[data[0] % 5];
    {
        std::ofstream out(path, std::ios::binary | std::ios::trunc);
        out.write(reinterpret_cast<const char*>(data + 1), std::streamsize(size - 1));
    }
    Image im;
    if (!fuzz::accepts([&] { im = readImage(path); })) return 0;
    FUZZ_CHECK(im.width >= 1 && im.height >= 1 && im.channels >= 1);
    FUZZ_CHECK(im.pixels.size() == size_t(im.width) * im.height * im.channels);
    fuzz::accepts([&] {
        const std::vector<float> texels = generators::cpu::weatherMapTexels(im, path);
        FUZZ_CHECK(texels.size() == size_t(im.width) * im.height * 4);
        for (float v : texels) FUZZ_CHECK(v >= 0.0f && v <= 1.0f);
    });
    fuzz::accepts([&] {
        generators::cpu::checkFlowImage(im, path);
        const double extent = 40000.0, scale = 5.0;
        for (double x : {-1e9, -1.0, 0.0, 123.4, 39999.9, 4e4, 1e12})
            for (double y : {-3e7, 0.0, 20000.0, 40000.0}) {
                const glm::dvec2 v = generators::cpu::flowAt(im, scale, {x, y}, extent);
                FUZZ_CHECK(std::isfinite(v.x) && std::isfinite(v.y));
            }
    });
    return 0;
}
