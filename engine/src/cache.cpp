#include <welkin/cache.hpp>

#include <cstdlib>

namespace welkin {

std::filesystem::path cacheDirectory() {
    if (const char* w = std::getenv("WELKIN_CACHE_DIR"); w && *w) return std::filesystem::path(w);
    if (const char* x = std::getenv("XDG_CACHE_HOME"); x && *x) return std::filesystem::path(x) / "welkin";
    if (const char* h = std::getenv("HOME"); h && *h) return std::filesystem::path(h) / ".cache" / "welkin";
    return std::filesystem::temp_directory_path() / "welkin";
}

}  // namespace welkin
