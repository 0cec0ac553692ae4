// Precondition checks at the API boundary, with the project's one-line messages.
//
//   welkin::checkRange("Observer", "height (m)", h, -1e4, 1e9);
//       // throws welkin::Error("Observer: height (m) 2e+09 not in [-10000, 1e+09]")
//   welkin::checkOpenRange("HostDepth", "nearM", near, 0, welkin::kInfinity);
//       // "HostDepth: nearM 0 not in (0, inf)"
//   welkin::checkRange("Observer", "latitude", lat, -pi / 2, pi / 2, {180 / pi, " deg"});
//       // compared in radians, shown in degrees: "Observer: latitude 114.6 deg not in [-90, 90]"
//
// An empty `where` drops the prefix (command-line options: "--lat 100 not in [-90, 90]").
// NaN is never in range. Numbers are printed with %g (6 significant digits).
#pragma once
#include <limits>

namespace welkin {

inline constexpr double kInfinity = std::numeric_limits<double>::infinity();

/// How a value and its bounds are shown in the message: multiplied by `scale`, followed by
/// `unit` (e.g. {180 / pi, " deg"} for an angle held in radians). The comparison is unscaled.
struct Shown {
    double scale = 1.0;
    const char* unit = "";
};

/// Throws welkin::Error("<where>: <what> <v><unit> not in [<lo>, <hi>]") unless lo <= v <= hi.
void checkRange(const char* where, const char* what, double v, double lo, double hi, Shown shown = {});
/// Throws welkin::Error("<where>: <what> <v><unit> not in (<lo>, <hi>)") unless lo < v < hi.
/// Either bound may be infinite (printed "inf").
void checkOpenRange(const char* where, const char* what, double v, double lo, double hi, Shown shown = {});

}  // namespace welkin
