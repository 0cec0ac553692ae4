// welkin bench display: the frames `welkin view` displays (render, tone map, present) side by side
// with Stellarium's in the same run, and the frame budget per element (docs/BENCHMARKS.md, section
// "Displayed frames"; issue 22).
//
//   xvfb-run -a -s '-screen 0 1920x1080x24' build/bin/welkin bench display
//
// Side by side: for each scene and time rate, `welkin view --no-panel` and (where installed)
// Stellarium run in turn under the X server of DISPLAY at 1280x720, in alternation (welkin,
// Stellarium, welkin, Stellarium, ...: load drifts fall on both), each with the swap-timing shim
// preloaded (apps/frame_shim/swap_timer_shim.c: a CLOCK_MONOTONIC time per glXSwapBuffers /
// eglSwapBuffers). After a warm-up from its first presented frame, the frames presented in a
// fixed window are counted (frame_times.hpp); the program is then ended. Stellarium is driven by
// a startup script (.ssc) in a private user directory: place, date, view, atmosphere and Milky Way
// on, GUI hidden, its frame-rate limits raised so that it draws as fast as it can (as welkin does).
//
// Frame budget: each scene rendered headless (EGL) at 1280x720 and 1920x1080 with the processor's
// glFinish-bracketed timing (as `welkin render --stats`); each element's update + render, the tone
// map and the whole frame as ratios to a trivial fullscreen pass timed alternately with them.
#include "bench_util.hpp"
#include "command.hpp"
#include "frame_times.hpp"
#include "scene_options.hpp"

#include <welkin/error.hpp>
#include <welkin/gl/context.hpp>
#include <welkin/keys.hpp>
#include <welkin/processor.hpp>

#include <epoxy/gl.h>
#include <nlohmann/json.hpp>

#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <memory>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include <fcntl.h>
#include <sys/wait.h>
#include <unistd.h>

namespace welkin::cli {
namespace {

/// One of the fixed views (Malta, looking south 30 degrees up with a 60 degree vertical field).
struct DisplayScene {
    const char* name;
    const char* time;  // UTC, ISO 8601
    const char* what;
};

/// The four scenes of issue 22 (sun and moon positions from `welkin astro`).
const std::vector<DisplayScene>& displayScenes() {
    static const std::vector<DisplayScene> s = {
        {"day", "2026-06-21T10:00:00Z", "midsummer noon (local 12:00), Sun 71 deg up in the south-east, above the field"},
        {"twilight", "2026-08-12T18:10:00Z", "civil twilight, Sun 3.4 deg below the horizon in the west-north-west"},
        {"moonlit", "2026-08-26T21:00:00Z", "night, a 98 % lit Moon 35 deg up at azimuth 160 deg, in the field"},
        {"moonless", "2026-08-12T22:00:00Z", "night, new Moon (the issue's reference view)"},
    };
    return s;
}

/// The options of `welkin bench display`, checked by validate() (one-line errors naming the option).
struct DisplayBenchOptions {
    double seconds = 10;              ///< counted window per run, s [1, 600]
    double warmup = 5;                ///< discarded after each program's first presented frame, s [0, 600]
    int rounds = 2;                   ///< welkin/Stellarium alternations per scene and rate [1, 20]
    std::string scenes = "day,twilight,moonlit,moonless";  ///< comma list of displayScenes() names
    std::string rates = "0,1";        ///< comma list of time rates, simulated s per real s, each in [0, 1e5]
    std::string size = "1280x720";    ///< window size of the side-by-side runs
    std::string budgetSizes = "1280x720,1920x1080";  ///< frame-budget sizes; "none": skip the budget
    int budgetFrames = 7;             ///< timed frames per budget measurement [1, 1000]
    std::string stellarium = "auto";  ///< auto (PATH), off, or the program's path
    double startTimeout = 300;        ///< longest wait for a program's first frame, s [10, 3600]
    std::string out = "docs/BENCHMARKS.md";  ///< its section from "<!-- welkin bench display -->" is rewritten; "" none
    std::string readme = "README.md";         ///< its table between the display markers is rewritten; "" none
    bool sideBySide = true;           ///< false (--no-side-by-side): the budget only, no X display needed
    std::vector<std::string> vars;    ///< --var KEY=VALUE for welkin's side (view and budget), e.g. an A/B of a key

    std::vector<DisplayScene> sceneList;  ///< filled by validate()
    std::vector<double> rateList;         ///< filled by validate()
    int width = 0, height = 0;
    std::vector<std::pair<int, int>> budgetSizeList;

    void validate();
};

std::vector<std::string> splitComma(const std::string& s) {
    std::vector<std::string> out;
    std::stringstream ss(s);
    std::string item;
    while (std::getline(ss, item, ',')) out.push_back(item);
    return out;
}

std::string fmt(double v, int digits) {
    char b[64];
    std::snprintf(b, sizeof b, "%.*f", digits, v);
    return b;
}

void DisplayBenchOptions::validate() {
    auto range = [](const char* opt, double v, double lo, double hi) {
        char b[160];
        std::snprintf(b, sizeof b, "%s %g not in [%g, %g]", opt, v, lo, hi);
        if (!(v >= lo && v <= hi)) throw Error(b);
    };
    range("--seconds", seconds, 1, 600);
    range("--warmup", warmup, 0, 600);
    range("--rounds", rounds, 1, 20);
    range("--budget-frames", budgetFrames, 1, 1000);
    range("--start-timeout", startTimeout, 10, 3600);
    sceneList.clear();
    for (const std::string& n : splitComma(scenes)) {
        bool found = false;
        for (const DisplayScene& s : displayScenes())
            if (n == s.name) sceneList.push_back(s), found = true;
        if (!found) throw Error("--scenes '" + n + "' is not one of day, twilight, moonlit, moonless");
    }
    if (sceneList.empty()) throw Error("--scenes is empty: give some of day, twilight, moonlit, moonless");
    rateList.clear();
    for (const std::string& r : splitComma(rates)) {
        char* end = nullptr;
        const double v = std::strtod(r.c_str(), &end);
        if (r.empty() || *end || !(v >= 0 && v <= 1e5)) throw Error("--rates '" + r + "' is not a time rate in [0, 1e5]");
        rateList.push_back(v);
    }
    if (rateList.empty()) throw Error("--rates is empty: give time rates in [0, 1e5] (0: time stopped)");
    parseSize(size, "--size", width, height);
    budgetSizeList.clear();
    if (budgetSizes != "none")
        for (const std::string& z : splitComma(budgetSizes)) {
            int w = 0, h = 0;
            parseSize(z, "--budget-sizes", w, h);
            budgetSizeList.push_back({w, h});
        }
    if (stellarium != "auto" && stellarium != "off" && access(stellarium.c_str(), X_OK) != 0)
        throw Error("--stellarium '" + stellarium + "' is not auto, off or an executable");
    for (const auto& [opt, path] : {std::pair{"--out", out}, std::pair{"--readme", readme}})
        if (!path.empty() && !std::filesystem::is_regular_file(path))
            throw Error(std::string(opt) + " '" + path + "' is not an existing file (its display section is rewritten; '' for none)");
}

constexpr const char* kLat = "35.9";
constexpr const char* kLon = "14.5";
constexpr const char* kHeightM = "50";
constexpr const char* kMarker = "<!-- welkin bench display -->";
constexpr const char* kGenerated = "<!-- welkin bench display: generated -->";
constexpr const char* kReadmeBegin = "<!-- welkin bench display: readme begin -->";
constexpr const char* kReadmeEnd = "<!-- welkin bench display: readme end -->";

std::string findOnPath(const std::string& name) {
    const char* path = std::getenv("PATH");
    std::stringstream ss(path ? path : "");
    std::string dir;
    while (std::getline(ss, dir, ':')) {
        const std::string p = (dir.empty() ? "." : dir) + "/" + name;
        if (access(p.c_str(), X_OK) == 0) return p;
    }
    return "";
}

std::string readFile(const std::string& path) {
    std::ifstream f(path, std::ios::binary);
    return std::string((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
}

void writeFileAtomically(const std::string& path, const std::string& text, const char* option) {
    const std::filesystem::path target(path);
    const std::filesystem::path tmp = target.parent_path() / ("." + target.filename().string() + ".display.tmp");
    {
        std::ofstream f(tmp, std::ios::binary);
        f << text;
        f.close();
        if (!f) throw Error(std::string(option) + " '" + path + "': cannot write " + tmp.string());
    }
    std::filesystem::rename(tmp, target);
}

/// One program's run: started with the shim, ended after warm-up + window (or the start timeout).
struct RunResult {
    FrameWindow window;
    bool started = false;  // presented at least one frame
    std::string log;       // the program's stdout and stderr
};

RunResult runTimed(const std::vector<std::string>& argv, const std::string& dir, const std::string& tag,
                   const DisplayBenchOptions& o, const std::map<std::string, std::string>& env) {
    const std::string swapLog = dir + "/" + tag + ".swaps";
    const std::string outLog = dir + "/" + tag + ".log";
    std::filesystem::remove(swapLog);
    const pid_t pid = fork();
    if (pid < 0) throw Error("bench display: cannot fork");
    if (pid == 0) {
        setpgid(0, 0);  // its own process group: ended as a whole
        const int fd = open(outLog.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
        if (fd >= 0) {
            dup2(fd, 1);
            dup2(fd, 2);
        }
        setenv("WELKIN_SWAP_LOG", swapLog.c_str(), 1);
        setenv("LD_PRELOAD", WELKIN_SWAP_SHIM, 1);
        for (const auto& [k, v] : env) setenv(k.c_str(), v.c_str(), 1);
        std::vector<char*> args;
        for (const std::string& a : argv) args.push_back(const_cast<char*>(a.c_str()));
        args.push_back(nullptr);
        execvp(args[0], args.data());
        _exit(127);
    }
    setpgid(pid, pid);
    RunResult r;
    const auto started = std::chrono::steady_clock::now();
    bool exited = false;
    for (;;) {
        std::this_thread::sleep_for(std::chrono::milliseconds(200));
        int status = 0;
        if (waitpid(pid, &status, WNOHANG) == pid) {
            exited = true;
            break;
        }
        const std::vector<std::int64_t> ns = parseSwapLog(readFile(swapLog), swapLog);
        const double waited = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
        if (ns.empty() && waited > o.startTimeout) break;
        const double start = windowStart(ns, o.warmup);
        if (start == start && double(ns.back()) * 1e-9 >= start + o.seconds) break;
        if (!ns.empty() && waited > o.startTimeout + o.warmup + o.seconds + 60) break;  // a stalled program
    }
    if (!exited) {
        kill(-pid, SIGTERM);
        for (int i = 0; i < 50; ++i) {
            std::this_thread::sleep_for(std::chrono::milliseconds(100));
            if (waitpid(pid, nullptr, WNOHANG) == pid) {
                exited = true;
                break;
            }
        }
        if (!exited) {
            kill(-pid, SIGKILL);
            waitpid(pid, nullptr, 0);
        }
    }
    const std::vector<std::int64_t> ns = parseSwapLog(readFile(swapLog), swapLog);
    r.started = !ns.empty();
    r.window = frameWindow(ns, o.warmup, o.seconds);
    r.log = outLog;
    return r;
}

std::string rateText(double rate) {
    if (rate == 0) return "still";
    char b[32];
    std::snprintf(b, sizeof b, "time x%g", rate);
    return b;
}

/// `text` (an INI file) with `key = value` in `[section]`: the key's line replaced, or added at the
/// section's start; the section appended when missing.
std::string setIni(std::string text, const std::string& section, const std::string& key, const std::string& value) {
    const std::string header = "[" + section + "]";
    size_t at = text.rfind(header, 0) == 0 ? 0 : text.find("\n" + header);
    if (at == std::string::npos) return text + (text.empty() || text.back() == '\n' ? "" : "\n") + header + "\n" + key + " = " + value + "\n";
    if (text[at] == '\n') ++at;
    size_t line = text.find('\n', at);
    const size_t bodyStart = line == std::string::npos ? text.size() : line + 1;
    size_t end = text.find("\n[", bodyStart - 1);
    end = end == std::string::npos ? text.size() : end + 1;
    for (size_t p = bodyStart; p < end;) {
        const size_t e = std::min(text.find('\n', p), end);
        const std::string l = text.substr(p, e - p);
        const size_t eq = l.find('=');
        if (eq != std::string::npos) {
            std::string k = l.substr(0, eq);
            while (!k.empty() && (k.back() == ' ' || k.back() == '\t')) k.pop_back();
            if (k == key) return text.substr(0, p) + key + " = " + value + text.substr(e);
        }
        p = e + 1;
    }
    return text.substr(0, bodyStart) + key + " = " + value + "\n" + text.substr(bodyStart);
}

/// Stellarium's private user directory: its default configuration (a config.ini without its
/// version is replaced by the defaults at start) with the window size and the frame-rate limits
/// changed, and the startup script of one scene.
void writeStellariumSetup(const std::string& stellarium, const std::string& userDir, const DisplayScene& s, double rate,
                          const DisplayBenchOptions& o) {
    std::error_code ec;
    const std::filesystem::path exe = std::filesystem::canonical(stellarium, ec);
    const std::filesystem::path defaults = exe.parent_path().parent_path() / "share/stellarium/data/default_cfg.ini";
    std::string cfg = readFile(defaults.string());
    if (cfg.empty()) throw Error("--stellarium: its default configuration " + defaults.string() + " is missing or empty");
    for (const auto& [k, v] : std::vector<std::pair<std::string, std::string>>{{"fullscreen", "false"},
                                                                                 {"screen_w", std::to_string(o.width)},
                                                                                 {"screen_h", std::to_string(o.height)},
                                                                                 {"screen_x", "0"},
                                                                                 {"screen_y", "0"},
                                                                                 {"minimum_fps", "10000"},
                                                                                 {"maximum_fps", "10000"}})
        cfg = setIni(cfg, "video", k, v);
    std::filesystem::create_directories(userDir + "/scripts");
    writeFileAtomically(userDir + "/config.ini", cfg, "--stellarium");
    std::string iso = s.time;
    if (!iso.empty() && iso.back() == 'Z') iso.pop_back();
    std::ofstream f(userDir + "/scripts/welkin_bench.ssc");
    f << "// welkin bench display: " << s.name << "\n"
      << "core.setGuiVisible(false);\n"
      << "core.setObserverLocation(" << kLon << ", " << kLat << ", " << kHeightM << ", 0, \"Malta\", \"Earth\");\n"
      << "core.setDate(\"" << iso << "\", \"utc\");\n"
      << "core.setTimeRate(" << rate << ");\n"
      << "LandscapeMgr.setFlagAtmosphere(true);\n"
      << "MilkyWay.setFlagShow(true);\n"
      << "core.setProjectionMode(\"ProjectionPerspective\");\n"  // welkin view's projection (Stellarium's default is stereographic)
      << "core.moveToAltAzi(30, 180, 0);\n"
      << "StelMovementMgr.zoomTo(60, 0);\n";
    if (std::getenv("WELKIN_BENCH_DISPLAY_SHOTS"))  // a check of the view: a screenshot after the warm-up
        f << "core.wait(" << o.warmup << ");\ncore.screenshot(\"stellarium-" << s.name << "\", false, \"" << userDir << "/\", true);\n";
}

struct SideResult {
    std::string scene;
    double rate = 0;
    std::vector<FrameWindow> welkin, stellarium;
};

struct BudgetRow {
    std::string what;
    std::map<std::string, double> ratio;  // scene name -> x trivial pass
};

struct BudgetTable {
    int width = 0, height = 0;
    std::vector<BudgetRow> rows;
    std::map<std::string, double> trivialMs;
};

BudgetTable measureBudget(int w, int h, const DisplayBenchOptions& o, std::string& renderer) {
    Logger log;
    auto ctx = gl::HeadlessContext::create({}, log);
    renderer = ctx->description();
    BudgetTable t;
    t.width = w;
    t.height = h;
    std::vector<std::string> order;
    std::map<std::string, std::map<std::string, double>> ratios;
    for (const DisplayScene& s : o.sceneList) {
        SceneOptions so;
        so.time = s.time;
        so.latDeg = std::atof(kLat);
        so.lonDeg = std::atof(kLon);
        so.heightM = std::atof(kHeightM);
        so.azDeg = 180;
        so.altDeg = 30;
        so.fovDeg = 60;
        so.size = std::to_string(w) + "x" + std::to_string(h);
        so.vars = o.vars;
        SkyProcessor sky(SkyVars::earth(), log, ProcessorOptions{.timing = true});
        sky.vars().set(keys::interactive, true);  // as welkin view
        so.apply(sky);
        sky.setAnimationTime(std::nullopt);  // as welkin view: the eye adapts by the wall clock between frames
        TrivialPass trivial(w, h);
        // The displayed frame as welkin view draws it: renderFrame() (the HDR composite and the
        // eye's meter), then the tone map into the display: here an SRGB8_ALPHA8 target of the
        // size, as welkin view's sRGB-capable window (the framebuffer encodes on write, docs/eye.md).
        gl::Texture2D display(w, h, GL_SRGB8_ALPHA8);
        gl::Framebuffer displayFbo = gl::Framebuffer::create();
        displayFbo.attach(GL_COLOR_ATTACHMENT0, display);
        displayFbo.checkComplete("bench display's display target");
        for (int i = 0; i < 2; ++i) {  // tables and first-frame work out of the way
            sky.renderFrame();
            sky.toneMapInto(displayFbo.id());
        }
        std::map<std::string, std::vector<double>> ms;
        std::vector<double> trivialMs;
        for (int i = 0; i < o.budgetFrames; ++i) {
            trivialMs.push_back(medianMs(3, [&] { trivial.draw(); }));  // three a frame: the load's noise
            sky.renderFrame();
            const nlohmann::json st = sky.stats();
            sky.toneMapInto(displayFbo.id());
            const double displayMs = sky.stats()["tonemap_ms"].get<double>();
            for (const auto& e : st["elements"]) {
                const std::string n = e["name"].get<std::string>();
                double v = e["update_ms"].get<double>() + e["render_ms"].get<double>();
                ms[n].push_back(v);
            }
            // renderFrame()'s part (the automatic exposure's meter and adaptation) and the pass
            // into the display.
            ms["tone map"].push_back(st["tonemap_ms"].get<double>() + displayMs);
            ms["generators (shared)"].push_back(st["generators_ms"].get<double>());
            ms["whole frame (renderFrame + tone map)"].push_back(st["frame_ms"].get<double>() + displayMs);
        }
        const double tr = medianOf(trivialMs);
        t.trivialMs[s.name] = tr;
        for (const auto& e : sky.elements())
            if (std::find(order.begin(), order.end(), e->name()) == order.end()) order.push_back(e->name());
        for (auto& [n, v] : ms) ratios[n][s.name] = medianOf(v) / tr;
        sky.release();
    }
    for (const char* extra : {"generators (shared)", "tone map", "whole frame (renderFrame + tone map)"}) order.push_back(extra);
    for (const std::string& n : order) t.rows.push_back({n, ratios[n]});
    return t;
}

std::string budgetMarkdown(const BudgetTable& t, const DisplayBenchOptions& o) {
    std::ostringstream md;
    md << "| " << t.width << "x" << t.height << " |";
    for (const DisplayScene& s : o.sceneList) md << " " << s.name << " |";
    md << "\n|---|";
    for (size_t i = 0; i < o.sceneList.size(); ++i) md << "---|";
    md << "\n";
    for (const BudgetRow& r : t.rows) {
        md << "| " << r.what << " |";
        for (const DisplayScene& s : o.sceneList) {
            auto it = r.ratio.find(s.name);
            md << " " << (it == r.ratio.end() ? std::string("-") : fmt(it->second, 2)) << " |";
        }
        md << "\n";
    }
    md << "| *trivial pass, ms* |";
    for (const DisplayScene& s : o.sceneList) md << " " << fmt(t.trivialMs.at(s.name), 2) << " |";
    md << "\n";
    return md.str();
}

std::string loadAvg() {
    std::ifstream f("/proc/loadavg");
    std::string a, b, c;
    f >> a >> b >> c;
    return a.empty() ? "unknown" : a + " " + b + " " + c;
}

int run(DisplayBenchOptions o) {
    o.validate();
    const auto started = std::chrono::steady_clock::now();
    const std::string loadStart = loadAvg();
    std::string stellarium;
    if (o.stellarium == "auto") stellarium = findOnPath("stellarium");
    else if (o.stellarium != "off") stellarium = o.stellarium;
    const char* display = std::getenv("DISPLAY");
    if (o.sideBySide && (!display || !*display))
        throw Error("no X display (DISPLAY unset): run it as xvfb-run -a -s '-screen 0 1920x1080x24' welkin bench display, or give --no-side-by-side");
    const std::string stVersion = stellarium.empty() ? "" : shellOut("dpkg-query -W -f='${Version}' stellarium 2>/dev/null");

    char tmpl[] = "/tmp/welkin-bench-display-XXXXXX";
    if (!mkdtemp(tmpl)) throw Error("bench display: cannot create a temporary directory in /tmp");
    const std::string dir = tmpl;
    const std::string self = std::filesystem::read_symlink("/proc/self/exe").string();

    std::vector<SideResult> side;
    if (o.sideBySide) {
        for (const DisplayScene& s : o.sceneList)
            for (double rate : o.rateList) {
                SideResult sr{s.name, rate, {}, {}};
                for (int round = 0; round < o.rounds; ++round) {
                    const std::string tag = std::string(s.name) + "-" + fmt(rate, 0) + "-" + std::to_string(round);
                    std::vector<std::string> wargs = {self, "view", "--time", s.time, "--lat", kLat, "--lon", kLon, "--height", kHeightM,
                                                      "--az", "180", "--alt", "30", "--fov", "60", "--size", o.size, "--no-panel",
                                                      "--speed", fmt(rate, 6)};
                    for (const std::string& v : o.vars) wargs.insert(wargs.end(), {"--var", v});
                    RunResult wr = runTimed(wargs, dir, "welkin-" + tag, o, {});
                    if (!wr.started) throw Error("welkin view showed no frame in " + fmt(o.startTimeout, 0) + " s (--start-timeout); its output: " + wr.log);
                    std::fprintf(stderr, "welkin bench display: %s %s round %d: welkin %.2f fps (median %.1f ms)\n", s.name,
                                 rateText(rate).c_str(), round + 1, wr.window.fps, wr.window.medianMs);
                    sr.welkin.push_back(wr.window);
                    if (!stellarium.empty()) {
                        const std::string userDir = dir + "/stellarium-" + tag;
                        writeStellariumSetup(stellarium, userDir, s, rate, o);
                        RunResult st = runTimed({stellarium, "--user-dir", userDir, "--startup-script", "welkin_bench.ssc"}, dir,
                                                "stellarium-" + tag, o, {});
                        if (!st.started)
                            throw Error("Stellarium showed no frame in " + fmt(o.startTimeout, 0) + " s (--start-timeout); its output: " + st.log);
                        std::fprintf(stderr, "welkin bench display: %s %s round %d: Stellarium %.2f fps (median %.1f ms)\n", s.name,
                                     rateText(rate).c_str(), round + 1, st.window.fps, st.window.medianMs);
                        sr.stellarium.push_back(st.window);
                    }
                }
                side.push_back(std::move(sr));
            }
    }
    std::string renderer;
    std::vector<BudgetTable> budgets;
    for (auto [w, h] : o.budgetSizeList) {
        std::fprintf(stderr, "welkin bench display: frame budget at %dx%d\n", w, h);
        budgets.push_back(measureBudget(w, h, o, renderer));
    }

    // The Markdown.
    char date[64];
    const std::time_t now = std::time(nullptr);
    std::strftime(date, sizeof date, "%Y-%m-%d %H:%M UTC", std::gmtime(&now));
    const std::string commit = sourceCommit(WELKIN_SOURCE_DIR);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
    const std::string cores = shellOut("nproc 2>/dev/null");
    std::ostringstream md, table;
    const DisplayBenchOptions defaults;
    std::string cmdline = o.sideBySide ? "xvfb-run -a -s '-screen 0 1920x1080x24' welkin bench display" : "welkin bench display --no-side-by-side";
    if (o.scenes != defaults.scenes) cmdline += " --scenes " + o.scenes;
    if (o.rates != defaults.rates) cmdline += " --rates " + o.rates;
    if (o.rounds != defaults.rounds) cmdline += " --rounds " + std::to_string(o.rounds);
    if (o.seconds != defaults.seconds) cmdline += " --seconds " + fmt(o.seconds, 0);
    if (o.warmup != defaults.warmup) cmdline += " --warmup " + fmt(o.warmup, 0);
    if (o.budgetSizes != defaults.budgetSizes) cmdline += " --budget-sizes " + o.budgetSizes;
    for (const std::string& v : o.vars) cmdline += " --var " + v;
    if (o.budgetFrames != defaults.budgetFrames) cmdline += " --budget-frames " + std::to_string(o.budgetFrames);
    md << kGenerated << "\n\nGenerated by `" << cmdline << "`"
       << " (apps/welkin/bench_display.cpp) on " << date << ", commit " << commit << ", " << (cores.empty() ? "?" : cores)
       << " cores, load average " << loadStart << " at the start and " << loadAvg() << " at the end, " << fmt(seconds, 0) << " s in all.";
    if (o.sideBySide)
        md << " Warm-up " << fmt(o.warmup, 0) << " s, window " << fmt(o.seconds, 0) << " s, " << o.rounds
           << " round(s) per row (welkin then Stellarium each round); fps and median frame time are the medians over the rounds.";
    md << "\n\n";
    const bool loaded = !cores.empty() && std::atof(loadStart.c_str()) > std::atof(cores.c_str());
    const std::string loadNote = loaded ? "**The machine was loaded by other jobs (load average above its core count): these figures are "
                                          "indicative only; rerun the command on a quiet machine.**"
                                        : "";
    if (loaded) md << loadNote << "\n\n";
    if (o.sideBySide) {
        md << "### Side by side at " << o.size << "\n\n"
           << (stellarium.empty() ? "Stellarium is not installed here: welkin alone.\n\n"
                                  : "Stellarium " + stVersion + " (" + stellarium + ").\n\n")
           << "| scene | time | welkin fps | welkin median ms | Stellarium fps | Stellarium median ms | welkin / Stellarium fps |\n"
           << "|---|---|---|---|---|---|---|\n";
        table << "| scene | time | welkin fps | Stellarium fps | ratio |\n|---|---|---|---|---|\n";
        for (const SideResult& r : side) {
            std::vector<double> wf, wm, sf, sm;
            for (const FrameWindow& w : r.welkin) wf.push_back(w.fps), wm.push_back(w.medianMs);
            for (const FrameWindow& w : r.stellarium) sf.push_back(w.fps), sm.push_back(w.medianMs);
            const bool st = !sf.empty();
            const std::string ratio = st && medianOf(sf) > 0 ? fmt(medianOf(wf) / medianOf(sf), 2) : "-";
            md << "| " << r.scene << " | " << rateText(r.rate) << " | " << fmt(medianOf(wf), 1) << " | " << fmt(medianOf(wm), 1) << " | "
               << (st ? fmt(medianOf(sf), 1) : "-") << " | " << (st ? fmt(medianOf(sm), 1) : "-") << " | " << ratio << " |\n";
            table << "| " << r.scene << " | " << rateText(r.rate) << " | " << fmt(medianOf(wf), 1) << " | " << (st ? fmt(medianOf(sf), 1) : "-")
                  << " | " << ratio << " |\n";
        }
        md << "\n";
    }
    if (!budgets.empty()) {
        md << "### Frame budget per element (this build)\n\nEach element's update + render per frame, the tone map (the eye's "
              "meter in `renderFrame()` and the pass into the display, `toneMapInto()`), the shared generators and the displayed "
              "frame's work (`renderFrame()` + that pass), time stopped, as ratios to a trivial fullscreen pass timed alternately "
              "with the frames (median of "
           << o.budgetFrames << " frames; renderer " << renderer << ").\n\n";
        for (const BudgetTable& t : budgets) md << budgetMarkdown(t, o) << "\n";
    }
    std::printf("%s", md.str().c_str());
    if (!o.out.empty()) {
        std::string text = readFile(o.out);
        size_t at = text.find(kGenerated);
        if (at == std::string::npos) {
            if (text.find(kMarker) == std::string::npos) text += "\n" + std::string(kMarker) + "\n\n## Displayed frames\n\n";
            at = text.size();
        }
        writeFileAtomically(o.out, text.substr(0, at) + md.str(), "--out");
        std::printf("welkin bench display: wrote %s (from the line '%s' to the end)\n", o.out.c_str(), kGenerated);
    }
    if (!o.readme.empty() && o.sideBySide) {
        std::string text = readFile(o.readme);
        const size_t b = text.find(kReadmeBegin), e = text.find(kReadmeEnd);
        if (b != std::string::npos && e != std::string::npos && e > b) {
            const std::string body = std::string(kReadmeBegin) + "\n" + "Measured " + date + " (" + (cores.empty() ? "?" : cores) +
                                     " cores, llvmpipe, load average " + loadStart + "; method: docs/BENCHMARKS.md, *Displayed frames*):\n\n" +
                                     table.str() + (loaded ? "\n" + loadNote + "\n" : std::string()) + "\n";
            writeFileAtomically(o.readme, text.substr(0, b) + body + text.substr(e), "--readme");
            std::printf("welkin bench display: wrote %s (between '%s' and '%s')\n", o.readme.c_str(), kReadmeBegin, kReadmeEnd);
        } else {
            std::fprintf(stderr, "welkin bench display: %s has no '%s' ... '%s' markers: README not changed\n", o.readme.c_str(), kReadmeBegin,
                         kReadmeEnd);
        }
    }
    std::printf("welkin bench display: programs' logs and swap times in %s\n", dir.c_str());
    return 0;
}

BenchRegistrar reg("display", "welkin view's displayed frames side by side with Stellarium, and the frame budget per element",
                   [](CLI::App& sub) {
                       auto o = std::make_shared<DisplayBenchOptions>();  // the action below owns it
                       sub.add_option("--seconds", o->seconds, "counted window per run, s [1, 600]")->capture_default_str();
                       sub.add_option("--warmup", o->warmup, "discarded after a program's first frame, s [0, 600]")->capture_default_str();
                       sub.add_option("--rounds", o->rounds, "welkin/Stellarium alternations per scene and rate [1, 20]")->capture_default_str();
                       sub.add_option("--scenes", o->scenes, "comma list of day, twilight, moonlit, moonless")->capture_default_str();
                       sub.add_option("--rates", o->rates, "comma list of time rates (simulated s per real s) in [0, 1e5]; 0: stopped")
                           ->capture_default_str();
                       sub.add_option("--size", o->size, "window size of the side-by-side runs, WIDTHxHEIGHT")->capture_default_str();
                       sub.add_option("--budget-sizes", o->budgetSizes, "comma list of frame-budget sizes, or none")->capture_default_str();
                       sub.add_option("--budget-frames", o->budgetFrames, "timed frames per budget measurement [1, 1000]")->capture_default_str();
                       sub.add_option("--stellarium", o->stellarium, "auto (found on PATH), off, or the program's path")->capture_default_str();
                       sub.add_option("--start-timeout", o->startTimeout, "longest wait for a program's first frame, s [10, 3600]")
                           ->capture_default_str();
                       sub.add_option("--out", o->out, "Markdown file whose display section is rewritten ('' none)")->capture_default_str();
                       sub.add_option("--readme", o->readme, "file whose display table (between markers) is rewritten ('' none)")
                           ->capture_default_str();
                       sub.add_flag("--no-side-by-side{false}", o->sideBySide, "the frame budget only (no X display needed)");
                       sub.add_option("--var", o->vars, "KEY=VALUE set in welkin's frames (view and budget), repeatable: an A/B of a key");
                       return [o]() { return run(*o); };
                   });

}  // namespace
}  // namespace welkin::cli
