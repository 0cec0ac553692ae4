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

void writeTextAtomically(const std::string& path, const std::string& text) {
    namespace fs = std::filesystem;
    fs::path target(path);
    fs::path dir = target.parent_path().empty() ? fs::path(".") : target.parent_path();
    std::error_code ec;
    if (!fs::is_directory(dir, ec)) throw Error("--stats '" + path + "': directory '" + dir.string() + "' does not exist");
    std::string tmp = (dir / ("." + target.filename().string() + ".tmp" + std::to_string(::getpid()))).string();
    {
        std::ofstream f(tmp);
        if (!f) throw Error("--stats '" + path + "': cannot write in '" + dir.string() + "'");
        f << text;
        if (!f.flush()) {
            fs::remove(tmp, ec);
            throw Error("--stats '" + path + "': write failed");
        }
    }
    fs::rename(tmp, target, ec);
    if (ec) {
        fs::remove(tmp, ec);
        throw Error("--stats '" + path + "': " + ec.message());
    }
}

bool endsWith(std::string s, const std::string& ext) {
    std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    return s.size() >= ext.size() && s.compare(s.size() - ext.size(), ext.size(), ext) == 0;
}

int run(const RenderOptions& o) {
    // Validate everything before touching GL or the file system.
    o.scene.validate();
    checkWritable(o.out);
    if (!o.stats.empty() && !endsWith(o.stats, ".json")) throw Error("--stats '" + o.stats + "' must end in .json");

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
        writeImage(img, o.out);
        if (!o.stats.empty()) {
            nlohmann::json j = processor.stats();
            j["inputs"] = {{"time", o.scene.time},       {"lat_deg", o.scene.latDeg},       {"lon_deg", o.scene.lonDeg},
                           {"height_m", o.scene.heightM}, {"elements", o.scene.elementNames()}, {"projection", o.scene.projection},
                           {"size", o.scene.size},        {"exposure", o.scene.exposure},   {"quality", o.scene.quality},
                           {"out", o.out}};
            j["gl"] = ctx->description();
            writeTextAtomically(o.stats, j.dump(2) + "\n");
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
