// Runs the built `welkin` command and captures its exit status and output (stdout + stderr).
#pragma once
#include <array>
#include <cstdio>
#include <string>
#include <utility>
#include <vector>
#include <sys/wait.h>

namespace welkin::test {

struct CliResult {
    int status = -1;     ///< exit status
    std::string output;  ///< stdout and stderr together
};

/// Runs a shell command line (stderr is not redirected: add 2>&1 to capture it).
inline CliResult runShell(const std::string& cmd) {
    CliResult r;
    FILE* p = popen(cmd.c_str(), "r");
    if (!p) return r;
    std::array<char, 4096> buf;
    size_t n;
    while ((n = fread(buf.data(), 1, buf.size(), p)) > 0) r.output.append(buf.data(), n);
    int s = pclose(p);
    r.status = WIFEXITED(s) ? WEXITSTATUS(s) : -1;
    return r;
}

inline CliResult runCli(const std::string& args, const std::string& env = {}) {
    return runShell(env + (env.empty() ? "" : " ") + std::string("'") + WELKIN_CLI + "' " + args + " 2>&1");
}

/// A fresh empty directory under the build tree for a test's files.
inline std::string scratchDir(const std::string& name) {
    std::string d = std::string(WELKIN_BINARY_DIR) + "/test-output/" + name;
    std::string cmd = "rm -rf '" + d + "' && mkdir -p '" + d + "'";
    if (std::system(cmd.c_str()) != 0) return "/tmp";
    return d;
}

/// A command's bad options: for each (arguments, message), `welkin <command> <arguments>` must
/// exit with status 1 and print "welkin <command>: <message>". Returns the failures, one line
/// each ("<arguments> -> <output>"), so a test CHECKs that the list is empty.
inline std::vector<std::string> badOptionFailures(const std::string& command, const std::vector<std::pair<std::string, std::string>>& cases) {
    std::vector<std::string> failures;
    for (const auto& [args, message] : cases) {
        const CliResult r = runCli(command + " " + args);
        if (r.status != 1 || r.output.find("welkin " + command + ": " + message) == std::string::npos)
            failures.push_back(args + " -> status " + std::to_string(r.status) + ": " + r.output);
    }
    return failures;
}

}  // namespace welkin::test
