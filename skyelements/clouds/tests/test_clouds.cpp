// Clouds element: presets and validation, the lighting math against independent references,
// and small renders (fisheye/perspective, tens of pixels, few samples) for the element's
// behaviour: nothing drawn at coverage 0, the Sun hidden under a full deck, lit from the Sun's
// side, finite everywhere, deterministic.
#include <catch2/catch.hpp>

#include "gl_test_context.hpp"

#include <epoxy/gl.h>

#include <welkin/camera.hpp>
#include <welkin/elements/clouds.hpp>
#include <welkin/elements/registry.hpp>
#include <welkin/generators/atmosphere.hpp>
#include <welkin/generators/cloud_keys.hpp>
#include <welkin/generators/reference_clouds.hpp>
#include <welkin/generators/sky_model.hpp>
#include <welkin/gl/objects.hpp>
#include <welkin/keys.hpp>
#include <welkin/processor.hpp>

#include <nlohmann/json.hpp>

#include <cmath>
#include <numbers>

using namespace welkin;
namespace ck = welkin::generators::cloudkeys;
namespace ek = welkin::elements::cloudelemkeys;

namespace {
constexpr double kDeg = std::numbers::pi / 180.0;

// A weather map of n x n texels: every texel (R density, G base, B top, A rain) from f(u, v).
struct Weather {
    gl::Texture2D tex;
    template <class F>
    Weather(int n, F f) : tex((test::glContext(), n), n, GL_RGBA32F) {
        std::vector<float> px(size_t(4 * n * n));
        for (int y = 0; y < n; ++y)
            for (int x = 0; x < n; ++x) {
                glm::vec4 c = f((x + 0.5) / n, (y + 0.5) / n);
                for (int k = 0; k < 4; ++k) px[size_t(4 * (y * n + x) + k)] = c[k];
            }
        glTextureSubImage2D(tex.id(), 0, 0, 0, n, n, GL_RGBA, GL_FLOAT, px.data());
        glTextureParameteri(tex.id(), GL_TEXTURE_WRAP_S, GL_REPEAT);
        glTextureParameteri(tex.id(), GL_TEXTURE_WRAP_T, GL_REPEAT);
        glTextureParameteri(tex.id(), GL_TEXTURE_MIN_FILTER, GL_LINEAR);
        glTextureParameteri(tex.id(), GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    }
    TextureRef ref() const { return {tex.id(), GL_TEXTURE_2D, tex.width(), tex.height(), 0}; }
};

// A weather map (128 x 128 texels over extentM metres) of one Gaussian blob, density
// exp(-(r / radiusM)^4), base at the layer's bottom, top `top` (of the layer), centred northM north
// of the map's centre.
Weather blobWeather(double extentM, double northM, double radiusM, float top) {
    return Weather(128, [=](double u, double v) {
        const double x = (u - 0.5) * extentM, y = (v - 0.5) * extentM - northM;
        const double r2 = (x * x + y * y) / (radiusM * radiusM);
        return glm::vec4(float(std::exp(-r2 * r2)), 0.0f, top, 0.0f);
    });
}

// A perspective camera of width x height pixels looking at (azimuth, altitude), vertical field fov (rad).
Camera perspective(int width, int height, double azimuthRad, double altitudeRad, double fovRad) {
    Camera cam;
    cam.projection = Projection::Perspective;
    cam.width = width;
    cam.height = height;
    cam.azimuthRad = azimuthRad;
    cam.altitudeRad = altitudeRad;
    cam.verticalFovRad = fovRad;
    return cam;
}

struct Scene {
    SkyProcessor p{SkyVars::earth(), Logger(), ProcessorOptions{.astronomy = false}};
    elements::Clouds* clouds = nullptr;
    Scene(double sunAltDeg, const Weather& w, Projection proj = Projection::Fisheye, int width = 48, int height = 48,
          bool withSky = true) {
        test::glContext();
        p.vars().set(atmosphere::kAtmosphere, std::make_shared<const atmosphere::Atmosphere>(atmosphere::Atmosphere::earthClear()));
        p.vars().set(keys::sunDirection, directionFromAzAlt(180 * kDeg, sunAltDeg * kDeg));
        p.vars().set(keys::moonDirection, glm::dvec3(0, 0, -1));
        p.vars().set(ck::weatherMap, w.ref());
        p.vars().set(ck::weatherExtent, 20000.0);
        Camera cam;
        cam.projection = proj;
        cam.width = width;
        cam.height = height;
        p.setCamera(cam);
        if (withSky) {  // the Sky by name (the registry), at quality low
            p.add(elements::makeElement("sky"));
            p.vars().setFromString("sky.quality", "low");
        }
        auto c = std::make_unique<elements::Clouds>();
        clouds = c.get();
        p.add(std::move(c));
        p.vars().set(ek::samples, 16);      // few samples: llvmpipe
        p.vars().set(ek::lightSamples, 4);
        p.setAnimationTime(0.0);
        p.setExposure({.automatic = false, .ev100 = 12});
    }
    Image render() {
        p.renderFrame();
        return p.readHdr();
    }
};

double luminance(const Image& img, int x, int y) {
    return 0.2126 * img.at(x, y, 0) + 0.7152 * img.at(x, y, 1) + 0.0722 * img.at(x, y, 2);
}
bool finiteNonNegative(const Image& img) {
    for (float v : img.pixels)
        if (!std::isfinite(v) || v < 0.0f) return false;
    return true;
}
const auto kFull = [](double, double) { return glm::vec4(1, 0, 1, 0); };
}  // namespace

TEST_CASE("Clouds presets and validation", "[cpu][clouds]") {
    CHECK(elements::cloudPreset("overcast").coverage > elements::cloudPreset("fair").coverage);
    CHECK(elements::cloudPreset("clear").coverage == 0.0);
    CHECK_THROWS_WITH(elements::cloudPreset("stormy"), "clouds.preset: 'stormy' not one of fair, overcast, scattered-cirrus, towering, clear");
    SkyProcessor p(SkyVars::earth(), Logger(), ProcessorOptions{.astronomy = false});
    p.add(std::make_unique<elements::Clouds>());
    auto& e = *p.elements().back();
    CHECK_NOTHROW(e.validateOptions(p.vars()));
    CHECK_THROWS_WITH(p.vars().setFromString("clouds.coverage", "1.3"), Catch::Contains("clouds.coverage"));
    CHECK_THROWS_WITH(p.vars().setFromString("clouds.samples", "2"), Catch::Contains("not in [4, 512]"));
    // The preset's top (fair: 3000 m) under a base the user set too high.
    p.vars().set(ck::bottom, 2950.0);
    CHECK_THROWS_WITH(e.validateOptions(p.vars()), "clouds.top_m 3000 must be at least clouds.bottom_m + 100 m (3050)");
    p.vars().set(ck::bottom, 1000.0);
    // An enumerated key: a name not in the list is refused where it is set, the value unchanged.
    CHECK_THROWS_WITH(p.vars().set(ek::preset, std::string("stormy")), "key 'clouds.preset': 'stormy' is not one of fair, overcast, scattered-cirrus, towering, clear");
    CHECK(p.vars().get(ek::preset) == "fair");
}

TEST_CASE("Clouds lighting math against references", "[cpu][clouds]") {
    using namespace elements::cloudcpu;
    // The phase functions integrate to 1 over the sphere (midpoint rule in nu, 20000 steps:
    // error < 1e-4 even for the g = 0.8 peak of width ~(1 - g)^2).
    for (double g : {-0.3, 0.0, 0.5, 0.8}) {
        double s = 0;
        const int n = 20000;
        for (int i = 0; i < n; ++i) s += 2 * std::numbers::pi * henyeyGreenstein(-1 + (i + 0.5) * 2.0 / n, g) * 2.0 / n;
        CHECK(s == Approx(1.0).epsilon(1e-4));
    }
    // The droplets' phase (Jendersie & d'Eon's fit) and its delta-M scaled lobe integrate to 1:
    // midpoint rule in the angle, 400,000 steps of 7.9e-6 rad across a diffraction peak ~0.0076 rad wide.
    {
        double sFull = 0, sScaled = 0, gFull = 0;
        const int m = 400000;
        for (int i = 0; i < m; ++i) {
            const double th = (i + 0.5) * std::numbers::pi / m, w = 2 * std::numbers::pi * std::sin(th) * std::numbers::pi / m;
            sFull += cloudPhase(std::cos(th)) * w;
            sScaled += scaledPhase(std::cos(th)) * w;
            gFull += cloudPhase(std::cos(th)) * std::cos(th) * w;
        }
        CHECK(sFull == Approx(1.0).epsilon(1e-3));
        CHECK(sScaled == Approx(1.0).epsilon(1e-4));
        // Its asymmetry against Lorenz-Mie's for r_eff 10 um droplets, 0.86 (Hansen & Travis 1974;
        // the path tracer's table: 0.863): the fit is within 0.02 (measured 0.879: the peak 0.9946
        // and the Draine lobe 0.763, weighted 0.50 / 0.50).
        CHECK(std::abs(gFull - 0.86) < 0.02);
        // A diffraction peak over 1000 /sr, and the backward rise of the fogbow/glory region: the
        // phase at 180 deg above its side-scattering minimum near 90-100 deg.
        CHECK(cloudPhase(1.0) > 1000.0);
        CHECK(cloudPhase(-1.0) > 3.0 * cloudPhase(std::cos(95.0 * std::numbers::pi / 180.0)));
    }
    // Energy-conserving step: the exact integral of S exp(-sigma s) over [0, dt]; small-step limit
    // S dt; large-step limit S / sigma (a thick step never gives more than its saturated value).
    CHECK(integrateStep(2.0, 0.1, 5.0) == Approx(2.0 * (1 - std::exp(-0.5)) / 0.1).epsilon(1e-12));
    CHECK(integrateStep(2.0, 1e-9, 5.0) == Approx(10.0).epsilon(1e-6));
    CHECK(integrateStep(2.0, 0.1, 1e4) == Approx(20.0).epsilon(1e-9));
    // Bohren 1987: a cloud of tau = 10, g = 0.85 transmits 1 / (1 + 0.75 x 0.15 x 10) = 47 %.
    CHECK(twoStreamTransmission(10.0, 0.85) == Approx(0.4706).epsilon(1e-3));
}

namespace {
// The real-time march's fluxes for a homogeneous conservative slab of optical depth tau lit by a
// beam at cos(zenith) mu0 (black ground): the formal solution with the shader's source
// (cloudcpu::lightTransfer at the scaled optical depths towards and away from the light) and its
// delta-M scaled extinction, fractions of the beam's flux. T includes the beam's own scaled
// transmittance (the photometry's direct term). Midpoint rules: 200 depths, 48 x 32 directions.
struct SlabFlux {
    double T = 0, R = 0;
};
SlabFlux realTimeSlab(double tau, double mu0, bool table = true) {
    using namespace elements::cloudcpu;
    const double ts = kDropletWDraine * tau, pi = std::numbers::pi;
    const int nt = 200, nm = 48, nf = 32;
    SlabFlux f;
    f.T = std::exp(-ts / mu0);
    for (int im = 0; im < nm; ++im) {
        const double mu = (im + 0.5) / nm;
        for (int jf = 0; jf < nf; ++jf) {
            const double sn = std::sqrt(1 - mu * mu) * std::sqrt(1 - mu0 * mu0) * std::cos((jf + 0.5) * 2 * pi / nf);
            double lt = 0, lr = 0;
            for (int it = 0; it < nt; ++it) {
                const double t = (it + 0.5) * ts / nt, w = ts / nt / mu;
                const double jt = table ? lightTransferTable(mu * mu0 + sn, mu, t / mu0, (ts - t) / mu0, mu0) : lightTransfer(mu * mu0 + sn, t / mu0, (ts - t) / mu0, mu0);
                const double jr = table ? lightTransferTable(-mu * mu0 + sn, -mu, t / mu0, (ts - t) / mu0, mu0) : lightTransfer(-mu * mu0 + sn, t / mu0, (ts - t) / mu0, mu0);
                lt += jt * std::exp(-(ts - t) / mu) * w;
                lr += jr * std::exp(-t / mu) * w;
            }
            f.T += lt * mu * (1.0 / nm) * (2 * pi / nf) / mu0;
            f.R += lr * mu * (1.0 / nm) * (2 * pi / nf) / mu0;
        }
    }
    return f;
}
}  // namespace

TEST_CASE("Clouds: the real-time light transfer of a slab against adding-doubling", "[cpu][clouds]") {
    // The shader's transport (its CPU twin) for plane-parallel clouds against the adding-doubling
    // solution (cloudref, Henyey-Greenstein of the droplets' asymmetry 0.86: a slab's fluxes depend
    // on the phase function through little more than g) at the optical depths of stratocumulus and
    // cumulus, the Sun overhead and 60 deg from the zenith.
    const auto moments = cloudref::hgMoments(0.86, 64);
    for (double tau : {10.0, 30.0, 100.0}) {
        for (double mu0 : {1.0, 0.5}) {
            const SlabFlux rt = realTimeSlab(tau, mu0), fit = realTimeSlab(tau, mu0, false);
            const cloudref::SlabSolution ad = cloudref::addingDoubling(tau, 1.0, moments, mu0, 16);
            INFO("tau " << tau << " mu0 " << mu0 << ": T " << rt.T << " against " << ad.transmission << ", R " << rt.R << " against " << ad.reflection
                        << " (without the table: T " << fit.T << ", R " << fit.R << ")");
            // Tolerance: with the transfer table (what the march uses; computed from adding-doubling
            // for the droplets' Mie phase, skyelements/clouds/README.md "Transfer table") measured T
            // 0.96-1.04x, R 0.97-0.99x of this adding-doubling (HG of the same g: a slab's fluxes
            // depend on the phase through little more than g; 16 streams; the midpoint quadrature
            // above ~1 %). Accepted: T 0.92-1.08x, R 0.9-1.1x. Without the table (the fitted
            // diffusion form alone) T 0.87-0.99x, R 0.72-1.20x: it must stay inside the fit's own
            // bounds, T 0.85-1.2x, R 0.7-1.3x (welkin bench cloud-fit holds it in 0.87-1.18x and
            // 0.72-1.28x); the former octaves gave T 0.1-0.3x here.
            CHECK(rt.T > 0.92 * ad.transmission);
            CHECK(rt.T < 1.08 * ad.transmission);
            CHECK(rt.R > 0.9 * ad.reflection);
            CHECK(rt.R < 1.1 * ad.reflection);
            CHECK(fit.T > 0.85 * ad.transmission);
            CHECK(fit.T < 1.2 * ad.transmission);
            CHECK(fit.R > 0.7 * ad.reflection);
            CHECK(fit.R < 1.3 * ad.reflection);
        }
    }
}

TEST_CASE("Clouds: the transfer table against the path tracer's radiance of thick slabs", "[cpu][clouds]") {
    // The transfer table (cloudcpu::diffusionShape, clouds_transfer_table.shared.glsl) is computed
    // from adding-doubling; this checks what the march gets from it against an independent
    // computation, the path tracer (cloudref: Monte Carlo, the droplets' Mie phase truncated at 3 deg
    // with the extinction scaled, per unit irradiance). A slab lit by an overhead Sun (azimuthally
    // symmetric, so the table's azimuth average is the radiance itself; the deck scene's case),
    // seen from below (transmitted) and from above (reflected), 20-70 deg from the vertical: the
    // formal solution with cloudcpu::lightTransferTable and with the table off (lightTransfer).
    using namespace elements::cloudcpu;
    const cloudref::TabulatedPhase mie = cloudref::cloudDropletPhase();
    const cloudref::TruncatedPhase cut = cloudref::truncatePhase(mie, 3.0 * kDeg);
    double worstTable = 0, worstFit = 0, sumTable = 0, sumFit = 0;
    int n = 0;
    for (double tau : {8.0, 16.0}) {
        const cloudref::SlabMedium slab(0.0, 1000.0, tau * (1.0 - cut.removedFraction) / 1000.0);
        cloudref::Scene sc;
        sc.medium = &slab;
        sc.phase = &cut.phase;
        sc.lights.sunDirection = {0.0, 0.0, 1.0};
        sc.lights.sunIrradiance = glm::dvec3(1.0);
        for (double deg : {20.0, 45.0, 70.0, -30.0, -60.0}) {  // < 0: seen from above
            const bool below = deg > 0;
            const double th = std::abs(deg) * kDeg, mv = std::cos(th);
            const glm::dvec3 view(std::sin(th), 0.0, below ? mv : -mv);
            const cloudref::Estimate e = cloudref::radiance(sc, below ? glm::dvec3(0.0, 0.0, -10.0) : glm::dvec3(0.0, 0.0, 1010.0), view, 16000, 7,
                                                            uint64_t(100 + deg + tau));
            const double ts = kDropletWDraine * tau;
            double lt = 0.0, lf = 0.0;
            for (int i = 0; i < 400; ++i) {
                const double z = (i + 0.5) * ts / 400;  // scaled depth from the lit top
                const double w = std::exp(-(below ? ts - z : z) / mv) * ts / 400 / mv;
                lt += lightTransferTable(view.z, view.z, z, ts - z, 1.0) * w;
                lf += lightTransfer(view.z, z, ts - z, 1.0) * w;
            }
            const double rt = lt / e.mean.y, rf = lf / e.mean.y;
            INFO("tau " << tau << ", " << deg << " deg: table " << lt << ", no table " << lf << ", path tracer " << e.mean.y << " +- " << e.sigma.y);
            // Tolerance: the path tracer's relative error at 16000 paths is 1.7-3.2 % (checked: < 4 %;
            // 4 sigma: up to 13 %), the table's trilinear interpolation in log tau and mu and the
            // 96-layer formal solution that made it ~2 %: accepted 0.85-1.15x. Measured (2026-11-27) 0.95-1.07x
            // with the table, 0.72-1.12x without (the deck's tau 16 seen 20-45 deg from the vertical:
            // 0.73-0.80x).
            CHECK(e.sigma.y < 0.04 * e.mean.y);
            CHECK(rt > 0.85);
            CHECK(rt < 1.15);
            worstTable = std::max(worstTable, std::abs(std::log(rt)));
            worstFit = std::max(worstFit, std::abs(std::log(rf)));
            sumTable += std::log(rt) * std::log(rt);
            sumFit += std::log(rf) * std::log(rf);
            ++n;
        }
    }
    CHECK(n == 10);
    const double rmsTable = std::sqrt(sumTable / n), rmsFit = std::sqrt(sumFit / n);
    INFO("log RMS table " << rmsTable << " (worst " << worstTable << "), without " << rmsFit << " (worst " << worstFit << ")");
    // The table must improve on the fitted form it corrects (measured log RMS 0.034 against 0.164,
    // worst 0.063 against 0.319): at most half the error.
    CHECK(rmsTable < 0.5 * rmsFit);
    CHECK(worstTable < 0.5 * worstFit);
}

TEST_CASE("Clouds: the lights' transfer against the path tracer's radiance through thin slabs, near the Sun", "[cpu][clouds]") {
    // What the slab fluxes cannot see: the angular shape of the light a thin cloud passes near the
    // Sun's direction (the silver lining; a cumulus lit from behind). The real-time transfer's
    // formal solution for a slab (cloudcpu::lightTransfer, delta-M scaled extinction), seen from
    // below at 5, 10 and 20 deg from the Sun overhead, against the path tracer (cloudref, the
    // droplets' Mie phase truncated at 3 deg with the extinction scaled, 6000 paths a direction,
    // per unit irradiance of the Sun).
    using namespace elements::cloudcpu;
    const cloudref::TabulatedPhase mie = cloudref::cloudDropletPhase();
    const cloudref::TruncatedPhase cut = cloudref::truncatePhase(mie, 3.0 * kDeg);
    for (double tau : {1.0, 4.0}) {
        const cloudref::SlabMedium slab(0.0, 1000.0, tau * (1.0 - cut.removedFraction) / 1000.0);
        cloudref::Scene sc;
        sc.medium = &slab;
        sc.phase = &cut.phase;
        sc.lights.sunDirection = {0.0, 0.0, 1.0};
        sc.lights.sunIrradiance = glm::dvec3(1.0);
        for (double deg : {5.0, 10.0, 20.0}) {
            const double th = deg * kDeg, mv = std::cos(th);
            const cloudref::Estimate e = cloudref::radiance(sc, {0.0, 0.0, -10.0}, {std::sin(th), 0.0, mv}, 6000, 3, uint64_t(deg));
            const double ts = kDropletWDraine * tau;
            double L = 0.0;
            for (int i = 0; i < 400; ++i) {
                const double z = (i + 0.5) * ts / 400;  // scaled depth from the lit top
                L += lightTransfer(mv, z, ts - z, 1.0) * std::exp(-(ts - z) / mv) * ts / 400 / mv;
            }
            INFO("tau " << tau << ", " << deg << " deg from the Sun: real time " << L << " /sr, path tracer " << e.mean.y << " +- " << e.sigma.y);
            // Tolerance: measured 0.94-1.08x (the fit to 315 directions of 14 slabs, skyelements/clouds/README.md
            // "Light transport"), the path tracer's error at 6000 paths ~2 % (4 sigma: 8 %): accepted
            // 0.8-1.25x. The transport before the forward-peaked orders gave 0.46-0.52x at 5 deg and
            // 0.82-0.94x at 10-20 deg.
            CHECK(L > 0.8 * e.mean.y);
            CHECK(L < 1.25 * e.mean.y);
        }
    }
}

namespace {
// The same for the ambient light: a slab lit from above by a uniform hemisphere of horizontal
// illuminance 1 (the sky's diffuse light), the source cloudcpu::ambientTransfer at the scaled
// vertical depths to the lit top and to the bottom. T includes the unscattered diffuse light,
// 2 int mu e^(-tau_s / mu) dmu; R = 1 - T for adding-doubling (conservative). Same midpoint rules.
SlabFlux realTimeAmbientSlab(double tau) {
    using namespace elements::cloudcpu;
    const double ts = kDropletWDraine * tau, pi = std::numbers::pi;
    const int nt = 200, nm = 48;
    SlabFlux f;
    for (int im = 0; im < nm; ++im) {
        const double mu = (im + 0.5) / nm;
        f.T += 2 * mu * std::exp(-ts / mu) / nm;
        double lt = 0, lr = 0;
        for (int it = 0; it < nt; ++it) {
            const double t = (it + 0.5) * ts / nt, w = ts / nt / mu;
            // Seen from below (looking up, towards the lit side: nu = mu) and from above (nu = -mu).
            lt += ambientTransfer(mu, t, ts - t) * std::exp(-(ts - t) / mu) * w;
            lr += ambientTransfer(-mu, t, ts - t) * std::exp(-t / mu) * w;
        }
        f.T += 2 * pi * lt * mu / nm;
        f.R += 2 * pi * lr * mu / nm;
    }
    return f;
}
}  // namespace

TEST_CASE("Clouds: the finite cloud's depth to its far side", "[cpu][clouds]") {
    using welkin::elements::cloudcpu::finiteBackDepth;
    // A deck: the width across the sample far larger than the depth along the light leaves the
    // depth as it was (a uniform slab's transport, checked against adding-doubling above, keeps).
    // Tolerance: tauB / (1 + tauB / tauWidth) differs from tauB by tauB^2 / tauWidth = 1e-6 here.
    CHECK(finiteBackDepth(10.0, 1e8) == Approx(10.0).epsilon(1e-6));
    // A cumulus as wide as it is deep along the light diffuses like a slab of half that depth (the
    // light leaks out through both ways); never deeper than either, no depth without either.
    CHECK(finiteBackDepth(8.0, 8.0) == Approx(4.0).epsilon(1e-12));
    CHECK(finiteBackDepth(5.0, 20.0) == Approx(finiteBackDepth(20.0, 5.0)).epsilon(1e-12));
    CHECK(finiteBackDepth(5.0, 20.0) < 5.0);
    CHECK(finiteBackDepth(0.0, 20.0) == 0.0);
    CHECK(finiteBackDepth(5.0, 0.0) == 0.0);
    CHECK(finiteBackDepth(0.0, 0.0) == 0.0);
    // Through the transport: a thinner "slab" reflects less, so a cumulus' diffuse light seen from
    // above (the view 120 deg from a Sun 60 deg up, near its lit face) is dimmer than a deck's.
    const double muL = 0.5, nu = -0.5, muV = -0.57, tauL = 0.5;
    const double deck = welkin::elements::cloudcpu::lightTransferTable(nu, muV, tauL, finiteBackDepth(20.0, 1e8), muL);
    const double cumulus = welkin::elements::cloudcpu::lightTransferTable(nu, muV, tauL, finiteBackDepth(20.0, 10.0), muL);
    INFO("deck " << deck << ", cumulus " << cumulus << " 1/sr");
    CHECK(cumulus < deck);
}

TEST_CASE("Clouds: a light below lightDarkElevation lights no point of the layer the march reaches", "[cpu][clouds]") {
    // The bound that drops a light's march from the shader (Clouds' CLD_LIGHTS variants): below
    // it the atmosphere's transmittance to the light (the CPU twin of the shader's, with its
    // smoothed horizon) must be exactly 0 at every point of the layer on every view ray from the
    // observer that misses the ground, or the variant would drop light. Checked by brute force:
    // rays every 0.25 deg of elevation from the observer's horizon (-dip) up and 8 azimuths, points
    // every 250 m to 500 km. And not vacuous: 0.6 deg above the bound some point is lit (from above
    // the layer 3.4 deg: there the march stops where the ray first leaves the layer, short of the
    // farthest points the bound allows for).
    namespace gc = welkin::generators::cpu;
    const welkin::generators::SkyModel m;
    const welkin::generators::Lut2D T = gc::transmittanceLut(m, welkin::generators::SkyQuality::tiny());
    const double R = m.bottomRadius, radius = 0.00465;
    struct Case { double hObs, bottom, top, slack; };
    for (const Case c : {Case{0.0, 1000.0, 3000.0, 0.01}, Case{2000.0, 1500.0, 9000.0, 0.01}, Case{10000.0, 1000.0, 3000.0, 0.06}}) {
        const double dark = welkin::elements::cloudcpu::lightDarkElevation(R, c.hObs, c.top, radius);
        const double dipObs = std::acos(R / (R + c.hObs));
        auto litPoints = [&](double elevation) {
            const glm::dvec3 l(0.0, std::cos(elevation), std::sin(elevation));  // towards the north
            int lit = 0;
            for (int ia = 0; ia < 8; ++ia)
                for (double el = -dipObs + 1e-5; el < 0.5 * std::numbers::pi; el += 0.25 * std::numbers::pi / 180.0) {
                    const double az = ia * std::numbers::pi / 4.0;
                    const glm::dvec3 d(std::sin(az) * std::cos(el), std::cos(az) * std::cos(el), std::sin(el));
                    for (double t = 0.0; t < 5e5; t += 250.0) {
                        const glm::dvec3 q = glm::dvec3(0.0, 0.0, R + c.hObs) + t * d;  // from the planet's centre
                        const double a = glm::length(q) - R;
                        if (a < 0.0 || a > c.top + 2e4) break;  // the ground, or far above the layer
                        if (a < c.bottom || a > c.top) continue;
                        const double muS = glm::dot(glm::normalize(q), l);
                        if (gc::transmittanceToLight(m, T, a, muS, radius).y > 0.0) ++lit;
                    }
                }
            return lit;
        };
        INFO("observer " << c.hObs << " m, layer " << c.bottom << "-" << c.top << " m, dark below " << dark * 180.0 / std::numbers::pi << " deg");
        CHECK(dark < 0.0);
        CHECK(litPoints(dark) == 0);
        CHECK(litPoints(dark + c.slack) > 0);
    }
}

TEST_CASE("Clouds: the lit face's cosine", "[cpu][clouds]") {
    using welkin::elements::cloudcpu::litFaceCosine;
    using welkin::elements::cloudcpu::kDiffusionS;
    // A deck lit at muL: the depth to the sky above is muL times the depth towards the light, and
    // the slab's own muL comes back at every depth (the deck's transport, checked against
    // adding-doubling above, is unchanged). Tolerance: rounding only.
    for (double muL : {0.2, 0.5, 0.9})
        for (double tauL : {0.0, 0.3, 4.0, 40.0}) CHECK(litFaceCosine(muL * tauL, tauL, muL) == Approx(muL).epsilon(1e-12));
    // The side of a cumulus facing a low Sun, at its lit face: far more cloud above than along the
    // light, the face's cosine 1 (within the memory's e^(-s_L): 1 - 0.7 (1 - e^(-0.0028)) here).
    CHECK(litFaceCosine(5.0, 0.01, 0.3) == Approx(1.0).margin(2e-3));
    // Deep inside (the light's path 40 scaled depths, 11 transport depths) the face is forgotten:
    // within (1 - muL) e^(-s_L) = 1e-5 of muL.
    CHECK(litFaceCosine(100.0, 40.0, 0.5) == Approx(0.5).margin(0.5 * std::exp(-kDiffusionS * 40.0) + 1e-12));
    // Never outside [muL, 1]; a light below the horizon gives no negative cosine.
    for (double up : {0.0, 0.1, 1.0, 10.0})
        for (double tl : {0.0, 0.1, 1.0, 10.0}) {
            const double m = litFaceCosine(up, tl, 0.4);
            CHECK(m >= 0.4 - 1e-12);
            CHECK(m <= 1.0 + 1e-12);
        }
    CHECK(litFaceCosine(1.0, 1.0, -0.2) >= 0.0);
    // Through the transport: the side facing the light diffuses more than the slab's oblique face
    // (the muL^q of the diffusion term; the path tracer's cumulus-side, README "The lit face").
    const double side = welkin::elements::cloudcpu::lightTransferTable(0.0, 0.4, 1.0, 8.0, litFaceCosine(6.0, 1.0, 0.5));
    const double slab = welkin::elements::cloudcpu::lightTransferTable(0.0, 0.4, 1.0, 8.0, 0.5);
    INFO("side " << side << ", slab " << slab << " 1/sr");
    CHECK(side > slab);
}

TEST_CASE("Clouds: the transfer table's depth where the cloud is a deck", "[cpu][clouds]") {
    using namespace welkin::elements::cloudcpu;
    // deckness: 0 for a cloud no wider than it is deep along the light, -> 1 for a sheet far wider,
    // squared (the measure of the README); rounding-level tolerances.
    CHECK(deckness(5.0, 5.0) == 0.0);
    CHECK(deckness(2.0, 5.0) == 0.0);
    CHECK(deckness(15.0, 5.0) == Approx(0.25).epsilon(1e-12));
    CHECK(deckness(1e8, 5.0) == Approx(1.0).epsilon(1e-6));
    CHECK(deckness(0.0, 0.0) == 0.0);
    // The depth read: a cumulus' at the face the light leaves by towards the view, a deck's at the
    // sample's own depth tauL / (tauL + tauB).
    CHECK(tableDepth(0.5, 1.0, 3.0, 0.0) == 1.0);
    CHECK(tableDepth(-0.5, 1.0, 3.0, 0.0) == 0.0);
    CHECK(tableDepth(0.0, 1.0, 3.0, 0.0) == Approx(0.5).epsilon(1e-12));
    CHECK(tableDepth(0.5, 1.0, 3.0, 1.0) == Approx(0.25).epsilon(1e-12));
    // Inside a thick deck lit from overhead (tau 80 along the axis), at mid-depth, looking 7 deg up:
    // the table at the depth is adding-doubling's internal radiance over the diffusion form's,
    // above the far face's value (the diffusion form's light deep inside is ~0.5x adding-doubling's,
    // README "The transfer table").
    const double inside = lightTransferTable(0.125, 0.125, 20.0, 20.0, 1.0, 1.0);
    const double face = lightTransferTable(0.125, 0.125, 20.0, 20.0, 1.0, 0.0);
    INFO("inside " << inside << ", face " << face << " 1/sr");
    CHECK(inside > 1.2 * face);
}

TEST_CASE("Clouds: the real-time ambient transfer of a slab against adding-doubling", "[cpu][clouds]") {
    using namespace elements::cloudcpu;
    // The forward share of the scaled phase (the constant the ambient's single scattering uses):
    // midpoint rule over nu in [0, 1], 100,000 steps (the Draine lobe is smooth: error < 1e-6).
    double fwd = 0;
    for (int i = 0; i < 100000; ++i) fwd += 2 * std::numbers::pi * scaledPhase((i + 0.5) / 100000) / 100000;
    CHECK(fwd == Approx(kDraineForwardFraction).margin(5e-4));  // the constant is given to 3 digits
    // Diffuse light through slabs of stratocumulus and cumulus depth: adding-doubling's
    // hemispheric transmission 2 int T(mu) mu dmu (8-point Gauss-Legendre in mu, HG g 0.86).
    const auto moments = cloudref::hgMoments(0.86, 64);
    const double gx[4] = {0.1834346425, 0.5255324099, 0.7966664774, 0.9602898565};
    const double gw[4] = {0.3626837834, 0.3137066459, 0.2223810345, 0.1012285363};
    for (double tau : {3.0, 10.0, 30.0, 100.0}) {
        double tD = 0;
        for (int i = 0; i < 4; ++i)
            for (int sgn : {-1, 1}) {
                const double mu = 0.5 + 0.5 * sgn * gx[i];
                tD += 0.5 * gw[i] * 2 * mu * cloudref::addingDoubling(tau, 1.0, moments, mu, 16).transmission;
            }
        const SlabFlux rt = realTimeAmbientSlab(tau);
        INFO("tau " << tau << ": T " << rt.T << " against " << tD << ", R " << rt.R << " against " << 1 - tD);
        // Tolerance: the diffusion term is the Sun's, fitted at mu0 1 and 0.5 within -9 %..+11 % (T)
        // and -21 %..+18 % (R); the diffuse field adds its mean over mu (2 / (1 + q)) and the
        // single scattering's hemispheric approximation. Accepted as for the Sun: T 0.85-1.2x,
        // R 0.7-1.3x. The former ambient (E_d / pi x 0.25-1 by height) is not a transfer and
        // gave no flux balance at all.
        CHECK(rt.T > 0.85 * tD);
        CHECK(rt.T < 1.2 * tD);
        CHECK(rt.R > 0.7 * (1 - tD));
        CHECK(rt.R < 1.3 * (1 - tD));
    }
}

TEST_CASE("Clouds at coverage 0 without cirrus draw nothing", "[gl][clouds]") {
    Weather w(8, kFull);
    Scene with(30, w);
    with.p.vars().set(ck::coverage, 0.0);
    with.p.vars().set(ck::cirrusCoverage, 0.0);
    const Image a = with.render();
    CHECK_FALSE(with.clouds->drew());
    Scene without(30, w);
    without.p.remove("clouds");
    const Image b = without.render();
    REQUIRE(a.pixels.size() == b.pixels.size());
    CHECK(a.pixels == b.pixels);  // bit-identical: the element did not draw
}

TEST_CASE("Clouds: a full deck hides the Sun and dims the ground's illuminance", "[gl][clouds]") {
    Weather w(8, kFull);
    Scene s(60, w, Projection::Fisheye, 32, 32);
    s.p.vars().set(ck::coverage, 1.0);
    s.p.vars().set(ck::cirrusCoverage, 0.0);
    const Image img = s.render();
    CHECK(s.clouds->drew());
    CHECK(finiteNonNegative(img));
    const auto& ph = s.clouds->photometry();
    REQUIRE(ph.valid);
    // A 1 km deck at 0.05 /m of (eroded) density ~0.3-1 has tau ~ 15-50 at the sun's 30 deg
    // slant: the beam is gone (the march stops at T < 1e-3).
    CHECK(ph.sunTransmittance < 1e-3);
    CHECK(ph.direct < 1e-3 * ph.clearDirect + 1e-9);
    CHECK(ph.global < 0.5 * ph.clearGlobal);
    CHECK(ph.diffuse > 0.0);
    INFO("global " << ph.global << " clear " << ph.clearGlobal << " diffuse " << ph.diffuse);
    nlohmann::json j = s.p.stats();
    CHECK(j["sky"]["horizontal_illuminance_lux"].get<double>() == Approx(ph.global));
    CHECK(j["sky"]["clear_horizontal_illuminance_lux"].get<double>() == Approx(ph.clearGlobal));
}

TEST_CASE("Clouds: the sunward side of a cloud is brighter", "[gl][clouds]") {
    // One round cloud 1.5 km in radius centred 4 km north of the observer (the weather map of
    // 20 km repeats: the next copies are 20 km away), the Sun low in the east; seen from the
    // observer, the cloud's east (sunward) half faces the light.
    Weather w(128, [](double u, double v) {
        const double x = (u - 0.5) * 20000, y = (v - 0.5) * 20000 - 4000;
        const double r = std::sqrt(x * x + y * y);
        return glm::vec4(r < 1500 ? 1.0f : 0.0f, 0.0f, 1.0f, 0.0f);
    });
    Scene s(15, w, Projection::Perspective, 64, 48);
    s.p.vars().set(keys::sunDirection, directionFromAzAlt(90 * kDeg, 15 * kDeg));
    s.p.vars().set(ck::weatherOffset, glm::dvec2(10000, 10000));  // u = 0.5 at the observer
    s.p.vars().set(ck::coverage, 1.0);
    s.p.vars().set(ck::cirrusCoverage, 0.0);
    s.p.vars().set(ck::bottom, 1500.0);
    s.p.vars().set(ck::top, 2500.0);
    const Camera cam = perspective(64, 48, 0, std::atan2(2000.0, 4000.0), 50 * kDeg);  // north, at the cloud's middle
    s.p.setCamera(cam);
    const Image img = s.render();
    const Image ref = [&] {
        Scene sky(15, w, Projection::Perspective, 64, 48);
        sky.p.vars().set(keys::sunDirection, directionFromAzAlt(90 * kDeg, 15 * kDeg));
        sky.p.remove("clouds");
        sky.p.setCamera(cam);
        return sky.render();
    }();
    // Mean of the pixels the cloud covers (luminance changed by > 5 %) in the east (right) half
    // and the west (left) half.
    double east = 0, west = 0;
    int ne = 0, nw = 0;
    for (int y = 0; y < 48; ++y)
        for (int x = 0; x < 64; ++x) {
            const double l = luminance(img, x, y), l0 = luminance(ref, x, y);
            if (std::abs(l - l0) < 0.05 * l0) continue;
            if (x >= 32) { east += l; ++ne; } else { west += l; ++nw; }
        }
    REQUIRE(ne > 20);
    REQUIRE(nw > 20);
    INFO("east " << east / ne << " west " << west / nw);
    CHECK(east / ne > 1.1 * west / nw);  // the lit half at least 10 % brighter
}

TEST_CASE("Clouds: finite, non-negative pixels from below, inside, above, at night, Sun at zenith", "[gl][clouds][slow]") {
    Weather w(16, [](double u, double v) { return glm::vec4(float(0.5 + 0.5 * std::sin(6.283 * u) * std::cos(6.283 * v)), 0.1f, 0.9f, 0.0f); });
    struct Case { double h, sunAlt; };
    for (Case c : {Case{0, 30}, Case{2500, 30}, Case{6000, 30}, Case{0, 90}, Case{0, -20}, Case{4e5, 45}}) {
        Scene s(c.sunAlt, w, Projection::Fisheye, 24, 24);
        s.p.vars().set(keys::observerHeight, c.h);
        s.p.vars().set(ck::coverage, 0.8);
        s.p.vars().set(ck::cirrusCoverage, 0.5);
        if (c.sunAlt < 0) s.p.vars().set(keys::moonDirection, directionFromAzAlt(0, 40 * kDeg));
        const Image img = s.render();
        INFO("height " << c.h << " sun " << c.sunAlt);
        CHECK(finiteNonNegative(img));
        CHECK(s.clouds->drew());
    }
}

TEST_CASE("Clouds: same inputs, same image", "[gl][clouds]") {
    Weather w(16, [](double u, double v) { return glm::vec4(float(u), 0.0f, float(0.5 + 0.5 * v), 0.0f); });
    Scene a(40, w, Projection::Fisheye, 24, 24), b(40, w, Projection::Fisheye, 24, 24);
    const Image ia = a.render(), ib = b.render();
    CHECK(ia.pixels == ib.pixels);
}

TEST_CASE("Clouds: a preset fills only the keys nobody set", "[gl][clouds]") {
    Weather w(8, kFull);
    Scene s(40, w, Projection::Fisheye, 8, 8);
    s.p.vars().set(ek::preset, std::string("overcast"));
    s.p.vars().set(ck::coverage, 0.3);  // the user's coverage wins over the preset's 0.9
    s.render();
    CHECK(s.p.vars().get(ck::coverage) == 0.3);
    CHECK(s.p.vars().get(ck::bottom) == elements::cloudPreset("overcast").bottom);
    // A run-time preset change moves the keys the preset wrote, not the user's.
    s.p.vars().set(ek::preset, std::string("fair"));
    s.render();
    CHECK(s.p.vars().get(ck::coverage) == 0.3);
    CHECK(s.p.vars().get(ck::bottom) == elements::cloudPreset("fair").bottom);
}

TEST_CASE("Clouds: the overcast preset at noon gives an overcast day's illuminance", "[gl][clouds][slow]") {
    // The generated weather map and noise (the element's own generators), the Sun 60 deg up.
    test::glContext();
    SkyProcessor p(SkyVars::earth(), Logger(), ProcessorOptions{.astronomy = false});
    p.vars().set(atmosphere::kAtmosphere, std::make_shared<const atmosphere::Atmosphere>(atmosphere::Atmosphere::earthClear()));
    p.vars().set(keys::sunDirection, directionFromAzAlt(180 * kDeg, 60 * kDeg));
    p.vars().set(keys::moonDirection, glm::dvec3(0, 0, -1));
    Camera cam;
    cam.projection = Projection::Fisheye;
    cam.width = cam.height = 8;
    p.setCamera(cam);
    p.add(elements::makeElement("sky"));
    p.vars().setFromString("sky.quality", "low");
    auto c = std::make_unique<elements::Clouds>();
    auto* clouds = c.get();
    p.add(std::move(c));
    p.vars().set(ek::preset, std::string("overcast"));
    p.vars().set(ek::samples, 24);
    p.setAnimationTime(0.0);
    p.renderFrame();
    const auto& ph = clouds->photometry();
    REQUIRE(ph.valid);
    INFO("global " << ph.global << " direct " << ph.direct << " diffuse " << ph.diffuse << " clear " << ph.clearGlobal);
    // Overcast summer noon at mid-latitudes: 10-40 klux global (CIE 110-1994 / Kittler et al.
    // 1998 overcast sky daylight levels; Darula & Kittler 2002: overcast horizontal illuminance
    // ~ 0.2-0.4 of the clear sky's at the same solar altitude). The clear sky here: ~105 klux;
    // measured under the preset's deck: ~13 klux, all diffuse, with the smooth density before
    // 2026-11-24; 14.2 klux (the Sun's beam 0.3 klux through the thinner cells) since the carved
    // stratocumulus shape and the preset's coverage 0.9 (was 0.98) let the deck vary.
    // Since the light transport of 2026-11-26 (energy kept): 68 klux at the preset's former
    // scattering 0.04 /m, 33.9 klux (Sun's beam 0) at 0.2 /m. Since the ambient from the sky the
    // clouds are under (the ground lit through the deck, the skylight carried through it by the
    // ambient transfer; 2026-11-27): 38.5 klux at 0.13 /m (44 klux at 0.1 /m); 36.2 klux with the
    // depth to the far side marched (2026-11-27). Since the forward-peaked orders and the light
    // march at the full LOD (2026-11-27): 41.8 klux (0.40 of the clear sky's) at 0.13 /m, 38.7 klux
    // (0.37) at the preset's 0.15 /m. With the transfer table (2026-11-27 14:21 UTC): 35.6 klux
    // (0.34).
    // The right reason: the deck's bases are lit by the ground under the deck (the photometry's
    // fixed point: the same global illuminance), not by the clear sky's ~105 klux; the flux balance
    // itself is checked against adding-doubling by the uniform slab test below.
    CHECK(ph.groundLux == Approx(ph.global).epsilon(1e-3));  // the observer is on the ground: the same lux (float read-back)
    CHECK(elements::cloudPreset("overcast").scattering <= 0.15);  // a stratocumulus' 0.05-0.1 /m, over a deck whose mean density is ~0.3
    CHECK(ph.global > 10000.0);
    CHECK(ph.global < 40000.0);
    CHECK(ph.global < 0.4 * ph.clearGlobal);
    CHECK(ph.direct < 0.05 * ph.clearDirect);  // the Sun's beam (nearly) hidden
}

TEST_CASE("Clouds: a uniform slab transmits what adding-doubling says", "[gl][clouds]") {
    // A horizontally uniform deck: weather R = 1 (base 0, top 1) everywhere, noise textures of 1
    // (the Perlin-Worley shape is then 1), no erosion, coverage 1, the stratocumulus gradient
    // (clouds.cloud_type 0: a sheet): the density is the height profile alone, the same in every
    // column. Its vertical optical depth from the profile's integral (cloud_density.hpp's
    // heightGradient, type 0: smoothstep(0, .1, a) (1 - smoothstep(.65, 1, a)) (.75 + .25 a)).
    Weather w(8, kFull);
    Weather one2(8, [](double, double) { return glm::vec4(1.0f); });
    gl::Texture3D base(4, 4, 4, GL_RGBA32F), detail(4, 4, 4, GL_RGBA32F);
    std::vector<float> ones(4 * 4 * 4 * 4, 1.0f);
    for (auto* t : {&base, &detail}) {
        glTextureSubImage3D(t->id(), 0, 0, 0, 0, 4, 4, 4, GL_RGBA, GL_FLOAT, ones.data());
        glTextureParameteri(t->id(), GL_TEXTURE_WRAP_S, GL_REPEAT);
        glTextureParameteri(t->id(), GL_TEXTURE_WRAP_T, GL_REPEAT);
        glTextureParameteri(t->id(), GL_TEXTURE_WRAP_R, GL_REPEAT);
    }
    auto ss = [](double e0, double e1, double x) { const double t = std::clamp((x - e0) / (e1 - e0), 0.0, 1.0); return t * t * (3 - 2 * t); };
    double integral = 0;  // of the profile over the layer fraction, midpoint rule (1e4 steps)
    for (int i = 0; i < 10000; ++i) {
        const double a = (i + 0.5) / 10000;
        integral += ss(0, 0.1, a) * (1 - ss(0.65, 1, a)) * (0.75 + 0.25 * a) / 10000;
    }
    const double thickness = 1000, tau = 10;
    const double sigma = tau / (integral * thickness);
    Scene s(90, w, Projection::Fisheye, 8, 8);
    s.p.vars().set(ck::noiseBase, TextureRef{base.id(), GL_TEXTURE_3D, 4, 4, 4});
    s.p.vars().set(ck::noiseDetail, TextureRef{detail.id(), GL_TEXTURE_3D, 4, 4, 4});
    s.p.vars().set(ck::curlNoise, one2.ref());
    s.p.vars().set(ck::coverage, 1.0);
    s.p.vars().set(ck::detailScale, 0.0);
    s.p.vars().set(ck::cloudType, 0.0);
    s.p.vars().set(ck::cirrusCoverage, 0.0);
    s.p.vars().set(ck::bottom, 1000.0);
    s.p.vars().set(ck::top, 1000.0 + thickness);
    s.p.vars().set(ck::scattering, sigma);
    s.p.vars().set(ek::samples, 64);
    s.p.vars().set(ek::lightSamples, 8);
    s.render();
    const auto& ph = s.clouds->photometry();
    REQUIRE(ph.valid);
    // The Sun's beam straight down: e^(-w_D tau) with the delta-M scaled extinction (the diffraction
    // peak's half of the scattering stays in the beam; e^-5 = 6.8e-3); 5 %: the 64-sample march of
    // the smoothstep profile (its midpoint-rule error) and the half-float cache.
    CHECK(ph.sunTransmittance == Approx(std::exp(-elements::cloudcpu::kDropletWDraine * tau)).epsilon(0.05));
    // Adding-doubling (cloudref; HG of the droplets' g 0.86) for the same optical depth: the beam
    // (Sun at the zenith) transmitted with T(1), the clear sky's diffuse light with the
    // hemispheric mean 2 int T(mu) mu dmu (8-point Gauss-Legendre in mu, sky taken as uniform), and
    // the ground's light (albedo 0.2 of the shader's CLD_GROUND_ALBEDO) reflected back down by the
    // deck's diffuse reflection 1 - T_diffuse: x 1 / (1 - 0.2 (1 - T_diffuse)).
    const auto moments = cloudref::hgMoments(0.86, 64);
    const double tBeam = cloudref::addingDoubling(tau, 1.0, moments, 1.0, 16).transmission;
    const double gx[4] = {0.1834346425, 0.5255324099, 0.7966664774, 0.9602898565};
    const double gw[4] = {0.3626837834, 0.3137066459, 0.2223810345, 0.1012285363};
    double tDiffuse = 0;
    for (int i = 0; i < 4; ++i)
        for (int sgn : {-1, 1}) {
            const double mu = 0.5 + 0.5 * sgn * gx[i];
            tDiffuse += 0.5 * gw[i] * 2 * mu * cloudref::addingDoubling(tau, 1.0, moments, mu, 16).transmission;
        }
    const double expected =
        (tBeam * ph.clearDirect + tDiffuse * ph.clearDiffuse) / ph.clearGlobal / (1.0 - 0.2 * (1.0 - tDiffuse));
    const double measured = ph.global / ph.clearGlobal;
    INFO("global/clear " << measured << " adding-doubling " << expected << " (beam " << tBeam << ", diffuse " << tDiffuse << ")");
    // Tolerance: measured 0.696 against 0.651 (1.07x) with the transfer table (2026-11-27 14:21 UTC; its
    // slab fluxes are adding-doubling's for the Mie phase, this sky's ground and skylight add the rest);
    // 0.597 (0.92x) with the regenerated constants and the atmosphere's ground albedo 0.1
    // (welkin bench cloud-fit, 2026-11-27 11:00 UTC); 0.670 (1.03x) with the forward-peaked orders' first fit; 0.656 before them (0.668 before the far side's depth was marched; 0.64 with the former ambient, the clear sky's
    // E_d / pi by height and the ground lit by the clear sky's global light). The transfer's fit to
    // adding-doubling at tau 10 is 0.91x for the beam (the CPU slab test) and 1.06x for the
    // skylight (the CPU ambient test), the ground's light reflected back by the same ambient
    // transfer, so 0.85-1.15x. The former octave transport gave 0.12 (0.18x).
    CHECK(measured > 0.85 * expected);
    CHECK(measured < 1.15 * expected);
    // The ground's light that lit the deck's base is the light under the deck (the fixed point).
    CHECK(ph.groundLux == Approx(ph.global).epsilon(1e-3));
}

TEST_CASE("Clouds: the real-time path's direction cache", "[gl][clouds]") {
    // clouds.reprojection: the clouds are kept in a direction-space cache refreshed one Bayer phase
    // per frame. Checked: its first frame (a full fill) against the per-pixel path; that every
    // texel is refreshed exactly once per cycle of clouds.cache_frames (after the wind moves the
    // clouds, which does not refill the cache, one cycle later the image equals a fresh full fill
    // with the new offset, bit for bit, for the 2 x 2 and 8 x 8 orders); that turning the camera needs no refill (the cache is the
    // same: the image equals a fresh processor's at the new camera); that a jump of the Sun
    // refills it over one cycle, the cache before the jump drawn meanwhile.
    Weather w(32, [](double u, double v) { return glm::vec4(float(0.5 + 0.5 * std::sin(6.283 * u) * std::cos(6.283 * v)), 0.1f, 0.9f, 0.0f); });
    auto scene = [&](double sunAlt, int frames) {
        auto s = std::make_unique<Scene>(sunAlt, w, Projection::Fisheye, 32, 32);
        s->p.vars().set(ck::coverage, 0.8);
        s->p.vars().set(ck::cirrusCoverage, 0.4);
        s->p.vars().set(ek::reprojection, true);
        s->p.vars().set(ek::cacheWidth, 256);
        s->p.vars().set(ek::cacheFrames, frames);
        return s;
    };
    SECTION("the first frame against the per-pixel path") {
        // A perspective view whose pixels (12 deg / 32 = 0.38 deg) match the cache's texels
        // (1024 wide: 0.35 deg), so both resolve the clouds alike and what differs is the
        // rays' dither (by cache texel, by pixel) and the cache's bilinear resampling.
        auto s = scene(30, 64);
        s->p.vars().set(ek::cacheWidth, 1024);
        const Camera cam = perspective(32, 32, 200 * kDeg, 8 * kDeg, 12 * kDeg);
        s->p.setCamera(cam);
        const Image cached = s->render();
        s->p.vars().set(ek::reprojection, false);
        const Image direct = s->render();
        s->p.vars().set(ek::samples, 256);
        const Image reference = s->render();  // the per-pixel path converged (256 samples)
        auto relRms = [](const Image& a, const Image& b) {
            double num = 0, den = 0;
            for (int y = 0; y < 32; ++y)
                for (int x = 0; x < 32; ++x) {
                    const double la = luminance(a, x, y), lb = luminance(b, x, y);
                    num += (la - lb) * (la - lb), den += lb * lb;
                }
            return std::sqrt(num / den);
        };
        double worst = 0;
        int outliers = 0;
        for (int y = 0; y < 32; ++y)
            for (int x = 0; x < 32; ++x) {
                const double a = luminance(cached, x, y), b = luminance(direct, x, y);
                if (b > 0) worst = std::max(worst, std::abs(a - b) / b);
                if (b > 0) outliers += std::abs(a - b) / b > 0.6;
            }
        const double rms = relRms(cached, direct), noise = relRms(direct, reference);
        INFO("relative RMS " << rms << ", the 16-sample march's own error " << noise << ", worst pixel " << worst << ", pixels off by > 60 %: " << outliers);
        // Both march 16 samples with a per-ray dither (by cache texel, by pixel): each is off the
        // converged image by the march's own noise (measured here against 256 samples: 7.5 % with
        // the carved cumulus density of 2026-11-24, whose sharper edges band more than the earlier
        // blobs' 4.4-4.7 %), so two independent ditherings differ by up to ~sqrt(2) x that
        // (measured 7.5 %); 1.6 x leaves room for the cache's bilinear resampling. One pixel by the
        // banding of 16 steps through a cloud edge, up to tens of per cent; since the forward-peaked
        // orders (2026-11-27) a thin fringe towards the Sun (30 deg up, 20 deg from the view) is up to
        // ~2x the sky behind it, so the fringe pixels that one march catches and the other misses are
        // off by up to ~110 % (measured: 12 of the 1024 beyond 60 %, the worst 109 %; the march's own
        // error against 256 samples rose from 7.5 % to 14.8 % with them). A wrong mapping or a stale
        // texel would put most cloud pixels off by the clouds' whole contrast: at most 25 (2.5 %)
        // beyond 60 %, none beyond 150 %.
        CHECK(noise < 0.2);  // the reference itself is sane (a broken march would not converge)
        CHECK(rms < 1.6 * noise);
        CHECK(outliers <= 25);
        CHECK(worst < 1.5);
        CHECK(finiteNonNegative(cached));
    }
    for (int frames : {4, 64}) {
        DYNAMIC_SECTION("the wind's move refreshed over one cycle of " << frames << " frames") {
            auto s = scene(30, frames);
            s->render();  // the full fill
            const Image before = s->render();
            s->p.vars().set(ck::weatherOffset, glm::dvec2(700, 300));  // the wind: no refill
            // The photometry (the bases' light from below) follows the wind within
            // Clouds::kPhotometryFrames frames, and the texels refreshed before it used the old
            // one: a cycle after that, every texel is fresh.
            Image img;
            // (+1: the refresh's two passes are spread over two frames.)
            for (int i = 0; i < frames + elements::Clouds::kPhotometryFrames + 1; ++i) img = s->render();
            auto fresh = scene(30, frames);
            fresh->p.vars().set(ck::weatherOffset, glm::dvec2(700, 300));
            CHECK(img.pixels == fresh->render().pixels);
            CHECK(img.pixels != before.pixels);  // the move shows
        }
    }
    SECTION("turning the camera needs no refill") {
        auto s = scene(30, 64);
        s->render();
        const Camera cam = perspective(32, 32, 40 * kDeg, 20 * kDeg, 60 * kDeg);
        s->p.setCamera(cam);
        const Image turned = s->render();
        auto fresh = scene(30, 64);
        fresh->p.setCamera(cam);
        CHECK(turned.pixels == fresh->render().pixels);
    }
    for (int frames : {4, 64}) {
        DYNAMIC_SECTION("a jump of the Sun: refilled over one cycle of " << frames << " frames, the cache before it drawn meanwhile") {
            // Issue 22 item 5: the whole refill in the frame after a jump made it ~50x a still
            // frame. Counted, not timed: each frame after the jump marches one Bayer phase (1/frames
            // of the texels, as the running refresh) into a second cache while the one before the
            // jump is drawn; after `frames` frames the two swap, and the drawn cache is bit for bit
            // the one a fresh fill at the new light gives.
            auto s = scene(30, frames);
            s->render();
            CHECK(s->clouds->cachePhasesLastFrame() == frames);  // the first frame: whole
            s->render();
            CHECK(s->clouds->cachePhasesLastFrame() == 1);  // the running refresh
            const std::vector<float> before = s->clouds->readCache(false);
            s->p.vars().set(keys::sunDirection, directionFromAzAlt(180 * kDeg, 40 * kDeg));
            const int refills = s->clouds->cacheJumpRefills();
            // The jump's frame: the first of the photometry's two passes (spread over frames), and
            // no phase marched (the refill waits for the new photometry, whose ground light lights
            // the bases), the old cache drawn.
            s->render();
            CHECK(s->clouds->photometryPending());
            CHECK(s->clouds->cachePhasesLastFrame() == 0);
            CHECK(s->clouds->cacheJumpRefills() == refills);
            CHECK(s->clouds->readCache(false) == before);
            for (int i = 0; i < frames; ++i) {
                s->render();
                CHECK(s->clouds->cachePhasesLastFrame() == 1);
                if (i < frames - 1) {
                    CHECK(s->clouds->cacheRefilling());
                    CHECK(s->clouds->readCache(false) == before);  // the old cache, untouched
                }
            }
            CHECK(s->clouds->cacheJumpRefills() == refills + 1);
            CHECK_FALSE(s->clouds->cacheRefilling());
            auto fresh40 = scene(40, frames);
            fresh40->render();
            CHECK(s->clouds->readCache(false) == fresh40->clouds->readCache(false));
            CHECK(s->clouds->readCache(true) == fresh40->clouds->readCache(true));
        }
    }
    SECTION("time running: the photometry at most once in kPhotometryFrames frames, at once after a jump") {
        // The Sun moves 0.1 deg a frame (time at ~1440x at 30 frames/s): beyond the photometry's
        // 5e-4 rad tolerance every frame, so before the interval every frame ran the pass (two
        // passes with read-backs). Counted, not timed.
        auto s = scene(30, 64);
        s->render();
        const int before = s->clouds->photometryRuns();
        const int n = 4 * elements::Clouds::kPhotometryFrames;
        for (int i = 1; i <= n; ++i) {
            s->p.vars().set(keys::sunDirection, directionFromAzAlt(180 * kDeg, (30 + 0.1 * i) * kDeg));
            s->render();
        }
        // n / kPhotometryFrames runs, and one more at the second frame, whose inputs other than the
        // moving ones changed (the Sky's tables, built in the first frame after the clouds' pass).
        const int runs = s->clouds->photometryRuns() - before;
        CHECK(runs >= n / elements::Clouds::kPhotometryFrames);
        CHECK(runs <= n / elements::Clouds::kPhotometryFrames + 1);
        // A jump (a new time: 5 deg) reruns it in the same frame.
        const int atJump = s->clouds->photometryRuns();
        s->p.vars().set(keys::sunDirection, directionFromAzAlt(180 * kDeg, 40 * kDeg));
        s->render();
        CHECK(s->clouds->photometryRuns() == atJump + 1);
        // Off the real-time path (welkin render), every frame whose light moved runs it.
        s->p.vars().set(ek::reprojection, false);
        const int offline = s->clouds->photometryRuns();
        for (int i = 1; i <= 3; ++i) {
            s->p.vars().set(keys::sunDirection, directionFromAzAlt(180 * kDeg, (40 + 0.1 * i) * kDeg));
            s->render();
        }
        CHECK(s->clouds->photometryRuns() == offline + 3);
    }
    SECTION("a jump: the photometry's passes one a frame, the result bit for bit a whole one's") {
        // Issue 22 items 4-5: the photometry (two marches of the 16 x 16 hemisphere with their
        // read-backs on the ground) was computed whole in the jump's frame, on top of the first
        // phase of the cache's refill. Counted, not timed: in real time one pass a frame, the
        // photometry before the jump shown until the second; then every field equals, bit for bit,
        // that of a twin off the real-time path (clouds.reprojection false) that computed it whole
        // in the jump's frame from the same inputs (time stopped).
        auto s = scene(30, 64);
        auto t = scene(30, 64);
        t->p.vars().set(ek::reprojection, false);
        for (int i = 0; i < 3; ++i) s->render(), t->render();
        REQUIRE(s->clouds->photometry().valid);
        const elements::Clouds::Photometry before = s->clouds->photometry();
        s->p.vars().set(keys::sunDirection, directionFromAzAlt(180 * kDeg, 40 * kDeg));
        t->p.vars().set(keys::sunDirection, directionFromAzAlt(180 * kDeg, 40 * kDeg));
        s->render(), t->render();
        CHECK(t->clouds->photometryPassesLastFrame() == 2);  // whole: the ground unlit, then lit
        CHECK(s->clouds->photometryPassesLastFrame() == 1);
        CHECK(s->clouds->photometryPending());
        CHECK(s->clouds->photometry().global == before.global);  // the last complete one stands
        CHECK(s->clouds->photometry().sunTransmittance == before.sunTransmittance);
        s->render();
        CHECK(s->clouds->photometryPassesLastFrame() == 1);
        CHECK_FALSE(s->clouds->photometryPending());
        const elements::Clouds::Photometry& a = s->clouds->photometry();
        const elements::Clouds::Photometry& b = t->clouds->photometry();
        CHECK(a.global != before.global);  // the jump shows
        CHECK(a.global == b.global);
        CHECK(a.direct == b.direct);
        CHECK(a.diffuse == b.diffuse);
        CHECK(a.sunTransmittance == b.sunTransmittance);
        CHECK(a.moonTransmittance == b.moonTransmittance);
        CHECK(a.groundLux == b.groundLux);
        // Then nothing more while time stays stopped.
        s->render();
        CHECK(s->clouds->photometryPassesLastFrame() == 0);
    }
    SECTION("clouds.cache_frames must be a Bayer order") {
        SkyVars v = SkyVars::earth();
        elements::Clouds c;
        v.set(ek::cacheFrames, 8);
        CHECK_THROWS_WITH(c.validateOptions(v), "clouds.cache_frames 8 not one of 1, 4, 16, 64 (the Bayer orders)");
    }
}

TEST_CASE("Clouds: a single cumulus is as bright as a real one", "[gl][clouds]") {
    // One cumulus (the bench cloud-reference's `cumulus-side` cloud: a Gaussian blob ~2.4 km across
    // on the weather map, 4 km north of the observer, 1.5-3.5 km, the generated noise, 0.05 /m).
    // Each view is rendered with the clouds and without them (coverage 0: the Sky alone), so the
    // cloud's pixels are those it changes by more than 5 %.
    const Weather blob = blobWeather(20000.0, 4000.0, 1200.0, 0.9f);
    const int W = 48, H = 36;
    Scene s(60, blob, Projection::Perspective, W, H);
    s.p.vars().set(ck::weatherOffset, glm::dvec2(10000, 10000));  // the blob's centre 4 km north
    s.p.vars().set(ck::coverage, 1.0);
    s.p.vars().set(ck::cloudType, 1.0);
    s.p.vars().set(ck::cirrusCoverage, 0.0);
    s.p.vars().set(ck::bottom, 1500.0);
    s.p.vars().set(ck::top, 3500.0);
    s.p.vars().set(ck::scattering, 0.05);
    s.p.vars().set(ek::samples, 32);
    s.p.vars().set(ek::lightSamples, 6);
    // Without the clouds' shadow on the air's in-scattering: the clear-sky frames (coverage 0) must
    // show the same air as the frames with the cloud, so that only the cloud's pixels differ.
    s.p.vars().set(ek::skyShadow, false);
    struct View {
        Image clouds, sky;
        bool cloud(int x, int y) const { return std::abs(luminance(clouds, x, y) - luminance(sky, x, y)) > 0.05 * luminance(sky, x, y); }
    };
    auto render = [&](glm::dvec3 sun, double camAltDeg, double fovDeg) {
        s.p.vars().set(keys::sunDirection, sun);
        const Camera cam = perspective(W, H, 0, camAltDeg * kDeg, fovDeg * kDeg);  // north, at the cloud
        s.p.setCamera(cam);
        View v;
        s.p.vars().set(ck::coverage, 1.0);
        v.clouds = s.render();
        s.p.vars().set(ck::coverage, 0.0);
        v.sky = s.render();
        return v;
    };
    SECTION("lit from the side: a bright sunlit side, a base brighter than the sky beside it") {
        // The Sun 60 deg up in the east, 90 deg from the view (north).
        const View v = render(directionFromAzAlt(90 * kDeg, 60 * kDeg), 28, 36);
        std::vector<double> east;
        double base = 0, skyBeside = 0;
        int nBase = 0, nBeside = 0, lowest = -1;  // the cloud's lowest row (the image's top row is y = 0)
        for (int y = 0; y < H; ++y)
            for (int x = 0; x < W; ++x)
                if (v.cloud(x, y)) lowest = std::max(lowest, y);
        for (int y = 0; y < H; ++y)
            for (int x = 0; x < W; ++x) {
                const double l = luminance(v.clouds, x, y);
                if (v.cloud(x, y) && x >= W / 2) east.push_back(l);
                // The base: the cloud's lowest three rows of pixels, and the clear sky in the same rows.
                if (y > lowest - 3) {
                    if (v.cloud(x, y)) { base += l; ++nBase; }
                    else { skyBeside += l; ++nBeside; }
                }
            }
        REQUIRE(east.size() > 20);
        REQUIRE(nBase > 3);
        REQUIRE(nBeside > 3);
        std::sort(east.begin(), east.end());
        const double litSide = east[east.size() * 3 / 4];
        INFO("sunlit side (75th percentile of the east half) " << litSide << " cd/m^2, base " << base / nBase << ", sky beside it " << skyBeside / nBeside);
        // Real sunlit cumulus: 10,000-30,000 cd/m^2 (a white Lambertian surface under a 90,000 lx
        // beam is 28,600 cd/m^2); the 75th percentile of the sunlit half, not its brightest pixel.
        CHECK(litSide > 10000.0);
        CHECK(litSide < 40000.0);  // and not brighter than any sunlit white surface can be
        CHECK(base / nBase > skyBeside / nBeside);
    }
    SECTION("the Sun behind the cloud: a silver lining") {
        // The Sun 30 deg up in the north, behind the cloud's middle (2.5 km up, 4 km away: 32 deg).
        const View v = render(directionFromAzAlt(0, 30 * kDeg), 30, 50);
        double edge = 0, centre = 0;
        int ne = 0, nc = 0;
        for (int y = 0; y < H; ++y)
            for (int x = 0; x < W; ++x) {
                if (!v.cloud(x, y)) continue;
                // Distance (pixels, Chebyshev) to the nearest clear pixel: 1 at the silhouette.
                int d = 1;
                for (bool inside = true; inside && d < 8; d += inside ? 1 : 0) {
                    for (int j = -d; j <= d && inside; ++j)
                        for (int i = -d; i <= d && inside; ++i) {
                            const int xx = x + i, yy = y + j;
                            if (xx >= 0 && yy >= 0 && xx < W && yy < H && !v.cloud(xx, yy)) inside = false;
                        }
                }
                const double l = luminance(v.clouds, x, y);
                if (d == 1) { edge += l; ++ne; }
                else if (d >= 4) { centre += l; ++nc; }
            }
        INFO(ne << " silhouette px, " << nc << " inside px; edge " << edge / std::max(ne, 1) << " centre " << centre / std::max(nc, 1) << " cd/m^2");
        REQUIRE(ne > 10);
        // At least 8 inside pixels for the inside's mean: the mask (5 % from the clear sky) drops
        // inside pixels as bright as the aureole behind them, so their count moves with the
        // inside's luminance (10 since the lit face's cosine, 2026-11-27 evening; more than 10 before).
        REQUIRE(nc >= 8);
        // Measured 41,490 against 18,840 (2.20x) with the transfer table (2026-11-27 14:21 UTC); 40,760
        // against 19,390 (2.10x) with the regenerated constants (welkin bench cloud-fit,
        // 2026-11-27 11:00 UTC); 41,100 against 29,200 (1.41x) with the forward-peaked low orders' first
        // fit and the light march at the full LOD (before: 23,300 against 20,300, 1.15x). The path
        // tracer's rim over its inside is 1.81 at the bench's 40 x 22 px (bench cloud-reference,
        // cumulus-behind; skyelements/clouds/README.md "Brightness against real cumulus"); 1.3 keeps most of the
        // measured margin and fails if the forward orders or the eroded light march are lost (1.15).
        CHECK(edge / ne > centre / nc);
        CHECK(edge / ne > 1.3 * (centre / nc));
    }
}

TEST_CASE("Clouds: the towering preset: a tall cumulus with a flat, darker base and a bright sunlit side", "[gl][clouds]") {
    // The preset's values (clouds.cpp's sources: cumulus congestus bases 1-1.5 km, tops 6-8 km and
    // beyond for cumulonimbus; extinction 0.075-0.2 /m for 0.5-1.5 g/m^3 of liquid water).
    const elements::CloudPreset& t = elements::cloudPreset("towering");
    CHECK(t.bottom >= 1000.0);
    CHECK(t.bottom <= 1500.0);
    CHECK(t.top >= 6000.0);
    CHECK(t.cirrusHeight > t.top);
    CHECK(t.scattering >= 0.075);
    CHECK(t.scattering <= 0.2);
    CHECK(t.cloudType == 1.0);  // the cumulus gradient: every base on the layer's bottom (flat)
    // One of its towers: a weather-map blob 2.5 km in radius, its top at the layer's top, 12 km
    // north; the preset's layer, scattering, detail and coverage; the generated noise. The Sun 30 deg
    // up in the east (90 deg from the view).
    const Weather blob = blobWeather(40000.0, 12000.0, 2500.0, 1.0f);
    const int W = 48, H = 40;
    Scene s(30, blob, Projection::Perspective, W, H);
    s.p.vars().set(ck::weatherExtent, 40000.0);
    s.p.vars().set(ck::weatherOffset, glm::dvec2(20000, 20000));
    s.p.vars().setFromString("clouds.preset", "towering");
    s.p.vars().set(ck::cirrusCoverage, 0.0);
    s.p.vars().set(ek::samples, 64);
    s.p.vars().set(ek::lightSamples, 6);
    s.p.vars().set(ek::skyShadow, false);  // the clear frame must have the same air
    s.p.vars().set(keys::sunDirection, directionFromAzAlt(90 * kDeg, 30 * kDeg));
    const Camera cam = perspective(W, H, 0, 20 * kDeg, 50 * kDeg);
    s.p.setCamera(cam);
    const Image clouds = s.render();
    s.p.vars().set(ck::coverage, 0.0);
    const Image sky = s.render();
    auto cloud = [&](int x, int y) { return std::abs(luminance(clouds, x, y) - luminance(sky, x, y)) > 0.05 * luminance(sky, x, y); };
    int top = H, lowest = -1;
    std::vector<double> east;
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x)
            if (cloud(x, y)) {
                top = std::min(top, y);
                lowest = std::max(lowest, y);
                if (x >= W / 2) east.push_back(luminance(clouds, x, y));
            }
    REQUIRE(east.size() > 20);
    // Its height: 8 km at 12 km is 34 deg up; the image spans -5..45 deg (1.25 deg a row): the
    // tower's top rows above 25 deg (row < 16).
    const double topDeg = 45.0 - (top + 0.5) * 50.0 / H;
    // The base: the lowest two rows with at least 4 cloud pixels each. Since the transfer table
    // (2026-11-27 afternoon: the light leaving a cloud's face at grazing angles is ~0.6x the
    // diffusion form's) the base seen 5 deg up differs from the sky behind it by less than the
    // mask's 5 % in places, which leaves single pixels below it (rows of 1-3).
    double base = 0;
    int nBase = 0, rows = 0;
    for (int y = lowest; y >= 0 && rows < 2; --y) {
        int n = 0;
        double sum = 0;
        for (int x = 0; x < W; ++x)
            if (cloud(x, y)) sum += luminance(clouds, x, y), ++n;
        if (n >= 4) base += sum, nBase += n, ++rows;
    }
    std::string mask;  // the cloud pixels, row by row (for a failure's message)
    for (int y = 0; y < H; ++y) {
        for (int x = 0; x < W; ++x) mask += cloud(x, y) ? '#' : '.';
        mask += '\n';
    }
    INFO("cloud pixels:\n" << mask);
    REQUIRE(nBase > 3);
    std::sort(east.begin(), east.end());
    const double litSide = east[east.size() * 3 / 4];
    INFO("top " << topDeg << " deg up; sunlit side (75th percentile of the east half) " << litSide << " cd/m^2, base (lowest two rows) " << base / nBase);
    CHECK(topDeg > 25.0);
    // A sunlit cumulus side: 10,000-30,000 cd/m^2 (the single-cumulus test's reasons).
    CHECK(litSide > 10000.0);
    CHECK(litSide < 40000.0);
    // The base lies under 6.8 km of cloud (vertical optical depth in the hundreds): lit only by the
    // ground and the light diffusing through the tower's sides, it is darker than the sunlit side
    // (measured: top 29 deg up, sunlit side 10,408 cd/m^2, base 5,343: 0.51x with the finite cloud's
    // depth to its far side, 2026-11-27 17:40 UTC, the tower's sunlit side no longer a slab's
    // reflection; 11,236 and 5,266, 0.47x with the transfer table, 14:19 UTC; 11,910 and 5,450,
    // 0.46x with the regenerated constants and the atmosphere's ground albedo, 11:00 UTC; 13,950
    // and 5,420, 0.39x, before). The bound is a margin over the measured ratio, not a reference's
    // (the tower is not among the path-traced scenes): 0.55 was 0.5 until the finite depth, which
    // took 7 % from the sunlit side; it fails if the base is lit as brightly as the side.
    CHECK(base / nBase < 0.55 * litSide);
}
