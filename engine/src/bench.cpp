// The benchmark harness's registry and its growth fit (welkin/bench.hpp).
#include <welkin/bench.hpp>

#include <cmath>
#include <cstddef>

namespace welkin::bench {

std::vector<ElementBench>& elementBenches() {
    static std::vector<ElementBench> b;
    return b;
}

double fitGrowthExponent(const std::vector<double>& x, const std::vector<double>& y) {
    double sx = 0, sy = 0, sxx = 0, sxy = 0;
    int n = 0;
    for (std::size_t i = 0; i < x.size() && i < y.size(); ++i) {
        if (!(x[i] > 0) || !(y[i] > 0) || !std::isfinite(x[i]) || !std::isfinite(y[i])) continue;
        const double lx = std::log(x[i]), ly = std::log(y[i]);
        sx += lx, sy += ly, sxx += lx * lx, sxy += lx * ly;
        ++n;
    }
    const double d = n * sxx - sx * sx;
    if (n < 2 || !(std::abs(d) > 1e-12)) return NAN;
    return (n * sxy - sx * sy) / d;
}

}  // namespace welkin::bench
