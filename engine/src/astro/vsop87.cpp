// VSOP87B evaluation: compiled-in truncated series and the full series from kstars-data.
#include <welkin/astro/vsop87.hpp>
#include <welkin/error.hpp>

#include "fast_trig.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <memory>
#include <mutex>
#include <sstream>
#include <vector>

namespace welkin::astro {

namespace detail {
extern const VsopBody kNearMercury, kNearVenus, kNearEarth, kNearMars, kNearJupiter, kNearSaturn, kNearUranus, kNearNeptune;
extern const VsopBody kWideMercury, kWideVenus, kWideEarth, kWideMars, kWideJupiter, kWideSaturn, kWideUranus, kWideNeptune;
}

const char* vsopName(VsopPlanet p) {
    static const char* names[] = {"mercury", "venus", "earth", "mars", "jupiter", "saturn", "uranus", "neptune"};
    return names[static_cast<int>(p)];
}

const VsopBody& vsop87Truncated(VsopPlanet p, double t) {
    static const VsopBody* near[] = {&detail::kNearMercury, &detail::kNearVenus,   &detail::kNearEarth,  &detail::kNearMars,
                                     &detail::kNearJupiter, &detail::kNearSaturn, &detail::kNearUranus, &detail::kNearNeptune};
    static const VsopBody* wide[] = {&detail::kWideMercury, &detail::kWideVenus,   &detail::kWideEarth,  &detail::kWideMars,
                                     &detail::kWideJupiter, &detail::kWideSaturn, &detail::kWideUranus, &detail::kWideNeptune};
    return *(std::fabs(t) <= kVsopNearSpan ? near : wide)[static_cast<int>(p)];
}

std::string vsop87Directory() {
    const char* env = std::getenv("WELKIN_VSOP87_DIR");
    return env && *env ? std::string(env) : std::string("/usr/share/kstars");
}

std::vector<VsopTerm> parseVsop87Series(std::string_view text, const std::string& sourceName) {
    std::vector<VsopTerm> terms;
    size_t pos = 0;
    int lineNo = 0;
    while (pos < text.size()) {
        size_t end = text.find('\n', pos);
        if (end == std::string_view::npos) end = text.size();
        const std::string line(text.substr(pos, end - pos));
        pos = end + 1;
        ++lineNo;
        if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
        std::istringstream ls(line);
        VsopTerm t{};
        if (!(ls >> t.a >> t.b >> t.c) || !std::isfinite(t.a) || !std::isfinite(t.b) || !std::isfinite(t.c))
            throw Error("vsop87Full(): " + sourceName + ":" + std::to_string(lineNo) + ": expected three numbers \"A B C\"");
        // Plausible sizes: the kstars-data files reach |A| 26,088 (Mercury's mean motion, the
        // constant term of its L1 series in rad/millennium; distances reach 30.07 au), |B| 6.29
        // rad, |C| 94,138 rad/millennium; the evaluator's cosine is accurate for |B + C t| < 6.5e6
        // (fast_trig.hpp), which these limits keep over |t| <= 4 millennia. Beyond them a sum
        // turns inf or NaN.
        if (!(std::fabs(t.a) <= 1e5 && std::fabs(t.b) <= 1e3 && std::fabs(t.c) <= 1e6))
            throw Error("vsop87Full(): " + sourceName + ":" + std::to_string(lineNo) +
                        ": term out of range (|A| <= 1e5, |B| <= 1000 rad, |C| <= 1e6 rad/millennium)");
        terms.push_back(t);
    }
    std::stable_sort(terms.begin(), terms.end(), [](const VsopTerm& x, const VsopTerm& y) { return std::fabs(x.a) > std::fabs(y.a); });
    return terms;
}

namespace {

// Storage of one body's full series: the terms live in `storage`, the spans in `body`.
struct LoadedBody {
    std::array<std::vector<VsopTerm>, 18> storage;
    VsopBody body;
};

std::vector<VsopTerm> readSeriesFile(const std::string& path, bool required) {
    std::ifstream in(path, std::ios::binary);
    if (!in) {
        if (required) throw Error("vsop87Full(): cannot read " + path + " (install the Debian package kstars-data or set WELKIN_VSOP87_DIR)");
        return {};
    }
    std::ostringstream text;
    text << in.rdbuf();
    return parseVsop87Series(text.str(), path);
}

std::unique_ptr<LoadedBody> loadBody(VsopPlanet p, const std::string& dir) {
    auto lb = std::make_unique<LoadedBody>();
    const char coords[3] = {'L', 'B', 'R'};
    for (int c = 0; c < 3; ++c) {
        for (int k = 0; k < 6; ++k) {
            // The power-0 series always exist; higher powers may be empty (absent or 0 lines).
            std::string path = dir + "/" + vsopName(p) + "." + coords[c] + std::to_string(k) + ".vsop";
            auto& v = lb->storage[c * 6 + k];
            v = readSeriesFile(path, k == 0);
            VsopSeries s{v.empty() ? nullptr : v.data(), static_cast<int>(v.size())};
            (c == 0 ? lb->body.L : c == 1 ? lb->body.B : lb->body.R)[k] = s;
        }
    }
    return lb;
}

}  // namespace

void checkVsop87Files(const std::string& directory) {
    for (int p = 0; p < 8; ++p) loadBody(static_cast<VsopPlanet>(p), directory);
}

const VsopBody& vsop87Full(VsopPlanet p) {
    static std::mutex mutex;
    static std::array<std::unique_ptr<LoadedBody>, 8> cache;
    std::lock_guard<std::mutex> lock(mutex);
    auto& slot = cache[static_cast<int>(p)];
    if (!slot) slot = loadBody(p, vsop87Directory());
    return slot->body;
}

namespace {

// Sum over the powers of t of one coordinate; `rate` (if wanted) from the terms with
// |A| >= rateMinAmplitude (the series are sorted by decreasing |A|, so the loop can stop early).
inline void evalCoordinate(const VsopSeries* series, double t, double rateMinAmplitude, double& value, double& rate) {
    value = 0.0;
    rate = 0.0;
    double tk = 1.0;    // t^k
    double tkm1 = 0.0;  // k t^(k-1)
    for (int k = 0; k < 6; ++k) {
        const VsopSeries& s = series[k];
        double sum = 0.0;
        for (int i = 0; i < s.count; ++i) {
            const VsopTerm& term = s.terms[i];
            sum += term.a * detail::fastCos(term.b + term.c * t);
        }
        value += sum * tk;
        if (rateMinAmplitude >= 0.0) {
            double dsum = 0.0;
            for (int i = 0; i < s.count && std::fabs(s.terms[i].a) >= rateMinAmplitude; ++i) {
                const VsopTerm& term = s.terms[i];
                dsum -= term.a * term.c * detail::fastSin(term.b + term.c * t);
            }
            rate += dsum * tk + sum * tkm1;
        }
        tkm1 = (k + 1) * tk;
        tk *= t;
    }
}

}  // namespace

VsopState evaluate(const VsopBody& body, double t, bool rates) {
    VsopState s;
    // Rate amplitude floor: the rates serve light time (tau <= 0.2 day) and aberration; terms
    // below 1e-4 (rad or au) change a rate by < 1e-3 relative, i.e. the position by < 0.01".
    const double floor = rates ? 1e-4 : -1.0;
    double dl = 0, db = 0, dr = 0;
    evalCoordinate(body.L, t, floor, s.lbr.x, dl);
    evalCoordinate(body.B, t, floor, s.lbr.y, db);
    evalCoordinate(body.R, t, floor, s.lbr.z, dr);
    if (rates) s.rate = glm::dvec3(dl, db, dr) / 365250.0;  // per millennium -> per day
    return s;
}

// VSOP87 ecliptic J2000 (dynamical) -> FK5 equatorial J2000: the rotation published with VSOP87
// (obliquity 23 26' 21.41136" plus the small offsets of the dynamical equinox).
static glm::dvec3 eclipticToEquatorial(const glm::dvec3& x) {
    return {x.x + 0.000000440360 * x.y - 0.000000190919 * x.z,
            -0.000000479966 * x.x + 0.917482137087 * x.y - 0.397776982902 * x.z,
            0.397776982902 * x.y + 0.917482137087 * x.z};
}

glm::dvec3 vsopToEquatorialJ2000(const glm::dvec3& lbr) {
    const double cb = std::cos(lbr.y);
    return eclipticToEquatorial({lbr.z * cb * std::cos(lbr.x), lbr.z * cb * std::sin(lbr.x), lbr.z * std::sin(lbr.y)});
}

glm::dvec3 vsopRateToEquatorialJ2000(const glm::dvec3& lbr, const glm::dvec3& rate) {
    const double cl = std::cos(lbr.x), sl = std::sin(lbr.x), cb = std::cos(lbr.y), sb = std::sin(lbr.y);
    const double r = lbr.z;
    glm::dvec3 d(rate.z * cb * cl - r * sb * rate.y * cl - r * cb * sl * rate.x,
                 rate.z * cb * sl - r * sb * rate.y * sl + r * cb * cl * rate.x,
                 rate.z * sb + r * cb * rate.y);
    return eclipticToEquatorial(d);
}

}  // namespace welkin::astro
