// welkin::cacheDirectory(): where the Mie and halo tables are cached, from the environment.
#include <welkin/cache.hpp>

#include <catch2/catch.hpp>

#include <cstdlib>
#include <optional>
#include <string>

namespace {
// Sets (or unsets) an environment variable for one scope, restoring it after.
struct EnvVar {
    std::string name;
    std::optional<std::string> old;
    EnvVar(std::string n, const char* value) : name(std::move(n)) {
        if (const char* o = std::getenv(name.c_str())) old = o;
        if (value) ::setenv(name.c_str(), value, 1);
        else ::unsetenv(name.c_str());
    }
    ~EnvVar() {
        if (old) ::setenv(name.c_str(), old->c_str(), 1);
        else ::unsetenv(name.c_str());
    }
};
}  // namespace

TEST_CASE("cacheDirectory: WELKIN_CACHE_DIR, then XDG_CACHE_HOME, then HOME", "[cpu][cache]") {
    EnvVar home("HOME", "/home/someone");
    {
        EnvVar xdg("XDG_CACHE_HOME", nullptr);
        EnvVar w("WELKIN_CACHE_DIR", nullptr);
        CHECK(welkin::cacheDirectory() == std::filesystem::path("/home/someone/.cache/welkin"));
    }
    {
        EnvVar xdg("XDG_CACHE_HOME", "/var/cache/user");
        EnvVar w("WELKIN_CACHE_DIR", nullptr);
        CHECK(welkin::cacheDirectory() == std::filesystem::path("/var/cache/user/welkin"));
        EnvVar w2("WELKIN_CACHE_DIR", "/tmp/welkin-tables");
        CHECK(welkin::cacheDirectory() == std::filesystem::path("/tmp/welkin-tables"));
    }
    {
        EnvVar xdg("XDG_CACHE_HOME", "");  // empty counts as unset (XDG base directory spec)
        EnvVar w("WELKIN_CACHE_DIR", "");
        CHECK(welkin::cacheDirectory() == std::filesystem::path("/home/someone/.cache/welkin"));
    }
}
