// The image codecs: the built-in uncompressed EXR writer/reader (engine/src/image_io/image_exr.cpp,
// used by WELKIN_IMAGE_IO=builtin builds) checked against the build's readImage (OpenImageIO in
// the default build: an independent decoder), and the atomic writer's round trips.
#include "../../engine/src/image_codec.hpp"

#include <welkin/error.hpp>
#include <welkin/image.hpp>

#include <catch2/catch.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <unistd.h>

namespace fs = std::filesystem;
using namespace welkin;

namespace {
Image sample(int w, int h, int c) {
    Image img;
    img.width = w;
    img.height = h;
    img.channels = c;
    img.pixels.resize(size_t(w) * h * c);
    // Values across welkin's range: starlight 1e-5 cd/m^2 to the solar disk 1.6e9, a negative
    // (signed HDR differences) and distinct per pixel and channel, so a swap shows.
    for (size_t i = 0; i < img.pixels.size(); ++i)
        img.pixels[i] = float((i % 7 == 0 ? 1.6e9 : 1e-5) * double(i + 1) * (i % 5 == 3 ? -1.0 : 1.0));
    return img;
}
fs::path tempDir() {
    fs::path d = fs::temp_directory_path() / ("welkin-image-io-" + std::to_string(::getpid()));
    fs::create_directories(d);
    return d;
}
}  // namespace

TEST_CASE("built-in EXR: float channels round-trip exactly through the build's reader and its own", "[cpu][image]") {
    const fs::path dir = tempDir();
    for (int c : {1, 3, 4}) {
        const Image img = sample(5, 3, c);
        const std::string path = (dir / ("rt" + std::to_string(c) + ".exr")).string();
        REQUIRE(detail::writeExrUncompressed(img, path).empty());
        for (const Image& back : {detail::readExrUncompressed(path), readImage(path)}) {
            REQUIRE(back.width == 5);
            REQUIRE(back.height == 3);
            REQUIRE(back.channels == c);
            // 32-bit float in, 32-bit float out: bit-exact, so any channel or row mix-up fails.
            for (size_t i = 0; i < img.pixels.size(); ++i) REQUIRE(back.pixels[i] == img.pixels[i]);
        }
    }
    fs::remove_all(dir);
}

TEST_CASE("built-in EXR: damaged and unsupported files are refused with the path named", "[cpu][image]") {
    const fs::path dir = tempDir();
    const std::string path = (dir / "t.exr").string();
    REQUIRE(detail::writeExrUncompressed(sample(4, 4, 3), path).empty());
    std::string bytes;
    {
        std::ifstream in(path, std::ios::binary);
        bytes.assign(std::istreambuf_iterator<char>(in), {});
    }
    const std::string cut = (dir / "cut.exr").string();
    for (size_t keep : {size_t(3), size_t(40), bytes.size() / 2, bytes.size() - 1}) {
        std::ofstream(cut, std::ios::binary).write(bytes.data(), std::streamsize(keep));
        REQUIRE_THROWS_WITH(detail::readExrUncompressed(cut), Catch::Contains("cut.exr"));
    }
    // Compression other than NONE: a compressed file must not be misread as raw floats.
    std::string zipped = bytes;
    const size_t at = zipped.find("compression");
    REQUIRE(at != std::string::npos);
    zipped[at + std::string("compression").size() * 2 + 2 + 4] = 3;  // name\0 type\0 size -> value
    std::ofstream(cut, std::ios::binary).write(zipped.data(), std::streamsize(zipped.size()));
    REQUIRE_THROWS_WITH(detail::readExrUncompressed(cut), Catch::Contains("compression 3"));
    // More channels than an Image of 1 to 4 can hold are refused by the writer too.
    REQUIRE_FALSE(detail::writeExrUncompressed(sample(2, 2, 5), path).empty());
    fs::remove_all(dir);
}

TEST_CASE("writeImage: EXR keeps floats, PNG stores 8-bit codes, no temporary file is left", "[cpu][image]") {
    const fs::path dir = tempDir();
    Image img = sample(6, 2, 3);
    writeImage(img, (dir / "a.exr").string());
    const Image e = readImage((dir / "a.exr").string());
    for (size_t i = 0; i < img.pixels.size(); ++i) REQUIRE(e.pixels[i] == img.pixels[i]);
    for (size_t i = 0; i < img.pixels.size(); ++i) img.pixels[i] = float(i % 256) / 255.0f;
    writeImage(img, (dir / "a.png").string());
    const Image p = readImage((dir / "a.png").string());
    REQUIRE(p.channels == 3);
    // 8-bit codes k are written from round(v * 255) and read as k / 255: exact for v = k / 255.
    for (size_t i = 0; i < img.pixels.size(); ++i) REQUIRE(p.pixels[i] == Approx(img.pixels[i]).margin(1e-6));
    size_t files = 0;
    for (const auto& f : fs::directory_iterator(dir)) files += f.is_regular_file();
    REQUIRE(files == 2);
    fs::remove_all(dir);
}
