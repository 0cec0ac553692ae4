// welkin demo education: the Moon, Mars and the planets over Malta on the night of 1-2 July 2018
// (Mars' great opposition was on 27 July), labelled with names and magnitudes, the bright stars
// named, the constellation figures, the ecliptic and the horizon grid (docs/demos.md).
//
//   welkin demo education --out shots --size 960x540                 # every scene, PNG each
//   welkin demo education --scenes jupiter-2300 --planet-scale 20    # one scene, planets x 20
//   welkin demo education --view                                     # the first scene, interactive
//
// Each scene is a `welkin render` (the same SceneOptions, applied the same way): the demo prints
// the path it wrote and the equivalent `welkin render` command line beneath it.
#include "command.hpp"
#include "scene_options.hpp"

#include <welkin/check.hpp>
#include <welkin/error.hpp>
#include <welkin/gl/context.hpp>
#include <welkin/image.hpp>
#include <welkin/processor.hpp>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <memory>
#include <sstream>
#include <string>
#include <unistd.h>
#include <vector>

namespace welkin::cli {

namespace {

// Valletta, Malta (the place of the design's scene); local time in July 2018 is CEST (UTC+2).
constexpr double kMaltaLatDeg = 35.90, kMaltaLonDeg = 14.51;
// The stars and the planets after the sky, so that their labels are written over it (each then
// applies the atmosphere's extinction itself; the Sky's light in front of a star is the same
// either way, and the Moon's opaque disk hides the little in front of it, < 1 % of its radiance).
constexpr const char* kElements = "nightsky,sky,stars,planet,constellations,grid";

struct EducationScene {
    const char* id;       // file name (id.png) and --scenes name
    const char* time;     // ISO 8601 with the local offset
    double azDeg, altDeg, fovDeg;  // view centre (azimuth from north through east), vertical field
    double ev100;         // manual exposure: darker with the Moon high (its aureole)
    const char* caption;  // what the scene shows
};

// Framed from `welkin astro --lat 35.90 --lon 14.51` at each instant (docs/demos.md lists the
// positions): at 23:00 the Moon (az 113, alt 3) and Mars (124, 6) rise in the south-east with
// Saturn higher (152, 26); at 01:00 they climb (Moon 133/23, Mars 146/23); at 04:00 they are in
// the south (Moon 179/38, Mars 192/30). Jupiter (213, 33 at 23:00) is in Libra, south-west.
const EducationScene kScenes[] = {
    {"moon-mars-2300", "2018-07-01T23:00:00+02:00", 125, 12, 40, -6, "23:00 CEST, south-east: the Moon and Mars rising, Saturn above them"},
    {"moon-mars-0100", "2018-07-02T01:00:00+02:00", 148, 22, 40, -4, "01:00 CEST, south-east: the Moon and Mars climbing along the ecliptic"},
    {"moon-mars-0400", "2018-07-02T04:00:00+02:00", 195, 25, 50, -4, "04:00 CEST, south: the Moon and Mars high before dawn, Saturn setting"},
    {"jupiter-2300", "2018-07-01T23:00:00+02:00", 215, 22, 50, -6, "23:00 CEST, south-west: Jupiter in Libra, between Spica and Antares"},
};

struct EducationOptions {
    std::string out = "welkin-education";
    std::string size = "1280x720";
    double planetScale = 1.0;        // planet.size_factor, [1, 100]
    double limitingMagnitude = 6.0;  // stars.magnitude_limit, [-2, 9]
    double starLabelMagnitude = 1.5; // stars.label_magnitude, [-2, 6]
    std::string scenes = "all";
    std::string exposure = "scene";  // manual EV100 for every scene, or each scene's own
    std::string quality = "medium";
    bool view = false;
};

std::vector<const EducationScene*> selectScenes(const std::string& list) {
    std::vector<const EducationScene*> out;
    std::string known;
    for (const EducationScene& s : kScenes) known += (known.empty() ? "" : ", ") + std::string(s.id);
    if (list == "all") {
        for (const EducationScene& s : kScenes) out.push_back(&s);
        return out;
    }
    std::stringstream ss(list);
    std::string item;
    while (std::getline(ss, item, ',')) {
        if (item.empty()) continue;
        const EducationScene* found = nullptr;
        for (const EducationScene& s : kScenes)
            if (item == s.id) found = &s;
        if (!found) throw Error("--scenes: unknown scene '" + item + "' (accepted: all, " + known + ")");
        bool seen = false;
        for (auto* s : out) seen = seen || s == found;
        if (!seen) out.push_back(found);
    }
    if (out.empty()) throw Error("--scenes: empty list (accepted: all, " + known + ")");
    return out;
}

std::string number(double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%g", v);
    return buf;
}

// The scene as `welkin render` options.
SceneOptions sceneOptions(const EducationScene& s, const EducationOptions& o) {
    const double ev = o.exposure == "scene" ? s.ev100 : std::stod(o.exposure);
    const double white = 1.2 * std::exp2(ev);  // cd/m^2 the tone map shows as white
    int w = 0, h = 0;
    parseSize(o.size, "--size", w, h);
    // Labels of at least 12 px: DejaVu's hyphen (the minus of "-2.2") vanishes at 11 px.
    const double labelPx = std::max(12.0, std::round(std::min(w, h) / 45.0));
    SceneOptions so;
    so.time = s.time;
    so.latDeg = kMaltaLatDeg;
    so.lonDeg = kMaltaLonDeg;
    so.elements = kElements;
    so.elementsGiven = true;
    so.azDeg = s.azDeg;
    so.altDeg = s.altDeg;
    so.fovDeg = s.fovDeg;
    so.size = o.size;
    so.exposure = number(ev);
    so.quality = o.quality;
    so.vars = {"planet.bodies=moon,mercury,venus,mars,jupiter,saturn",  // the naked-eye planets
               "planet.labels=true",
               "planet.label_magnitude=true",
               "planet.size_factor=" + number(o.planetScale),
               "stars.labels=true",
               "stars.label_magnitude=" + number(o.starLabelMagnitude),
               "stars.magnitude_limit=" + number(o.limitingMagnitude),
               "grid.ecliptic=true",
               // The overlay at fractions of the exposure's white (1.2 x 2^EV100 cd/m^2): names at
               // white, the grid dimmer than the figures (0.6, their default) so they stand apart.
               "planet.label_luminance_cd_m2=" + number(white),
               "stars.label_luminance_cd_m2=" + number(white),
               "constellations.label_luminance_cd_m2=0",
               "constellations.line_luminance_cd_m2=0",
               "grid.luminance_cd_m2=" + number(0.45 * white),
               "planet.label_size_px=" + number(labelPx),
               "stars.label_size_px=" + number(labelPx)};
    return so;
}

// The arguments a `welkin render` / `welkin view` needs for the scene (after the subcommand).
std::vector<std::string> sceneArguments(const SceneOptions& so) {
    std::vector<std::string> a = {"--time", so.time, "--lat", number(so.latDeg), "--lon", number(so.lonDeg),
                                  "--elements", so.elements, "--az", number(so.azDeg), "--alt", number(so.altDeg),
                                  "--fov", number(so.fovDeg), "--size", so.size};
    a.insert(a.end(), {"--exposure", so.exposure});
    if (so.quality != "medium") a.insert(a.end(), {"--quality", so.quality});
    for (const std::string& v : so.vars) a.insert(a.end(), {"--var", v});
    return a;
}

// Quotes an argument for a POSIX shell when it needs it.
std::string shellQuote(const std::string& s) {
    bool plain = !s.empty();
    for (char c : s) plain = plain && (std::isalnum(static_cast<unsigned char>(c)) || std::string("-_.,:/=+@%").find(c) != std::string::npos);
    if (plain) return s;
    std::string q = "'";
    for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
    return q + "'";
}

void validate(const EducationOptions& o) {
    int w = 0, h = 0;
    parseSize(o.size, "--size", w, h);
    welkin::checkRange("", "--planet-scale", o.planetScale, 1, 100);
    welkin::checkRange("", "--limiting-magnitude", o.limitingMagnitude, -2, 9);
    welkin::checkRange("", "--star-label-magnitude", o.starLabelMagnitude, -2, 6);
    if (o.exposure != "scene") {
        char* end = nullptr;
        const double ev = std::strtod(o.exposure.c_str(), &end);
        if (end == o.exposure.c_str() || *end != '\0') throw Error("--exposure '" + o.exposure + "' is neither an EV100 number nor scene");
        welkin::checkRange("", "--exposure", ev, -20, 30);
    }
    if (o.out.empty()) throw Error("--out: empty directory name");
}

int runView(const EducationOptions& o, const EducationScene& s) {
    const SceneOptions so = sceneOptions(s, o);
    so.validate();
    std::vector<std::string> args = {"welkin", "view"};
    for (std::string& a : sceneArguments(so)) args.push_back(std::move(a));
    std::string line;
    for (size_t i = 0; i < args.size(); ++i) line += (i ? " " : "") + shellQuote(args[i]);
    std::printf("%s\n", line.c_str());
    std::fflush(stdout);
    std::vector<char*> argv;
    for (std::string& a : args) argv.push_back(a.data());
    argv.push_back(nullptr);
    ::execv("/proc/self/exe", argv.data());
    throw Error(std::string("--view: cannot start the viewer (/proc/self/exe): ") + std::strerror(errno));
}

int run(const EducationOptions& o) {
    validate(o);
    const std::vector<const EducationScene*> scenes = selectScenes(o.scenes);
    std::vector<SceneOptions> options;
    for (const EducationScene* s : scenes) {
        options.push_back(sceneOptions(*s, o));
        options.back().validate();
    }
    if (o.view) return runView(o, *scenes.front());

    namespace fs = std::filesystem;
    std::error_code ec;
    if (fs::exists(o.out, ec) && !fs::is_directory(o.out, ec)) throw Error("--out '" + o.out + "' exists and is not a directory");
    fs::create_directories(o.out, ec);
    if (ec) throw Error("--out '" + o.out + "': cannot create the directory: " + ec.message());
    std::vector<std::string> paths;
    for (const EducationScene* s : scenes) {
        paths.push_back((fs::path(o.out) / (std::string(s->id) + ".png")).string());
        checkWritable(paths.back());
    }

    Logger log;
    auto ctx = gl::HeadlessContext::create({}, log);
    for (size_t i = 0; i < scenes.size(); ++i) {
        SkyProcessor processor(SkyVars::earth(), log);
        options[i].apply(processor);
        processor.renderFrame();
        Image img = processor.readToneMapped();
        for (float v : img.pixels)
            if (!std::isfinite(v)) throw Error(std::string("scene ") + scenes[i]->id + ": a non-finite pixel; nothing written");
        writeImage(img, paths[i]);  // a temporary file beside it, renamed
        std::string cmd = "welkin render";
        for (const std::string& a : sceneArguments(options[i])) cmd += " " + shellQuote(a);
        cmd += " --out " + shellQuote(paths[i]);
        std::printf("%s\n  %s\n  %s\n", paths[i].c_str(), scenes[i]->caption, cmd.c_str());
        std::fflush(stdout);
    }
    return 0;
}

DemoRegistrar reg("education", "the Moon, Mars and the planets over Malta, 1-2 July 2018, labelled, with star names, figures, the ecliptic",
                  [](CLI::App& sub) {
    auto o = std::make_shared<EducationOptions>();  // the action below owns it
    std::string ids;
    for (const EducationScene& s : kScenes) ids += (ids.empty() ? "" : ", ") + std::string(s.id);
    sub.add_option("--out", o->out, "directory for the images (created if missing; each written atomically)")->capture_default_str();
    sub.add_option("--size", o->size, "image size WIDTHxHEIGHT, each in [1, 16384]")->capture_default_str();
    sub.add_option("--planet-scale", o->planetScale, "enlargement of the Moon and planets' disks, [1, 100] (planet.size_factor)")->capture_default_str();
    sub.add_option("--limiting-magnitude", o->limitingMagnitude, "faintest stars drawn, mag [-2, 9] (stars.magnitude_limit; the sky's own limit applies too)")
        ->capture_default_str();
    sub.add_option("--star-label-magnitude", o->starLabelMagnitude, "name the stars at least this bright, mag [-2, 6] (stars.label_magnitude)")
        ->capture_default_str();
    sub.add_option("--scenes", o->scenes, "comma list of scenes, or all (" + ids + ")")->capture_default_str();
    sub.add_option("--exposure", o->exposure, "manual exposure EV100 in [-20, 30] for every scene, or scene (each its own: -6, or -4 with the Moon high); labels and lines follow its white")
        ->capture_default_str();
    sub.add_option("--quality", o->quality, "low | medium | high | reference")->capture_default_str();
    sub.add_flag("--view", o->view, "open the first selected scene in the interactive viewer (welkin view) instead of writing images");
    return [o]() { return run(*o); };
});

}  // namespace
}  // namespace welkin::cli
