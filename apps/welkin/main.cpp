// welkin: the command-line front end. Subcommands live in cmd_*.cpp and register themselves.
#include "command.hpp"

#include <welkin/error.hpp>

#include <algorithm>
#include <cstdio>
#include <iostream>

namespace welkin::cli {
std::vector<Command>& commands() {
    static std::vector<Command> c;
    return c;
}
std::vector<Command>& benchmarks() {
    static std::vector<Command> b;
    return b;
}
}  // namespace welkin::cli

int main(int argc, char** argv) {
    using namespace welkin::cli;
    CLI::App app{"welkin: physically based skies for any date, time and place on Earth", "welkin"};
    app.set_version_flag("--version", std::string("welkin ") + WELKIN_VERSION);
    app.require_subcommand(1);

    auto byName = [](const Command& a, const Command& b) { return a.name < b.name; };
    std::sort(commands().begin(), commands().end(), byName);
    std::sort(benchmarks().begin(), benchmarks().end(), byName);

    std::vector<std::pair<CLI::App*, Action>> actions;
    for (auto& c : commands()) {
        CLI::App* sub = app.add_subcommand(c.name, c.description);
        actions.emplace_back(sub, c.setup(*sub));
    }
    if (!benchmarks().empty()) {
        CLI::App* bench = app.add_subcommand("bench", "measure speed and accuracy");
        bench->require_subcommand(1);
        for (auto& b : benchmarks()) {
            CLI::App* sub = bench->add_subcommand(b.name, b.description);
            actions.emplace_back(sub, b.setup(*sub));
        }
    }
    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        // CLI11's own messages name the option; keep them on one line.
        return app.exit(e);
    }
    for (auto& [sub, action] : actions) {
        if (!sub->parsed()) continue;
        try {
            return action();
        } catch (const welkin::Error& e) {
            std::fprintf(stderr, "welkin %s: %s\n", sub->get_name().c_str(), e.what());
            return 1;
        } catch (const std::exception& e) {
            std::fprintf(stderr, "welkin %s: %s\n", sub->get_name().c_str(), e.what());
            return 1;
        }
    }
    return 0;
}
