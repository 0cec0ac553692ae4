// VSOP87 planetary theory (version B: heliocentric spherical coordinates referred to the
// ecliptic and equinox J2000), in two forms with one evaluator:
//
//   const auto& fast = welkin::astro::vsop87Truncated(welkin::astro::VsopPlanet::Mars, t);  // compiled in
//   const auto& full = welkin::astro::vsop87Full(welkin::astro::VsopPlanet::Mars);       // kstars-data files
//   double t = welkin::astro::julianMillenniaTT(jdTT);                                  // from J2000
//   welkin::astro::VsopState s = welkin::astro::evaluate(full, t);
//   // s.lbr = (L rad, B rad, R au), s.rate = d/dt in rad/day and au/day
//
// The truncated series (engine/src/astro/vsop87_fast_tables.cpp, see tools/gen_fast_tables.py)
// keep the terms whose size over the date span exceeds a per-planet threshold; the full series are read once from
// /usr/share/kstars/<planet>.{L,B,R}{0..5}.vsop (Debian package kstars-data; override with the
// environment variable WELKIN_VSOP87_DIR) and cached for the life of the process. Each file line
// is "A B C": the term A cos(B + C t), t in Julian millennia of TT from J2000.0.
#pragma once
#include <glm/glm.hpp>

#include <string>
#include <string_view>
#include <vector>

namespace welkin::astro {

/// One periodic term A cos(B + C t): A in rad (L, B) or au (R), B in rad, C in rad/millennium.
struct VsopTerm {
    double a, b, c;
};
/// Terms of one power of t, sorted by decreasing |A|.
struct VsopSeries {
    const VsopTerm* terms = nullptr;
    int count = 0;
};
/// The 18 series of one body: coordinate = sum_k t^k * series_k, for L, B and R.
struct VsopBody {
    VsopSeries L[6], B[6], R[6];
};

enum class VsopPlanet { Mercury, Venus, Earth, Mars, Jupiter, Saturn, Uranus, Neptune };
/// Lower-case English name ("earth"), as in the kstars-data file names.
const char* vsopName(VsopPlanet p);

/// |t| (millennia from J2000) up to which the compact truncated set is used: years 1500-2500.
inline constexpr double kVsopNearSpan = 0.5;
/// Compiled-in truncated series (no I/O, no allocation) for dates near `t` (Julian millennia TT
/// from J2000): a compact set for |t| <= kVsopNearSpan, a larger one (about twice the terms)
/// truncated for the same accuracy out to |t| = 4 (years -2000 .. 6000).
const VsopBody& vsop87Truncated(VsopPlanet p, double t = 0.0);
/// Full series loaded from kstars-data on first use (thread-safe), then cached. Throws
/// welkin::Error naming the missing or malformed file.
const VsopBody& vsop87Full(VsopPlanet p);
/// Reads every full-series file of every planet under `directory` (no caching) and throws
/// welkin::Error naming the first missing or malformed file. For diagnostics and tests.
void checkVsop87Files(const std::string& directory);
/// One series file's text ("A B C" per line, blank lines ignored) as terms sorted by decreasing
/// |A|; what vsop87Full() reads each file with. Throws welkin::Error "vsop87Full(): source:line:
/// ..." for a line that is not three finite numbers or a term beyond |A| <= 1e5, |B| <= 1000 rad,
/// |C| <= 1e6 rad/millennium (the real files stay below 31, 6.3 and 1e5). `sourceName` names the
/// text in errors.
std::vector<VsopTerm> parseVsop87Series(std::string_view text, const std::string& sourceName);
/// Directory the full series are read from: $WELKIN_VSOP87_DIR or /usr/share/kstars.
std::string vsop87Directory();

/// Heliocentric position and its rate.
struct VsopState {
    glm::dvec3 lbr{0.0};   ///< L (rad, not reduced), B (rad), R (au)
    glm::dvec3 rate{0.0};  ///< dL/dt, dB/dt (rad/day), dR/dt (au/day); zero unless requested
};

/// Julian millennia of TT from J2000.0 (JD 2451545.0 TT), given the TT Julian date as two parts.
inline double julianMillenniaTT(double jd1, double jd2) { return ((jd1 - 2451545.0) + jd2) / 365250.0; }

/// Evaluates all terms of `body` at `t` (Julian millennia TT from J2000). With `rates`, also
/// the time derivatives from the terms with |A| >= 1e-4 (enough for light time and aberration:
/// the neglected terms move a light-time corrected position by < 0.01").
VsopState evaluate(const VsopBody& body, double t, bool rates = false);

/// Heliocentric rectangular coordinates in the equatorial frame of J2000 (FK5 axes as realised
/// by VSOP87, within 0.02" of ICRS), au, from spherical ecliptic VSOP87B values.
glm::dvec3 vsopToEquatorialJ2000(const glm::dvec3& lbr);
/// Same for a rate (derivative of the position), au/day.
glm::dvec3 vsopRateToEquatorialJ2000(const glm::dvec3& lbr, const glm::dvec3& rate);

}  // namespace welkin::astro
