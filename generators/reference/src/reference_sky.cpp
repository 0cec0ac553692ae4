// The reference integrator (see reference_sky.hpp for the method).
#include <welkin/color.hpp>
#include <welkin/error.hpp>
#include <welkin/generators/reference_sky.hpp>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <numbers>
#include <string>
#include <thread>

namespace welkin::atmosphere {
namespace {

constexpr double kPi = std::numbers::pi;

/// Gauss-Legendre nodes and weights on [0, 1] (Newton iteration on the Legendre polynomial).
void gaussLegendre01(int n, std::vector<double>& x, std::vector<double>& w) {
    x.assign(n, 0.0);
    w.assign(n, 0.0);
    for (int i = 0; i < n; ++i) {
        double z = std::cos(kPi * (i + 0.75) / (n + 0.5));
        double dp = 1.0;
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
            if (std::abs(dz) < 1e-15) break;
        }
        double p0 = 1.0, p1 = z;
        for (int k = 2; k <= n; ++k) {
            const double p2 = ((2.0 * k - 1.0) * z * p1 - (k - 1.0) * p0) / k;
            p0 = p1;
            p1 = p2;
        }
        dp = n * (z * p1 - p0) / (z * z - 1.0);
        x[i] = 0.5 * (1.0 - z);
        w[i] = 1.0 / ((1.0 - z * z) * dp * dp);  // 2 / ((1 - z^2) P'^2) on [-1, 1], halved for [0, 1]
    }
}

void checkOpt(const char* member, double v, double lo, double hi) {
    if (!(v >= lo && v <= hi))
        throw Error(std::string("ReferenceOptions::validate(): ") + member + " " + std::to_string(v) + " not in [" +
                    std::to_string(lo) + ", " + std::to_string(hi) + "]");
}

double clamp1(double x) { return std::clamp(x, -1.0, 1.0); }

/// Fraction of a uniform disk of angular radius `alpha` visible when its centre is `d` radians
/// above the horizon.
double diskFraction(double d, double alpha) {
    const double x = std::clamp(-d / alpha, -1.0, 1.0);
    return (std::acos(x) - x * std::sqrt(std::max(0.0, 1.0 - x * x))) / kPi;
}

}  // namespace

void ReferenceOptions::validate() const {
    checkOpt("spectralSamples", spectralSamples, 3, 64);
    checkOpt("altitudeSamples", altitudeSamples, 4, 256);
    checkOpt("sunZenithSamples", sunZenithSamples, 4, 512);
    checkOpt("viewZenithSamples", viewZenithSamples, 4, 512);
    checkOpt("viewAzimuthSamples", viewAzimuthSamples, 3, 512);
    checkOpt("gatherZenithSamples", gatherZenithSamples, 2, 64);
    checkOpt("gatherAzimuthSamples", gatherAzimuthSamples, 2, 256);
    checkOpt("gatherSteps", gatherSteps, 8, 4096);
    checkOpt("maxOrders", maxOrders, 1, 500);
    checkOpt("convergence", convergence, 0.0, 0.1);
    checkOpt("transmittanceRadiusSamples", transmittanceRadiusSamples, 16, 4096);
    checkOpt("transmittanceMuSamples", transmittanceMuSamples, 16, 4096);
    checkOpt("raySteps", raySteps, 16, 65536);
    checkOpt("threads", threads, 1, 64);
}

struct ReferenceSky::Impl {
    Atmosphere atm;
    ReferenceOptions opt;
    int nc = 3;
    std::vector<double> wl;
    std::vector<double> sR, sMs, sMe, sO, alb;
    double R = 0, Rt = 0, Htop = 0, Hr = 1, Hm = 1, oc = 0, ow = 1, alpha = 0.0047;
    std::vector<glm::dvec3> conv;  // rgb = sum_c conv[c] * transfer[c]
    double solarLux = 0.0;

    // Column densities (Rayleigh, Mie, ozone) to the top of the atmosphere on Bruneton's mapping.
    int tR = 0, tM = 0;
    std::vector<double> col;

    // Multiple-scattering tables: phase-weighted incoming radiance of orders >= 1, Rayleigh then
    // Mie, nc channels each, per (altitude, sun zenith, view zenith, azimuth).
    int nr = 0, ns = 0, nmu = 0, nphi = 0;
    std::vector<float> G;
    std::vector<double> Eground;  // sky irradiance at the ground from orders >= 1, per (sun zenith, channel)
    int orders = 1;
    double lastFraction = 0.0;
    double seconds = 0.0;

    // ---- densities -----------------------------------------------------------------------
    void densities(double h, double& dR, double& dM, double& dO) const {
        dR = std::exp(-h / Hr);
        dM = std::exp(-h / Hm);
        dO = std::max(0.0, 1.0 - std::abs(h - oc) / ow);
    }

    double miePhaseFn(double nu) const { return miePhase(atm, nu); }

    // ---- geometry ------------------------------------------------------------------------
    double distanceToTop(double r, double mu) const {
        const double disc = r * r * (mu * mu - 1.0) + Rt * Rt;
        return std::max(0.0, -r * mu + std::sqrt(std::max(0.0, disc)));
    }
    bool hitsGround(double r, double mu) const { return mu < 0.0 && r * r * (mu * mu - 1.0) + R * R >= 0.0; }
    double distanceToGround(double r, double mu) const {
        const double disc = r * r * (mu * mu - 1.0) + R * R;
        return std::max(0.0, -r * mu - std::sqrt(std::max(0.0, disc)));
    }
    double horizonMu(double r) const { return -std::sqrt(std::max(0.0, 1.0 - (R / r) * (R / r))); }

    /// Column densities along a straight ray from radius r, direction cosine mu, over [0, len]
    /// (composite Gauss-Legendre, panels concentrated towards the lowest point).
    std::array<double, 3> columnExact(double r, double mu, double len) const {
        static thread_local std::vector<double> gx, gw;
        if (gx.empty()) gaussLegendre01(8, gx, gw);
        std::array<double, 3> sum{0, 0, 0};
        auto segment = [&](double a, double b, bool lowAtA) {
            const int panels = 24;
            for (int k = 0; k < panels; ++k) {
                double u0 = double(k) / panels, u1 = double(k + 1) / panels;
                u0 *= u0;
                u1 *= u1;
                double s0, s1;
                if (lowAtA) s0 = a + (b - a) * u0, s1 = a + (b - a) * u1;
                else s0 = b - (b - a) * u1, s1 = b - (b - a) * u0;
                for (std::size_t q = 0; q < gx.size(); ++q) {
                    const double t = s0 + (s1 - s0) * gx[q];
                    const double rr = std::sqrt(r * r + t * t + 2.0 * r * mu * t);
                    double dR, dM, dO;
                    densities(rr - R, dR, dM, dO);
                    const double ww = gw[q] * (s1 - s0);
                    sum[0] += dR * ww;
                    sum[1] += dM * ww;
                    sum[2] += dO * ww;
                }
            }
        };
        const double tLow = std::clamp(-r * mu, 0.0, len);
        if (tLow > 0.0) segment(0.0, tLow, false);
        if (tLow < len) segment(tLow, len, true);
        return sum;
    }

    void buildTransmittance() {
        tR = opt.transmittanceRadiusSamples;
        tM = opt.transmittanceMuSamples;
        col.assign(std::size_t(tR) * tM * 3, 0.0);
        const double H = std::sqrt(Rt * Rt - R * R);
        parallel(tR, [&](int i) {
            const double rho = H * i / (tR - 1);
            const double r = std::sqrt(rho * rho + R * R);
            const double dmin = Rt - r, dmax = rho + H;
            for (int j = 0; j < tM; ++j) {
                const double d = dmin + (dmax - dmin) * j / (tM - 1);
                const double mu = d <= 0.0 ? 1.0 : clamp1((H * H - rho * rho - d * d) / (2.0 * r * d));
                const auto c = columnExact(r, mu, d);
                std::copy(c.begin(), c.end(), col.begin() + (std::size_t(i) * tM + j) * 3);
            }
        });
    }

    /// Column densities to the top from (r, mu), mu clamped to the horizon (table lookup).
    std::array<double, 3> columnToTop(double r, double mu) const {
        r = std::clamp(r, R, Rt);
        const double H = std::sqrt(Rt * Rt - R * R);
        const double rho = std::sqrt(std::max(0.0, r * r - R * R));
        mu = std::max(mu, horizonMu(r));
        const double d = distanceToTop(r, mu);
        const double dmin = Rt - r, dmax = rho + H;
        const double xr = rho / H;
        const double xm = dmax > dmin ? (d - dmin) / (dmax - dmin) : 0.0;
        const double ur = std::clamp(xr, 0.0, 1.0) * (tR - 1), um = std::clamp(xm, 0.0, 1.0) * (tM - 1);
        const int i = std::min(int(ur), tR - 2), j = std::min(int(um), tM - 2);
        const double fi = ur - i, fj = um - j;
        std::array<double, 3> out{};
        for (int k = 0; k < 3; ++k) {
            auto at = [&](int a, int b) { return col[(std::size_t(a) * tM + b) * 3 + k]; };
            out[k] = (at(i, j) * (1 - fj) + at(i, j + 1) * fj) * (1 - fi) + (at(i + 1, j) * (1 - fj) + at(i + 1, j + 1) * fj) * fi;
        }
        return out;
    }

    /// Transmittance to the light times the visible fraction of its disk, per channel, at a
    /// point of radius r where the light's zenith cosine is muS.
    void sunTransmittance(double r, double muS, double* out) const {
        const double muH = horizonMu(std::max(r, R));
        const double d = std::asin(clamp1(muS)) - std::asin(muH);
        const double f = diskFraction(d, alpha);
        if (f <= 0.0) {
            for (int c = 0; c < nc; ++c) out[c] = 0.0;
            return;
        }
        const auto cd = columnToTop(r, muS);
        for (int c = 0; c < nc; ++c) out[c] = f * std::exp(-(sR[c] * cd[0] + sMe[c] * cd[1] + sO[c] * cd[2]));
    }

    // ---- multiple-scattering table lookup ------------------------------------------------
    std::size_t gIndex(int ir, int is, int im, int ip) const {
        return (((std::size_t(ir) * ns + is) * nmu + im) * nphi + ip) * std::size_t(2 * nc);
    }
    static void cell(double u, int n, int& i, double& f) {
        u = std::clamp(u, 0.0, double(n - 1));
        i = std::min(int(u), n - 2);
        f = u - i;
    }
    /// Adds the phase-weighted radiance of `table` at point y (radius r, local up) for view
    /// direction w and light direction s: outR[c], outM[c].
    void lookupG(const std::vector<float>& table, double r, const glm::dvec3& up, const glm::dvec3& w, const glm::dvec3& s,
                 double* outR, double* outM) const {
        // View directions are tabulated in a frame whose pole is the light: gamma = angle from the
        // light (denser near 0: gamma = pi u^2, for the aureole), psi = azimuth around the light
        // measured from the local vertical (0 = towards the zenith), symmetric in [0, pi].
        const double mu = clamp1(glm::dot(w, up)), muS = clamp1(glm::dot(s, up)), nu = clamp1(glm::dot(w, s));
        const double den = std::sqrt(std::max(0.0, (1.0 - nu * nu) * (1.0 - muS * muS)));
        const double cpsi = den > 1e-12 ? clamp1((mu - nu * muS) / den) : 1.0;
        int i0, i1, i2, i3;
        double f0, f1, f2, f3;
        cell(std::sqrt(std::clamp((r - R) / Htop, 0.0, 1.0)) * (nr - 1), nr, i0, f0);
        sunZenithCell(std::acos(muS), i1, f1);
        cell(std::sqrt(std::acos(nu) / kPi) * (nmu - 1), nmu, i2, f2);
        cell(std::acos(cpsi) / kPi * (nphi - 1), nphi, i3, f3);
        // The tables hold log(G): interpolating the logarithm follows the exponential fall of the
        // scattered light across the terminator (linear interpolation there overestimates the
        // twilight sky by orders of magnitude) and is as accurate as linear elsewhere.
        for (int c = 0; c < nc; ++c) outR[c] = outM[c] = 0.0;
        for (int corner = 0; corner < 16; ++corner) {
            const int a = corner & 1, b = (corner >> 1) & 1, cc = (corner >> 2) & 1, d = (corner >> 3) & 1;
            const double wgt = (a ? f0 : 1 - f0) * (b ? f1 : 1 - f1) * (cc ? f2 : 1 - f2) * (d ? f3 : 1 - f3);
            if (wgt == 0.0) continue;
            const float* g = &table[gIndex(i0 + a, i1 + b, i2 + cc, i3 + d)];
            for (int c = 0; c < nc; ++c) {
                outR[c] += wgt * g[c];
                outM[c] += wgt * g[nc + c];
            }
        }
        for (int c = 0; c < nc; ++c) {
            outR[c] = std::exp(outR[c]);
            outM[c] = std::exp(outM[c]);
        }
    }
    /// Cell of the sun-zenith grid containing theta (radians).
    void sunZenithCell(double theta, int& i, double& f) const {
        const auto it = std::upper_bound(thetaS.begin(), thetaS.end(), theta);
        i = std::clamp(int(it - thetaS.begin()) - 1, 0, ns - 2);
        f = std::clamp((theta - thetaS[i]) / (thetaS[i + 1] - thetaS[i]), 0.0, 1.0);
    }
    /// Sun-zenith grid: node density 1 + 6 exp(-((theta - 95 deg) / 12 deg)^2), i.e. about 7 times
    /// denser around the terminator, where the light reaching a point changes fastest.
    void buildSunZenithGrid() {
        auto density = [](double th) {
            const double x = (th - 95.0 * kPi / 180.0) / (12.0 * kPi / 180.0);
            return 1.0 + 6.0 * std::exp(-x * x);
        };
        const int fine = 20000;
        std::vector<double> cum(fine + 1, 0.0);
        for (int k = 1; k <= fine; ++k) {
            const double a = kPi * (k - 1) / fine, b = kPi * k / fine;
            cum[k] = cum[k - 1] + 0.5 * (density(a) + density(b)) * (b - a);
        }
        thetaS.assign(ns, 0.0);
        for (int i = 0; i < ns; ++i) {
            const double target = cum[fine] * i / (ns - 1);
            const int k = std::clamp(int(std::lower_bound(cum.begin(), cum.end(), target) - cum.begin()), 1, fine);
            const double f = (target - cum[k - 1]) / (cum[k] - cum[k - 1]);
            thetaS[i] = kPi * (k - 1 + f) / fine;
        }
        thetaS.front() = 0.0;
        thetaS.back() = kPi;
    }
    std::vector<double> thetaS;
    static float toLog(double v) { return float(std::log(std::max(v, 1e-35))); }
    /// Sky irradiance at the ground for light zenith cosine muS (table `e`, per channel).
    void lookupE(const std::vector<double>& e, double muS, double* out) const {
        int i;
        double f;
        sunZenithCell(std::acos(clamp1(muS)), i, f);
        for (int c = 0; c < nc; ++c)
            out[c] = std::exp(std::log(std::max(e[std::size_t(i) * nc + c], 1e-300)) * (1 - f) +
                              std::log(std::max(e[std::size_t(i + 1) * nc + c], 1e-300)) * f);
    }

    // ---- ray march -----------------------------------------------------------------------
    struct MarchSpec {
        bool single = true;                       // exact single scattering
        const std::vector<float>* G = nullptr;    // tabulated scattering density (orders >= 2)
        bool groundDirect = true;                 // ground reflection of the direct light
        const std::vector<double>* E = nullptr;   // ground reflection of tabulated sky irradiance
    };

    /// Node positions along [0, D]: split at the lowest point and at Earth's shadow boundary,
    /// clustered (cosine spacing) towards every break point.
    void marchNodes(const glm::dvec3& p, const glm::dvec3& w, const glm::dvec3& s, double D, int n,
                    std::vector<double>& t) const {
        double breaks[6];
        int nb = 0;
        breaks[nb++] = 0.0;
        const double tLow = -glm::dot(p, w);
        if (tLow > 0.0 && tLow < D) breaks[nb++] = tLow;
        // Shadow cylinder |y - (y.s) s| = R on the night side (y.s < 0).
        const glm::dvec3 a = w - glm::dot(w, s) * s, b = p - glm::dot(p, s) * s;
        const double qa = glm::dot(a, a), qb = glm::dot(a, b), qc = glm::dot(b, b) - R * R;
        if (qa > 1e-18) {
            const double disc = qb * qb - qa * qc;
            if (disc > 0.0) {
                const double sq = std::sqrt(disc);
                for (double tc : {(-qb - sq) / qa, (-qb + sq) / qa})
                    if (tc > 0.0 && tc < D && glm::dot(p + tc * w, s) < 0.0) breaks[nb++] = tc;
            }
        }
        breaks[nb++] = D;
        for (int i = 1; i < nb; ++i)  // insertion sort (at most 5 entries)
            for (int j = i; j > 0 && breaks[j] < breaks[j - 1]; --j) std::swap(breaks[j], breaks[j - 1]);
        t.clear();
        t.push_back(0.0);
        for (int k = 0; k + 1 < nb; ++k) {
            const double lo = breaks[k], hi = breaks[k + 1];
            if (hi - lo <= 1e-9 * std::max(1.0, D)) continue;
            const int m = std::max(n / 4, int(std::ceil(n * (hi - lo) / D)));
            for (int j = 1; j <= m; ++j) t.push_back(lo + (hi - lo) * 0.5 * (1.0 - std::cos(kPi * j / m)));
        }
    }

    /// Radiance per unit light irradiance arriving at p from direction w (looking along w),
    /// over [0, D]; `groundHit` when the ray ends on the ground. Adds into out[nc].
    void march(const glm::dvec3& p, const glm::dvec3& w, const glm::dvec3& s, double D, bool groundHit, int n,
               const MarchSpec& spec, double* out) const {
        thread_local std::vector<double> t;
        marchNodes(p, w, s, D, n, t);
        const double nu = glm::dot(w, s);
        const double pR = rayleighPhase(nu), pM = miePhaseFn(nu);
        std::array<double, 64> tau{}, prevJ{}, prevT{}, cur{}, tsun{}, gR{}, gM{};
        double prevSigma[64];
        double prevT0 = 0.0;
        for (std::size_t k = 0; k < t.size(); ++k) {
            const glm::dvec3 y = p + t[k] * w;
            const double r = glm::length(y);
            const glm::dvec3 up = y / r;
            double dR, dM, dO;
            densities(r - R, dR, dM, dO);
            const double muS = glm::dot(s, up);
            if (spec.single) sunTransmittance(r, muS, tsun.data());
            if (spec.G) lookupG(*spec.G, r, up, w, s, gR.data(), gM.data());
            for (int c = 0; c < nc; ++c) {
                const double sigma = sR[c] * dR + sMe[c] * dM + sO[c] * dO;
                if (k > 0) tau[c] += 0.5 * (sigma + prevSigma[c]) * (t[k] - prevT0);
                prevSigma[c] = sigma;
                double J = 0.0;
                if (spec.single) J += (sR[c] * dR * pR + sMs[c] * dM * pM) * tsun[c];
                if (spec.G) J += sR[c] * dR * gR[c] + sMs[c] * dM * gM[c];
                const double T = std::exp(-tau[c]);
                cur[c] = T * J;
                if (k > 0) out[c] += 0.5 * (cur[c] + prevJ[c]) * (t[k] - prevT0);
                prevJ[c] = cur[c];
                prevT[c] = T;
            }
            prevT0 = t[k];
        }
        if (groundHit) {
            const glm::dvec3 y = p + D * w;
            const glm::dvec3 up = glm::normalize(y);
            const double muS = glm::dot(s, up);
            std::array<double, 64> e{};
            if (spec.groundDirect) {
                sunTransmittance(R, muS, tsun.data());
                for (int c = 0; c < nc; ++c) e[c] += tsun[c] * std::max(0.0, muS);
            }
            if (spec.E) {
                std::array<double, 64> es{};
                lookupE(*spec.E, muS, es.data());
                for (int c = 0; c < nc; ++c) e[c] += es[c];
            }
            for (int c = 0; c < nc; ++c) out[c] += prevT[c] * alb[c] / kPi * e[c];
        }
    }

    /// Distance along (r, mu) to the end of the ray inside the atmosphere.
    void rayExtent(double r, double mu, double& D, bool& ground) const {
        ground = hitsGround(r, mu);
        D = ground ? distanceToGround(r, mu) : distanceToTop(r, mu);
    }

    // ---- parallel helper -----------------------------------------------------------------
    template <class F>
    void parallel(int n, F&& f) const {
        const int threads = std::min(opt.threads, n);
        if (threads <= 1) {
            for (int i = 0; i < n; ++i) f(i);
            return;
        }
        std::vector<std::thread> pool;
        for (int k = 0; k < threads; ++k)
            pool.emplace_back([&, k] {
                for (int i = k; i < n; i += threads) f(i);
            });
        for (auto& th : pool) th.join();
    }

    // ---- multiple scattering -------------------------------------------------------------
    void buildMultipleScattering() {
        nr = opt.altitudeSamples;
        ns = opt.sunZenithSamples;
        nmu = opt.viewZenithSamples;
        nphi = opt.viewAzimuthSamples;
        buildSunZenithGrid();
        const std::size_t tableSize = gIndex(nr, 0, 0, 0);
        G.assign(tableSize, 0.0f);  // linear sum of the orders while building, log(G) after
        Eground.assign(std::size_t(ns) * nc, 0.0);
        orders = 1;
        lastFraction = 1.0;
        if (opt.maxOrders <= 1) return;

        std::vector<double> gx, gw;
        gaussLegendre01(opt.gatherZenithSamples, gx, gw);
        const int nq = opt.gatherAzimuthSamples;
        std::vector<float> prev, next(tableSize, 0.0f);
        std::vector<double> ePrev, eNext(std::size_t(ns) * nc, 0.0);
        double totalNorm = 0.0;
        for (int order = 2; order <= opt.maxOrders; ++order) {
            std::fill(next.begin(), next.end(), 0.0f);
            std::fill(eNext.begin(), eNext.end(), 0.0);
            MarchSpec spec;
            if (order == 2) {
                spec.single = true;
                spec.groundDirect = true;
            } else {
                spec.single = false;
                spec.groundDirect = false;
                spec.G = &prev;
                spec.E = &ePrev;
            }
            parallel(nr * ns, [&](int cellIndex) {
                const int ir = cellIndex / ns, is = cellIndex % ns;
                const double u = double(ir) / (nr - 1);
                const double r = R + Htop * u * u;
                const double ths = thetaS[is];
                const glm::dvec3 s(std::sin(ths), 0.0, std::cos(ths));
                const glm::dvec3 p(0.0, 0.0, r);
                const double muH = horizonMu(r);
                // Table directions in the light-centred frame (see lookupG).
                const glm::dvec3 e1 = std::abs(std::sin(ths)) > 1e-9 ? glm::normalize(glm::dvec3(0, 0, 1) - s.z * s) : glm::dvec3(1, 0, 0);
                const glm::dvec3 e2 = glm::cross(s, e1);
                std::vector<glm::dvec3> outDir(std::size_t(nmu) * nphi);
                for (int im = 0; im < nmu; ++im)
                    for (int ip = 0; ip < nphi; ++ip) {
                        const double uu = double(im) / (nmu - 1);
                        const double ga = kPi * uu * uu, ps = kPi * ip / (nphi - 1);
                        outDir[std::size_t(im) * nphi + ip] = std::cos(ga) * s + std::sin(ga) * (std::cos(ps) * e1 + std::sin(ps) * e2);
                    }
                // Incoming directions and their radiance L(w), per channel.
                struct In {
                    glm::dvec3 w, wm;  // direction and its mirror about the Sun's vertical plane
                    double weight;
                    std::array<double, 64> L;
                };
                std::vector<In> ins;
                ins.reserve(std::size_t(2 * gx.size() * nq));
                for (int side = 0; side < 2; ++side)
                    for (std::size_t q = 0; q < gx.size(); ++q) {
                        const double uq = gx[q];
                        double mu, wmu;
                        if (side == 0) mu = muH - (1.0 + muH) * uq * uq, wmu = 2.0 * (1.0 + muH) * uq * gw[q];
                        else mu = muH + (1.0 - muH) * uq * uq, wmu = 2.0 * (1.0 - muH) * uq * gw[q];
                        mu = clamp1(mu);
                        const double st = std::sqrt(std::max(0.0, 1.0 - mu * mu));
                        for (int l = 0; l < nq; ++l) {
                            const double ph = kPi * (l + 0.5) / nq;
                            In in;
                            in.w = {st * std::cos(ph), st * std::sin(ph), mu};
                            in.wm = {in.w.x, -in.w.y, in.w.z};
                            in.weight = wmu * kPi / nq;
                            in.L.fill(0.0);
                            double D;
                            bool ground;
                            rayExtent(r, mu, D, ground);
                            if (side == 0 && r <= R * (1.0 + 1e-12)) ground = true, D = 0.0;
                            march(p, in.w, s, D, ground, opt.gatherSteps, spec, in.L.data());
                            ins.push_back(in);
                        }
                    }
                // Ground irradiance (only at the ground level grid row).
                if (ir == 0) {
                    for (const In& in : ins)
                        if (in.w.z > 0.0)
                            for (int c = 0; c < nc; ++c) eNext[std::size_t(is) * nc + c] += 2.0 * in.weight * in.w.z * in.L[c];
                }
                // Phase-weighted gather for every table direction.
                // Rayleigh: P_R(w.v) = 3 / (16 pi) (1 + (w.v)^2), so G_R(v) needs only the zeroth
                // and second moments of the incoming radiance: G_R = 3 / (16 pi) (E0 + v.M.v), exact.
                const std::size_t nin = ins.size();
                std::vector<double> e0(nc, 0.0), mom(std::size_t(6) * nc, 0.0);  // xx yy zz xy xz yz
                std::vector<double> wx(nin), wy(nin), wz(nin), lw(std::size_t(nc) * nin), pm(nin);
                for (std::size_t q = 0; q < nin; ++q) {
                    const In& in = ins[q];
                    wx[q] = in.w.x, wy[q] = in.w.y, wz[q] = in.w.z;
                    for (int c = 0; c < nc; ++c) {
                        const double a = in.weight * in.L[c];
                        lw[std::size_t(c) * nin + q] = a;
                        // The mirrored direction (x, -y, z) carries the same radiance: xy and yz cancel.
                        e0[c] += 2.0 * a;
                        mom[6 * c + 0] += 2.0 * a * in.w.x * in.w.x;
                        mom[6 * c + 1] += 2.0 * a * in.w.y * in.w.y;
                        mom[6 * c + 2] += 2.0 * a * in.w.z * in.w.z;
                        mom[6 * c + 4] += 2.0 * a * in.w.x * in.w.z;
                    }
                }
                const double g = atm.mieG, g2 = g * g;
                const bool hg = atm.miePhase == MiePhaseFunction::HenyeyGreenstein;
                const double kM = hg ? (1.0 - g2) / (4.0 * kPi) : 3.0 * (1.0 - g2) / (8.0 * kPi * (2.0 + g2));
                for (int o = 0; o < nmu * nphi; ++o) {
                    const glm::dvec3& v = outDir[o];
                    // Aerosols: both mirrored directions, in a loop the compiler can vectorise.
                    for (std::size_t q = 0; q < nin; ++q) {
                        const double n1 = wx[q] * v.x + wy[q] * v.y + wz[q] * v.z;
                        const double n2 = n1 - 2.0 * wy[q] * v.y;
                        const double d1 = 1.0 + g2 - 2.0 * g * n1, d2 = 1.0 + g2 - 2.0 * g * n2;
                        const double a1 = hg ? 1.0 : 1.0 + n1 * n1, a2 = hg ? 1.0 : 1.0 + n2 * n2;
                        pm[q] = kM * (a1 / (d1 * std::sqrt(d1)) + a2 / (d2 * std::sqrt(d2)));
                    }
                    float* gOut = &next[gIndex(ir, is, o / nphi, o % nphi)];
                    for (int c = 0; c < nc; ++c) {
                        const double* l = &lw[std::size_t(c) * nin];
                        double accM = 0.0;
                        for (std::size_t q = 0; q < nin; ++q) accM += pm[q] * l[q];
                        const double* mm = &mom[6 * c];
                        const double vmv = mm[0] * v.x * v.x + mm[1] * v.y * v.y + mm[2] * v.z * v.z + 2.0 * mm[4] * v.x * v.z;
                        gOut[c] = float(3.0 / (16.0 * kPi) * (e0[c] + vmv));
                        gOut[nc + c] = float(accM);
                    }
                }
            });
            double orderNorm = 0.0;
            for (std::size_t k = 0; k < tableSize; ++k) {
                G[k] += next[k];
                orderNorm += std::abs(double(next[k]));
                next[k] = toLog(next[k]);  // the next order looks this one up in log space
            }
            for (std::size_t k = 0; k < eNext.size(); ++k) Eground[k] += eNext[k];
            totalNorm += orderNorm;
            orders = order;
            lastFraction = totalNorm > 0.0 ? orderNorm / totalNorm : 0.0;
            if (lastFraction < opt.convergence) break;
            prev.swap(next);
            if (next.size() != tableSize) next.assign(tableSize, 0.0f);
            ePrev = eNext;
        }
        for (float& g : G) g = toLog(g);
    }

    // ---- queries -------------------------------------------------------------------------
    std::vector<double> transfer(double heightM, const glm::dvec3& viewIn, const glm::dvec3& sunIn) const {
        std::vector<double> out(nc, 0.0);
        const glm::dvec3 w = glm::normalize(viewIn), s = glm::normalize(sunIn);
        glm::dvec3 p(0.0, 0.0, R + std::max(0.0, heightM));
        if (!entersAtmosphere(p, w)) return out;
        const double r = glm::length(p);
        const double mu = glm::dot(w, p / r);
        double D;
        bool ground;
        rayExtent(r, mu, D, ground);
        MarchSpec spec;
        spec.single = true;
        spec.groundDirect = true;
        spec.G = orders > 1 ? &G : nullptr;
        spec.E = orders > 1 ? &Eground : nullptr;
        march(p, w, s, D, ground, opt.raySteps, spec, out.data());
        for (double& v : out) v = std::max(0.0, v);
        return out;
    }

    /// Moves p to where the ray enters the atmosphere if it starts above it; false if it misses.
    bool entersAtmosphere(glm::dvec3& p, const glm::dvec3& w) const {
        const double r = glm::length(p);
        if (r <= Rt) return true;
        const double b = glm::dot(p, w), c = r * r - Rt * Rt;
        const double disc = b * b - c;
        if (disc <= 0.0) return false;
        const double t = -b - std::sqrt(disc);
        if (t < 0.0) return false;
        p += t * w;
        p *= Rt / glm::length(p);  // exactly on the boundary
        return true;
    }

    std::vector<double> channelTransmittance(double heightM, const glm::dvec3& dirIn) const {
        std::vector<double> out(nc, 1.0);
        const glm::dvec3 w = glm::normalize(dirIn);
        glm::dvec3 p(0.0, 0.0, R + std::max(0.0, heightM));
        if (!entersAtmosphere(p, w)) return out;
        const double r = glm::length(p), mu = glm::dot(w, p / r);
        if (hitsGround(r, mu)) return std::vector<double>(nc, 0.0);
        const auto cd = columnExact(r, mu, distanceToTop(r, mu));
        for (int c = 0; c < nc; ++c) out[c] = std::exp(-(sR[c] * cd[0] + sMe[c] * cd[1] + sO[c] * cd[2]));
        return out;
    }

    glm::dvec3 toRgb(const std::vector<double>& v) const {
        glm::dvec3 rgb(0.0);
        for (int c = 0; c < nc; ++c) rgb += conv[c] * v[c];
        return rgb;
    }
};

ReferenceSky::ReferenceSky(const Atmosphere& atmosphere, const ReferenceOptions& options) : impl_(std::make_unique<Impl>()) {
    const auto t0 = std::chrono::steady_clock::now();
    atmosphere.validate();
    options.validate();
    Impl& m = *impl_;
    m.atm = atmosphere;
    m.opt = options;
    m.R = atmosphere.bottomRadiusM;
    m.Rt = atmosphere.topRadiusM;
    m.Htop = m.Rt - m.R;
    m.Hr = atmosphere.rayleighScaleHeightM;
    m.Hm = atmosphere.mieScaleHeightM;
    m.oc = atmosphere.ozoneCenterAltitudeM;
    m.ow = atmosphere.ozoneHalfWidthM;
    m.alpha = atmosphere.sunAngularRadiusRad;

    if (options.mode == SpectralMode::Rgb) {
        const RgbCoefficients c = options.rgbWavelengthsNm ? atmosphere.rgbAtWavelengths(*options.rgbWavelengthsNm) : atmosphere.rgb();
        m.nc = 3;
        for (int i = 0; i < 3; ++i) {
            m.wl.push_back(c.wavelengthsNm[i]);
            m.sR.push_back(c.rayleighScattering[i]);
            m.sMs.push_back(c.mieScattering[i]);
            m.sMe.push_back(c.mieExtinction[i]);
            m.sO.push_back(c.ozoneAbsorption[i]);
            m.alb.push_back(c.groundAlbedo[i]);
            glm::dvec3 e(0.0);
            e[i] = c.solarIlluminance[i];
            m.conv.push_back(e);
        }
    } else {
        const int n = options.spectralSamples;
        const double lo = atmosphere.wavelengthsNm.front(), hi = atmosphere.wavelengthsNm.back();
        std::vector<double> nm;
        if (atmosphere.size() <= std::size_t(n)) nm = atmosphere.wavelengthsNm;
        else
            for (int i = 0; i < n; ++i) nm.push_back(lo + (hi - lo) * i / (n - 1));
        const Atmosphere a = atmosphere.resampled(nm);
        m.nc = int(nm.size());
        m.wl = nm;
        m.sR = a.rayleighScattering;
        m.sMs = a.mieScattering;
        m.sMe = a.mieExtinction;
        m.sO = a.ozoneAbsorption;
        m.alb = a.groundAlbedo;
        // Transfer at the channel wavelengths -> piecewise linear on the atmosphere's own grid ->
        // times its solar spectrum -> CIE 1931 -> linear sRGB.
        const auto& full = atmosphere.wavelengthsNm;
        const auto w = color::spectralToLinearSrgbWeights(full);
        m.conv.assign(nm.size(), glm::dvec3(0.0));
        for (std::size_t k = 0; k < full.size(); ++k) {
            const double l = full[k];
            const glm::dvec3 base = w[k] * atmosphere.solarIrradiance[k];
            if (nm.size() == 1 || l <= nm.front()) {
                m.conv.front() += base;
                continue;
            }
            if (l >= nm.back()) {
                m.conv.back() += base;
                continue;
            }
            const std::size_t j = std::size_t(std::upper_bound(nm.begin(), nm.end(), l) - nm.begin());
            const double f = (l - nm[j - 1]) / (nm[j] - nm[j - 1]);
            m.conv[j - 1] += base * (1.0 - f);
            m.conv[j] += base * f;
        }
    }
    if (m.nc > 64) throw Error("ReferenceSky: at most 64 channels");
    glm::dvec3 sunRgb(0.0);
    for (const auto& c : m.conv) sunRgb += c;
    m.solarLux = color::luminance(sunRgb);

    m.buildTransmittance();
    m.buildMultipleScattering();
    m.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

ReferenceSky::~ReferenceSky() = default;
ReferenceSky::ReferenceSky(ReferenceSky&&) noexcept = default;
ReferenceSky& ReferenceSky::operator=(ReferenceSky&&) noexcept = default;

namespace {
void checkDirection(const char* who, const char* arg, const glm::dvec3& d) {
    const double l = glm::length(d);
    if (!(std::abs(l - 1.0) < 1e-6))
        throw Error(std::string("ReferenceSky::") + who + "(): " + arg + " is not a unit vector (length " + std::to_string(l) + ")");
}
void checkHeight(const char* who, double h) {
    if (!(h >= -1e4 && h <= 1e9))
        throw Error(std::string("ReferenceSky::") + who + "(): height " + std::to_string(h) + " m not in [-1e4, 1e9]");
}
}  // namespace

std::vector<double> ReferenceSky::transfer(double heightM, const glm::dvec3& view, const glm::dvec3& sun) const {
    checkHeight("transfer", heightM);
    checkDirection("transfer", "view", view);
    checkDirection("transfer", "sun", sun);
    return impl_->transfer(heightM, view, sun);
}

glm::dvec3 ReferenceSky::radiance(double heightM, const glm::dvec3& view, const glm::dvec3& sun,
                                  const std::optional<ExtraLight>& extra) const {
    glm::dvec3 rgb = impl_->toRgb(transfer(heightM, view, sun));
    if (extra && extra->illuminanceLux > 0.0) {
        checkDirection("radiance", "extra->direction", extra->direction);
        rgb += impl_->toRgb(impl_->transfer(heightM, view, extra->direction)) * (extra->illuminanceLux / impl_->solarLux);
    }
    return glm::max(rgb, glm::dvec3(0.0));
}

std::vector<double> ReferenceSky::spectralRadiance(double heightM, const glm::dvec3& view, const glm::dvec3& sun) const {
    const Impl& m = *impl_;
    if (m.opt.mode != SpectralMode::Spectral) throw Error("ReferenceSky::spectralRadiance(): needs SpectralMode::Spectral");
    const std::vector<double> t = transfer(heightM, view, sun);
    std::vector<double> out;
    for (std::size_t k = 0; k < m.atm.size(); ++k) {
        const double l = m.atm.wavelengthsNm[k];
        double v;
        if (l <= m.wl.front()) v = t.front();
        else if (l >= m.wl.back()) v = t.back();
        else {
            const std::size_t j = std::size_t(std::upper_bound(m.wl.begin(), m.wl.end(), l) - m.wl.begin());
            const double f = (l - m.wl[j - 1]) / (m.wl[j] - m.wl[j - 1]);
            v = t[j - 1] * (1.0 - f) + t[j] * f;
        }
        out.push_back(v * m.atm.solarIrradiance[k]);
    }
    return out;
}

std::vector<double> ReferenceSky::channelTransmittance(double heightM, const glm::dvec3& direction) const {
    checkHeight("channelTransmittance", heightM);
    checkDirection("channelTransmittance", "direction", direction);
    return impl_->channelTransmittance(heightM, direction);
}

glm::dvec3 ReferenceSky::transmittance(double heightM, const glm::dvec3& direction) const {
    const glm::dvec3 t = impl_->toRgb(channelTransmittance(heightM, direction));
    const glm::dvec3 e = impl_->toRgb(std::vector<double>(impl_->nc, 1.0));
    return glm::max(t / e, glm::dvec3(0.0));
}

glm::dvec3 ReferenceSky::sunDiskRadiance(double heightM, const glm::dvec3& sun) const {
    checkHeight("sunDiskRadiance", heightM);
    checkDirection("sunDiskRadiance", "sun", sun);
    const Impl& m = *impl_;
    const double a = m.alpha;
    const double solidAngle = 2.0 * kPi * (1.0 - std::cos(a));
    return m.toRgb(m.channelTransmittance(heightM, sun)) / solidAngle;
}

SkyIlluminance ReferenceSky::illuminance(double heightM, const glm::dvec3& sunIn, const std::optional<ExtraLight>& extra,
                                         int zenithNodes, int azimuthNodes) const {
    checkHeight("illuminance", heightM);
    checkDirection("illuminance", "sun", sunIn);
    if (zenithNodes < 2 || zenithNodes > 256 || azimuthNodes < 2 || azimuthNodes > 1024)
        throw Error("ReferenceSky::illuminance(): zenithNodes not in [2, 256] or azimuthNodes not in [2, 1024]");
    const Impl& m = *impl_;
    const double h = std::max(0.0, heightM);
    struct Light {
        glm::dvec3 dir;
        double scale;
    };
    std::vector<Light> lights{{sunIn, 1.0}};
    if (extra && extra->illuminanceLux > 0.0) {
        checkDirection("illuminance", "extra->direction", extra->direction);
        lights.push_back({extra->direction, extra->illuminanceLux / m.solarLux});
    }
    SkyIlluminance out;
    std::vector<double> gx, gw;
    gaussLegendre01(zenithNodes, gx, gw);
    for (const Light& L : lights) {
        // Direct: transmitted beam times the visible fraction of the disk, on a horizontal surface.
        const double r = m.R + h;
        const double muS = L.dir.z;
        std::vector<double> t(m.nc, 0.0);
        if (r <= m.Rt) m.sunTransmittance(r, muS, t.data());
        else if (!m.hitsGround(r, muS)) t = m.channelTransmittance(h, L.dir);
        for (int c = 0; c < m.nc; ++c) t[c] *= std::max(0.0, muS);
        const glm::dvec3 direct = m.toRgb(t) * L.scale;
        out.direct += color::luminance(direct);
        out.globalRgb += direct;
        // Diffuse: quadrature of the sky radiance over the upper hemisphere.
        for (int i = 0; i < zenithNodes; ++i) {
            const double mu = gx[i], st = std::sqrt(1.0 - mu * mu);
            for (int j = 0; j < 2 * azimuthNodes; ++j) {
                const double ph = kPi * (j + 0.5) / azimuthNodes;
                const glm::dvec3 v(st * std::cos(ph), st * std::sin(ph), mu);
                const glm::dvec3 rgb = m.toRgb(m.transfer(h, v, L.dir)) * L.scale;
                const double wgt = gw[i] * mu * kPi / azimuthNodes;
                out.diffuse += color::luminance(rgb) * wgt;
                out.globalRgb += rgb * wgt;
            }
        }
    }
    out.global = out.direct + out.diffuse;
    return out;
}

const std::vector<double>& ReferenceSky::wavelengths() const { return impl_->wl; }
const Atmosphere& ReferenceSky::atmosphere() const { return impl_->atm; }
const ReferenceOptions& ReferenceSky::options() const { return impl_->opt; }
int ReferenceSky::orders() const { return impl_->orders; }
double ReferenceSky::lastOrderFraction() const { return impl_->lastFraction; }
double ReferenceSky::precomputeSeconds() const { return impl_->seconds; }
glm::dvec3 ReferenceSky::toRgb(const std::vector<double>& transfer) const { return impl_->toRgb(transfer); }

}  // namespace welkin::atmosphere
