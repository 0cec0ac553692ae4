// `welkin render --out/--stats/--lighting` path handling (apps/welkin/output_paths.hpp
// checkRenderOutputPaths): the input is split at its first two NUL bytes into the three paths.
// Only file-system queries are made (nothing is written). An accepted set names an image file,
// .json files, and never the same file twice.
#include "fuzz_common.hpp"

#include <output_paths.hpp>

#include <filesystem>

using namespace welkin;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    const std::string all = fuzz::text(data, size);
    const size_t a = all.find('\0');
    const size_t b = a == std::string::npos ? std::string::npos : all.find('\0', a + 1);
    const std::string out = all.substr(0, a);
    const std::string stats = a == std::string::npos ? std::string() : all.substr(a + 1, b == std::string::npos ? std::string::npos : b - a - 1);
    const std::string lighting = b == std::string::npos ? std::string() : all.substr(b + 1);
    if (!fuzz::accepts([&] { cli::checkRenderOutputPaths(out, stats, lighting); }, false)) return 0;
    FUZZ_CHECK(!out.empty());
    if (!stats.empty()) FUZZ_CHECK(cli::endsWithIgnoringCase(stats, ".json"));
    if (!lighting.empty()) FUZZ_CHECK(cli::endsWithIgnoringCase(lighting, ".json"));
    if (!stats.empty() && !lighting.empty()) {
        std::error_code e1, e2;
        const auto c1 = std::filesystem::weakly_canonical(std::filesystem::absolute(stats, e1), e1);
        const auto c2 = std::filesystem::weakly_canonical(std::filesystem::absolute(lighting, e2), e2);
        if (!e1 && !e2) FUZZ_CHECK(c1 != c2);
    }
    return 0;
}
