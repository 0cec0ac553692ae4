// The clouds' reference path tracer and the slab adding-doubling solver (reference_clouds.hpp).
#include <welkin/error.hpp>
#include <welkin/generators/mie.hpp>
#include <welkin/generators/reference_clouds.hpp>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <numbers>
#include <string>
#include <thread>

namespace welkin::cloudref {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kInf = std::numeric_limits<double>::infinity();

double luminance(const glm::dvec3& c) { return 0.2126 * c.r + 0.7152 * c.g + 0.0722 * c.b; }

/// An orthonormal frame around unit n (Duff et al. 2017).
void basis(const glm::dvec3& n, glm::dvec3& t, glm::dvec3& b) {
    const double s = std::copysign(1.0, n.z);
    const double a = -1.0 / (s + n.z);
    const double c = n.x * n.y * a;
    t = {1.0 + s * n.x * n.x * a, s * c, -s * n.x};
    b = {c, s + n.y * n.y * a, -n.y};
}

/// The direction at cos(theta) = mu from d, at azimuth phi.
glm::dvec3 turn(const glm::dvec3& d, double mu, double phi) {
    glm::dvec3 t, b;
    basis(d, t, b);
    const double s = std::sqrt(std::max(0.0, 1.0 - mu * mu));
    return glm::normalize(mu * d + s * (std::cos(phi) * t + std::sin(phi) * b));
}

/// Interval of t where the ray is inside the sphere of radius r about (0, 0, -R): the quadratic
/// in the cancellation-free form |o + R z|^2 - r^2 = |o|^2 + 2 R o.z - (r - R)(r + R).
bool sphereInterval(const glm::dvec3& o, const glm::dvec3& d, double R, double r, double& t0, double& t1) {
    const glm::dvec3 oc = o + glm::dvec3(0.0, 0.0, R);
    const double b = glm::dot(oc, d);
    const double c = glm::dot(o, o) + 2.0 * R * o.z - (r - R) * (r + R);
    const double disc = b * b - c;
    if (disc < 0.0) return false;
    const double s = std::sqrt(disc);
    // Stable roots: q = -(b + sign(b) s), roots q and c / q.
    const double q = -(b + std::copysign(s, b));
    double a0 = q, a1 = (q != 0.0) ? c / q : -b;
    if (a0 > a1) std::swap(a0, a1);
    t0 = a0;
    t1 = a1;
    return true;
}

/// Distance to the ground along the ray (kInf if none), and its outward normal there.
double groundHit(const Ground& g, const glm::dvec3& o, const glm::dvec3& d, glm::dvec3& n) {
    if (g.kind == Ground::Kind::Plane) {
        if (d.z >= 0.0 || o.z <= g.heightM) return kInf;
        n = {0.0, 0.0, 1.0};
        return (g.heightM - o.z) / d.z;
    }
    if (g.kind == Ground::Kind::Sphere) {
        double t0, t1;
        if (!sphereInterval(o, d, g.radiusM, g.radiusM, t0, t1)) return kInf;
        if (!(t0 > 1e-3)) return kInf;  // behind, or the point just left (offset 1e-6 m along the normal)
        const double t = t0;
        n = glm::normalize(o + t * d + glm::dvec3(0.0, 0.0, g.radiusM));
        return t;
    }
    return kInf;
}

/// Delta tracking: the distance to the first real collision within [0, tMax] (true), or false.
bool deltaTrack(const Medium& m, const glm::dvec3& o, const glm::dvec3& d, double tMax, Rng& rng, double& tHit) {
    Interval iv[4];
    const int n = m.support(o, d, tMax, iv);
    const double maj = m.majorantPerM();
    for (int k = 0; k < n; ++k) {
        double t = iv[k].t0;
        for (;;) {
            t -= std::log1p(-rng.uniform()) / maj;
            if (t >= iv[k].t1) break;
            if (rng.uniform() * maj < m.extinctionPerM(o + t * d)) {
                tHit = t;
                return true;
            }
        }
    }
    return false;
}

/// The Sun's transmittance from p: 0 behind the ground, else ratio tracking.
double sunTransmittance(const Scene& s, const glm::dvec3& p, Rng& rng) {
    glm::dvec3 n;
    if (std::isfinite(groundHit(s.ground, p, s.lights.sunDirection, n))) return 0.0;
    return ratioTrackingTransmittance(*s.medium, p, s.lights.sunDirection, kInf, rng);
}

/// One path's radiance (see the header's method).
glm::dvec3 tracePath(const Scene& s, glm::dvec3 o, glm::dvec3 d, Rng& rng) {
    glm::dvec3 L(0.0);
    double thr = 1.0;
    const bool sun = s.lights.sunIrradiance != glm::dvec3(0.0);
    long collisions = 0;
    for (long k = 0; k <= 4 * s.maxScatterings + 16; ++k) {
        glm::dvec3 n(0.0);
        const double tg = groundHit(s.ground, o, d, n);
        double t = 0.0;
        if (deltaTrack(*s.medium, o, d, tg, rng, t)) {
            const glm::dvec3 p = o + t * d;
            thr *= s.medium->albedo(p);
            if (sun) {
                const double tr = sunTransmittance(s, p, rng);
                if (tr > 0.0) L += thr * s.phase->eval(glm::dot(d, s.lights.sunDirection)) * tr * s.lights.sunIrradiance;
            }
            if (++collisions >= s.maxScatterings) break;
            d = turn(d, s.phase->sampleCos(rng.uniform()), 2.0 * kPi * rng.uniform());
            o = p;
            continue;
        }
        if (std::isfinite(tg)) {
            if (s.ground.albedo <= 0.0) break;
            const glm::dvec3 p = o + tg * d + 1e-6 * n;
            thr *= s.ground.albedo;
            const double cs = glm::dot(n, s.lights.sunDirection);
            if (sun && cs > 0.0) {
                const double tr = ratioTrackingTransmittance(*s.medium, p, s.lights.sunDirection, kInf, rng);
                L += thr / kPi * cs * tr * s.lights.sunIrradiance;
            }
            // Cosine-weighted hemisphere (the Lambertian BRDF's weight is its albedo).
            const double u = rng.uniform();
            d = turn(n, std::sqrt(1.0 - u), 2.0 * kPi * rng.uniform());
            o = p;
            continue;
        }
        if (s.lights.sky) L += thr * s.lights.sky(d);
        break;
    }
    return L;
}

void checkScene(const Scene& s) {
    if (!s.medium || !s.phase) throw Error("cloudref::Scene: medium and phase must be set");
    if (!(s.ground.albedo >= 0.0 && s.ground.albedo <= 1.0)) throw Error("cloudref::Ground::albedo: must be in [0, 1]");
}

struct Sums {
    glm::dvec3 s{0.0}, s2{0.0};
    double y = 0.0, y2 = 0.0;
};

Sums radianceSums(const Scene& s, const glm::dvec3& o, const glm::dvec3& d, int paths, uint64_t seed, uint64_t stream) {
    Rng rng(seed, stream);
    Sums r;
    for (int i = 0; i < paths; ++i) {
        const glm::dvec3 L = tracePath(s, o, d, rng);
        r.s += L;
        r.s2 += L * L;
        const double y = luminance(L);
        r.y += y;
        r.y2 += y * y;
    }
    return r;
}

double sigmaOfMean(double s, double s2, double n) {
    if (n < 2) return 0.0;
    const double mean = s / n;
    return std::sqrt(std::max(0.0, (s2 / n - mean * mean) / (n - 1.0)));
}

/// Gauss-Legendre nodes and weights on [0, 1] (Newton on P_n from Tricomi's initial guess).
void gaussLegendre01(int n, std::vector<double>& x, std::vector<double>& w) {
    x.assign(n, 0.0);
    w.assign(n, 0.0);
    for (int i = 0; i < n; ++i) {
        double z = std::cos(kPi * (i + 0.75) / (n + 0.5)), dp = 1.0;
        for (int it = 0; it < 100; ++it) {
            double p0 = 1.0, p1 = z;
            for (int k = 2; k <= n; ++k) {
                const double p2 = ((2.0 * k - 1.0) * z * p1 - (k - 1.0) * p0) / k;
                p0 = p1;
                p1 = p2;
            }
            dp = n * (z * p1 - p0) / (z * z - 1.0);
            const double dz = p1 / dp;
            z -= dz;
            if (std::abs(dz) < 1e-16) break;
        }
        x[i] = 0.5 * (1.0 - z);
        w[i] = 1.0 / ((1.0 - z * z) * dp * dp);  // 2 / ((1 - z^2) P'^2) halved for [0, 1]
    }
}

using Mat = std::vector<double>;  // n x n, row major

Mat matMul(const Mat& a, const Mat& b, int n) {
    Mat c(size_t(n) * n, 0.0);
    for (int i = 0; i < n; ++i)
        for (int k = 0; k < n; ++k) {
            const double v = a[size_t(i) * n + k];
            for (int j = 0; j < n; ++j) c[size_t(i) * n + j] += v * b[size_t(k) * n + j];
        }
    return c;
}
std::vector<double> matVec(const Mat& a, const std::vector<double>& v, int n) {
    std::vector<double> r(n, 0.0);
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j) r[i] += a[size_t(i) * n + j] * v[j];
    return r;
}
/// Gauss-Jordan inverse with partial pivoting.
Mat matInverse(Mat a, int n) {
    Mat inv(size_t(n) * n, 0.0);
    for (int i = 0; i < n; ++i) inv[size_t(i) * n + i] = 1.0;
    for (int c = 0; c < n; ++c) {
        int p = c;
        for (int r = c + 1; r < n; ++r)
            if (std::abs(a[size_t(r) * n + c]) > std::abs(a[size_t(p) * n + c])) p = r;
        if (a[size_t(p) * n + c] == 0.0) throw Error("cloudref::addingDoubling: singular matrix");
        for (int j = 0; j < n; ++j) {
            std::swap(a[size_t(c) * n + j], a[size_t(p) * n + j]);
            std::swap(inv[size_t(c) * n + j], inv[size_t(p) * n + j]);
        }
        const double piv = 1.0 / a[size_t(c) * n + c];
        for (int j = 0; j < n; ++j) {
            a[size_t(c) * n + j] *= piv;
            inv[size_t(c) * n + j] *= piv;
        }
        for (int r = 0; r < n; ++r) {
            if (r == c) continue;
            const double f = a[size_t(r) * n + c];
            if (f == 0.0) continue;
            for (int j = 0; j < n; ++j) {
                a[size_t(r) * n + j] -= f * a[size_t(c) * n + j];
                inv[size_t(r) * n + j] -= f * inv[size_t(c) * n + j];
            }
        }
    }
    return inv;
}

}  // namespace

// ---- Rng ----------------------------------------------------------------------------------------

Rng::Rng(uint64_t seed, uint64_t stream) {
    // SplitMix64 of the stream decorrelates neighbouring pixels' sequences.
    uint64_t z = stream + 0x9e3779b97f4a7c15ULL;
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    z ^= z >> 31;
    inc_ = (z << 1u) | 1u;
    state_ = 0;
    next();
    state_ += seed * 0x2545F4914F6CDD1DULL + 0x853c49e6748fea9bULL;
    next();
}

uint32_t Rng::next() {
    const uint64_t old = state_;
    state_ = old * 6364136223846793005ULL + inc_;
    const uint32_t xorshifted = uint32_t(((old >> 18u) ^ old) >> 27u);
    const uint32_t rot = uint32_t(old >> 59u);
    return (xorshifted >> rot) | (xorshifted << ((32u - rot) & 31u));
}

double Rng::uniform() {
    const uint64_t hi = next(), lo = next();
    return double(((hi << 32) | lo) >> 11) * 0x1.0p-53;
}

// ---- Media --------------------------------------------------------------------------------------

SlabMedium::SlabMedium(double z0, double z1, double extinctionPerM) : z0_(z0), z1_(z1), sigma_(extinctionPerM) {
    if (!(z1 > z0)) throw Error("cloudref::SlabMedium: z1 must be above z0");
    if (!(extinctionPerM > 0.0) || !std::isfinite(extinctionPerM)) throw Error("cloudref::SlabMedium: extinction must be > 0");
}

double SlabMedium::extinctionPerM(const glm::dvec3& p) const { return (p.z >= z0_ && p.z <= z1_) ? sigma_ : 0.0; }

int SlabMedium::support(const glm::dvec3& o, const glm::dvec3& d, double tMax, Interval out[4]) const {
    double t0, t1;
    if (d.z == 0.0) {
        if (o.z < z0_ || o.z > z1_) return 0;
        t0 = 0.0;
        t1 = kInf;
    } else {
        const double a = (z0_ - o.z) / d.z, b = (z1_ - o.z) / d.z;
        t0 = std::max(0.0, std::min(a, b));
        t1 = std::max(a, b);
    }
    t1 = std::min(t1, tMax);
    if (t1 <= t0) return 0;
    out[0] = {t0, t1};
    return 1;
}

BoxMedium::BoxMedium(glm::dvec3 lo, glm::dvec3 hi, double sigmaMaxPerM, std::function<double(const glm::dvec3&)> density)
    : lo_(lo), hi_(hi), sigma_(sigmaMaxPerM), density_(std::move(density)) {
    if (!(hi.x > lo.x && hi.y > lo.y && hi.z > lo.z)) throw Error("cloudref::BoxMedium: hi must exceed lo on every axis");
    if (!(sigmaMaxPerM > 0.0) || !std::isfinite(sigmaMaxPerM)) throw Error("cloudref::BoxMedium: extinction must be > 0");
}

bool BoxMedium::contains(const glm::dvec3& p) const {
    return p.x >= lo_.x && p.x <= hi_.x && p.y >= lo_.y && p.y <= hi_.y && p.z >= lo_.z && p.z <= hi_.z;
}

double BoxMedium::extinctionPerM(const glm::dvec3& p) const {
    if (!contains(p)) return 0.0;
    return density_ ? sigma_ * std::clamp(density_(p), 0.0, 1.0) : sigma_;
}

int BoxMedium::support(const glm::dvec3& o, const glm::dvec3& d, double tMax, Interval out[4]) const {
    double t0 = 0.0, t1 = tMax;
    for (int a = 0; a < 3; ++a) {
        if (d[a] == 0.0) {
            if (o[a] < lo_[a] || o[a] > hi_[a]) return 0;
            continue;
        }
        double ta = (lo_[a] - o[a]) / d[a], tb = (hi_[a] - o[a]) / d[a];
        if (ta > tb) std::swap(ta, tb);
        t0 = std::max(t0, ta);
        t1 = std::min(t1, tb);
    }
    if (t1 <= t0) return 0;
    out[0] = {t0, t1};
    return 1;
}

CloudFieldMedium::CloudFieldMedium(const generators::CloudLayerBlock& block, const generators::cpu::CloudTextures& textures,
                                   generators::CloudLod lod)
    : block_(block), tex_(textures), lod_(lod) {
    R_ = block.radii[0];
    rb_ = block.radii[1];
    rt_ = block.radii[2];
    sigma_ = block.shape[2];
    albedo_ = 0.99999;
    if (!(sigma_ > 0.0)) throw Error("cloudref::CloudFieldMedium: clouds.scattering_per_m must be > 0");
}

double CloudFieldMedium::extinctionPerM(const glm::dvec3& p) const {
    return sigma_ * generators::cpu::cloudDensity(block_, tex_, p, lod_);
}

int CloudFieldMedium::support(const glm::dvec3& o, const glm::dvec3& d, double tMax, Interval out[4]) const {
    double a0, a1;
    if (!sphereInterval(o, d, R_, rt_, a0, a1)) return 0;
    a0 = std::max(a0, 0.0);
    a1 = std::min(a1, tMax);
    if (a1 <= a0) return 0;
    double b0, b1;
    int n = 0;
    if (!sphereInterval(o, d, R_, rb_, b0, b1) || b1 <= a0 || b0 >= a1) {
        out[n++] = {a0, a1};
        return n;
    }
    if (b0 > a0) out[n++] = {a0, b0};
    if (b1 < a1) out[n++] = {b1, a1};
    return n;
}

double ratioTrackingTransmittance(const Medium& m, const glm::dvec3& o, const glm::dvec3& d, double tMax, Rng& rng) {
    Interval iv[4];
    const int n = m.support(o, d, tMax, iv);
    const double maj = m.majorantPerM();
    double T = 1.0;
    for (int k = 0; k < n; ++k) {
        double t = iv[k].t0;
        for (;;) {
            t -= std::log1p(-rng.uniform()) / maj;
            if (t >= iv[k].t1) break;
            T *= 1.0 - m.extinctionPerM(o + t * d) / maj;
            if (T < 1e-30) return 0.0;  // below any output's resolution
        }
    }
    return T;
}

// ---- Phase functions ----------------------------------------------------------------------------

HenyeyGreenstein::HenyeyGreenstein(double g) : g_(g) {
    if (!(g > -1.0 && g < 1.0)) throw Error("cloudref::HenyeyGreenstein: g must be in (-1, 1)");
}

double HenyeyGreenstein::eval(double mu) const {
    const double d = 1.0 + g_ * g_ - 2.0 * g_ * mu;
    return (1.0 - g_ * g_) / (4.0 * kPi * d * std::sqrt(d));
}

double HenyeyGreenstein::sampleCos(double u) const {
    if (std::abs(g_) < 1e-6) return 1.0 - 2.0 * u;
    const double s = (1.0 - g_ * g_) / (1.0 - g_ + 2.0 * g_ * u);
    return std::clamp((1.0 + g_ * g_ - s * s) / (2.0 * g_), -1.0, 1.0);
}

TabulatedPhase::TabulatedPhase(const std::vector<double>& theta, const std::vector<double>& phase) {
    if (theta.size() < 2 || theta.size() != phase.size()) throw Error("cloudref::TabulatedPhase: need >= 2 angles and as many values");
    if (std::abs(theta.front()) > 1e-12 || std::abs(theta.back() - kPi) > 1e-9)
        throw Error("cloudref::TabulatedPhase: angles must run from 0 to pi");
    const size_t n = theta.size() - 1;
    cosEdges_.resize(n + 1);
    value_.resize(n);
    cdf_.assign(n + 1, 0.0);
    for (size_t i = 0; i <= n; ++i) cosEdges_[i] = std::cos(theta[i]);
    cosEdges_.front() = 1.0;
    cosEdges_.back() = -1.0;
    double total = 0.0, gsum = 0.0;
    for (size_t i = 0; i < n; ++i) {
        if (!(theta[i + 1] > theta[i])) throw Error("cloudref::TabulatedPhase: angles must increase");
        if (!(phase[i] >= 0.0)) throw Error("cloudref::TabulatedPhase: values must be >= 0");
        // Mean of the (linearly interpolated in theta) table over the interval, per unit cos:
        // two-point trapezoid of p sin(theta) d(theta) over the interval's cos width.
        const double dc = cosEdges_[i] - cosEdges_[i + 1];
        const double mass = 0.5 * (phase[i] * std::sin(theta[i]) + phase[i + 1] * std::sin(theta[i + 1])) * (theta[i + 1] - theta[i]);
        value_[i] = dc > 0.0 ? std::max(mass, 0.5 * (phase[i] + phase[i + 1]) * dc * 1e-12) / dc : 0.0;
        total += value_[i] * dc;
        cdf_[i + 1] = total;
    }
    for (size_t i = 0; i < n; ++i) {
        value_[i] /= 2.0 * kPi * total;  // now 1/sr, integral over the sphere 1
        cdf_[i + 1] /= total;
        const double dc = cosEdges_[i] - cosEdges_[i + 1];
        gsum += 2.0 * kPi * value_[i] * dc * 0.5 * (cosEdges_[i] + cosEdges_[i + 1]);
    }
    cdf_.back() = 1.0;
    g_ = gsum;
}

double TabulatedPhase::eval(double mu) const {
    // First edge below mu (edges decrease).
    const auto it = std::upper_bound(cosEdges_.begin(), cosEdges_.end(), mu, std::greater<double>());
    size_t i = size_t(std::max<std::ptrdiff_t>(0, (it - cosEdges_.begin()) - 1));
    i = std::min(i, value_.size() - 1);
    return value_[i];
}

double TabulatedPhase::sampleCos(double u) const {
    const auto it = std::upper_bound(cdf_.begin(), cdf_.end(), u);
    size_t i = size_t(std::max<std::ptrdiff_t>(0, (it - cdf_.begin()) - 1));
    i = std::min(i, value_.size() - 1);
    const double p = cdf_[i + 1] - cdf_[i];
    const double f = p > 0.0 ? (u - cdf_[i]) / p : 0.5;
    return cosEdges_[i] + f * (cosEdges_[i + 1] - cosEdges_[i]);
}

TabulatedPhase cloudDropletPhase(double rEffM, double vEff, double wavelengthNm, int radii, int angles) {
    if (!(rEffM >= 1e-6 && rEffM <= 50e-6)) throw Error("cloudref::cloudDropletPhase: rEff must be in [1, 50] um");
    if (!(vEff >= 0.01 && vEff <= 0.5)) throw Error("cloudref::cloudDropletPhase: vEff must be in [0.01, 0.5]");
    if (radii < 4 || angles < 100) throw Error("cloudref::cloudDropletPhase: radii >= 4 and angles >= 100");
    // Angles: a third over 0-10 deg (the diffraction peak), half over 10-170, the rest to 180 (glory).
    std::vector<double> th;
    const int a0 = angles / 3, a1 = angles / 2, a2 = angles - a0 - a1;
    const double d = kPi / 180.0;
    for (int i = 0; i < a0; ++i) th.push_back(10.0 * d * i / a0);
    for (int i = 0; i < a1; ++i) th.push_back(10.0 * d + 160.0 * d * i / a1);
    for (int i = 0; i <= a2; ++i) th.push_back(170.0 * d + 10.0 * d * i / a2);
    std::vector<double> mu(th.size());
    for (size_t i = 0; i < th.size(); ++i) mu[i] = std::cos(th[i]);
    const std::complex<double> m = generators::waterRefractiveIndex(wavelengthNm);
    // Gamma distribution n(r) ~ r^((1 - 3v)/v) exp(-r / (r_eff v)) on [r_eff/20, r_eff (1 + 10 sqrt v)].
    const double rLo = rEffM / 20.0, rHi = rEffM * (1.0 + 10.0 * std::sqrt(vEff));
    std::vector<double> sum(th.size(), 0.0), p;
    for (int k = 0; k < radii; ++k) {
        const double r = rLo + (rHi - rLo) * (k + 0.5) / radii;
        const double n = std::exp((1.0 - 3.0 * vEff) / vEff * std::log(r / rEffM) - (r - rEffM) / (rEffM * vEff));
        const generators::MieSphere s(m, 2.0 * kPi * r / (wavelengthNm * 1e-9));
        const double w = n * kPi * r * r * s.qsca();
        s.phases(mu, p);
        for (size_t i = 0; i < th.size(); ++i) sum[i] += w * p[i];
    }
    return TabulatedPhase(th, sum);
}

TruncatedPhase truncatePhase(const PhaseFunction& phase, double thetaCutRad, int angles) {
    if (!(thetaCutRad > 0.0 && thetaCutRad < 0.5 * kPi)) throw Error("cloudref::truncatePhase: thetaCutRad must be in (0, pi/2)");
    if (angles < 100) throw Error("cloudref::truncatePhase: angles must be >= 100");
    // Angles: a quadratic spacing over [0, pi] (dense near the peak).
    std::vector<double> th(static_cast<size_t>(angles)), v(static_cast<size_t>(angles));
    const double clip = phase.eval(std::cos(thetaCutRad));
    for (int i = 0; i < angles; ++i) {
        const double x = double(i) / (angles - 1);
        th[size_t(i)] = kPi * x * x;
        v[size_t(i)] = std::min(phase.eval(std::cos(th[size_t(i)])), clip);
    }
    // The removed fraction: int over the cone of (p - clip) 2 pi sin(theta) dtheta (midpoint rule,
    // 20000 steps across the cone).
    double removed = 0.0;
    const int n = 20000;
    for (int i = 0; i < n; ++i) {
        const double t = (i + 0.5) * thetaCutRad / n;
        removed += std::max(phase.eval(std::cos(t)) - clip, 0.0) * 2.0 * kPi * std::sin(t) * thetaCutRad / n;
    }
    return {TabulatedPhase(th, v), std::clamp(removed, 0.0, 0.999999)};
}

// ---- Estimators ---------------------------------------------------------------------------------

Estimate radiance(const Scene& scene, const glm::dvec3& origin, const glm::dvec3& dir, int paths, uint64_t seed, uint64_t stream) {
    checkScene(scene);
    if (paths < 1) throw Error("cloudref::radiance: paths must be >= 1");
    const Sums r = radianceSums(scene, origin, glm::normalize(dir), paths, seed, stream);
    Estimate e;
    e.mean = r.s / double(paths);
    for (int c = 0; c < 3; ++c) e.sigma[c] = sigmaOfMean(r.s[c], r.s2[c], paths);
    return e;
}

glm::dvec3 pixelDirection(const ImageRequest& q, double x, double y) {
    const glm::dvec3 f = glm::normalize(q.forward);
    const glm::dvec3 r = glm::normalize(glm::cross(f, q.up));
    const glm::dvec3 u = glm::cross(r, f);
    const double th = std::tan(0.5 * q.fovYRad), aspect = double(q.width) / q.height;
    const double sx = (2.0 * x / q.width - 1.0) * th * aspect, sy = (1.0 - 2.0 * y / q.height) * th;
    return glm::normalize(f + sx * r + sy * u);
}

Image render(const Scene& scene, const ImageRequest& q) {
    checkScene(scene);
    if (q.width < 1 || q.height < 1 || q.pathsPerPixel < 1) throw Error("cloudref::render: size and paths must be >= 1");
    if (!(q.fovYRad > 0.0 && q.fovYRad < kPi)) throw Error("cloudref::render: fovYRad must be in (0, pi)");
    Image im;
    im.width = q.width;
    im.height = q.height;
    const size_t n = size_t(q.width) * q.height;
    im.radiance.assign(n, glm::dvec3(0.0));
    im.luminanceSigma.assign(n, 0.0);
    im.transmittance.assign(n, 1.0);
    std::atomic<size_t> next{0};
    auto work = [&] {
        for (size_t i = next++; i < n; i = next++) {
            const int x = int(i % q.width), y = int(i / q.width);
            const glm::dvec3 d = pixelDirection(q, x + 0.5, y + 0.5);
            const Sums s = radianceSums(scene, q.origin, d, q.pathsPerPixel, q.seed, i);
            im.radiance[i] = s.s / double(q.pathsPerPixel);
            im.luminanceSigma[i] = sigmaOfMean(s.y, s.y2, q.pathsPerPixel);
            Rng rng(q.seed ^ 0x5bd1e995ULL, i);
            glm::dvec3 nrm;
            const double tg = groundHit(scene.ground, q.origin, d, nrm);
            double tr = 0.0;
            for (int k = 0; k < 4; ++k) tr += 0.25 * ratioTrackingTransmittance(*scene.medium, q.origin, d, tg, rng);
            im.transmittance[i] = tr;
        }
    };
    const int threads = std::clamp(q.threads, 1, 64);
    std::vector<std::thread> pool;
    for (int t = 1; t < threads; ++t) pool.emplace_back(work);
    work();
    for (auto& t : pool) t.join();
    return im;
}

SlabFluxes slabFluxes(const Scene& s, const glm::dvec3& dir0, long photons, uint64_t seed) {
    checkScene(s);
    if (photons < 2) throw Error("cloudref::slabFluxes: photons must be >= 2");
    const glm::dvec3 d0 = glm::normalize(dir0);
    if (!(d0.z < 0.0)) throw Error("cloudref::slabFluxes: the photons must travel downwards (dir.z < 0)");
    glm::dvec3 start(0.0);
    const CloudFieldMedium* shell = nullptr;  // a shell: its first crossing only (below it: the planet)
    if (const auto* slab = dynamic_cast<const SlabMedium*>(s.medium)) start = {0.0, 0.0, slab->z1()};
    else if (dynamic_cast<const BoxMedium*>(s.medium)) {
        // Top face's centre: find it from the support of a vertical ray from far above.
        Interval iv[4];
        const int n = s.medium->support({0.0, 0.0, 1e7}, {0.0, 0.0, -1.0}, kInf, iv);
        if (n == 0) throw Error("cloudref::slabFluxes: the box must cover x = y = 0");
        start.z = 1e7 - iv[0].t0;
    } else if (const auto* cf = dynamic_cast<const CloudFieldMedium*>(s.medium)) {
        start = {0.0, 0.0, cf->topM()};
        shell = cf;
    } else {
        throw Error("cloudref::slabFluxes: a SlabMedium, a BoxMedium or a CloudFieldMedium");
    }
    const Medium& m = *s.medium;
    const double maj = m.majorantPerM();
    double sr = 0, st = 0, sa = 0, sa2 = 0, sd = 0, scat = 0;
    for (long k = 0; k < photons; ++k) {
        Rng rng(seed, uint64_t(k));
        glm::dvec3 o = start, d = d0;
        double absorbed = 0.0;
        bool alive = true, scattered = false;
        long events = 0;
        while (alive) {
            Interval iv[4];
            int n = m.support(o, d, kInf, iv);
            if (shell) n = std::min(n, 1);
            bool hit = false;
            glm::dvec3 p(0.0);
            for (int i = 0; i < n && !hit; ++i) {
                double t = iv[i].t0;
                for (;;) {
                    t -= std::log1p(-rng.uniform()) / maj;
                    if (t >= iv[i].t1) break;
                    p = o + t * d;
                    const double sig = m.extinctionPerM(p);
                    const double a = m.albedo(p);
                    absorbed += sig * (1.0 - a) / maj;  // collision estimator of the absorption
                    const double u = rng.uniform() * maj;
                    if (u < sig) {
                        hit = true;
                        if (u >= sig * a) alive = false;  // analog absorption
                        break;
                    }
                }
            }
            if (!hit) {
                bool up = d.z > 0.0;
                if (shell && n > 0) {
                    const glm::dvec3 e = o + iv[0].t1 * d + glm::dvec3(0.0, 0.0, shell->planetRadiusM());
                    up = glm::length(e) > shell->planetRadiusM() + 0.5 * (shell->bottomM() + shell->topM());
                }
                if (up) sr += 1.0;
                else st += 1.0;
                if (!scattered && !up) sd += 1.0;
                break;
            }
            if (!alive) break;
            scattered = true;
            if (++events > s.maxScatterings) break;
            d = turn(d, s.phase->sampleCos(rng.uniform()), 2.0 * kPi * rng.uniform());
            o = p;
        }
        sa += absorbed;
        sa2 += absorbed * absorbed;
        scat += double(events);
    }
    const double N = double(photons);
    SlabFluxes f;
    f.reflection = sr / N;
    f.transmission = st / N;
    f.absorbed = sa / N;
    f.directTransmission = sd / N;
    f.reflectionSigma = std::sqrt(f.reflection * (1.0 - f.reflection) / (N - 1.0));
    f.transmissionSigma = std::sqrt(f.transmission * (1.0 - f.transmission) / (N - 1.0));
    f.absorbedSigma = sigmaOfMean(sa, sa2, N);
    f.meanScatterings = scat / N;
    return f;
}

// ---- Adding-doubling ----------------------------------------------------------------------------

std::vector<double> hgMoments(double g, int n) {
    std::vector<double> m(size_t(std::max(n, 1)));
    double v = 1.0;
    for (auto& x : m) {
        x = v;
        v *= g;
    }
    return m;
}

namespace {

// The N-stream adding-doubling shared by addingDoubling() and addingDoublingInternal(): the
// delta-M scaled phase (f the forward peak's fraction, the moment of order 2N; chi the truncated
// moments; omega the scaled albedo; scale the depth's factor 1 - albedo f), Gauss-Legendre streams
// mu, w on (0, 1], the Legendre polynomials at the streams (Pm) and at mu0 (P0).
struct Streams {
    int N, L;
    double f, omega, scale;
    std::vector<double> chi, mu, w, P0;
    std::vector<std::vector<double>> Pm;
    Mat I;  // the N x N identity

    Streams(double albedo, const std::vector<double>& moments, double mu0, int n) : N(n), L(2 * n) {
        f = moments.size() > size_t(L) ? moments[size_t(L)] : 0.0;  // terms kept: degree <= 2N - 1, exact with N nodes per hemisphere
        chi.assign(size_t(L), 0.0);
        for (int l = 0; l < L && size_t(l) < moments.size(); ++l) chi[size_t(l)] = (moments[size_t(l)] - f) / (1.0 - f);
        scale = 1.0 - albedo * f;
        omega = albedo * (1.0 - f) / (1.0 - albedo * f);
        gaussLegendre01(N, mu, w);
        Pm.resize(size_t(N));
        for (int i = 0; i < N; ++i) Pm[size_t(i)] = legendre(mu[size_t(i)]);
        P0 = legendre(mu0);
        I.assign(size_t(N) * N, 0.0);
        for (int i = 0; i < N; ++i) I[size_t(i) * N + i] = 1.0;
        mu0_ = mu0;
    }
    std::vector<double> legendre(double x) const {
        std::vector<double> P(static_cast<size_t>(L));
        P[0] = 1.0;
        if (L > 1) P[1] = x;
        for (int l = 2; l < L; ++l) P[size_t(l)] = ((2.0 * l - 1.0) * x * P[size_t(l) - 1] - (l - 1.0) * P[size_t(l) - 2]) / l;
        return P;
    }
    // The azimuth-averaged phase between two directions given by their Legendre values; opposite:
    // one of them in the other hemisphere (P_l(-x) = (-1)^l P_l(x)).
    double p0(const std::vector<double>& A, const std::vector<double>& B, bool opposite) const {
        double s = 0.0;
        for (int l = 0; l < L; ++l) s += (2.0 * l + 1.0) * chi[size_t(l)] * A[size_t(l)] * B[size_t(l)] * ((opposite && (l & 1)) ? -1.0 : 1.0);
        return s;
    }
    // A homogeneous layer: reflection and transmission matrices between the streams, the direct
    // beam's diffuse reflection r and transmission t (radiance per unit incident flux), and the
    // direct beam's own transmission e.
    struct Layer {
        Mat R, T;
        std::vector<double> r, t;
        double e = 1.0;
    };
    // The layer of scaled optical depth ts: a first-order thin layer (depth below 1e-9) doubled.
    Layer build(double ts) const {
        Layer y;
        y.R.assign(size_t(N) * N, 0.0);
        y.T = I;
        y.r.assign(size_t(N), 0.0);
        y.t.assign(size_t(N), 0.0);
        if (ts <= 0.0) return y;
        int doublings = 0;
        double delta = ts;
        while (delta > 1e-9) {
            delta *= 0.5;
            ++doublings;
        }
        Mat& R = y.R;
        Mat& T = y.T;
        for (int i = 0; i < N; ++i) {
            const double mi = mu[size_t(i)];
            for (int j = 0; j < N; ++j) {
                const double k = omega * delta / (2.0 * mi) * w[size_t(j)];
                R[size_t(i) * N + j] = k * p0(Pm[size_t(i)], Pm[size_t(j)], true);
                T[size_t(i) * N + j] = k * p0(Pm[size_t(i)], Pm[size_t(j)], false) + (i == j ? std::exp(-delta / mi) : 0.0);
            }
            y.r[size_t(i)] = omega * delta / (4.0 * kPi * mi) * p0(Pm[size_t(i)], P0, true);
            y.t[size_t(i)] = omega * delta / (4.0 * kPi * mi) * p0(Pm[size_t(i)], P0, false);
        }
        double e = std::exp(-delta / mu0_);
        for (int k = 0; k < doublings; ++k) {
            Mat RR = matMul(R, R, N);
            for (size_t q = 0; q < RR.size(); ++q) RR[q] = I[q] - RR[q];
            const Mat Q = matInverse(RR, N);
            std::vector<double> Rr = matVec(R, y.r, N);
            std::vector<double> src(static_cast<size_t>(N));
            for (int i = 0; i < N; ++i) src[size_t(i)] = y.t[size_t(i)] + e * Rr[size_t(i)];
            const std::vector<double> D = matVec(Q, src, N);
            std::vector<double> U = matVec(R, D, N);
            for (int i = 0; i < N; ++i) U[size_t(i)] += e * y.r[size_t(i)];
            const std::vector<double> TU = matVec(T, U, N), TD = matVec(T, D, N);
            for (int i = 0; i < N; ++i) {
                y.r[size_t(i)] += TU[size_t(i)];
                y.t[size_t(i)] = TD[size_t(i)] + e * y.t[size_t(i)];
            }
            const Mat QT = matMul(Q, T, N);
            const Mat TRQT = matMul(matMul(T, R, N), QT, N);
            for (size_t q = 0; q < R.size(); ++q) R[q] += TRQT[q];
            T = matMul(T, QT, N);
            e *= e;
        }
        y.e = e;
        return y;
    }

private:
    double mu0_;
};

}  // namespace

SlabSolution addingDoubling(double tau, double albedo, const std::vector<double>& moments, double mu0, int N) {
    if (!(tau >= 0.0 && tau <= 1e4)) throw Error("cloudref::addingDoubling: tau must be in [0, 1e4]");
    if (!(albedo >= 0.0 && albedo <= 1.0)) throw Error("cloudref::addingDoubling: albedo must be in [0, 1]");
    if (!(mu0 > 0.0 && mu0 <= 1.0)) throw Error("cloudref::addingDoubling: mu0 must be in (0, 1]");
    if (N < 2 || N > 128) throw Error("cloudref::addingDoubling: streams must be in [2, 128]");
    if (moments.empty() || std::abs(moments[0] - 1.0) > 1e-12) throw Error("cloudref::addingDoubling: moments[0] must be 1");
    SlabSolution out;
    out.directTransmission = std::exp(-tau / mu0);
    if (tau == 0.0) {
        out.transmission = 1.0;
        return out;
    }
    const Streams st(albedo, moments, mu0, N);
    const Streams::Layer y = st.build(st.scale * tau);
    const std::vector<double>&mu = st.mu, &w = st.w, &r = y.r, &t = y.t;
    const double e = y.e;
    double up = 0.0, down = 0.0;
    for (int i = 0; i < N; ++i) {
        up += 2.0 * kPi * w[size_t(i)] * mu[size_t(i)] * r[size_t(i)];
        down += 2.0 * kPi * w[size_t(i)] * mu[size_t(i)] * t[size_t(i)];
    }
    out.reflection = up / mu0;
    out.transmission = down / mu0 + e;  // e: the scaled problem's direct beam (includes the peak)
    out.mu = mu;
    out.reflectedRadiance = r;
    out.transmittedRadiance = t;
    return out;
}

SlabInternal addingDoublingInternal(double tau, double albedo, const std::vector<double>& moments, double mu0, double depth, int N) {
    if (!(tau > 0.0 && tau <= 1e4)) throw Error("cloudref::addingDoublingInternal: tau must be in (0, 1e4]");
    if (!(depth >= 0.0 && depth <= tau)) throw Error("cloudref::addingDoublingInternal: depth must be in [0, tau]");
    if (!(albedo >= 0.0 && albedo <= 1.0)) throw Error("cloudref::addingDoublingInternal: albedo must be in [0, 1]");
    if (!(mu0 > 0.0 && mu0 <= 1.0)) throw Error("cloudref::addingDoublingInternal: mu0 must be in (0, 1]");
    if (N < 2 || N > 128) throw Error("cloudref::addingDoublingInternal: streams must be in [2, 128]");
    if (moments.empty() || std::abs(moments[0] - 1.0) > 1e-12) throw Error("cloudref::addingDoublingInternal: moments[0] must be 1");
    const Streams st(albedo, moments, mu0, N);
    // The layers above and below the depth; at the interface (the adding equations) the light going
    // down D = (1 - R_A R_B)^-1 (t_A + e_A R_A r_B) and up U = R_B D + e_A r_B (a homogeneous layer
    // reflects alike from both sides).
    const Streams::Layer A = st.build(st.scale * depth), B = st.build(st.scale * (tau - depth));
    Mat RR = matMul(A.R, B.R, N);
    for (size_t q = 0; q < RR.size(); ++q) RR[q] = st.I[q] - RR[q];
    const Mat Q = matInverse(RR, N);
    const std::vector<double> Rr = matVec(A.R, B.r, N);
    std::vector<double> src(static_cast<size_t>(N));
    for (int i = 0; i < N; ++i) src[size_t(i)] = A.t[size_t(i)] + A.e * Rr[size_t(i)];
    SlabInternal out;
    out.mu = st.mu;
    out.down = matVec(Q, src, N);
    out.up = matVec(B.R, out.down, N);
    for (int i = 0; i < N; ++i) out.up[size_t(i)] += A.e * B.r[size_t(i)];
    return out;
}

std::vector<double> phaseMoments(const PhaseFunction& phase, int n, int steps) {
    if (n < 1 || n > 4096) throw Error("cloudref::phaseMoments: n must be in [1, 4096]");
    if (steps < 100) throw Error("cloudref::phaseMoments: steps must be >= 100");
    std::vector<double> m(size_t(n), 0.0);
    for (int i = 0; i < steps; ++i) {
        const double x = -1.0 + (i + 0.5) * 2.0 / steps, p = phase.eval(x);
        double p0 = 1.0, p1 = x;
        m[0] += p;
        if (n > 1) m[1] += p * x;
        for (int l = 2; l < n; ++l) {
            const double p2 = ((2.0 * l - 1.0) * x * p1 - (l - 1.0) * p0) / l;
            m[size_t(l)] += p * p2;
            p0 = p1;
            p1 = p2;
        }
    }
    for (int l = n - 1; l >= 0; --l) m[size_t(l)] /= m[0];
    return m;
}

}  // namespace welkin::cloudref
