// `welkin demo heritage`: the temple of Kalabsha and the church of Panagia Angeloktisti at Kiti
// at their real places and orientations, drawn by the host example's scene renderer
// (welkin_host_scene: one renderer for the host example and the demos) lit only by welkin's
// sky, at sunrise, noon, sunset and night of a date (default: the next equinox), inside and out,
// and the rising Sun seen along Kalabsha's axis on the day it lines up (docs/demos.md).
//
//   welkin demo heritage --out heritage                      # both sites, every view, 960x540
//   welkin demo heritage --site kalabsha --date 2027-10-20 --views noon,alignment --size 480x270 --out img
//
// Options: --site kalabsha|kiti|all, --date YYYY-MM-DD (default: the next equinox), --out DIR,
// --size WxH, --clouds none|fair|overcast, --views LIST, --assets DIR, --prefix TEXT (see --help).
// Images: DIR/<prefix><site>-<view>.png, each written to a temporary file and renamed.
//
// The models are glTF files made by apps/demos/heritage/make_heritage.py, found in --assets,
// else share/welkin/demos/heritage beside the installed command, else the source tree.
#include "command.hpp"
#include "heritage.hpp"

#include <welkin/error.hpp>
#include <welkin/gl/context.hpp>
#include <welkin/image.hpp>
#include <welkin/log.hpp>
#include <welkin/point_source.hpp>

#include <welkin_host/host_app.hpp>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

namespace {

namespace fs = std::filesystem;
using namespace welkin;
using namespace welkin::heritage;

struct Options {
    std::string site = "all";   ///< kalabsha, kiti or all
    std::string date;           ///< YYYY-MM-DD; empty: the next equinox after today (UTC)
    std::string out = "heritage";  ///< folder for the images, created if needed
    std::string size = "960x540";  ///< WxH, each in [16, 4096]
    std::string clouds = "none";   ///< none, fair, overcast
    std::string views = "all";     ///< comma-separated subset of kViews, or all
    std::string assets;            ///< folder of the glTF models; empty: found (see above)
    std::string prefix;            ///< put before each file name (<prefix><site>-<view>.png); no '/'
};

const std::vector<std::string> kViews = {"sunrise", "noon", "sunset", "night", "inside", "alignment"};

std::vector<std::string> parseViews(const std::string& text) {
    if (text == "all") return kViews;
    std::vector<std::string> out;
    std::stringstream ss(text);
    std::string v;
    while (std::getline(ss, v, ',')) {
        bool known = false;
        for (const auto& k : kViews) known = known || k == v;
        if (!known) throw Error("--views '" + text + "': '" + v + "' is not one of sunrise, noon, sunset, night, inside, alignment, all");
        out.push_back(v);
    }
    if (out.empty()) throw Error("--views is empty (give some of sunrise, noon, sunset, night, inside, alignment, or all)");
    return out;
}

std::string findAssets(const std::string& given) {
    std::vector<fs::path> candidates;
    if (!given.empty()) {
        candidates.push_back(given);
    } else {
        std::error_code ec;
        const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
        if (!ec) candidates.push_back(exe.parent_path().parent_path() / "share/welkin/demos/heritage");
        candidates.push_back(fs::path(WELKIN_SOURCE_DIR) / "apps/demos/heritage");
    }
    for (const auto& c : candidates) {
        bool all = true;
        for (const auto& s : sites()) all = all && fs::is_regular_file(c / s.modelFile);
        if (all) return c.string();
    }
    if (!given.empty()) throw Error("--assets '" + given + "' has no kalabsha.gltf and kiti.gltf (apps/demos/heritage, or make_heritage.py's output)");
    throw Error("the heritage models are not installed (share/welkin/demos/heritage) nor in the source tree; give --assets DIR");
}

UtcInstant nowUtc() {
    const std::time_t t = std::chrono::system_clock::to_time_t(std::chrono::system_clock::now());
    std::tm tm{};
    gmtime_r(&t, &tm);
    return UtcInstant::fromDateTime({tm.tm_year + 1900, tm.tm_mon + 1, tm.tm_mday, tm.tm_hour, tm.tm_min, double(std::min(tm.tm_sec, 59))});
}

struct Shot {
    std::string view;
    UtcInstant time;
    LocalView local;
    std::string what;
};

int run(const Options& o) {
    // Everything the user gives is checked before any rendering.
    int width = 0, height = 0;
    {
        char tail = 0;
        if (std::sscanf(o.size.c_str(), "%dx%d%c", &width, &height, &tail) != 2 || width < 16 || height < 16 || width > 4096 || height > 4096)
            throw Error("--size '" + o.size + "' must be WxH with W and H in [16, 4096]");
    }
    host::CloudCover clouds;
    try {
        clouds = host::parseCloudCover(o.clouds);
    } catch (const std::invalid_argument& e) {
        throw Error(e.what());
    }
    std::vector<const SiteInfo*> chosen;
    if (o.site == "all")
        for (const auto& s : sites()) chosen.push_back(&s);
    else
        chosen.push_back(&site(o.site));
    const std::vector<std::string> views = parseViews(o.views);
    Date date;
    if (o.date.empty()) {
        const UtcInstant now = nowUtc();
        const UtcInstant eq = nextEquinox(now);
        date = dateOf(eq);
        std::printf("date: %s, the %s equinox (%s), the next after today (%s)\n", date.iso().c_str(), date.month < 6 ? "March" : "September",
                    roundToSecond(eq).toIso().c_str(), dateOf(now).iso().c_str());
    } else {
        date = parseDate(o.date);
        std::printf("date: %s\n", date.iso().c_str());
    }
    if (o.prefix.find('/') != std::string::npos || o.prefix.find('\\') != std::string::npos)
        throw Error("--prefix '" + o.prefix + "' must be part of a file name (no '/')");
    const std::string assets = findAssets(o.assets);
    {
        std::error_code ec;
        fs::create_directories(o.out, ec);
        if (ec || !fs::is_directory(o.out)) throw Error("--out '" + o.out + "' is not a folder that can be created (" + ec.message() + ")");
        checkWritable((fs::path(o.out) / "heritage-check.png").string());
    }

    // The astronomy first: the times of every view, printed with the Sun's place.
    struct Plan {
        const SiteInfo* site;
        std::vector<Shot> shots;
    };
    std::vector<Plan> plans;
    for (const SiteInfo* s : chosen) {
        const astro::Site where = astroSite(*s);
        SunDay day = sunDay(*s, date);
        for (UtcInstant* t : {&day.sunrise, &day.noon, &day.sunset, &day.night}) *t = roundToSecond(*t);
        std::printf("%s: %.4f N %.4f E, %.0f m; axis azimuth %.1f deg\n", s->title.c_str(), s->latitudeDeg, s->longitudeDeg, s->heightM,
                    s->axisAzimuthDeg);
        std::printf("  %s (local mean solar day): sunrise %s, culmination %s, sunset %s, night %s\n", date.iso().c_str(),
                    day.sunrise.toIso().c_str(), day.noon.toIso().c_str(), day.sunset.toIso().c_str(), day.night.toIso().c_str());
        const Alignment al = alignmentDays(where, date.year, s->axisAzimuthDeg);
        const Sunrise* nearest = nullptr;
        for (const auto& d : al.days) {
            if (al.exact)
                std::printf("  the Sun rises along %s (azimuth %.1f deg) on %s (sunrise %s at azimuth %.2f deg)\n", s->axisName.c_str(),
                            s->axisAzimuthDeg, d.date.iso().c_str(), roundToSecond(d.time).toIso().c_str(), d.azimuthDeg);
            else
                std::printf("  the Sun never rises along %s (azimuth %.1f deg): sunrise azimuths in %d span [%.1f, %.1f] deg; closest on %s "
                            "(azimuth %.2f deg)\n",
                            s->axisName.c_str(), s->axisAzimuthDeg, date.year, al.minAzimuthDeg, al.maxAzimuthDeg, d.date.iso().c_str(),
                            d.azimuthDeg);
            // The alignment image shows the alignment day nearest to --date.
            const JulianDate day0 = UtcInstant::fromDateTime({date.year, date.month, date.day}).julianDate();
            if (!nearest || std::abs(daysBetween(d.time.julianDate(), day0)) < std::abs(daysBetween(nearest->time.julianDate(), day0)))
                nearest = &d;
        }
        Plan plan{s, {}};
        for (const auto& v : views) {
            if (v == "sunrise") plan.shots.push_back({v, day.sunrise, s->outside, "sunrise, outside"});
            else if (v == "noon") plan.shots.push_back({v, day.noon, s->outside, "the Sun's culmination, outside"});
            else if (v == "sunset") plan.shots.push_back({v, day.sunset, s->outside, "sunset, outside"});
            else if (v == "night") plan.shots.push_back({v, day.night, s->outside, "night (2 h after astronomical dusk), outside"});
            else if (v == "inside") plan.shots.push_back({v, day.noon, s->inside, "the culmination, inside"});
            else if (v == "alignment" && s->hasAlignmentView && nearest) {
                // The whole disk just clear of the horizon (its centre 0.5 deg up), minutes after sunrise.
                const UtcInstant t = roundToSecond(sunAtAltitude(where, nearest->date, 0.5));
                plan.shots.push_back({v, t, s->alignment, "the rising Sun along the axis on " + nearest->date.iso()});
            } else if (v == "alignment") {
                std::printf("  (no alignment image for %s: its day is stated above)\n", s->id.c_str());
            }
        }
        plans.push_back(std::move(plan));
    }

    Logger log;
    auto context = gl::HeadlessContext::create({}, log);
    for (const Plan& plan : plans) {
        const SiteInfo& s = *plan.site;
        host::AppOptions options;
        options.sceneFiles = {(fs::path(assets) / s.modelFile).string()};
        options.site = {s.latitudeDeg, s.longitudeDeg, s.heightM};
        options.clouds = clouds;
        options.shadows.halfExtentM = 150.0f;  // the buildings, sharper than the village's 400 m
        host::HostApp app(options, log);
        // Displayed images: the stars and planets as the eye sees them (docs/eye.md).
        app.sky().vars().set(keys::pointSources, std::string("perceptual"));
        for (const Shot& shot : plan.shots) {
            app.sky().setAnimationTime(0.0);  // deterministic: the same inputs give the same image
            app.sky().resetAdaptation();      // each view a cut: the eye adapted to it alone
            app.render(shot.time, camera(s, shot.local), width, height);
            const fs::path file = fs::path(o.out) / (o.prefix + s.id + "-" + shot.view + ".png");
            writeImage(app.readToneMapped(), file.string());  // a temporary file, then renamed
            const SunPosition p = sunPosition(s, shot.time);
            std::printf("%s  %s  Sun altitude %.2f deg, azimuth %.2f deg  (%s)\n", file.string().c_str(), shot.time.toIso().c_str(),
                        p.altitudeDeg, p.azimuthDeg, shot.what.c_str());
            std::printf("    welkin demo heritage --site %s --date %s --views %s --size %dx%d --clouds %s --out %s%s%s\n", s.id.c_str(),
                        date.iso().c_str(), shot.view.c_str(), width, height, o.clouds.c_str(), o.out.c_str(),
                        o.prefix.empty() ? "" : " --prefix ", o.prefix.c_str());
            std::fflush(stdout);
        }
    }
    return 0;
}

welkin::cli::DemoRegistrar reg("heritage", "Kalabsha and Kiti under welkin's sky: sunrise, noon, sunset, night, inside, the axis' sunrise",
                               [](CLI::App& sub) -> welkin::cli::Action {
                                   auto o = std::make_shared<Options>();
                                   sub.add_option("--site", o->site, "kalabsha, kiti or all (default all)");
                                   sub.add_option("--date", o->date, "YYYY-MM-DD, the local date (default: the next equinox)");
                                   sub.add_option("--out", o->out, "folder for the images, created if needed (default heritage)");
                                   sub.add_option("--size", o->size, "WxH pixels, each in [16, 4096] (default 960x540)");
                                   sub.add_option("--clouds", o->clouds, "none, fair or overcast (default none)");
                                   sub.add_option("--views", o->views,
                                                  "comma-separated: sunrise, noon, sunset, night, inside, alignment (Kalabsha), or all");
                                   sub.add_option("--assets", o->assets, "folder of kalabsha.gltf and kiti.gltf (default: found)");
                                   sub.add_option("--prefix", o->prefix, "text put before each image's name <site>-<view>.png");
                                   return [o]() { return run(*o); };
                               });

}  // namespace
