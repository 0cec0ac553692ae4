// welkin render: one frame, headless, to an EXR (linear radiance, cd/m^2) or PNG (tone-mapped).
#include "command.hpp"
#include "scene_options.hpp"

#include <welkin/error.hpp>
#include <welkin/gl/context.hpp>
#include <welkin/image.hpp>
#include <welkin/processor.hpp>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <unistd.h>

namespace welkin::cli {

namespace {

struct RenderOptions {
    SceneOptions scene;
    std::string out;
    std::string stats;
    bool debug = false;
};

// Checks that `path` can be created: its directory exists and is writable, it is not a
// directory, and an existing file there is writable.
void checkTextWritable(const std::string& path, const char* option) {
    namespace fs = std::filesystem;
    fs::path target(path);
    fs::path dir = target.parent_path().empty() ? fs::path(".") : target.parent_path();
    std::error_code ec;
    if (!fs::is_directory(dir, ec)) throw Error(std::string(option) + " '" + path + "': directory '" + dir.string() + "' does not exist");
    if (::access(dir.c_str(), W_OK) != 0) throw Error(std::string(option) + " '" + path + "': directory '" + dir.string() + "' is not writable");
    if (fs::is_directory(target, ec)) throw Error(std::string(option) + " '" + path + "' is a directory");
    if (fs::exists(target, ec) && ::access(path.c_str(), W_OK) != 0)
        throw Error(std::string(option) + " '" + path + "' exists and is not writable");
}

// Writes `text` to a temporary file beside `path` and returns its name (renamed by the caller).
std::string writeTemporary(const std::string& path, const std::string& text) {
    namespace fs = std::filesystem;
    fs::path target(path);
    fs::path dir = target.parent_path().empty() ? fs::path(".") : target.parent_path();
    std::string tmp = (dir / ("." + target.filename().string() + ".tmp" + std::to_string(::getpid()))).string();
    std::ofstream f(tmp);
    if (f) f << text;
    if (!f || !f.flush()) {
        std::error_code ignored;
        fs::remove(tmp, ignored);
        throw Error("--stats '" + path + "': write failed");
    }
    return tmp;
}

bool endsWith(std::string s, const std::string& ext) {
    std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    return s.size() >= ext.size() && s.compare(s.size() - ext.size(), ext.size(), ext) == 0;
}

int run(const RenderOptions& o) {
    // Validate everything before touching GL or the file system.
    o.scene.validate();
    checkWritable(o.out);
    if (!o.stats.empty()) {
        if (!endsWith(o.stats, ".json")) throw Error("--stats '" + o.stats + "' must end in .json");
        checkTextWritable(o.stats, "--stats");
    }

    Logger log;
    auto ctx = gl::HeadlessContext::create({.debug = o.debug}, log);
    int status = 0;
    {
        SkyProcessor processor(SkyVars::earth(), log, ProcessorOptions{.timing = !o.stats.empty()});
        o.scene.apply(processor);
        processor.renderFrame();
        Image img = endsWith(o.out, ".exr") ? processor.readHdr() : processor.readToneMapped();
        for (float v : img.pixels)
            if (!std::isfinite(v)) throw Error("render produced a non-finite pixel; nothing written");
        // The stats go to a temporary file first; the image is written (atomically) only when
        // they are safe, and the stats are renamed last, so a failure leaves neither file.
        std::string statsTmp;
        if (!o.stats.empty()) {
            nlohmann::json j = processor.stats();
            j["inputs"] = {{"time", o.scene.time},       {"lat_deg", o.scene.latDeg},       {"lon_deg", o.scene.lonDeg},
                           {"height_m", o.scene.heightM}, {"elements", o.scene.elementNames()}, {"projection", o.scene.projection},
                           {"size", o.scene.size},        {"exposure", o.scene.exposure},   {"quality", o.scene.quality},
                           {"out", o.out}};
            j["gl"] = ctx->description();
            statsTmp = writeTemporary(o.stats, j.dump(2) + "\n");
        }
        namespace fs = std::filesystem;
        std::error_code ec, ignored;
        try {
            writeImage(img, o.out);
        } catch (...) {
            if (!statsTmp.empty()) fs::remove(statsTmp, ignored);
            throw;
        }
        if (!statsTmp.empty()) {
            fs::rename(statsTmp, o.stats, ec);
            if (ec) {
                std::string why = ec.message();
                fs::remove(statsTmp, ignored);
                fs::remove(o.out, ignored);
                throw Error("--stats '" + o.stats + "': " + why);
            }
        }
        std::printf("%s\n", o.out.c_str());
    }
    return status;
}

Registrar reg("render", "render one frame headless to .exr (linear cd/m^2) or .png (tone-mapped sRGB)", [](CLI::App& sub) {
    auto* o = new RenderOptions();  // lives for the whole process
    o->scene.addTo(sub, true);
    sub.add_option("--out", o->out, "output image: .exr (float radiance, cd/m^2) or .png (tone-mapped)")->required();
    sub.add_option("--stats", o->stats, "write inputs, physical quantities and per-element costs as JSON");
    sub.add_flag("--gl-debug", o->debug, "create a debug GL context and log its messages");
    return [o]() { return run(*o); };
});

}  // namespace
}  // namespace welkin::cli
