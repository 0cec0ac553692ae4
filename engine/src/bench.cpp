// The benchmark harness's registry and its growth fit (welkin/bench.hpp).
#include <welkin/bench.hpp>

#include <cctype>
#include <cmath>
#include <cstddef>
#include <istream>
#include <sstream>

namespace welkin::bench {

std::vector<ElementBench>& elementBenches() {
    static std::vector<ElementBench> b;
    return b;
}

std::vector<CommandBench>& commandBenches() {
    static std::vector<CommandBench> b;
    return b;
}

namespace {
bool isRuntimeObject(const std::string& path) {
    for (const char* lib : {"libc.so", "libstdc++", "libm.so", "libgcc", "ld-linux"})
        if (path.find(lib) != std::string::npos) return true;
    return false;
}
}  // namespace

CallgrindCosts parseCallgrind(std::istream& in, const std::string& ownObject) {
    // "ob=" / "fn=" set the current object and function; "cob=" / "cfn=" name a call's target
    // (its object is the caller's when no "cob=" is given); a name's first use is "(id) name",
    // later ones "(id)". A cost line ("position Ir ...") right after "calls=" is that call's
    // inclusive cost; every other cost line is the current function's self cost.
    CallgrindCosts c;
    std::map<std::string, std::string> obNames, fnNames;
    auto name = [](std::map<std::string, std::string>& names, const std::string& rest) {
        if (rest.empty() || rest[0] != '(') return rest;
        const std::size_t close = rest.find(')');
        if (close == std::string::npos) return rest;
        const std::string id = rest.substr(0, close + 1);
        if (rest.size() > close + 2) names[id] = rest.substr(close + 2);
        return names[id];
    };
    std::string ob, fn, cob;
    bool ownOb = false, afterCalls = false, cobSet = false;
    std::string line;
    while (std::getline(in, line)) {
        if (line.empty()) continue;
        const char ch = line[0];
        if (std::isdigit(static_cast<unsigned char>(ch)) || ch == '+' || ch == '-' || ch == '*') {
            std::istringstream ls(line);
            std::string pos;
            double ir = 0;
            if (!(ls >> pos >> ir)) ir = 0;
            if (afterCalls) {
                afterCalls = false;
                if (ownOb && isRuntimeObject(cobSet ? cob : ob)) {
                    c.ownCalls += ir;
                    c.byFunction[fn] += ir;
                }
                cobSet = false;
                continue;
            }
            c.total += ir;
            if (ownOb) {
                c.own += ir;
                c.byFunction[fn] += ir;
            } else if (isRuntimeObject(ob)) {
                c.runtime += ir;
            }
        } else if (line.rfind("ob=", 0) == 0) {
            ob = name(obNames, line.substr(3));
            ownOb = ob == ownObject;
        } else if (line.rfind("fn=", 0) == 0) {
            fn = name(fnNames, line.substr(3));
        } else if (line.rfind("cob=", 0) == 0) {
            cob = name(obNames, line.substr(4));
            cobSet = true;
        } else if (line.rfind("cfn=", 0) == 0) {
            name(fnNames, line.substr(4));
        } else if (line.rfind("calls=", 0) == 0) {
            afterCalls = true;
        }
    }
    return c;
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
