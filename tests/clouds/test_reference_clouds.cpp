// The clouds' reference path tracer (generators/reference/reference_clouds.hpp) against
// independent solutions: the adding-doubling solver (itself checked against energy conservation,
// exact single scattering and its own convergence), analytic transmittances and exact single
// scattering. Monte Carlo tolerances are 4 standard errors (computed by the estimator from the
// same samples: a correct estimator fails one check in ~16000) plus the deterministic solver's
// discretisation error where stated.
#include <welkin/generators/cloud_density.hpp>
#include <welkin/generators/reference_clouds.hpp>

#include <catch2/catch.hpp>

#include <cmath>
#include <numbers>

using namespace welkin::cloudref;
namespace gen = welkin::generators;

namespace {
constexpr double kPi = std::numbers::pi;

/// Exact single-scattering reflection of a homogeneous slab lit at cos(zenith) mu0, by a
/// quadrature independent of the adding-doubling code: midpoint rule over 4000 x 720 directions
/// of the upper hemisphere of I(mu, phi) = w/(4 pi) p(cos theta) mu0/(mu0 + mu) (1 - e^{-tau (1/mu0 + 1/mu)}).
double singleScatteringReflection(double tau, double g, double mu0) {
    const HenyeyGreenstein hg(g);
    const int nm = 4000, np = 720;
    const double s0 = std::sqrt(1.0 - mu0 * mu0);
    double flux = 0.0;
    for (int i = 0; i < nm; ++i) {
        const double mu = (i + 0.5) / nm, s = std::sqrt(1.0 - mu * mu);
        for (int j = 0; j < np; ++j) {
            const double phi = 2.0 * kPi * (j + 0.5) / np;
            // Incoming beam travels down (-s0, 0, -mu0); scattered up along (s cos, s sin, mu).
            const double c = -s0 * s * std::cos(phi) - mu0 * mu;
            const double I = hg.eval(c) * mu0 / (mu0 + mu) * (1.0 - std::exp(-tau * (1.0 / mu0 + 1.0 / mu)));
            flux += I * mu * (1.0 / nm) * (2.0 * kPi / np);
        }
    }
    return flux / mu0;
}

Scene slabScene(const Medium& m, const PhaseFunction& p) {
    Scene s;
    s.medium = &m;
    s.phase = &p;
    return s;
}

glm::dvec3 beam(double mu0) { return {std::sqrt(1.0 - mu0 * mu0), 0.0, -mu0}; }
}  // namespace

TEST_CASE("Cloud reference: adding-doubling conserves energy, converges and has the single-scattering limit", "[cpu][cloudref]") {
    const auto m = hgMoments(0.85, 300);
    for (double tau : {1.0, 10.0, 100.0}) {
        for (double mu0 : {1.0, 0.5, 0.2}) {
            const SlabSolution a = addingDoubling(tau, 1.0, m, mu0, 32);
            INFO("tau " << tau << " mu0 " << mu0 << " R " << a.reflection << " T " << a.transmission);
            // Conservative scattering: the quadrature integrates the truncated phase function exactly,
            // so R + T = 1 up to the thin layer's first-order error (~tau x 1e-9) and rounding.
            CHECK(a.reflection + a.transmission == Approx(1.0).margin(1e-6));
            // Convergence in the streams: 16 and 32 per hemisphere agree to 1e-3 of the flux (the
            // solver is then far better than the 1 % the Monte Carlo comparison needs).
            const SlabSolution b = addingDoubling(tau, 1.0, m, mu0, 16);
            CHECK(b.transmission == Approx(a.transmission).margin(1e-3));
        }
    }
    // Absorption removes light: R + T < 1 when the albedo is below 1.
    const SlabSolution abs = addingDoubling(10.0, 0.9, m, 1.0);
    CHECK(abs.reflection + abs.transmission < 0.9);
    // The thin limit: reflection is single scattering. The second order adds ~7-11 tau relative
    // here (measured: 0.7 % and 1.1 % at tau = 1e-3, 0.09 % and 0.14 % at 1e-4, 0.010 % and 0.016 %
    // at 1e-5 for mu0 = 1 and 0.4: linear in tau), so at tau = 1e-5 the two agree to 5e-4.
    for (double mu0 : {1.0, 0.4}) {
        const double ss = singleScatteringReflection(1e-5, 0.85, mu0);
        const SlabSolution t = addingDoubling(1e-5, 1.0, m, mu0);
        INFO("mu0 " << mu0 << " AD " << t.reflection << " single " << ss);
        CHECK(t.reflection == Approx(ss).epsilon(5e-4));
        // Everything else is transmitted (conservation of the thin layers: ~tau x 1e-9 / mu_min^2 < 1e-7).
        CHECK(t.transmission + t.reflection == Approx(1.0).margin(1e-7));
    }
    // Bad input: a clear error.
    CHECK_THROWS_WITH(addingDoubling(-1.0, 1.0, m, 1.0), Catch::Contains("tau"));
    CHECK_THROWS_WITH(addingDoubling(1.0, 1.0, m, 0.0), Catch::Contains("mu0"));
}

TEST_CASE("Cloud reference: slabs' transmission and reflection match adding-doubling", "[cpu][cloudref]") {
    // HG g = 0.85, conservative scattering; tau 1 and 10 at two Sun angles, tau 50 overhead.
    const HenyeyGreenstein hg(0.85);
    const auto m = hgMoments(0.85, 300);
    struct Case { double tau, mu0; long photons; };
    for (const Case c : {Case{1.0, 1.0, 4000}, Case{1.0, 0.5, 4000}, Case{10.0, 1.0, 4000}, Case{10.0, 0.5, 4000}, Case{50.0, 1.0, 1500}}) {
        const SlabMedium slab(0.0, 1000.0, c.tau / 1000.0);
        const SlabFluxes f = slabFluxes(slabScene(slab, hg), beam(c.mu0), c.photons, 11);
        const SlabSolution a = addingDoubling(c.tau, 1.0, m, c.mu0);
        INFO("tau " << c.tau << " mu0 " << c.mu0 << " MC T " << f.transmission << " +- " << f.transmissionSigma << " AD T "
                    << a.transmission << "; MC R " << f.reflection << " AD R " << a.reflection << "; scatterings "
                    << f.meanScatterings);
        // 4 standard errors plus the solver's 1e-3 (its convergence, above).
        CHECK(std::abs(f.transmission - a.transmission) < 4.0 * f.transmissionSigma + 1e-3);
        CHECK(std::abs(f.reflection - a.reflection) < 4.0 * f.reflectionSigma + 1e-3);
        CHECK(f.absorbed == 0.0);  // conservative: nothing is absorbed
        // Direct beam: the analog count of unscattered photons against e^{-tau / mu0}.
        const double d = std::exp(-c.tau / c.mu0), sd = std::sqrt(d * (1 - d) / c.photons);
        CHECK(std::abs(f.directTransmission - d) < 4.0 * sd + 1e-12);
    }
    // The thin (Rayleigh-free, tau -> 0) limit: everything is transmitted.
    const SlabMedium thin(0.0, 1000.0, 1e-6 / 1000.0);
    const SlabFluxes f = slabFluxes(slabScene(thin, hg), beam(0.7), 2000, 3);
    CHECK(f.transmission == 1.0);  // P(any collision) = 1.4e-6 per photon: all 2000 pass
}

TEST_CASE("Cloud reference: a truncated forward peak keeps a slab's fluxes", "[cpu][cloudref]") {
    // The droplets' Mie phase with its diffraction peak cut at 3 deg (the removed fraction f
    // treated as unscattered, extinction x (1 - f)) against adding-doubling for the full phase.
    const TabulatedPhase mie = cloudDropletPhase(10e-6, 0.1, 550.0, 24, 1500);
    const TruncatedPhase cut = truncatePhase(mie, 3.0 * std::numbers::pi / 180.0);
    // The peak within 3 deg holds a large share of the scattering (diffraction: about half).
    CHECK(cut.removedFraction > 0.3);
    CHECK(cut.removedFraction < 0.6);
    // The peak is gone: inside the cone the clipped value, renormalised by 1 / (1 - f) (10 %: both
    // tables average over their angular intervals).
    CHECK(cut.phase.eval(1.0) == Approx(mie.eval(std::cos(3.0 * std::numbers::pi / 180.0)) / (1 - cut.removedFraction)).epsilon(0.1));
    // The truncated phase's g follows the delta-M relation g* = (g - f) / (1 - f) (the cone's mean
    // cosine is ~1: within 0.002 of 1 for 3 deg).
    CHECK(cut.phase.g() == Approx((mie.g() - cut.removedFraction) / (1 - cut.removedFraction)).margin(0.01));
    std::vector<double> m(64);
    {
        // Legendre moments of the full phase (midpoint rule in cos, 4e5 steps, resolving the peak).
        const int n = 400000;
        for (int i = 0; i < n; ++i) {
            const double x = -1 + (i + 0.5) * 2.0 / n, p = mie.eval(x) * 2 * std::numbers::pi * 2.0 / n;
            double p0 = 1, p1 = x;
            m[0] += p;
            m[1] += p * x;
            for (int l = 2; l < 64; ++l) {
                const double p2 = ((2 * l - 1) * x * p1 - (l - 1) * p0) / l;
                m[size_t(l)] += p * p2;
                p0 = p1;
                p1 = p2;
            }
        }
        for (int l = 63; l >= 0; --l) m[size_t(l)] /= m[0];
    }
    for (double mu0 : {1.0, 0.5}) {
        const double tau = 10.0;
        const SlabMedium slab(0.0, 1000.0, (1 - cut.removedFraction) * tau / 1000.0);
        const SlabFluxes f = slabFluxes(slabScene(slab, cut.phase), beam(mu0), 3000, 13);
        const SlabSolution a = addingDoubling(tau, 1.0, m, mu0, 16);
        INFO("mu0 " << mu0 << " f " << cut.removedFraction << " MC T " << f.transmission << " +- " << f.transmissionSigma << " AD T " << a.transmission);
        // 4 standard errors plus 0.01: delta-M's own error in a slab's fluxes (Wiscombe 1977: < 1 %
        // of the incident flux for g ~ 0.85 at these depths).
        CHECK(std::abs(f.transmission - a.transmission) < 4.0 * f.transmissionSigma + 0.01);
    }
}

TEST_CASE("Cloud reference: energy is conserved in a closed heterogeneous box", "[cpu][cloudref]") {
    // A 1 km box whose extinction varies (0 to 0.02 /m, tau ~ 10 across), HG g = 0.85.
    const HenyeyGreenstein hg(0.85);
    auto density = [](const glm::dvec3& p) { return 0.5 + 0.5 * std::sin(p.x / 97.0) * std::cos(p.z / 151.0 + p.y / 211.0); };
    BoxMedium box({-500.0, -500.0, 0.0}, {500.0, 500.0, 1000.0}, 0.02, density);
    const long n = 3000;
    // Conservative scattering: every photon leaves, absorbed exactly 0.
    const SlabFluxes c = slabFluxes(slabScene(box, hg), beam(0.8), n, 5);
    CHECK(c.reflection + c.transmission == Approx(1.0).margin(1e-12));
    CHECK(c.absorbed == 0.0);
    // Albedo 0.9: the escape counts (analog) and the collision estimator of the absorption are
    // different estimators; their sum is 1 in expectation only if the free paths are sampled
    // right (a wrong majorant, a skipped interval or a lost photon breaks it).
    box.setAlbedo(0.9);
    const SlabFluxes a = slabFluxes(slabScene(box, hg), beam(0.8), n, 6);
    const double esc = a.reflection + a.transmission;
    const double sEsc = std::sqrt(esc * (1 - esc) / n);
    INFO("escaped " << esc << " absorbed " << a.absorbed << " +- " << a.absorbedSigma);
    CHECK(a.absorbed > 0.1);  // a real absorption (tau ~ 10 at albedo 0.9)
    // The two are anticorrelated; 4 x (sigma_esc + sigma_abs) bounds the sum's error.
    CHECK(std::abs(esc + a.absorbed - 1.0) < 4.0 * (sEsc + a.absorbedSigma));
}

TEST_CASE("Cloud reference: ratio tracking gives a heterogeneous medium's transmittance", "[cpu][cloudref]") {
    // Extinction 0.003 (z / 1000) /m in a 1 km box: vertical optical depth 1.5; along a ray of cos
    // zenith 0.6 from the bottom, tau = 1.5 / 0.6 (analytic integral of the linear profile).
    BoxMedium box({-1e4, -1e4, 0.0}, {1e4, 1e4, 1000.0}, 0.003, [](const glm::dvec3& p) { return p.z / 1000.0; });
    const glm::dvec3 d(0.8, 0.0, 0.6);
    Rng rng(9, 0);
    const int n = 8000;
    double s = 0, s2 = 0;
    for (int i = 0; i < n; ++i) {
        const double t = ratioTrackingTransmittance(box, {0.0, 0.0, 0.0}, d, 1e30, rng);
        s += t;
        s2 += t * t;
    }
    const double mean = s / n, sigma = std::sqrt((s2 / n - mean * mean) / (n - 1));
    const double exact = std::exp(-1.5 / 0.6);
    INFO("ratio tracking " << mean << " +- " << sigma << " exact " << exact);
    CHECK(std::abs(mean - exact) < 4.0 * sigma);
    CHECK(sigma < 0.04 * exact);  // and the estimate is useful (~2 % at 8000 estimates)
}

TEST_CASE("Cloud reference: single scattering matches the analytic first order", "[cpu][cloudref]") {
    // A camera under a slab of tau 0.5 looking up at cos zenith 0.8, the Sun at cos zenith 0.6 and
    // 60 deg of azimuth away. First order (exact): L = w E p(cos) mu_s / (mu_s - mu) (e^{-tau/mu_s} - e^{-tau/mu}).
    const HenyeyGreenstein hg(0.85);
    const SlabMedium slab(1000.0, 2000.0, 0.5 / 1000.0);
    Scene s = slabScene(slab, hg);
    s.maxScatterings = 1;
    const double mu = 0.8, mus = 0.6;
    const glm::dvec3 view(std::sqrt(1 - mu * mu), 0.0, mu);
    const double sa = std::sqrt(1 - mus * mus);
    s.lights.sunDirection = {sa * std::cos(kPi / 3), sa * std::sin(kPi / 3), mus};
    s.lights.sunIrradiance = glm::dvec3(1000.0, 2000.0, 3000.0);
    const double tau = 0.5;
    const double p = hg.eval(glm::dot(view, s.lights.sunDirection));
    const double first = p * mus / (mus - mu) * (std::exp(-tau / mus) - std::exp(-tau / mu));
    const Estimate e = radiance(s, {0.0, 0.0, 0.0}, view, 4000, 21);
    for (int c = 0; c < 3; ++c) {
        INFO("channel " << c << " MC " << e.mean[c] << " +- " << e.sigma[c] << " analytic " << first * s.lights.sunIrradiance[c]);
        CHECK(std::abs(e.mean[c] - first * s.lights.sunIrradiance[c]) < 4.0 * e.sigma[c]);
    }
    // All orders add light (forward-peaked multiple scattering towards the camera).
    s.maxScatterings = 1000000;
    const Estimate all = radiance(s, {0.0, 0.0, 0.0}, view, 4000, 21);
    CHECK(all.mean.g > e.mean.g + 4.0 * (all.sigma.g + e.sigma.g));
    // A uniform sky (100 cd/m^2 from every direction), no Sun, no ground: conservative scattering
    // cannot change a uniform radiance field, and every path ends in the sky with its throughput 1.
    s.lights.sunIrradiance = glm::dvec3(0.0);
    s.lights.sky = [](const glm::dvec3&) { return glm::dvec3(100.0); };
    const Estimate sky = radiance(s, {0.0, 0.0, 0.0}, view, 2000, 4);
    CHECK(sky.mean.r == Approx(100.0).epsilon(1e-12));
}

TEST_CASE("Cloud reference: tabulated Mie droplet phase function", "[cpu][cloudref]") {
    // A cloud droplet distribution (r_eff 10 um, v_eff 0.1) at 550 nm, a coarse table for speed.
    const TabulatedPhase p = cloudDropletPhase(10e-6, 0.1, 550.0, 16, 900);
    // Published asymmetry of liquid water clouds in the visible: 0.85-0.87 (Hansen & Travis 1974
    // fig. 12; Hu & Stamnes 1993 for r_eff 10 um: 0.86).
    CHECK(p.g() > 0.84);
    CHECK(p.g() < 0.88);
    // Normalisation: the table integrates to 1 (a midpoint sum over the angle, 4e5 steps: 100x
    // finer than the table's forward intervals, so the sum's error is ~1e-4).
    double integral = 0.0;
    const int n = 400000;
    for (int i = 0; i < n; ++i) {
        const double th = kPi * (i + 0.5) / n;
        integral += 2.0 * kPi * p.eval(std::cos(th)) * std::sin(th) * kPi / n;
    }
    CHECK(integral == Approx(1.0).epsilon(1e-3));
    // The forward peak and the glory: the phase at 0 deg far above 90 deg; at 180 deg above 170 deg.
    CHECK(p.eval(1.0) > 1000.0 * p.eval(0.0));
    CHECK(p.eval(-1.0) > p.eval(std::cos(170.0 * kPi / 180.0)));
    // Sampling follows eval: the fraction of samples beyond 90 deg against the integral there.
    double back = 0.0;
    for (int i = 0; i < 20000; ++i) back += 2.0 * kPi * p.eval(-1.0 + (i + 0.5) / 20000.0) / 20000.0;
    Rng rng(3, 0);
    int count = 0;
    const int draws = 20000;
    for (int i = 0; i < draws; ++i) count += p.sampleCos(rng.uniform()) < 0.0 ? 1 : 0;
    const double frac = double(count) / draws, sf = std::sqrt(back * (1 - back) / draws);
    INFO("backward fraction sampled " << frac << " integral " << back);
    CHECK(std::abs(frac - back) < 4.0 * sf + 1e-4);
}

TEST_CASE("Cloud reference: deterministic per seed, whatever the threads", "[cpu][cloudref]") {
    const HenyeyGreenstein hg(0.85);
    const SlabMedium slab(1000.0, 2000.0, 0.005);
    Scene s = slabScene(slab, hg);
    s.ground = {Ground::Kind::Plane, 0.0, 0.0, 0.3};
    s.lights.sunDirection = glm::normalize(glm::dvec3(0.3, 0.2, 1.0));
    s.lights.sunIrradiance = glm::dvec3(1e5);
    s.lights.sky = [](const glm::dvec3& d) { return glm::dvec3(d.z > 0 ? 3000.0 : 0.0); };
    ImageRequest q;
    q.width = 8;
    q.height = 6;
    q.pathsPerPixel = 4;
    q.forward = {0.0, 1.0, 0.5};
    const Image a = render(s, q);
    q.threads = 3;
    const Image b = render(s, q);
    for (size_t i = 0; i < a.radiance.size(); ++i) CHECK(a.radiance[i] == b.radiance[i]);
    q.seed = 2;
    const Image c = render(s, q);
    CHECK(a.radiance[5] != c.radiance[5]);
    for (const auto& L : a.radiance) CHECK(std::isfinite(L.r));
}

TEST_CASE("Cloud reference: a uniform deck of the clouds' own density field matches adding-doubling", "[cpu][cloudref]") {
    // The real-time clouds' density function (its CPU twin) with textures of 1 and full coverage:
    // a horizontally uniform stratocumulus sheet whose density varies only with height. A
    // plane-parallel slab's fluxes depend only on its total optical depth (the transfer equation
    // in optical-depth coordinates), so the deck must transmit what a homogeneous slab of the
    // same tau does: tau = 10, Sun overhead, albedo 0.99999.
    gen::cpu::Image ones2{4, 4, 1, std::vector<float>(4 * 4 * 4, 1.0f)};
    gen::cpu::Image ones3{4, 4, 4, std::vector<float>(4 * 4 * 4 * 4, 1.0f)};
    gen::cpu::Image weather{4, 4, 1, {}};
    for (int i = 0; i < 16; ++i) weather.rgba.insert(weather.rgba.end(), {1.0f, 0.0f, 1.0f, 0.0f});  // R coverage, G base 0, B top 1
    const gen::cpu::CloudTextures tex{weather, ones3, ones3, ones2};
    const double bottom = 1000.0, top = 2000.0;
    gen::CloudLayerBlock b = gen::CloudLayerBlock::make(6360e3, bottom, top, 1.0, 0.0, 1.0, 9000.0, 0.0, 40000.0, {0.0, 0.0}, {0.0, 0.0, 0.0},
                                                        gen::kDefaultNoiseBasePeriodM, gen::kDefaultNoiseDetailPeriodM,
                                                        gen::kDefaultCurlPeriodM, std::nullopt, 0.0);
    // The vertical integral of the density (midpoint rule on the twin itself, 2e4 steps).
    double integral = 0.0;
    for (int i = 0; i < 20000; ++i)
        integral += gen::cpu::cloudDensity(b, tex, {0.0, 0.0, bottom + (top - bottom) * (i + 0.5) / 20000}, gen::CloudLod::Full) * (top - bottom) / 20000;
    REQUIRE(integral > 100.0);
    const double tau = 10.0;
    b = gen::CloudLayerBlock::make(6360e3, bottom, top, 1.0, 0.0, tau / integral, 9000.0, 0.0, 40000.0, {0.0, 0.0}, {0.0, 0.0, 0.0},
                                   gen::kDefaultNoiseBasePeriodM, gen::kDefaultNoiseDetailPeriodM, gen::kDefaultCurlPeriodM,
                                   std::nullopt, 0.0);
    const CloudFieldMedium deck(b, tex);
    const HenyeyGreenstein hg(0.85);
    const long n = 2000;
    const SlabFluxes f = slabFluxes(slabScene(deck, hg), {0.0, 0.0, -1.0}, n, 8);
    const SlabSolution a = addingDoubling(tau, 0.99999, hgMoments(0.85, 300), 1.0);
    INFO("deck T " << f.transmission << " +- " << f.transmissionSigma << " AD " << a.transmission << " R " << f.reflection << " AD "
                   << a.reflection);
    // 4 sigma + the solver's 1e-3 + the float32 block's rounding of sigma and the sphere's
    // curvature over the ~5 km the photons spread (both < 1e-3).
    CHECK(std::abs(f.transmission - a.transmission) < 4.0 * f.transmissionSigma + 2e-3);
    CHECK(std::abs(f.reflection - a.reflection) < 4.0 * f.reflectionSigma + 2e-3);
}
