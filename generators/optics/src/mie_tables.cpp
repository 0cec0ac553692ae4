// The Mie phase tables (see mie_tables.hpp).
#include <welkin/cache.hpp>
#include <welkin/check.hpp>
#include <welkin/color.hpp>
#include <welkin/error.hpp>
#include <welkin/generators/mie.hpp>
#include <welkin/generators/mie_tables.hpp>
#include <welkin/glsl_cpp.hpp>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <mutex>
#include <thread>

#include <unistd.h>

namespace welkin::glsl::dp::mie_angle_shared {
#include "mie_angle.shared.glsl"
}  // namespace welkin::glsl::dp::mie_angle_shared

namespace welkin::generators {

namespace {
constexpr double kDeg = M_PI / 180.0;
// Knots of the angle mapping (u, theta in degrees) for its inverse mieAngleFromU();
// mie_angle.shared.glsl (mieUFromAngle) holds the same numbers.
constexpr double kU[5] = {0.0, 0.25, 0.70, 0.80, 1.0};
constexpr double kTheta[5] = {0.0, 120.0, 150.0, 175.0, 180.0};
constexpr double kWaterDensity = 998.2;  // kg/m^3 at 20 degC
// Bump when the table's math or layout changes: part of the cache file's hash.
constexpr const char* kTableVersion = "welkin-mie-table-2";
// Mean apparent angular radius of the Sun: 959.63 arcsec at 1 AU (IAU 2015 nominal solar
// radius / 1 AU), 0.2666 deg.
constexpr double kSunRadius = 959.63 / 3600.0 * kDeg;

uint64_t fnv1a(const std::string& s) {
    uint64_t h = 1469598103934665603ull;
    for (unsigned char c : s) {
        h ^= c;
        h *= 1099511628211ull;
    }
    return h;
}
}  // namespace

double mieAngleFromU(double u) {
    u = std::clamp(u, 0.0, 1.0);
    int i = 0;
    while (i < 3 && u > kU[i + 1]) ++i;
    const double t = (u - kU[i]) / (kU[i + 1] - kU[i]);
    return (kTheta[i] + t * (kTheta[i + 1] - kTheta[i])) * kDeg;
}

// The shaders' text, mie_angle.shared.glsl, in double (the knots below hold the same numbers).
double mieUFromAngle(double theta) { return glsl::dp::mie_angle_shared::welkin_mieUFromAngle(theta); }

// --- Distributions ------------------------------------------------------------------------------

DropDistribution DropDistribution::gamma(double rEffM, double vEff, double rateMmH) {
    DropDistribution d;
    d.kind = Kind::Gamma;
    d.effectiveRadiusM = rEffM;
    d.effectiveVariance = vEff;
    d.rateMmH = rateMmH;
    d.validate();
    return d;
}

DropDistribution DropDistribution::marshallPalmer(double rateMmH) {
    DropDistribution d;
    d.kind = Kind::MarshallPalmer;
    d.rateMmH = rateMmH;
    d.validate();
    return d;
}

void DropDistribution::validate() const {
    checkRange("DropDistribution", "rate (mm/h)", rateMmH, 0.0, 200.0);
    if (kind == Kind::Gamma) {
        checkRange("DropDistribution", "effective radius (m)", effectiveRadiusM, 5e-6, 2e-3);
        checkRange("DropDistribution", "effective variance", effectiveVariance, 1e-3, 0.5);
    } else if (rateMmH <= 0.0) {
        throw Error("DropDistribution: Marshall-Palmer needs a rate > 0 mm/h (got 0)");
    }
}

double DropDistribution::rEff() const {
    if (kind == Kind::Gamma) return effectiveRadiusM;
    const double lambdaPerM = 4.1e3 * std::pow(rateMmH, -0.21);
    return std::clamp(1.5 / lambdaPerM, 5e-6, 2e-3);
}

double liquidWaterContent(double rateMmH) {
    return rateMmH <= 0.0 ? 0.0 : 0.0889e-3 * std::pow(rateMmH, 0.84);
}

std::vector<double> DropDistribution::binConcentrations(const std::vector<double>& radii, double ratio) const {
    std::vector<double> w(radii.size(), 0.0);
    const double dlnr = std::log(ratio);
    double logMax = -1e300;
    std::vector<double> logn(radii.size());
    for (std::size_t i = 0; i < radii.size(); ++i) {
        const double r = radii[i];
        // log of n(r) r dln r (number per log-radius bin), up to a constant.
        if (kind == Kind::Gamma) {
            const double v = effectiveVariance, a = (1.0 - 3.0 * v) / v;
            logn[i] = a * std::log(r) - r / (effectiveRadiusM * v) + std::log(r * dlnr);
        } else {
            const double lambdaPerM = 4.1e3 * std::pow(rateMmH, -0.21);  // per metre of diameter
            logn[i] = -lambdaPerM * 2.0 * r + std::log(r * dlnr);
        }
        logMax = std::max(logMax, logn[i]);
    }
    double water = 0.0;
    for (std::size_t i = 0; i < radii.size(); ++i) {
        w[i] = std::exp(logn[i] - logMax);
        water += w[i] * 4.0 / 3.0 * M_PI * radii[i] * radii[i] * radii[i] * kWaterDensity;
    }
    const double W = liquidWaterContent(rateMmH);
    for (double& x : w) x *= (water > 0.0 ? W / water : 0.0);
    return w;
}

// --- The 2-D table ------------------------------------------------------------------------------

MieTable::Quality MieTable::quality(const std::string& name) {
    Quality q;
    q.name = name;
    if (name == "low") {
        q.wavelengths = 32; q.radii = 24; q.angles = 256; q.subRadii = 1;
    } else if (name == "default") {
        q.wavelengths = 32; q.radii = 48; q.angles = 512; q.subRadii = 1;
    } else if (name == "high") {
        q.wavelengths = 40; q.radii = 96; q.angles = 1024; q.subRadii = 2;
    } else {
        throw Error("MieTable::quality(): '" + name + "' is not one of low, default, high");
    }
    return q;
}

uint64_t MieTable::hash() const {
    char buf[256];
    std::snprintf(buf, sizeof buf, "%s|%d|%d|%d|%d|%.9g|%.9g", kTableVersion, q.wavelengths, q.radii, q.angles,
                  q.subRadii, q.rMinM, q.rMaxM);
    return fnv1a(buf);
}

MieTable MieTable::build(const Quality& q, int threads) {
    checkRange("MieTable::build()", "wavelengths", q.wavelengths, 30, 400);
    checkRange("MieTable::build()", "radii", q.radii, 2, 1024);
    checkRange("MieTable::build()", "angles", q.angles, 16, 16384);
    checkRange("MieTable::build()", "subRadii", q.subRadii, 1, 16);
    checkRange("MieTable::build()", "rMinM", q.rMinM, 1e-7, 1e-2);
    checkRange("MieTable::build()", "rMaxM", q.rMaxM, q.rMinM, 2.5e-3);
    const auto t0 = std::chrono::steady_clock::now();
    MieTable t;
    t.q = q;
    const int R = q.radii, A = q.angles, L = q.wavelengths;
    const double ratio = std::pow(q.rMaxM / q.rMinM, 1.0 / (R - 1));
    for (int i = 0; i < R; ++i) t.radiiM.push_back(q.rMinM * std::pow(ratio, i));
    std::vector<double> lambda(static_cast<std::size_t>(L)), mu(static_cast<std::size_t>(A));
    for (int l = 0; l < L; ++l) lambda[std::size_t(l)] = 380.0 + 400.0 * l / (L - 1);
    for (int a = 0; a < A; ++a) mu[std::size_t(a)] = std::cos(mieAngleFromU((a + 0.5) / A));
    // Channel weights w_c S (the solar spectrum through CIE 1931 into linear sRGB).
    const std::vector<glm::dvec3> w = color::spectralToLinearSrgbWeights(lambda);
    std::vector<glm::dvec3> ws(static_cast<std::size_t>(L));
    glm::dvec3 wsSum(0.0);
    for (int l = 0; l < L; ++l) {
        ws[std::size_t(l)] = w[std::size_t(l)] * color::solarIrradianceAstmG173(lambda[std::size_t(l)]);
        wsSum += ws[std::size_t(l)];
    }
    std::vector<std::complex<double>> m(static_cast<std::size_t>(L));
    for (int l = 0; l < L; ++l) m[std::size_t(l)] = waterRefractiveIndex(lambda[std::size_t(l)]);

    // Jobs: one per radius (all wavelengths and sub-radii), the largest first for load balance.
    std::vector<glm::dvec3> phaseAcc(std::size_t(R) * std::size_t(A), glm::dvec3(0.0));
    t.csca.assign(std::size_t(R), glm::dvec3(0.0));
    t.cext.assign(std::size_t(R), glm::dvec3(0.0));
    std::atomic<int> next{0};
    std::atomic<bool> failed{false};
    std::string error;
    std::mutex errorMutex;
    auto worker = [&] {
        std::vector<double> p;
        while (!failed) {
            const int job = next++;
            if (job >= R) break;
            const int ri = R - 1 - job;
            try {
                glm::dvec3 sca(0.0), ext(0.0);
                glm::dvec3* acc = &phaseAcc[std::size_t(ri) * std::size_t(A)];
                // Small drops get more sub-radii: their interference rings are wide (period ~pi/x)
                // and one radius per bin would print them into the table (rings in fogbows and
                // glories), while their terms are cheap: S = max(subRadii, min(16, 4000 / x_380nm))
                // adds < 10 % to the build.
                const double x380 = 2.0 * M_PI * t.radiiM[std::size_t(ri)] / 380e-9;
                const int S = std::max(q.subRadii, std::min(16, int(4000.0 / x380)));
                for (int s = 0; s < S; ++s) {
                    // Sub-radii spread evenly (in log) over the bin [r / sqrt(ratio), r sqrt(ratio)].
                    const double r = t.radiiM[std::size_t(ri)] * std::pow(ratio, (s + 0.5) / S - 0.5);
                    for (int l = 0; l < L; ++l) {
                        const double x = 2.0 * M_PI * r / (lambda[std::size_t(l)] * 1e-9);
                        MieSphere sphere(m[std::size_t(l)], x);
                        const double area = M_PI * r * r / S;
                        const double cs = sphere.qsca() * area, ce = sphere.qext() * area;
                        const glm::dvec3 wl = ws[std::size_t(l)] / wsSum;
                        sca += wl * cs;
                        ext += wl * ce;
                        sphere.phases(mu, p);
                        for (int a = 0; a < A; ++a) acc[a] += wl * (cs * p[std::size_t(a)]);
                    }
                }
                t.csca[std::size_t(ri)] = sca;
                t.cext[std::size_t(ri)] = ext;
            } catch (const std::exception& e) {
                std::lock_guard<std::mutex> lock(errorMutex);
                error = e.what();
                failed = true;
            }
        }
    };
    const int n = threads > 0 ? threads : std::max(1, int(std::thread::hardware_concurrency()));
    std::vector<std::thread> pool;
    for (int i = 0; i < n; ++i) pool.emplace_back(worker);
    for (auto& th : pool) th.join();
    if (failed) throw Error("MieTable::build(): " + error);
    t.phase.resize(phaseAcc.size());
    for (int ri = 0; ri < R; ++ri)
        for (int a = 0; a < A; ++a) {
            const std::size_t k = std::size_t(ri) * std::size_t(A) + std::size_t(a);
            t.phase[k] = glm::vec3(phaseAcc[k] / t.csca[std::size_t(ri)]);
        }
    t.buildSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return t;
}

std::string MieTable::cachePath(const Quality& q) {
    MieTable t;
    t.q = q;
    const std::filesystem::path dir = cacheDirectory();
    char name[64];
    std::snprintf(name, sizeof name, "mie-%016llx.bin", static_cast<unsigned long long>(t.hash()));
    return (dir / name).string();
}

namespace {
bool readCache(const std::string& path, MieTable& t) {
    std::ifstream in(path, std::ios::binary);
    if (!in) return false;
    uint64_t h = 0;
    int32_t r = 0, a = 0;
    in.read(reinterpret_cast<char*>(&h), sizeof h);
    in.read(reinterpret_cast<char*>(&r), sizeof r);
    in.read(reinterpret_cast<char*>(&a), sizeof a);
    if (!in || h != t.hash() || r != t.q.radii || a != t.q.angles) return false;
    t.radiiM.resize(std::size_t(r));
    t.csca.resize(std::size_t(r));
    t.cext.resize(std::size_t(r));
    t.phase.resize(std::size_t(r) * std::size_t(a));
    in.read(reinterpret_cast<char*>(t.radiiM.data()), std::streamsize(t.radiiM.size() * sizeof(double)));
    in.read(reinterpret_cast<char*>(t.csca.data()), std::streamsize(t.csca.size() * sizeof(glm::dvec3)));
    in.read(reinterpret_cast<char*>(t.cext.data()), std::streamsize(t.cext.size() * sizeof(glm::dvec3)));
    in.read(reinterpret_cast<char*>(t.phase.data()), std::streamsize(t.phase.size() * sizeof(glm::vec3)));
    return bool(in) && in.peek() == std::char_traits<char>::eof();
}

void writeCache(const std::string& path, const MieTable& t) {
    std::error_code ec;
    std::filesystem::create_directories(std::filesystem::path(path).parent_path(), ec);
    // A temporary name unique to this process and thread, renamed over the final name when complete.
    const std::string tmp = path + ".tmp" + std::to_string(::getpid()) + "-" +
                            std::to_string(std::hash<std::thread::id>{}(std::this_thread::get_id()));
    {
        std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
        if (!out) return;
        const uint64_t h = t.hash();
        const int32_t r = t.q.radii, a = t.q.angles;
        out.write(reinterpret_cast<const char*>(&h), sizeof h);
        out.write(reinterpret_cast<const char*>(&r), sizeof r);
        out.write(reinterpret_cast<const char*>(&a), sizeof a);
        out.write(reinterpret_cast<const char*>(t.radiiM.data()), std::streamsize(t.radiiM.size() * sizeof(double)));
        out.write(reinterpret_cast<const char*>(t.csca.data()), std::streamsize(t.csca.size() * sizeof(glm::dvec3)));
        out.write(reinterpret_cast<const char*>(t.cext.data()), std::streamsize(t.cext.size() * sizeof(glm::dvec3)));
        out.write(reinterpret_cast<const char*>(t.phase.data()), std::streamsize(t.phase.size() * sizeof(glm::vec3)));
        if (!out) {
            out.close();
            std::filesystem::remove(tmp, ec);
            return;
        }
    }
    std::filesystem::rename(tmp, path, ec);  // atomic on POSIX: readers see the old file or the new one
    if (ec) std::filesystem::remove(tmp, ec);
}
}  // namespace

const MieTable& MieTable::cached(const Quality& q) {
    static std::mutex mutex;
    static std::map<uint64_t, std::unique_ptr<MieTable>> tables;
    std::lock_guard<std::mutex> lock(mutex);
    MieTable probe;
    probe.q = q;
    const uint64_t h = probe.hash();
    auto it = tables.find(h);
    if (it != tables.end()) return *it->second;
    auto t = std::make_unique<MieTable>();
    t->q = q;
    const std::string path = cachePath(q);
    if (readCache(path, *t)) {
        t->fromCache = true;
    } else {
        *t = build(q);
        writeCache(path, *t);
    }
    return *tables.emplace(h, std::move(t)).first->second;
}

// --- The 1-D table ------------------------------------------------------------------------------

glm::dvec3 MiePhase1D::phaseAt(double theta) const {
    const int A = int(phase.size());
    const double f = mieUFromAngle(theta) * A - 0.5;
    const int i0 = std::clamp(int(std::floor(f)), 0, A - 1), i1 = std::min(i0 + 1, A - 1);
    const double t = std::clamp(f - std::floor(f), 0.0, 1.0);
    if (f < 0.0) return glm::dvec3(phase[0]);
    return glm::dvec3(phase[std::size_t(i0)]) * (1.0 - t) + glm::dvec3(phase[std::size_t(i1)]) * t;
}

MiePhase1D integrate(const MieTable& table, const DropDistribution& d, SunDisk sun) {
    d.validate();
    const int A = table.q.angles, R = int(table.radiiM.size());
    const std::vector<double> N = d.binConcentrations(table.radiiM, table.radiusRatio());
    MiePhase1D out;
    out.rEffM = d.rEff();
    std::vector<glm::dvec3> acc(std::size_t(A), glm::dvec3(0.0));
    for (int ri = 0; ri < R; ++ri) {
        const double n = N[std::size_t(ri)];
        if (n <= 0.0) continue;
        const glm::dvec3 s = n * table.csca[std::size_t(ri)];
        out.scatteringPerM += s;
        out.extinctionPerM += n * table.cext[std::size_t(ri)];
        const glm::vec3* p = &table.phase[std::size_t(ri) * std::size_t(A)];
        for (int a = 0; a < A; ++a) acc[std::size_t(a)] += s * glm::dvec3(p[a]);
    }
    // Unit-concentration phase when there is no water (rate 0): the shape of the distribution
    // still defines the table (it is used only where some rain is).
    glm::dvec3 norm = out.scatteringPerM;
    if (norm.x <= 0.0) {
        const DropDistribution unit = [&] { DropDistribution u = d; u.rateMmH = 1.0; return u; }();
        const std::vector<double> N1 = unit.binConcentrations(table.radiiM, table.radiusRatio());
        std::fill(acc.begin(), acc.end(), glm::dvec3(0.0));
        norm = glm::dvec3(0.0);
        for (int ri = 0; ri < R; ++ri) {
            const glm::dvec3 s = N1[std::size_t(ri)] * table.csca[std::size_t(ri)];
            norm += s;
            const glm::vec3* p = &table.phase[std::size_t(ri) * std::size_t(A)];
            for (int a = 0; a < A; ++a) acc[std::size_t(a)] += s * glm::dvec3(p[a]);
        }
    }
    MiePhase1D bare;
    bare.phase.resize(std::size_t(A));
    for (int a = 0; a < A; ++a) bare.phase[std::size_t(a)] = glm::vec3(acc[std::size_t(a)] / norm);
    out.phase.resize(std::size_t(A));
    for (int a = 0; a < A; ++a) {
        const double theta = mieAngleFromU((a + 0.5) / A);
        glm::dvec3 v(0.0);
        if (sun == SunDisk::Point) {
            v = glm::dvec3(bare.phase[std::size_t(a)]);
        } else {
            // A uniform disk seen across the bow: its brightness profile along the radial direction
            // is a semicircle, weight sqrt(1 - (t/alpha)^2) (valid where the bow's radius >> 0.27 deg;
            // at the anti-solar point it blurs the glory radially only). 33 points, midpoint rule.
            constexpr int K = 33;
            double wsum = 0.0;
            for (int k = 0; k < K; ++k) {
                const double s = -1.0 + (2.0 * k + 1.0) / K;
                const double wk = std::sqrt(1.0 - s * s);
                double th = theta + s * kSunRadius;
                if (th > M_PI) th = 2.0 * M_PI - th;  // across the anti-solar point
                if (th < 0.0) th = -th;
                v += wk * bare.phaseAt(th);
                wsum += wk;
            }
            v /= wsum;
        }
        out.phase[std::size_t(a)] = glm::vec3(glm::max(v, glm::dvec3(0.0)));  // gamut clip (see header)
    }
    return out;
}

}  // namespace welkin::generators
