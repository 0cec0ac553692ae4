// The benchmark harness's registration API: an element (or a generator family) describes how it is
// benchmarked from its own folder, and `welkin bench all` measures every registered element (and
// every element in the registry that registers nothing, with the default scene) the same way.
//
//   // skyelements/stars/bench/bench_stars.cpp (collected by skyelements/CMakeLists.txt):
//   #include <welkin/bench.hpp>
//   static welkin::bench::ElementBenchRegistrar reg({
//       .element = "stars",
//       .scene = {.time = "2026-01-15T22:00:00Z", .azimuthDeg = 180, .altitudeDeg = 40},
//       .sweeps = {{.name = "stars drawn", .unit = "stars", .workStat = "/stars/drawn",
//                   .points = {{.vars = {{"stars.magnitude_limit", "4"}}}, {.vars = {{"stars.magnitude_limit", "6"}}}}}},
//   });
//
// A bench with its own options and report (accuracy against a reference, table trace times, docs
// images) registers a command `welkin bench <name>` from the element's folder the same way:
//
//   // skyelements/halos/bench/bench_halos.cpp (compiled into the welkin command, which has CLI11):
//   static welkin::bench::CommandBenchRegistrar reg({"halos", "halo table trace times ...",
//       [](CLI::App& sub) { /* add options */ return std::function<int()>([] { /* run */ return 0; }); }});
//
// A bench file is compiled into the `welkin` command (not into the library), so its static
// registrar always runs. Values are strings, as with `--var key=value`, so a bench file needs no
// header from its element. Costs are measured by the command, never by the bench file: on
// llvmpipe (software rendering) each element's time per frame is reported as a ratio to a trivial
// fullscreen pass timed alternately with it in the same run.
#pragma once
#include <functional>
#include <iosfwd>
#include <map>
#include <string>
#include <utility>
#include <vector>

namespace CLI {
class App;  // CLI11's subcommand (only the welkin command, which links CLI11, defines command benches)
}

namespace welkin::bench {

/// `--var`-style settings: (key, value as text), applied in order after the elements are added.
using VarList = std::vector<std::pair<std::string, std::string>>;

/// The view an element is measured in.
struct Scene {
    std::string time = "2026-06-21T08:00:00Z";  ///< ISO 8601 instant at which time starts (default: Malta, mid-morning)
    double latitudeDeg = 35.9;                  ///< observer's geodetic latitude, degrees [-90, 90]
    double longitudeDeg = 14.5;                 ///< observer's longitude east, degrees [-180, 180]
    double azimuthDeg = 90;                     ///< camera heading, degrees from north towards east
    double altitudeDeg = 20;                    ///< camera pitch above the horizon, degrees [-90, 90]
    double fovDeg = 60;                         ///< vertical field of view, degrees (0, 180)
    std::vector<std::string> with;              ///< elements drawn with the measured one (it is added last; only its own cost is reported)
    VarList vars;                               ///< settings for the scene (e.g. rain on for the rainbow)
};

/// One point of a cost-against-work sweep.
struct WorkPoint {
    VarList vars;       ///< settings that set the amount of work
    double work = 0.0;  ///< the amount of work, when `WorkSweep::workStat` is empty (> 0)
};

/// Cost against work: the element's cost at each point, and the growth exponent fitted to
/// log(cost) against log(work). Pixels are swept by the harness for every element.
struct WorkSweep {
    std::string name;      ///< what grows ("stars drawn", "cloud samples per ray")
    std::string unit;      ///< its unit ("stars", "samples")
    std::string workStat;  ///< JSON pointer into SkyProcessor::stats() giving the work after a frame ("/stars/drawn"); empty: WorkPoint::work
    std::vector<WorkPoint> points;
};

/// How one element is benchmarked.
struct ElementBench {
    std::string element;      ///< the registry name (= the folder name)
    std::string description;  ///< one line: what the scene shows
    Scene scene;
    std::vector<WorkSweep> sweeps;
};

/// Every registered element bench (registration order; the command sorts by name).
std::vector<ElementBench>& elementBenches();

/// A static registrar: one per element bench file.
struct ElementBenchRegistrar {
    explicit ElementBenchRegistrar(ElementBench b) { elementBenches().push_back(std::move(b)); }
};

/// A table that `welkin bench all` adds to docs/BENCHMARKS.md from a command bench's CSV (the
/// accuracy of each quality preset against its reference, table build times against table size):
/// `welkin bench all` runs `welkin bench <name> <args...> --csv <temporary file>` as a child
/// process, then prints the CSV's rows as a Markdown table under `title`, with the command line.
///
///   .reports = {{.element = "rainbow", .title = "Rainbow: Mie tables by quality",
///                .what = "Build time of the droplet tables ...",
///                .args = {"--qualities", "low,default,high", "--repeats", "5"},
///                .quickArgs = {"--qualities", "low", "--repeats", "1"},
///                .columns = {"what", "quality_or_size:quality or size", "ms", "ratio_trivial:x trivial pass"}}}
struct ReportTable {
    std::string element;                 ///< the element it belongs to (`bench all --only` selects by it)
    std::string title;                   ///< the section's heading
    std::string what;                    ///< a paragraph: what is measured, against which reference
    std::vector<std::string> args;       ///< the bench's arguments in a full run (`--csv` is added)
    std::vector<std::string> quickArgs;  ///< with `bench all --quick` (empty: `args`)
    /// CSV columns shown, in order (empty: all), each "name", "name:heading" or "name*scale:heading"
    /// (a number multiplied by scale, e.g. "rms_rel*100:RMS error %").
    std::vector<std::string> columns;
};

/// A benchmark command `welkin bench <name>`: `setup` adds its options to the subcommand and
/// returns the action run after parsing (the process exit status; a welkin::Error it throws is
/// printed as one line and exits with status 1), as the command's own subcommands do.
struct CommandBench {
    std::string name;         ///< the subcommand's name ("halos", "cloud-reference")
    std::string description;  ///< one line for `welkin bench --help`
    std::function<std::function<int()>(CLI::App& sub)> setup;
    std::vector<ReportTable> reports;  ///< tables `welkin bench all` writes from this command's CSV (none: not run by it)
};

/// Every registered command bench (registration order; the command sorts by name).
std::vector<CommandBench>& commandBenches();

/// A static registrar: one per command bench file.
struct CommandBenchRegistrar {
    explicit CommandBenchRegistrar(CommandBench b) { commandBenches().push_back(std::move(b)); }
};

/// Instructions (callgrind's Ir) of one callgrind output file, attributed for the framework's CPU
/// cost per frame (`welkin bench all` runs `welkin bench framework` under callgrind):
///   own      self cost of every function in the object file `ownObject` (the welkin executable:
///            the processor, SkyVars, the generator graph, the state guard, the elements' and the
///            generators' CPU work, and the std templates they instantiate; all statically linked);
///   ownCalls inclusive cost of the calls those functions make into the C/C++ runtime (an object
///            whose path contains libc.so, libstdc++, libm.so, libgcc or ld-linux: malloc, memcpy,
///            string and stream code called by welkin);
///   runtime  self cost in the runtime in all (called by welkin or by the driver);
///   total    every instruction in the file; total - own - runtime is the driver's (Mesa, LLVM and
///            its JIT code, libepoxy), whose GL calls welkin makes are not welkin's cost.
/// welkin's cost is own + ownCalls. byFunction: the same by welkin function (self + its runtime calls).
struct CallgrindCosts {
    double total = 0, own = 0, ownCalls = 0, runtime = 0;
    std::map<std::string, double> byFunction;
};

/// Parses callgrind's output format (name compression "(id) name", "calls=" lines followed by the
/// call's inclusive cost, first event = Ir). Lines it does not know are ignored.
CallgrindCosts parseCallgrind(std::istream& in, const std::string& ownObject);

/// Least-squares slope of log(y) against log(x): the growth exponent of cost y against work x
/// (1 = linear). Points with x <= 0 or y <= 0 are ignored; NaN with fewer than two distinct x.
double fitGrowthExponent(const std::vector<double>& x, const std::vector<double>& y);

}  // namespace welkin::bench
