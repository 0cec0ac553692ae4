#include "output_paths.hpp"

#include <welkin/error.hpp>
#include <welkin/image.hpp>

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <unistd.h>

namespace welkin::cli {

namespace fs = std::filesystem;

bool endsWithIgnoringCase(std::string path, const std::string& ext) {
    std::transform(path.begin(), path.end(), path.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    return path.size() >= ext.size() && path.compare(path.size() - ext.size(), ext.size(), ext) == 0;
}

void checkFileWritable(const std::string& path, const char* option) {
    const fs::path target(path);
    const fs::path dir = target.parent_path().empty() ? fs::path(".") : target.parent_path();
    std::error_code ec;
    if (!fs::is_directory(dir, ec)) throw Error(std::string(option) + " '" + path + "': directory '" + dir.string() + "' does not exist");
    if (::access(dir.c_str(), W_OK) != 0) throw Error(std::string(option) + " '" + path + "': directory '" + dir.string() + "' is not writable");
    if (fs::is_directory(target, ec)) throw Error(std::string(option) + " '" + path + "' is a directory");
    if (fs::exists(target, ec) && ::access(path.c_str(), W_OK) != 0)
        throw Error(std::string(option) + " '" + path + "' exists and is not writable");
}

namespace {
// The same file named two ways ("a.json", "./a.json", "d/../a.json", a link to it).
bool sameFile(const std::string& a, const std::string& b) {
    if (a == b) return true;
    std::error_code ea, eb;
    const fs::path ca = fs::weakly_canonical(fs::absolute(a, ea), ea), cb = fs::weakly_canonical(fs::absolute(b, eb), eb);
    return !ea && !eb && ca == cb;
}
}  // namespace

void checkRenderOutputPaths(const std::string& out, const std::string& stats, const std::string& lighting) {
    checkWritable(out);
    if (!stats.empty()) {
        if (!endsWithIgnoringCase(stats, ".json")) throw Error("--stats '" + stats + "' must end in .json");
        checkFileWritable(stats, "--stats");
    }
    if (!lighting.empty()) {
        if (!endsWithIgnoringCase(lighting, ".json")) throw Error("--lighting '" + lighting + "' must end in .json");
        checkFileWritable(lighting, "--lighting");
        if (!stats.empty() && sameFile(lighting, stats)) throw Error("--lighting '" + lighting + "' is also the --stats file ('" + stats + "')");
    }
}

}  // namespace welkin::cli
