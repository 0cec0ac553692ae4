// welkin bench cloud-fit: regenerates the fitted constants of the clouds' light transfer
// (clouds_transfer.shared.glsl's cld_lightTransfer: the diffusion term's k, c, h, z and the
// forward-peaked orders' w_m, g_m; cloudcpu::kLightTransferFit in clouds.hpp) from the path
// tracer (generators/reference, cloudref) and adding-doubling. Deterministic per seed.
//
// The data: the path tracer's radiance of conservative plane-parallel slabs of the droplets' Mie
// phase (cloudref::cloudDropletPhase, r_eff 10 um), its forward peak truncated at 3 deg with the
// extinction scaled (cloudref::truncatePhase), optical depth tau = 0.5, 1, 2, 4, 8, 16, 32, the Sun
// overhead and 60 deg from the zenith (unit irradiance), seen from below at 3.5-80 deg from the Sun
// and from above at 0-80 deg from the backscatter direction (kDirections; views within 80 deg of
// the vertical), --paths paths a direction; and adding-doubling's transmission and reflection
// (HG g 0.86, 16 streams) at tau = 3, 10, 30, 100, mu0 = 1 and 0.5.
// The model: the formal solution of the same slabs with the transfer's own text (the shared GLSL
// compiled here again in double with the constants as variables) and its delta-M scaled extinction.
// The fit: Nelder-Mead (restarted from the best vertex until a pass gains < 1e-7, at most --passes passes, 4) on the mean squared log ratio of the
// model's radiances to the path tracer's, plus a penalty where the model's slab fluxes leave
// 0.87-1.18x (transmission) or 0.72-1.28x (reflection) of adding-doubling's (inside the element's
// slab test's 0.85-1.2x and 0.7-1.3x). Nine free constants: k, c, h, z, w_0, g_0, one w for the orders 1-4,
// g_1, and g_2 = g_3 = g_4. A = 2, q = 0.75 and the 0.2 floor of the
// light's cosine are kept (the ambient's constants, fitted to adding-doubling alone).
// Prints the committed and the fitted constants, the objective at both, the radiance ratios by
// group, the slab fluxes against adding-doubling (the element test's quadrature), and the C++
// initialiser to paste into clouds.hpp; writes the constants as CSV.
#include "bench_util.hpp"

#include <CLI/CLI.hpp>
#include <welkin/bench.hpp>
#include <welkin/csv.hpp>
#include <welkin/elements/clouds.hpp>
#include <welkin/error.hpp>
#include <welkin/generators/reference_clouds.hpp>
#include <welkin/glsl_cpp.hpp>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <string>
#include <thread>
#include <vector>

namespace welkin::cli::cloudfit {
// The constants the transfer's text reads while the fit evaluates it (one thread evaluates).
thread_local elements::cloudcpu::LightTransferConstants gFit = elements::cloudcpu::kLightTransferFit;
// The constants the fit keeps (clouds.hpp's cloudcpu::kDiffusion*, as clouds.cpp; the ambient's
// k, z, h, c are cloudcpu::kAmbientTransfer's, one source for both).
constexpr double kA = elements::cloudcpu::kDiffusionA, kQ = elements::cloudcpu::kDiffusionQ, kMuMin = elements::cloudcpu::kDiffusionMuMin,
                 kS = elements::cloudcpu::kDiffusionS;
}  // namespace welkin::cli::cloudfit

// The transfer's text once more, its fitted constants read from gFit.
namespace welkin::glsl::dp::cloud_fit_transfer {
#define CLD_PI std::numbers::pi
#define CLD_W_DRAINE welkin::elements::cloudcpu::kDropletWDraine
#define CLD_G_DRAINE welkin::elements::cloudcpu::kDropletGDraine
#define CLD_ALPHA_DRAINE welkin::elements::cloudcpu::kDropletAlphaDraine
#define CLD_MS_S welkin::cli::cloudfit::kS
#define CLD_MS_K welkin::elements::cloudcpu::kAmbientTransfer.k
#define CLD_MS_Z welkin::elements::cloudcpu::kAmbientTransfer.z
#define CLD_MS_A welkin::cli::cloudfit::kA
#define CLD_MS_H welkin::elements::cloudcpu::kAmbientTransfer.h
#define CLD_MS_C (welkin::elements::cloudcpu::kAmbientTransfer.c / welkin::elements::cloudcpu::kDropletWDraine)
#define CLD_MS_Q welkin::cli::cloudfit::kQ
#define CLD_MS_MU_MIN welkin::cli::cloudfit::kMuMin
#define CLD_MS_AMBIENT (2.0 / (1.0 + welkin::cli::cloudfit::kQ))
#define CLD_AMB_FORWARD welkin::elements::cloudcpu::kDraineForwardFraction
#define CLD_DIFFUSIVITY welkin::elements::cloudcpu::kDiffusivity
#define CLD_SUN_K welkin::cli::cloudfit::gFit.k
#define CLD_SUN_Z welkin::cli::cloudfit::gFit.z
#define CLD_SUN_H welkin::cli::cloudfit::gFit.h
#define CLD_SUN_C (welkin::cli::cloudfit::gFit.c / welkin::elements::cloudcpu::kDropletWDraine)
#define CLD_FW_W0 welkin::cli::cloudfit::gFit.w[0]
#define CLD_FW_W1 welkin::cli::cloudfit::gFit.w[1]
#define CLD_FW_W2 welkin::cli::cloudfit::gFit.w[2]
#define CLD_FW_W3 welkin::cli::cloudfit::gFit.w[3]
#define CLD_FW_W4 welkin::cli::cloudfit::gFit.w[4]
#define CLD_FW_G0 welkin::cli::cloudfit::gFit.g[0]
#define CLD_FW_G1 welkin::cli::cloudfit::gFit.g[1]
#define CLD_FW_G2 welkin::cli::cloudfit::gFit.g[2]
#define CLD_FW_G3 welkin::cli::cloudfit::gFit.g[3]
#define CLD_FW_G4 welkin::cli::cloudfit::gFit.g[4]
#include "../shaders/clouds_transfer.shared.glsl"
#include "../src/clouds_transfer_undef.inc"
}  // namespace welkin::glsl::dp::cloud_fit_transfer

namespace welkin::cli {
namespace {

using elements::cloudcpu::kDropletWDraine;
using elements::cloudcpu::LightTransferConstants;
constexpr double kDeg = std::numbers::pi / 180.0;
// The free constants: k, c, h, z; w_0, g_0 (the diffraction peak's wings); one weight w for the
// orders m = 1..4 and their lobes' g_1 and g_2 = g_3 = g_4. Fitted apart, the orders' weights and
// lobes trade off against each other (a 300-path run of all thirteen put w_2 = 0, w_3 = 1.7): the
// committed fit's w_1..4 were within 4 % of one value and g_2..4 within 5 %.
constexpr int kParams = 9;
const char* const kNames[14] = {"k", "c", "h", "z", "w0", "w1", "w2", "w3", "w4", "g0", "g1", "g2", "g3", "g4"};

std::vector<double> toParams(const LightTransferConstants& c) {
    return {c.k, c.c, c.h, c.z, c.w[0], c.g[0], 0.25 * (c.w[1] + c.w[2] + c.w[3] + c.w[4]), c.g[1], (c.g[2] + c.g[3] + c.g[4]) / 3.0};
}
LightTransferConstants fromParams(const std::vector<double>& p) {
    return {p[0], p[1], p[2], p[3], {p[4], p[6], p[6], p[6], p[6]}, {p[5], p[7], p[8], p[8], p[8]}};
}
double constant(const LightTransferConstants& c, int i) {
    return i < 4 ? (&c.k)[i] : i < 9 ? c.w[i - 4] : c.g[i - 9];
}

double transfer(const LightTransferConstants& c, double nu, double tauL, double tauB, double muL) {
    cloudfit::gFit = c;
    return glsl::dp::cloud_fit_transfer::cld_lightTransfer(nu, tauL, tauB, muL);
}

// One path-traced direction of one slab.
struct Sample {
    double tau = 0, mu0 = 1;
    glm::dvec3 view{0.0};  // the camera ray (below the slab: up, above: down)
    double L = 0, sigma = 0;  // path tracer, per unit irradiance (1/sr)
    const char* group = "";
};

// The directions: from below (transmitted), at alpha deg from the Sun in the vertical plane
// through the Sun (on the zenith's side; with the Sun 60 deg from the zenith also on the far side
// up to 20 deg, and across the plane at 10, 30 and 60 deg); from above (reflected), at alpha deg
// from the backscatter direction the same way (across at 20 and 60 deg). Views beyond 80 deg from
// the vertical are left out. 41 directions a slab with the Sun oblique, 16 with it overhead.
const double kBelowDeg[] = {3.5, 5, 7.5, 10, 15, 20, 30, 45, 60, 80};
const double kAboveDeg[] = {0, 10, 20, 40, 60, 80};
const double kTaus[] = {0.5, 1, 2, 4, 8, 16, 32};
const double kMu0s[] = {1.0, 0.5};

std::vector<Sample> directions() {
    std::vector<Sample> out;
    for (double tau : kTaus)
        for (double mu0 : kMu0s) {
            const glm::dvec3 s(std::sqrt(1.0 - mu0 * mu0), 0.0, mu0);
            // Unit vectors perpendicular to the axis a: e1 in the vertical plane towards the zenith, e2 across it.
            auto add = [&](const glm::dvec3& a, double alphaDeg, bool below, int side) {
                const glm::dvec3 e1 = std::abs(a.z) > 0.9999 ? glm::dvec3(1, 0, 0) : glm::normalize(glm::dvec3(0, 0, below ? 1 : -1) - a.z * a);
                const glm::dvec3 e2 = glm::normalize(glm::cross(a, e1));
                const glm::dvec3 e = side == 0 ? e1 : side == 1 ? -e1 : e2;
                const glm::dvec3 d = glm::normalize(std::cos(alphaDeg * kDeg) * a + std::sin(alphaDeg * kDeg) * e);
                if (std::abs(d.z) < std::cos(80.0 * kDeg) - 1e-9 || (below ? d.z < 0 : d.z > 0)) return;
                Sample smp;
                smp.tau = tau;
                smp.mu0 = mu0;
                smp.view = d;
                smp.group = !below ? "reflected" : alphaDeg <= 25 && tau <= 4 ? "forward, tau <= 4" : alphaDeg <= 25 ? "forward, tau >= 8" : "transmitted, > 25 deg";
                out.push_back(smp);
            };
            const bool oblique = mu0 < 1.0;
            for (double a : kBelowDeg) {
                add(s, a, true, 0);
                if (oblique && a <= 20) add(s, a, true, 1);
                if (oblique && (a == 10 || a == 30 || a == 60)) add(s, a, true, 2);
            }
            for (double a : kAboveDeg) {
                add(-s, a, false, 0);
                if (oblique && a > 0 && a <= 20) add(-s, a, false, 1);
                if (oblique && (a == 20 || a == 60)) add(-s, a, false, 2);
            }
        }
    return out;
}

// The model's radiance for a sample: the formal solution through the slab's scaled depth ts, the
// source integrated exactly against the view's exponential over n layers.
double modelRadiance(const LightTransferConstants& c, const Sample& s, int n = 96) {
    const double ts = kDropletWDraine * s.tau;
    const glm::dvec3 sun(std::sqrt(1.0 - s.mu0 * s.mu0), 0.0, s.mu0);
    const double mv = std::abs(s.view.z), nu = glm::dot(s.view, sun), dt = ts / n;
    const bool below = s.view.z > 0;
    double L = 0.0;
    for (int i = 0; i < n; ++i) {
        const double t = (i + 0.5) * dt;  // scaled depth from the lit top
        const double near = below ? ts - (i + 1) * dt : i * dt;  // the layer's near face's depth from the camera's side
        const double w = std::exp(-near / mv) * (1.0 - std::exp(-dt / mv));
        L += transfer(c, nu, t / s.mu0, (ts - t) / s.mu0, s.mu0) * w;
    }
    return L;
}

// The model's slab fluxes (fractions of the beam's flux; T with the scaled direct beam): the same
// formal solution integrated over the hemispheres, midpoint in mu (nm) and in azimuth (nf over pi,
// symmetric), n layers. With (200, 48, 16) this is the element test's realTimeSlab.
struct Flux {
    double T = 0, R = 0;
};
Flux modelFlux(const LightTransferConstants& c, double tau, double mu0, int n, int nm, int nf, bool exactLayers) {
    const double ts = kDropletWDraine * tau, pi = std::numbers::pi, dt = ts / n;
    Flux f;
    f.T = std::exp(-ts / mu0);
    for (int im = 0; im < nm; ++im) {
        const double mu = (im + 0.5) / nm;
        for (int jf = 0; jf < nf; ++jf) {
            const double sn = std::sqrt(1 - mu * mu) * std::sqrt(1 - mu0 * mu0) * std::cos((jf + 0.5) * pi / nf);
            double lt = 0, lr = 0;
            for (int it = 0; it < n; ++it) {
                const double t = (it + 0.5) * dt;
                double wt, wr;
                if (exactLayers) {
                    const double a = 1.0 - std::exp(-dt / mu);
                    wt = std::exp(-(ts - (it + 1) * dt) / mu) * a;
                    wr = std::exp(-it * dt / mu) * a;
                } else {
                    wt = std::exp(-(ts - t) / mu) * dt / mu;
                    wr = std::exp(-t / mu) * dt / mu;
                }
                lt += transfer(c, mu * mu0 + sn, t / mu0, (ts - t) / mu0, mu0) * wt;
                lr += transfer(c, -mu * mu0 + sn, t / mu0, (ts - t) / mu0, mu0) * wr;
            }
            f.T += lt * mu * (1.0 / nm) * (2 * pi / nf) / mu0;
            f.R += lr * mu * (1.0 / nm) * (2 * pi / nf) / mu0;
        }
    }
    return f;
}

struct FluxCase {
    double tau, mu0;
    cloudref::SlabSolution ad;
};

// The fit's bounds on the flux ratios (inside the element test's 0.85-1.2 and 0.7-1.3).
constexpr double kTLo = 0.87, kTHi = 1.18, kRLo = 0.72, kRHi = 1.28;

struct Objective {
    const std::vector<Sample>* samples;
    const std::vector<FluxCase>* fluxes;
    double logRms = 0, penalty = 0;
    double operator()(const std::vector<double>& p) {
        const LightTransferConstants c = fromParams(p);
        // Outside the constants' meaning: w >= 0, 0 <= g < 0.995, k, c, z > 0.
        double bad = 0;
        for (int i = 0; i < 5; ++i) bad += std::max(0.0, -c.w[i]);
        for (int i = 0; i < 4; ++i) bad += std::max(0.0, -c.g[i]) + std::max(0.0, c.g[i] - 0.995);
        bad += std::max(0.0, 1e-3 - c.k) + std::max(0.0, 1e-3 - c.c) + std::max(0.0, 1e-3 - c.z);
        if (bad > 0) return 1e3 + bad;
        double s2 = 0;
        {
            // The directions over two threads (each has its own copy of the constants).
            double part[2] = {0, 0};
            auto sum = [&](int k) {
                for (size_t i = size_t(k); i < samples->size(); i += 2) {
                    const Sample& s = (*samples)[i];
                    const double r = std::log(std::max(modelRadiance(c, s), 1e-30) / s.L);
                    part[k] += r * r;
                }
            };
            std::thread t1(sum, 1);
            sum(0);
            t1.join();
            s2 = part[0] + part[1];
        }
        logRms = std::sqrt(s2 / double(samples->size()));
        penalty = 0;
        for (const FluxCase& fc : *fluxes) {
            const Flux f = modelFlux(c, fc.tau, fc.mu0, 48, 12, 6, true);
            const double lt = std::log(f.T / fc.ad.transmission), lr = std::log(f.R / fc.ad.reflection);
            penalty += std::pow(std::max(0.0, lt - std::log(kTHi)), 2) + std::pow(std::max(0.0, std::log(kTLo) - lt), 2) +
                       std::pow(std::max(0.0, lr - std::log(kRHi)), 2) + std::pow(std::max(0.0, std::log(kRLo) - lr), 2);
        }
        return logRms * logRms + 100.0 * penalty;
    }
};

// Nelder-Mead (Lagarias et al. 1998's coefficients 1, 2, 0.5, 0.5), initial simplex steps of 10 %
// of each value (0.05 where it is near 0); at most maxEvals evaluations; deterministic.
std::vector<double> nelderMead(Objective& f, std::vector<double> x0, int maxEvals, int& evals) {
    const int n = int(x0.size());
    std::vector<std::vector<double>> v(n + 1, x0);
    std::vector<double> fv(n + 1);
    for (int i = 0; i < n; ++i) v[i + 1][i] += std::abs(x0[i]) > 0.05 ? 0.1 * x0[i] : 0.05;
    for (int i = 0; i <= n; ++i) fv[i] = f(v[i]), ++evals;
    int used = n + 1;
    auto at = [&](const std::vector<double>& c, const std::vector<double>& w, double t) {
        std::vector<double> r(n);
        for (int i = 0; i < n; ++i) r[i] = c[i] + t * (w[i] - c[i]);
        return r;
    };
    while (used < maxEvals) {
        std::vector<int> idx(n + 1);
        for (int i = 0; i <= n; ++i) idx[i] = i;
        std::stable_sort(idx.begin(), idx.end(), [&](int a, int b) { return fv[a] < fv[b]; });
        const int best = idx[0], worst = idx[n], second = idx[n - 1];
        if (fv[worst] - fv[best] < 1e-10 * (1.0 + std::abs(fv[best]))) break;
        std::vector<double> cen(n, 0.0);
        for (int i = 0; i <= n; ++i)
            if (i != worst)
                for (int j = 0; j < n; ++j) cen[j] += v[i][j] / n;
        const auto xr = at(cen, v[worst], -1.0);
        const double fr = f(xr);
        ++used;
        if (fr < fv[best]) {
            const auto xe = at(cen, v[worst], -2.0);
            const double fe = f(xe);
            ++used;
            if (fe < fr) v[worst] = xe, fv[worst] = fe;
            else v[worst] = xr, fv[worst] = fr;
        } else if (fr < fv[second]) {
            v[worst] = xr, fv[worst] = fr;
        } else {
            const bool outside = fr < fv[worst];
            const auto xc = outside ? at(cen, xr, 0.5) : at(cen, v[worst], 0.5);
            const double fc = f(xc);
            ++used;
            if (fc < (outside ? fr : fv[worst])) {
                v[worst] = xc, fv[worst] = fc;
            } else {  // shrink towards the best
                for (int i = 0; i <= n; ++i)
                    if (i != best) {
                        v[i] = at(v[best], v[i], 0.5);
                        fv[i] = f(v[i]);
                        ++used;
                    }
            }
        }
    }
    evals += used - (n + 1);
    int best = 0;
    for (int i = 1; i <= n; ++i)
        if (fv[i] < fv[best]) best = i;
    return v[best];
}

struct FitOptions {
    int paths = 60000;  // path-traced paths a direction
    uint64_t seed = 1;
    int threads = 2;
    int evaluations = 3000;  // Nelder-Mead evaluations per pass
    int passes = 4;          // Nelder-Mead passes at most (each restarts from the best vertex)
    std::string start = "neutral";  // the fit's start: neutral (the constants before the fit) or committed
    std::string csv = "bench_cloud_fit.csv";
    bool list = false;  // print every direction
};

int run(const FitOptions& o) {
    if (o.paths < 100 || o.paths > 10000000) throw Error("--paths " + std::to_string(o.paths) + " not in [100, 1e7]");
    if (o.threads < 1 || o.threads > 64) throw Error("--threads " + std::to_string(o.threads) + " not in [1, 64]");
    if (o.evaluations < 100 || o.evaluations > 1000000) throw Error("--evaluations " + std::to_string(o.evaluations) + " not in [100, 1e6]");
    if (o.passes < 1 || o.passes > 20) throw Error("--passes " + std::to_string(o.passes) + " not in [1, 20]");
    if (o.start != "neutral" && o.start != "committed") throw Error("--start '" + o.start + "' not one of neutral, committed");
    checkOutputDirectory("--csv", o.csv);
    const auto t0 = std::chrono::steady_clock::now();
    const LightTransferConstants committed = elements::cloudcpu::kLightTransferFit;
    // The text compiled here is the element's: with the committed constants it must give
    // cloudcpu::lightTransfer exactly.
    for (double nu : {-0.9, 0.0, 0.7, 0.999})
        for (double tl : {0.0, 0.3, 5.0})
            for (double mu : {0.1, 0.6, 1.0}) {
                const double a = transfer(committed, nu, tl, 2.0, mu), b = elements::cloudcpu::lightTransfer(nu, tl, 2.0, mu);
                if (std::abs(a - b) > 1e-12 * std::abs(b)) throw Error("bench cloud-fit: the fit's transfer differs from cloudcpu::lightTransfer");
            }

    // The path tracer's slab radiances.
    std::vector<Sample> samples = directions();
    const cloudref::TabulatedPhase mie = cloudref::cloudDropletPhase();
    const cloudref::TruncatedPhase cut = cloudref::truncatePhase(mie, 3.0 * kDeg);
    std::printf("welkin bench cloud-fit: %zu slab directions, %d paths each, seed %llu, %d threads\n", samples.size(), o.paths,
                (unsigned long long)o.seed, o.threads);
    std::fflush(stdout);
    {
        std::atomic<size_t> next{0};
        auto work = [&] {
            for (size_t i = next++; i < samples.size(); i = next++) {
                Sample& s = samples[i];
                const cloudref::SlabMedium slab(0.0, 1000.0, s.tau * (1.0 - cut.removedFraction) / 1000.0);
                cloudref::Scene sc;
                sc.medium = &slab;
                sc.phase = &cut.phase;
                sc.lights.sunDirection = {std::sqrt(1.0 - s.mu0 * s.mu0), 0.0, s.mu0};
                sc.lights.sunIrradiance = glm::dvec3(1.0);
                const glm::dvec3 origin = s.view.z > 0 ? glm::dvec3(0.0, 0.0, -10.0) : glm::dvec3(0.0, 0.0, 1010.0);
                const cloudref::Estimate e = cloudref::radiance(sc, origin, s.view, o.paths, o.seed, i);
                s.L = e.mean.y;
                s.sigma = e.sigma.y;
            }
        };
        std::vector<std::thread> pool;
        for (int t = 0; t < o.threads; ++t) pool.emplace_back(work);
        for (auto& t : pool) t.join();
    }
    double noise = 0;
    for (const Sample& s : samples) noise += s.sigma / s.L;
    noise /= double(samples.size());
    const double tPt = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    std::printf("path tracer: %.0f s, mean relative standard error %.2f %%\n", tPt, 100 * noise);

    // Adding-doubling's fluxes.
    std::vector<FluxCase> fluxes;
    const auto moments = cloudref::hgMoments(0.86, 64);
    for (double tau : {3.0, 10.0, 30.0, 100.0})
        for (double mu0 : {1.0, 0.5}) fluxes.push_back({tau, mu0, cloudref::addingDoubling(tau, 1.0, moments, mu0, 16)});

    // The fit.
    Objective f{&samples, &fluxes};
    const double fCommitted = f(toParams(committed));
    const double rmsCommitted = f.logRms, penCommitted = f.penalty;
    // The neutral start: the ambient's diffusion constants (the lights' before any fit) and neutral orders.
    constexpr auto amb = elements::cloudcpu::kAmbientTransfer;
    const LightTransferConstants neutral{amb.k, amb.c, amb.h, amb.z, {0.5, 0.3, 0.3, 0.3, 0.3}, {0.95, 0.8, 0.7, 0.6, 0.6}};
    std::vector<double> x = toParams(o.start == "committed" ? committed : neutral);
    int evals = 0;
    double fx = f(x);
    for (int restart = 0; restart < o.passes; ++restart) {
        x = nelderMead(f, x, o.evaluations, evals);
        const double fn = f(x);
        std::printf("  Nelder-Mead pass %d: objective %.6f (log RMS %.4f, flux penalty %.2e), %d evaluations\n", restart + 1, fn, f.logRms, f.penalty, evals);
        std::fflush(stdout);
        if (fx - fn < 1e-7) break;
        fx = fn;
    }
    const LightTransferConstants fit = fromParams(x);
    const double fFit = f(x);
    const double tAll = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();

    std::printf("\nobjective (mean squared log ratio + 100 x flux penalty): committed %.5f (log RMS %.4f, penalty %.2e), fitted %.5f (log RMS %.4f, penalty %.2e)\n",
                fCommitted, rmsCommitted, penCommitted, fFit, f.logRms, f.penalty);
    std::printf("\n| constant | committed | fitted |\n|---|---|---|\n");
    for (int i = 0; i < 14; ++i) std::printf("| %s | %.4f | %.4f |\n", kNames[i], constant(committed, i), constant(fit, i));
    if (o.list) {
        std::printf("\n| tau | mu0 | view zenith deg | from the Sun deg | path tracer 1/sr | +- | committed / path tracer | fitted / path tracer |\n|---|---|---|---|---|---|---|---|\n");
        for (const Sample& s : samples) {
            const glm::dvec3 sun(std::sqrt(1.0 - s.mu0 * s.mu0), 0.0, s.mu0);
            std::printf("| %g | %g | %.1f | %.1f | %.5f | %.5f | %.3f | %.3f |\n", s.tau, s.mu0, std::acos(std::abs(s.view.z)) / kDeg,
                        std::acos(std::clamp(glm::dot(s.view, sun), -1.0, 1.0)) / kDeg, s.L, s.sigma, modelRadiance(committed, s) / s.L, modelRadiance(fit, s) / s.L);
        }
    }
    // The radiance ratios by group.
    std::printf("\nmodel / path tracer radiance, by group (committed | fitted): min, median, max\n");
    for (const char* g : {"forward, tau <= 4", "forward, tau >= 8", "transmitted, > 25 deg", "reflected"}) {
        std::vector<double> a, b;
        for (const Sample& s : samples)
            if (std::string(s.group) == g) a.push_back(modelRadiance(committed, s) / s.L), b.push_back(modelRadiance(fit, s) / s.L);
        std::sort(a.begin(), a.end());
        std::sort(b.begin(), b.end());
        std::printf("  %-22s %3zu: %.2f %.2f %.2f | %.2f %.2f %.2f\n", g, a.size(), a.front(), a[a.size() / 2], a.back(), b.front(), b[b.size() / 2], b.back());
    }
    // The fluxes with the element test's quadrature.
    std::printf("\nslab fluxes / adding-doubling (the element test's quadrature; accepted T 0.85-1.2, R 0.7-1.3), committed | fitted\n");
    for (const FluxCase& fc : fluxes) {
        const Flux a = modelFlux(committed, fc.tau, fc.mu0, 200, 48, 16, false), b = modelFlux(fit, fc.tau, fc.mu0, 200, 48, 16, false);
        std::printf("  tau %5.0f mu0 %.1f: T %.3f R %.3f | T %.3f R %.3f\n", fc.tau, fc.mu0, a.T / fc.ad.transmission, a.R / fc.ad.reflection,
                    b.T / fc.ad.transmission, b.R / fc.ad.reflection);
    }
    std::printf("\nclouds.hpp:\ninline constexpr LightTransferConstants kLightTransferFit{%.5f, %.4f, %.4f, %.4f,\n"
                "                                                          {%.4f, %.4f, %.4f, %.4f, %.4f},\n"
                "                                                          {%.4f, %.4f, %.4f, %.4f, %.4f}};\n",
                fit.k, fit.c, fit.h, fit.z, fit.w[0], fit.w[1], fit.w[2], fit.w[3], fit.w[4], fit.g[0], fit.g[1], fit.g[2], fit.g[3], fit.g[4]);
    std::printf("\ntotal %.0f s\n", tAll);
    if (!o.csv.empty()) {
        CsvWriter w(o.csv, {"constant", "committed", "fitted"});
        w.comment("welkin bench cloud-fit, " + std::to_string(o.paths) + " paths a direction, seed " + std::to_string(o.seed) + ", start " + o.start +
                  "; objective committed " + std::to_string(fCommitted) + ", fitted " + std::to_string(fFit));
        for (int i = 0; i < 14; ++i) w.row(std::string(kNames[i]), constant(committed, i), constant(fit, i));
        w.row(std::string("objective"), fCommitted, fFit);
        w.row(std::string("log_rms"), rmsCommitted, f.logRms);
        w.close();
        std::printf("wrote %s\n", o.csv.c_str());
    }
    return 0;
}

// ---- welkin bench cloud-table: the diffusion term's angular correction ------------------------
//
// For each node (tauAxis 1, 2, 4 ... 256 along the light's axis, muL 0.2 ... 1, the view's
// cos(zenith) muV -1 ... 1): a slab of vertical optical depth tauAxis muL of the droplets' Mie
// phase (cloudref::cloudDropletPhase, its Legendre moments), lit at muL; adding-doubling's
// azimuth-averaged diffuse radiance (32 streams, linear in mu between its nodes) less this model's
// single scattering and forward orders, over the model's diffusion term, both the formal solution
// of the slab (96 layers, each exact against the view's exponential) averaged over 24 azimuths;
// clamped to [0.25, 4]. |muV| below 0.05 is taken at 0.05; muV = 0 is the mean of both sides.
// Deterministic (no Monte Carlo). The committed constants (kLightTransferFit) are the model's:
// regenerate the table after `welkin bench cloud-fit`.
struct ShapeParts {
    double low = 0, multi = 0;
};
// The model's azimuth-averaged radiance at scaled depth fraction `depthFrac` of the slab,
// travelling along -view (muV > 0: downwards, the light from the layers above; < 0: upwards):
// its formal solution from the slab's face to the depth, 96 layers.
ShapeParts modelParts(double tau, double mu0, double muV, double depthFrac) {
    const LightTransferConstants c = elements::cloudcpu::kLightTransferFit;
    cloudfit::gFit = c;
    namespace tr = glsl::dp::cloud_fit_transfer;
    const int n = 96, nf = 24;
    const double ts = kDropletWDraine * tau, td = depthFrac * ts, mv = std::abs(muV), st = std::sqrt(1.0 - muV * muV);
    const glm::dvec3 sun(std::sqrt(1.0 - mu0 * mu0), 0.0, mu0);
    const bool below = muV > 0;
    const double a = below ? 0.0 : td, b = below ? td : ts, dt = (b - a) / n;  // the layers that send light to the depth
    ShapeParts p;
    if (dt <= 0.0) return p;
    for (int jf = 0; jf < nf; ++jf) {
        const double phi = (jf + 0.5) * std::numbers::pi / nf;
        const glm::dvec3 view(st * std::cos(phi), st * std::sin(phi), muV);
        const double nu = glm::dot(view, sun);
        for (int i = 0; i < n; ++i) {
            const double t = a + (i + 0.5) * dt;
            const double near = below ? td - (a + (i + 1) * dt) : a + i * dt - td;  // from the depth to the layer's near side
            const double w = std::exp(-near / mv) * (1.0 - std::exp(-dt / mv)) / nf;
            const double tl = t / mu0, tb = (ts - t) / mu0;
            p.low += (tr::cld_scaledPhase(nu) * std::exp(-tl) + tr::cld_forwardTransfer(nu, tl)) * w;
            p.multi += tr::cld_lightDiffusion(nu, tl, tb, mu0) * w;
        }
    }
    return p;
}
double interpolateMu(const std::vector<double>& mu, const std::vector<double>& v, double x) {
    if (x <= mu.front()) return v.front();
    if (x >= mu.back()) return v.back();
    size_t i = 1;
    while (mu[i] < x) ++i;
    const double f = (x - mu[i - 1]) / (mu[i] - mu[i - 1]);
    return v[i - 1] + f * (v[i] - v[i - 1]);
}
}  // namespace
std::vector<double> diffusionShapeTableComputed() {
    using elements::cloudcpu::kShapeDepthN;
    using elements::cloudcpu::kShapeMuLN;
    using elements::cloudcpu::kShapeMuVN;
    using elements::cloudcpu::kShapeTauN;
    const cloudref::TabulatedPhase mie = cloudref::cloudDropletPhase();
    const std::vector<double> moments = cloudref::phaseMoments(mie, 65);
    std::vector<double> table(size_t(kShapeTauN * kShapeMuLN * kShapeDepthN * kShapeMuVN));
    for (int i = 0; i < kShapeTauN; ++i)
        for (int j = 0; j < kShapeMuLN; ++j) {
            const double tauAxis = std::exp2(double(i)), mu0 = 0.2 + 0.2 * j, tau = tauAxis * mu0;
            // The ratio where the diffusion term carries the light (the model's low orders under
            // half of adding-doubling's radiance, its diffusion over a quarter); elsewhere (towards
            // the light, where adding-doubling's delta-M moved the peak into the direct beam and
            // the low orders dominate; thin slabs; the light going down at the lit face, where
            // there is none yet) the nearest such node's along the depth, else along muV, else 1.
            double v[kShapeDepthN][kShapeMuVN];
            bool ok[kShapeDepthN][kShapeMuVN];
            for (int m = 0; m < kShapeDepthN; ++m) {
                const double frac = double(m) / (kShapeDepthN - 1);
                const cloudref::SlabInternal in = cloudref::addingDoublingInternal(tau, 1.0, moments, mu0, frac * tau, 32);
                auto ratio = [&](double muV, bool& good) {
                    const ShapeParts p = modelParts(tau, mu0, muV, frac);
                    const double L = interpolateMu(in.mu, muV > 0 ? in.down : in.up, std::abs(muV));
                    good = L > 0.0 && p.low < 0.5 * L && p.multi > 0.25 * L;
                    return std::clamp((L - p.low) / std::max(p.multi, 1e-30), 0.25, 4.0);
                };
                for (int k = 0; k < kShapeMuVN; ++k) {
                    const double muV = -1.0 + 2.0 * k / (kShapeMuVN - 1);
                    if (std::abs(muV) < 0.05) {
                        bool a, b;
                        v[m][k] = 0.5 * (ratio(0.05, a) + ratio(-0.05, b));
                        ok[m][k] = a && b;
                    } else {
                        v[m][k] = ratio(muV, ok[m][k]);
                    }
                }
            }
            for (int m = 0; m < kShapeDepthN; ++m)
                for (int k = 0; k < kShapeMuVN; ++k) {
                    double x = 1.0;
                    bool found = false;
                    // A face's node for the light leaving by it (the lit face looking down, the far
                    // one looking up: what a cumulus reads, cld_tableDepth with deck 0) falls back
                    // along muV only, else 1, as the face-only table did: the same values.
                    const int mid = kShapeMuVN / 2;
                    const bool face = (m == 0 && k <= mid) || (m == kShapeDepthN - 1 && k >= mid);
                    if (face) {
                        // each candidate node at its own exit face (horizontal: the node itself)
                        auto fm = [&](int kk) { return kk < mid ? 0 : (kk > mid ? kShapeDepthN - 1 : m); };
                        for (int d = 0; d < kShapeMuVN && !found; ++d) {
                            if (k - d >= 0 && ok[fm(k - d)][k - d]) x = v[fm(k - d)][k - d], found = true;
                            else if (k + d < kShapeMuVN && ok[fm(k + d)][k + d]) x = v[fm(k + d)][k + d], found = true;
                        }
                        found = true;
                    }
                    for (int d = 0; d < kShapeDepthN && !found; ++d) {
                        if (m - d >= 0 && ok[m - d][k]) x = v[m - d][k], found = true;
                        else if (m + d < kShapeDepthN && ok[m + d][k]) x = v[m + d][k], found = true;
                    }
                    for (int d = 1; d < kShapeMuVN && !found; ++d) {
                        if (k - d >= 0 && ok[m][k - d]) x = v[m][k - d], found = true;
                        else if (k + d < kShapeMuVN && ok[m][k + d]) x = v[m][k + d], found = true;
                    }
                    table[size_t(((i * kShapeMuLN + j) * kShapeDepthN + m) * kShapeMuVN + k)] = x;
                }
        }
    return table;
}
namespace {

struct TableOptions {
    std::string out = "clouds_transfer_table.shared.glsl";
    bool check = false;
};

int runTable(const TableOptions& o) {
    const auto t0 = std::chrono::steady_clock::now();
    const std::vector<double> t = diffusionShapeTableComputed();
    const double* committed = elements::cloudcpu::diffusionShapeTable();
    double maxDiff = 0, lo = 1e9, hi = 0;
    for (size_t q = 0; q < t.size(); ++q) {
        maxDiff = std::max(maxDiff, std::abs(t[q] - committed[q]));
        lo = std::min(lo, t[q]);
        hi = std::max(hi, t[q]);
    }
    const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    std::printf("welkin bench cloud-table: %zu values in [%.3f, %.3f], %.1f s; largest difference from the committed table %.2e\n", t.size(), lo, hi, secs, maxDiff);
    using elements::cloudcpu::kShapeMuVN;
    using elements::cloudcpu::kShapeDepthN;
    std::printf("\n| tauAxis | muL | depth | muV -1 ... 1 (every second node) |\n|---|---|---|---|\n");
    for (int i = 0; i < elements::cloudcpu::kShapeTauN; i += 2)
        for (int j = 0; j < elements::cloudcpu::kShapeMuLN; j += 2)
            for (int m = 0; m < kShapeDepthN; m += 2) {
                std::printf("| %g | %.1f | %.2f |", std::exp2(double(i)), 0.2 + 0.2 * j, double(m) / (kShapeDepthN - 1));
                for (int k = 0; k < kShapeMuVN; k += 2)
                    std::printf(" %.2f", t[size_t(((i * elements::cloudcpu::kShapeMuLN + j) * kShapeDepthN + m) * kShapeMuVN + k)]);
                std::printf(" |\n");
            }
    if (o.check) {
        // The committed file holds 5 decimals.
        if (maxDiff > 2e-5) throw Error("bench cloud-table: the committed table differs from the computed one by " + std::to_string(maxDiff));
        std::printf("the committed table matches\n");
        return 0;
    }
    if (o.out.empty()) return 0;
    std::string txt =
        "// Generated by `welkin bench cloud-table` (skyelements/clouds/bench/bench_cloud_fit.cpp): do not edit.\n"
        "// The diffusion term's angular correction, cld_diffusionShape (clouds_transfer.shared.glsl):\n"
        "// [tauAxis 1, 2, 4 ... 256][muL 0.2, 0.4 ... 1][depth 0, 0.25 ... 1 of the slab][muV -1, -0.875 ... 1],\n"
        "// 9 x 5 x 5 x 17: adding-doubling's multiply scattered radiance over the diffusion term's\n"
        "// (skyelements/clouds/README.md, \"The transfer table\").\n"
        "const real cld_msTable[3825] = ARRAY_OF(real, 3825)\n";
    char buf[32];
    for (size_t q = 0; q < t.size(); ++q) {
        if (q % 17 == 0) txt += "    ";
        std::snprintf(buf, sizeof buf, "%.5f", t[q]);
        txt += buf;
        txt += q + 1 == t.size() ? "\n" : q % 17 == 16 ? ",\n" : ", ";
    }
    txt += "END_ARRAY;\n";
    FILE* f = std::fopen(o.out.c_str(), "w");
    if (!f) throw Error("--out: cannot write '" + o.out + "'");
    std::fputs(txt.c_str(), f);
    std::fclose(f);
    std::printf("wrote %s\n", o.out.c_str());
    return 0;
}

bench::CommandBenchRegistrar regTable({"cloud-table", "regenerate the clouds' transfer table (the diffusion term's angular correction) from adding-doubling",
                                       [](CLI::App& sub) {
                                           auto o = std::make_shared<TableOptions>();
                                           sub.add_option("--out", o->out, "the GLSL file to write (empty: none)")->capture_default_str();
                                           sub.add_flag("--check", o->check, "compare with the committed table (error if it differs by > 2e-5), write nothing");
                                           return [o]() { return runTable(*o); };
                                       }});

bench::CommandBenchRegistrar reg({"cloud-fit", "regenerate the clouds' light-transfer constants from the path tracer's slab radiances and adding-doubling",
                                  [](CLI::App& sub) {
                                      auto o = std::make_shared<FitOptions>();
                                      sub.add_option("--paths", o->paths, "path-traced paths a slab direction, [100, 1e7]")->capture_default_str();
                                      sub.add_option("--seed", o->seed, "path tracer seed")->capture_default_str();
                                      sub.add_option("--threads", o->threads, "path tracer threads, [1, 64] (results do not depend on it)")->capture_default_str();
                                      sub.add_option("--evaluations", o->evaluations, "Nelder-Mead evaluations per pass, [100, 1e6]")->capture_default_str();
                                      sub.add_option("--passes", o->passes, "Nelder-Mead passes at most, each restarted from the best vertex, [1, 20]")->capture_default_str();
                                      sub.add_option("--start", o->start, "the fit's start: neutral (the constants before any fit) or committed")->capture_default_str();
                                      sub.add_flag("--list", o->list, "print every direction: the path tracer's radiance and the model's ratio to it");
                                      sub.add_option("--csv", o->csv, "write the constants as CSV (empty: none)")->capture_default_str();
                                      return [o]() { return run(*o); };
                                  }});

}  // namespace
}  // namespace welkin::cli
