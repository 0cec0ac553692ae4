// Runs the built `welkin` command and captures its exit status and output (stdout + stderr).
#pragma once
#include <array>
#include <cstdio>
#include <string>
#include <sys/wait.h>

namespace welkin::test {

struct CliResult {
    int status = -1;     ///< exit status
    std::string output;  ///< stdout and stderr together
};

inline CliResult runCli(const std::string& args, const std::string& env = {}) {
    std::string cmd = env + (env.empty() ? "" : " ") + std::string("'") + WELKIN_CLI + "' " + args + " 2>&1";
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

/// A fresh empty directory under the build tree for a test's files.
inline std::string scratchDir(const std::string& name) {
    std::string d = std::string(WELKIN_BINARY_DIR) + "/test-output/" + name;
    std::string cmd = "rm -rf '" + d + "' && mkdir -p '" + d + "'";
    if (std::system(cmd.c_str()) != 0) return "/tmp";
    return d;
}

}  // namespace welkin::test
