// Subcommand registry of the `welkin` command: each cmd_*.cpp registers itself.
//
//   static welkin::cli::Registrar reg("astro", "positions of the Sun, Moon and planets",
//       [](CLI::App& sub) { /* add options */ return [&]() -> int { /* run */ return 0; }; });
//
// A subcommand's setup adds its options to `sub` and returns the action run after parsing.
// Actions return the process exit code; a welkin::Error thrown by an action is printed as one
// line "welkin <subcommand>: <message>" and exits with status 1.
#pragma once
#include <CLI/CLI.hpp>

#include <functional>
#include <string>
#include <vector>

namespace welkin::cli {

using Action = std::function<int()>;
using Setup = std::function<Action(CLI::App& sub)>;

struct Command {
    std::string name;
    std::string description;
    Setup setup;
};

/// All registered subcommands (order of registration across files is unspecified; main sorts).
std::vector<Command>& commands();

struct Registrar {
    Registrar(std::string name, std::string description, Setup setup) {
        commands().push_back({std::move(name), std::move(description), std::move(setup)});
    }
};

/// `welkin bench <name>`: benchmarks register here the same way.
std::vector<Command>& benchmarks();
struct BenchRegistrar {
    BenchRegistrar(std::string name, std::string description, Setup setup) {
        benchmarks().push_back({std::move(name), std::move(description), std::move(setup)});
    }
};

/// `welkin demo <name>`: the heritage and education demos register here the same way.
std::vector<Command>& demos();
struct DemoRegistrar {
    DemoRegistrar(std::string name, std::string description, Setup setup) {
        demos().push_back({std::move(name), std::move(description), std::move(setup)});
    }
};

}  // namespace welkin::cli
