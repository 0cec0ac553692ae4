// Regression tests for what the libFuzzer targets (tests/fuzz, docs/fuzzing.md) found: each
// input that crashed a parser, tripped a sanitizer or broke a target's property is kept in
// tests/fuzz/regressions/<target>/ (scripts/fuzz.sh replays them too) or written inline here, and
// must now be answered with a one-line welkin::Error (or parsed correctly).
#include <catch2/catch.hpp>

#include "error_of.hpp"

#include <output_paths.hpp>
#include <welkin/astro/stars.hpp>
#include <welkin/astro/vsop87.hpp>
#include <welkin/error.hpp>
#include <welkin/image.hpp>

#include <filesystem>
#include <fstream>
#include <sstream>

using namespace welkin;

namespace {
std::string regressionInput(const std::string& target, const std::string& name) {
    const std::string path = std::string(WELKIN_SOURCE_DIR) + "/tests/fuzz/regressions/" + target + "/" + name;
    std::ifstream in(path, std::ios::binary);
    REQUIRE(in.good());  // the input is kept in the repository: missing is a failure, not a skip
    std::ostringstream ss;
    ss << in.rdbuf();
    return ss.str();
}
using test::errorOf;
}  // namespace

TEST_CASE("fuzz regression: kstars binary file whose field table runs past its end", "[cpu][fuzz]") {
    // Found by fuzz_kstars_binary: a field count larger than the file made the field-name read
    // start beyond the end (std::length_error out of the parser, an uncaught exception).
    const std::string bytes = regressionInput("fuzz_kstars_binary", "field_table_past_eof");
    REQUIRE(bytes.size() == 269);  // the file as found: header and a few bytes of field table
    const std::string e = errorOf([&] { astro::parseKStarsBinaryStars(bytes, "named.dat"); });
    CHECK(e.rfind("named.dat: truncated in the field table", 0) == 0);
    CHECK(e.find('\n') == std::string::npos);
}

TEST_CASE("fuzz regression: --lighting and --stats naming one file two ways", "[cpu][fuzz]") {
    // Found while writing fuzz_output_paths (its property: never the same file twice): the
    // check compared the texts, so "d/a.json" and "d/./a.json" both passed and the two outputs
    // overwrote each other.
    namespace fs = std::filesystem;
    const fs::path dir = fs::temp_directory_path() / "welkin-fuzz-regression-paths";
    fs::create_directories(dir / "sub");
    const std::string out = (dir / "sky.png").string(), a = (dir / "a.json").string();
    CHECK(errorOf([&] { cli::checkRenderOutputPaths(out, a, (dir / "." / "a.json").string()); }).find("is also the --stats file") !=
          std::string::npos);
    CHECK(errorOf([&] { cli::checkRenderOutputPaths(out, a, (dir / "sub" / ".." / "a.json").string()); }).find("is also the --stats file") !=
          std::string::npos);
    // Two different files, and the texts that were always refused, keep their answers.
    CHECK(errorOf([&] { cli::checkRenderOutputPaths(out, a, (dir / "b.json").string()); }) == "(no error)");
    CHECK(errorOf([&] { cli::checkRenderOutputPaths(out, a, a); }).find("is also the --stats file") != std::string::npos);
    CHECK(errorOf([&] { cli::checkRenderOutputPaths(out, a, (dir / "b.txt").string()); }).find("--lighting") == 0);
    fs::remove_all(dir);
}

TEST_CASE("fuzz regression: star catalogue numbers beyond an int or a float", "[cpu][fuzz]") {
    // Found by running fuzz_star_catalogues on hand-made variants of its seeds: a HYG hip of
    // 1e20 was converted to int (undefined behaviour, UBSan), and a kstars proper motion of
    // 9e300 mas/yr became an infinite float in an accepted star.
    const std::string hyg = regressionInput("fuzz_star_catalogues", "hyg_hip_1e20").substr(1);  // byte 0 picks the parser
    CHECK(errorOf([&] { astro::parseHygCsv(hyg, "hyg.csv"); }).rfind("hyg.csv:2: hip", 0) == 0);
    const std::string kstars = regressionInput("fuzz_star_catalogues", "kstars_pm_overflows_float").substr(1);
    CHECK(errorOf([&] { astro::parseKStarsCatalogue(kstars, "stars.dat"); }).rfind("stars.dat:1: pmRA", 0) == 0);
    // The real values still parse: Sirius (kstars line) and HIP 32349 as a whole number.
    const auto sirius = astro::parseKStarsCatalogue("064508.92 -164258.0 -000546.0-001223.100379.2 -1.4400.01A0 1\n", "k");
    REQUIRE(sirius.size() == 1);
    CHECK(sirius[0].pmRaMasPerYear == Approx(-546.0f));
    const auto h = astro::parseHygCsv("ra,dec,hip,hd\n6.752481,-16.716116,32349,48915\n", "h");
    REQUIRE(h.size() == 1);
    CHECK(h[0].hip == 32349);
    CHECK(h[0].hd == 48915);
    CHECK(errorOf([&] { astro::parseHygCsv("ra,dec,hip\n1,2,-3\n", "h"); }).find("not a catalogue number") != std::string::npos);
}

TEST_CASE("fuzz regression: VSOP87 terms whose phase or frequency overflow the evaluation", "[cpu][fuzz]") {
    // Found by fuzz_vsop87 (found_huge_frequency: a C of ~1e100 on line 2, in a 120 s run) and
    // hand-made variants of its seeds: B or C of 1e300 was accepted and the series evaluated to
    // NaN (the planets' positions, then the image).
    for (const char* name : {"phase_1e300", "frequency_1e300"}) {
        const std::string text = regressionInput("fuzz_vsop87", name);
        CHECK(errorOf([&] { astro::parseVsop87Series(text, "x.vsop"); }).find("x.vsop:1: term out of range") != std::string::npos);
    }
    const std::string found = regressionInput("fuzz_vsop87", "found_huge_frequency");
    CHECK(errorOf([&] { astro::parseVsop87Series(found, "x.vsop"); }).find("x.vsop:2: term out of range") != std::string::npos);
    // A real term (the first of earth.L0) is kept.
    const auto terms = astro::parseVsop87Series("1.75347045673 0.00000000000 0.00000000000\n4.0 1.0 1e5\n", "earth.L0.vsop");
    REQUIRE(terms.size() == 2);
    CHECK(terms[0].a == 4.0);  // sorted by decreasing |A|
}

TEST_CASE("fuzz regression: a truncated PNG's error is one line", "[cpu][fuzz]") {
    // Found by fuzz_image_load (its property: errors are one line): OpenImageIO's message for a
    // PNG cut short spans lines, and readImage passed it on as it was.
    namespace fs = std::filesystem;
    const std::string bytes = regressionInput("fuzz_image_load", "png_multiline_error");
    REQUIRE(bytes[0] == 1);  // byte 0 picked the extension: .png
    const fs::path path = fs::temp_directory_path() / "welkin-fuzz-regression-truncated.png";
    {
        std::ofstream out(path, std::ios::binary);
        out.write(bytes.data() + 1, std::streamsize(bytes.size() - 1));
    }
    const std::string e = errorOf([&] { readImage(path.string()); });
    fs::remove(path);
    CHECK(e.rfind("readImage('", 0) == 0);
    CHECK(e.find('\n') == std::string::npos);
    CHECK(e.find('\r') == std::string::npos);
}
