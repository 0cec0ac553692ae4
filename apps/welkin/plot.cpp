// Plot scripts run from the benchmarks (plot.hpp).
#include "plot.hpp"

#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>

extern char** environ;

namespace welkin::cli {

namespace {

/// Runs argv[0] (searched on the PATH) with `args`; exit status, or -1 if it could not start or
/// did not exit normally. `quiet` sends its stdout and stderr to /dev/null.
int run(const std::vector<std::string>& args, bool quiet) {
    std::vector<char*> argv;
    for (const auto& a : args) argv.push_back(const_cast<char*>(a.c_str()));
    argv.push_back(nullptr);
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    if (quiet) {
        posix_spawn_file_actions_addopen(&actions, 1, "/dev/null", O_WRONLY, 0);
        posix_spawn_file_actions_addopen(&actions, 2, "/dev/null", O_WRONLY, 0);
    }
    pid_t pid = 0;
    const int err = posix_spawnp(&pid, argv[0], &actions, nullptr, argv.data(), environ);
    posix_spawn_file_actions_destroy(&actions);
    if (err != 0) return -1;
    int status = 0;
    if (waitpid(pid, &status, 0) != pid || !WIFEXITED(status)) return -1;
    return WEXITSTATUS(status);
}

std::string shellQuoted(const std::string& s) {
    if (s.find_first_not_of("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789_-+=./,:@%") == std::string::npos)
        return s;
    std::string out = "'";
    for (char c : s) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
    return out + "'";
}

}  // namespace

std::vector<std::string> defaultPythons() {
    std::vector<std::string> p;
    if (const char* env = std::getenv("WELKIN_PYTHON"); env && *env) p.push_back(env);
    p.push_back("/usr/bin/python3");
    p.push_back("python3");
    return p;
}

std::optional<std::string> findPythonWithMatplotlib(const std::vector<std::string>& pythons) {
    for (const auto& py : pythons)
        if (run({py, "-c", "import matplotlib"}, true) == 0) return py;
    return std::nullopt;
}

std::optional<std::string> findPlotScript(const std::string& name) {
    namespace fs = std::filesystem;
    std::vector<fs::path> dirs;
    if (const char* env = std::getenv("WELKIN_PLOT_DIR"); env && *env) dirs.emplace_back(env);
    std::error_code ec;
    const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
    if (!ec) dirs.push_back(exe.parent_path().parent_path() / "share" / "welkin" / "plots");
#ifdef WELKIN_SOURCE_DIR
    dirs.push_back(fs::path(WELKIN_SOURCE_DIR) / "scripts" / "plots");
#endif
    for (const auto& d : dirs)
        if (fs::is_regular_file(d / name, ec)) return (d / name).string();
    return std::nullopt;
}

PlotResult drawPlot(const std::string& script, const std::string& csv, const std::string& png,
                    const std::vector<std::string>& pythons) {
    const std::optional<std::string> path = findPlotScript(script);
    const std::string scriptShown = path ? *path : "scripts/plots/" + script;
    const std::string command = "python3 " + shellQuoted(scriptShown) + " " + shellQuoted(csv) + " " + shellQuoted(png);
    if (!path) return {false, "plot not drawn: " + script + " not found (set WELKIN_PLOT_DIR); draw it with: " + command};
    const std::optional<std::string> python = findPythonWithMatplotlib(pythons);
    if (!python)
        return {false, "plot not drawn: no python3 with matplotlib (Debian: apt-get install python3-matplotlib); draw it with: " +
                           command};
    const int status = run({*python, *path, csv, png}, false);
    if (status != 0)
        return {false, "plot not drawn: " + script + " exited with status " + std::to_string(status) + "; draw it with: " + command};
    return {true, "wrote " + png};
}

}  // namespace welkin::cli
