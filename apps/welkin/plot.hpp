// Plots of the `welkin bench` subcommands: benchmarks write CSV, and a Python script shipped with
// welkin (scripts/plots/, installed to share/welkin/plots/) draws the PNG with matplotlib.
//
//   welkin::cli::PlotResult p = welkin::cli::drawPlot("plot_bench_sky.py", "bench_sky.csv", "bench_sky.png");
//   std::printf("%s\n", p.message.c_str());   // "wrote bench_sky.png" or how to draw it by hand
//
// Without Python 3 and matplotlib the plot is not drawn and the message says how to draw it
// (never an error: the CSV is the benchmark's result).
#pragma once
#include <optional>
#include <string>
#include <vector>

namespace welkin::cli {

struct PlotResult {
    bool drawn = false;
    std::string message;  ///< one line: "wrote PNG", or why not and the command that draws it
};

/// Python interpreters tried in order: $WELKIN_PYTHON if set, /usr/bin/python3 (Debian's, where
/// python3-matplotlib installs), then python3 on the PATH.
std::vector<std::string> defaultPythons();

/// The first of `pythons` that runs and imports matplotlib, or nothing.
std::optional<std::string> findPythonWithMatplotlib(const std::vector<std::string>& pythons = defaultPythons());

/// Path of the plotting script `name`, searched in $WELKIN_PLOT_DIR, <executable dir>/../share/welkin/plots
/// (an installed welkin) and <source dir>/scripts/plots (a build tree); nothing if absent.
std::optional<std::string> findPlotScript(const std::string& name);

/// Runs `python script csv png`. Never throws for a missing interpreter, module or script.
PlotResult drawPlot(const std::string& script, const std::string& csv, const std::string& png,
                    const std::vector<std::string>& pythons = defaultPythons());

}  // namespace welkin::cli
