// welkin: the command-line front end. Subcommands live in cmd_*.cpp and register themselves.
#include "command.hpp"

#include <welkin/bench.hpp>
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
std::vector<Command>& demos() {
    static std::vector<Command> d;
    return d;
}
}  // namespace welkin::cli

int main(int argc, char** argv) {
    using namespace welkin::cli;
    CLI::App app{"welkin: physically based skies for any date, time and place on Earth", "welkin"};
    app.set_version_flag("--version", std::string("welkin ") + WELKIN_VERSION);
    app.require_subcommand(1);

    // Benchmark commands registered from the elements' folders (welkin/bench.hpp) join the command's own.
    for (const welkin::bench::CommandBench& b : welkin::bench::commandBenches()) benchmarks().push_back({b.name, b.description, b.setup});
    auto byName = [](const Command& a, const Command& b) { return a.name < b.name; };
    std::sort(commands().begin(), commands().end(), byName);
    std::sort(benchmarks().begin(), benchmarks().end(), byName);
    std::sort(demos().begin(), demos().end(), byName);

    struct Entry {
        CLI::App* sub;
        std::string fullName;  // "render", "bench sky"
        Action action;
    };
    std::vector<Entry> actions;
    for (auto& c : commands()) {
        CLI::App* sub = app.add_subcommand(c.name, c.description);
        actions.push_back({sub, c.name, c.setup(*sub)});
    }
    if (!benchmarks().empty()) {
        CLI::App* bench = app.add_subcommand("bench", "measure speed and accuracy");
        bench->require_subcommand(1);
        for (auto& b : benchmarks()) {
            CLI::App* sub = bench->add_subcommand(b.name, b.description);
            actions.push_back({sub, "bench " + b.name, b.setup(*sub)});
        }
    }
    if (!demos().empty()) {
        CLI::App* demo = app.add_subcommand("demo", "the heritage and education demos (docs/demos.md)");
        demo->require_subcommand(1);
        for (auto& d : demos()) {
            CLI::App* sub = demo->add_subcommand(d.name, d.description);
            actions.push_back({sub, "demo " + d.name, d.setup(*sub)});
        }
    }
    try {
        app.parse(argc, argv);
    } catch (const CLI::CallForHelp& e) {
        return app.exit(e);
    } catch (const CLI::CallForAllHelp& e) {
        return app.exit(e);
    } catch (const CLI::CallForVersion& e) {
        return app.exit(e);
    } catch (const CLI::ParseError& e) {
        // A bad value CLI11 itself refuses ("Could not convert: --lat = abc", an unknown option,
        // a missing required one): one line, as for the commands' own checks, prefixed with the
        // subcommand being parsed, and CLI11's non-zero status. (app.exit() would print a second
        // line, "Run with --help for more information.")
        std::string name = "welkin";
        for (const CLI::App* a = &app;;) {
            const auto subs = a->get_subcommands();
            if (subs.empty()) break;
            a = subs.front();
            name += " " + a->get_name();
        }
        std::fprintf(stderr, "%s: %s (see --help)\n", name.c_str(), e.what());
        return e.get_exit_code();
    }
    for (auto& [sub, name, action] : actions) {
        if (!sub->parsed()) continue;
        try {
            return action();
        } catch (const std::exception& e) {  // welkin::Error and anything else: one line, status 1
            std::fprintf(stderr, "welkin %s: %s\n", name.c_str(), e.what());
            return 1;
        }
    }
    return 0;
}
