// Public headers are loader-free: the generated TUs public_headers_loader_free.cpp and
// public_headers_after_glad.cpp (tests/CMakeLists.txt) fail the build otherwise. This test checks
// that they include every public header that exists in the source tree now.
#include <catch2/catch.hpp>

#include <algorithm>
#include <filesystem>
#include <string>
#include <vector>

namespace welkin::test {
extern const std::vector<std::string> kCompiledPublicHeaders;
}

TEST_CASE("The loader-free header check includes every public header", "[cpu][headers]") {
    namespace fs = std::filesystem;
    const fs::path src = WELKIN_SOURCE_DIR;
    std::vector<fs::path> roots = {src / "engine/include"};
    for (const char* layer : {"generators", "skyelements"})
        for (auto& d : fs::directory_iterator(src / layer))
            if (fs::is_directory(d.path() / "include")) roots.push_back(d.path() / "include");
    std::vector<std::string> onDisk;
    for (auto& root : roots)
        for (auto& f : fs::recursive_directory_iterator(root))
            if (f.is_regular_file() && (f.path().extension() == ".hpp" || f.path().extension() == ".h"))
                onDisk.push_back(fs::relative(f.path(), root).generic_string());
    std::vector<std::string> compiled = welkin::test::kCompiledPublicHeaders;
    std::sort(onDisk.begin(), onDisk.end());
    std::sort(compiled.begin(), compiled.end());
    CHECK(onDisk.size() > 30);  // engine, astro, gl, generators and elements: far more than 30 headers today
    for (auto& h : onDisk) {
        INFO("public header " << h << " (re-run cmake if it was just added)");
        CHECK(std::binary_search(compiled.begin(), compiled.end(), h));
    }
    CHECK(compiled.size() == onDisk.size());
}
