// The lunar limb profile and the contacts' margins (welkin/astro/lunar_limb.hpp).
#include <welkin/astro/lunar_limb.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numbers>

namespace welkin::astro {

namespace {
constexpr double kPi = std::numbers::pi;
// The margins' scan of position angle: 0.05 deg (7200 points).
constexpr int kScan = 7200;
}  // namespace

const std::array<float, kLimbProfileSamples>& lunarLimbProfileMeters() {
    static const std::array<float, kLimbProfileSamples> table = [] {
        // splitmix64 with a fixed seed: the same profile on every machine.
        uint64_t state = 0x6c756e61726c696dull;
        auto next = [&] {
            uint64_t z = (state += 0x9e3779b97f4a7c15ull);
            z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
            z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
            return double((z ^ (z >> 31)) >> 11) * 0x1.0p-53;
        };
        std::array<double, kLimbProfileSamples> h{};
        for (int k = 4; k < kLimbProfileSamples / 2; ++k) {
            const double phase = 2.0 * kPi * next(), amp = 1.0 / k;
            for (int i = 0; i < kLimbProfileSamples; ++i) h[std::size_t(i)] += amp * std::cos(k * 2.0 * kPi * i / kLimbProfileSamples + phase);
        }
        double ss = 0;
        for (double x : h) ss += x * x;
        const double scale = kLimbProfileRmsMeters / std::sqrt(ss / kLimbProfileSamples);
        std::array<float, kLimbProfileSamples> out{};
        for (std::size_t i = 0; i < out.size(); ++i) out[i] = float(h[i] * scale);
        return out;
    }();
    return table;
}

double lunarLimbHeightMeters(double paRad) {
    const auto& t = lunarLimbProfileMeters();
    double f = paRad / (2.0 * kPi) * kLimbProfileSamples;
    f -= std::floor(f / kLimbProfileSamples) * kLimbProfileSamples;
    const int i0 = int(f) % kLimbProfileSamples, i1 = (i0 + 1) % kLimbProfileSamples;
    const double w = f - std::floor(f);
    return t[std::size_t(i0)] * (1.0 - w) + t[std::size_t(i1)] * w;
}

namespace {
double limbRadiusRad(const LimbGeometry& g, double theta) {
    const double h = g.profile ? lunarLimbHeightMeters(theta) : 0.0;
    return std::asin(std::min((kMoonMeanRadiusMeters + h) / g.moonDistanceM, 1.0));
}
}  // namespace

double limbCoverMargin(const LimbGeometry& g) {
    const double d = g.separationRad, rs = g.sunRadiusRad;
    if (!g.profile) return d + rs - limbRadiusRad(g, 0.0);
    double worst = -1e30;
    for (int i = 0; i < kScan; ++i) {
        const double theta = 2.0 * kPi * i / kScan, a = theta - g.sunPaRad;
        // The ray from the Moon's centre at theta leaves the Sun's disk (centre d along sunPa) at
        // rho = d cos a + sqrt(rs^2 - d^2 sin^2 a); a ray that misses the disk has nothing to cover.
        const double disc = rs * rs - d * d * std::sin(a) * std::sin(a);
        if (disc < 0.0) continue;
        const double rho = d * std::cos(a) + std::sqrt(disc);
        if (rho <= 0.0) continue;
        worst = std::max(worst, rho - limbRadiusRad(g, theta));
    }
    return worst;
}

double limbInsideMargin(const LimbGeometry& g) {
    const double d = g.separationRad, rs = g.sunRadiusRad;
    if (!g.profile) return d + limbRadiusRad(g, 0.0) - rs;
    double worst = -1e30;
    for (int i = 0; i < kScan; ++i) {
        const double theta = 2.0 * kPi * i / kScan, a = theta - g.sunPaRad, r = limbRadiusRad(g, theta);
        // The limb point at theta from the Sun's centre (law of cosines).
        worst = std::max(worst, std::sqrt(std::max(r * r + d * d - 2.0 * r * d * std::cos(a), 0.0)) - rs);
    }
    return worst;
}

}  // namespace welkin::astro
