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
// A bench file is compiled into the `welkin` command (not into the library), so its static
// registrar always runs. Values are strings, as with `--var key=value`, so a bench file needs no
// header from its element. Costs are measured by the command, never by the bench file: on
// llvmpipe (software rendering) each element's time per frame is reported as a ratio to a trivial
// fullscreen pass timed alternately with it in the same run.
#pragma once
#include <functional>
#include <string>
#include <utility>
#include <vector>

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

/// Least-squares slope of log(y) against log(x): the growth exponent of cost y against work x
/// (1 = linear). Points with x <= 0 or y <= 0 are ignored; NaN with fewer than two distinct x.
double fitGrowthExponent(const std::vector<double>& x, const std::vector<double>& y);

}  // namespace welkin::bench
