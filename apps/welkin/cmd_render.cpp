// welkin render: one frame, headless, to an EXR (linear radiance, cd/m^2) or PNG (tone-mapped).
#include "command.hpp"
#include "scene_options.hpp"

#include <welkin/error.hpp>
#include <welkin/gl/context.hpp>
#include <welkin/image.hpp>
#include <welkin/keys.hpp>
#include <welkin/lighting.hpp>
#include <welkin/processor.hpp>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <unistd.h>

namespace welkin::cli {

namespace {

struct RenderOptions {
    SceneOptions scene;
    std::string out;
    std::string stats;
    std::string lighting;
    bool debug = false;
};

// Writes `text` to a temporary file beside `path` and returns its name (renamed by the caller).
std::string writeTemporary(const std::string& path, const std::string& text, const char* option) {
    namespace fs = std::filesystem;
    fs::path target(path);
    fs::path dir = target.parent_path().empty() ? fs::path(".") : target.parent_path();
    std::string tmp = (dir / ("." + target.filename().string() + ".tmp" + std::to_string(::getpid()))).string();
    std::ofstream f(tmp);
    if (f) f << text;
    if (!f || !f.flush()) {
        std::error_code ignored;
        fs::remove(tmp, ignored);
        throw Error(std::string(option) + " '" + path + "': write failed");
    }
    return tmp;
}


// The --lighting file: SkyLighting's values with their units and formulas written beside them.
nlohmann::json lightingJson(const SkyLighting& l, const std::string& time) {
    using nlohmann::json;
    auto v3 = [](const glm::dvec3& v) { return json::array({v.x, v.y, v.z}); };
    auto light = [&](const DirectionalLight& d) {
        return json{{"direction_enu", v3(d.directionEnu)},
                    {"illuminance_lux", d.illuminanceLux},
                    {"illuminance_rgb_lux", v3(d.illuminanceRgb)},
                    {"color_rgb", v3(d.colorRgb)}};
    };
    json sh = json::array();
    for (const glm::dvec3& e : l.sh9Irradiance()) sh.push_back(v3(e));
    const char* axes[6] = {"+E", "-E", "+N", "-N", "+U", "-U"};
    json axis = json::object();
    for (int a = 0; a < 6; ++a) axis[axes[a]] = v3(l.axisLights[size_t(a)]);
    json about = {
        {"frame", "directions are unit vectors in the observer's East-North-Up frame (x east, y north, z up)"},
        {"colors", "linear sRGB (D65); Y = 0.2126 r + 0.7152 g + 0.0722 b is the photometric quantity"},
        {"sun", "the Sun's light at the observer on a surface facing it: above the air x the atmosphere's transmittance x the clouds' "
                "x the part of its disk the Moon leaves (solar eclipse); illuminance_rgb_lux = illuminance_lux x color_rgb (color_rgb has luminance 1)"},
        {"moon", "the Moon's light at the observer (its phase and any lunar eclipse, then the atmosphere and the clouds), as for the Sun"},
        {"sh9_irradiance", "irradiance of the environment (sky, clouds, ground bounce; not the Sun's and Moon's disks) as 9 x RGB real "
                           "spherical-harmonic coefficients E_lm = A_l L_lm in lux, A = (pi, 2pi/3, pi/4) for l = 0, 1, 2, L_lm the "
                           "radiance's projection in cd/m^2 (lux/sr): E(n) = sum_lm E_lm Y_lm(n) lux on a surface of unit normal n. "
                           "Order and basis: Y00 = 0.282095, Y1-1 = 0.488603 y, Y10 = 0.488603 z, Y11 = 0.488603 x, Y2-2 = 1.092548 xy, "
                           "Y2-1 = 1.092548 yz, Y20 = 0.315392 (3z^2 - 1), Y21 = 1.092548 xz, Y22 = 0.546274 (x^2 - y^2)"},
        {"axis_lights", "SevenSky's six directional lights (lux): the environment's irradiance on a surface facing each axis, from the 16x16 "
                        "sky light map: sum over its texels on that side of L |d . axis| Omega; shade with sum D_axis max(n . axis, 0)"},
        {"ev100", "the exposure value at ISO 100 the tone map used (the eye's adaptation, or the manual setting)"},
        {"see", "docs/lighting.md"}};
    return json{{"about", about},
                {"time", time},
                {"sun", light(l.sun)},
                {"moon", light(l.moon)},
                {"sh9_irradiance", sh},
                {"axis_lights", axis},
                {"ev100", l.ev100}};
}

int run(const RenderOptions& o) {
    // Point sources as the eye sees them in a displayed PNG, physical in an EXR (docs/eye.md).
    SceneOptions scene = o.scene;
    scene.pointSources = endsWithIgnoringCase(o.out, ".exr") ? "physical" : "perceptual";
    // Validate everything before touching GL or the file system.
    scene.validate();
    checkRenderOutputPaths(o.out, o.stats, o.lighting);

    Logger log;
    auto ctx = gl::HeadlessContext::create({.debug = o.debug}, log);
    int status = 0;
    {
        SkyProcessor processor(SkyVars::earth(), log, ProcessorOptions{.timing = !o.stats.empty()});
        scene.apply(processor);
        if (!o.lighting.empty()) processor.vars().set(keys::lightingEnabled, true);  // sizes: lighting.* --var or defaults
        processor.renderFrame();
        Image img = endsWithIgnoringCase(o.out, ".exr") ? processor.readHdr() : processor.readToneMapped();
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
            statsTmp = writeTemporary(o.stats, j.dump(2) + "\n", "--stats");
        }
        std::string lightingTmp;
        if (!o.lighting.empty()) {
            try {
                lightingTmp = writeTemporary(o.lighting, lightingJson(processor.lighting(), processor.time().toIso()).dump(2) + "\n", "--lighting");
            } catch (...) {
                std::error_code ignored;
                if (!statsTmp.empty()) std::filesystem::remove(statsTmp, ignored);
                throw;
            }
        }
        namespace fs = std::filesystem;
        std::error_code ec, ignored;
        try {
            writeImage(img, o.out);
        } catch (...) {
            if (!statsTmp.empty()) fs::remove(statsTmp, ignored);
            if (!lightingTmp.empty()) fs::remove(lightingTmp, ignored);
            throw;
        }
        if (!lightingTmp.empty()) {
            fs::rename(lightingTmp, o.lighting, ec);
            if (ec) {
                std::string why = ec.message();
                fs::remove(lightingTmp, ignored);
                if (!statsTmp.empty()) fs::remove(statsTmp, ignored);
                fs::remove(o.out, ignored);
                throw Error("--lighting '" + o.lighting + "': " + why);
            }
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
    auto o = std::make_shared<RenderOptions>();  // the action below owns it
    o->scene.addTo(sub, true);
    sub.add_option("--out", o->out, "output image: .exr (float radiance, cd/m^2) or .png (tone-mapped)")->required();
    sub.add_option("--stats", o->stats, "write inputs, physical quantities and per-element costs as JSON");
    sub.add_option("--lighting", o->lighting, "turn SkyLighting on and write its values (Sun, Moon, SH irradiance, axis lights, EV100) as JSON (docs/lighting.md)");
    sub.add_flag("--gl-debug", o->debug, "create a debug GL context and log its messages");
    return [o]() { return run(*o); };
});

}  // namespace
}  // namespace welkin::cli
