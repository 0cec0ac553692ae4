// The solar eclipse's sky (docs/eclipse.md): the Moon's shadow on the air, against the astronomy
// (the total eclipse of 2026-08-12 over Burgos), physical facts and the CPU twin.
#include <catch2/catch.hpp>

#include "astronomy_at.hpp"
#include "gl_test_context.hpp"

#include <welkin/astro/astro_keys.hpp>
#include <welkin/elements/sky.hpp>
#include <welkin/elements/sky_offline.hpp>
#include <welkin/generators/atmosphere.hpp>
#include <welkin/generators/eclipse_reference.hpp>
#include <welkin/generators/sky_luts.hpp>
#include <welkin/time.hpp>
#include <welkin/keys.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

using namespace welkin;
using namespace welkin::generators;

namespace {
constexpr double kDeg = M_PI / 180;
double Y(const glm::dvec3& c) { return 0.2126 * c.r + 0.7152 * c.g + 0.0722 * c.b; }
constexpr const char* kTotality = "2026-08-12T18:29:00Z";  // mid-totality near Burgos (the astronomy: fraction 0)
constexpr double kLat = 42.34, kLon = -3.70;
// The multiple-scattering model's stated accuracy against the eclipse reference at totality: a
// factor. Measured with this test's coarse reference (docs/eclipse.md, "Accuracy", "One model at
// three places"): 0.97 to 1.54 in eight directions over Burgos on the renderer's air (welkin bench
// eclipse), 0.69 to 1.03 on SkyModel::earthClear(), this case's model; 2 leaves room for the
// atmospheres while the isotropic factor it replaced (0.41 at 45 deg across, L = 30 km) fails.
// (The horizon beneath the Sun is left out here: on this case's SkyModel::earthClear() the model
// is 0.13 of the reference there, its axis weight fitted to the renderer's more forward-scattering
// aerosol; the next case checks it on the renderer's atmosphere. docs/eclipse.md "Accuracy".)
constexpr double kEclipseModelFactor = 2.0;

cpu::EclipseGeometry geometryOf(const SkyVars& v) {
    return {.moonPos = v.get(astro::keys::moonPosition), .moonRadius = astro::keys::kMoonRadiusMeters,
            .sunPos = glm::normalize(v.get(keys::sunDirection)) * v.get(astro::keys::sunDistance), .sunRadius = kSunRadiusMeters};
}

// The eclipse sky's model (cpu::integrateEclipse with its multiple-scattering table, 128 steps)
// beside the eclipse reference (atmosphere::eclipseReferenceRadiance, exact to order 2) for an
// observer on the ground under `v`'s eclipse, in directions given from the Sun's azimuth. The
// reference is coarse (seconds, not minutes): 24 view points, an 8 x 12 gather of 16 points,
// 48 rings, the resolution every tolerance below was measured at.
class EclipseComparison {
public:
    struct Point {
        double model = 0, reference = 0, secondOrder = 0;  // luminance Y of each radiance, in the integrators' common unit
    };
    EclipseComparison(const SkyVars& v, const SkyModel& m, const Lut2D& T, const cpu::MsField& MS)
        : m_(m), T_(T), MS_(MS), sun_(glm::normalize(v.get(keys::sunDirection))), g_(geometryOf(v)),
          field_(cpu::eclipseMsTable(g_, cpu::eclipseMsLength(g_))), gm_(g_) {
        gm_.ms = &field_;
    }
    EclipseComparison(const EclipseComparison&) = delete;  // gm_ points into field_
    EclipseComparison& operator=(const EclipseComparison&) = delete;
    // dazDeg: azimuth from the Sun's, degrees; altDeg: altitude, degrees.
    Point at(double dazDeg, double altDeg) const {
        const glm::dvec3 dir = directionFromAzAlt(std::atan2(sun_.x, sun_.y) + dazDeg * kDeg, altDeg * kDeg);
        const atmosphere::EclipseReferenceOptions ro{.viewSteps = 24, .gatherZenith = 8, .gatherAzimuth = 12, .gatherSteps = 16, .rings = 48};
        const atmosphere::EclipseReferenceRadiance r = atmosphere::eclipseReferenceRadiance(m_, T_, MS_, 0.0, dir, sun_, g_, ro);
        const double model =
            Y(cpu::radiance(m_, cpu::integrateEclipse(m_, T_, MS_, 0.0, dir, sun_, gm_, 128, false, m_.sunAngularRadius), glm::dot(dir, sun_)));
        return {model, Y(r.radiance), Y(r.second)};
    }

private:
    const SkyModel& m_;
    const Lut2D& T_;
    const cpu::MsField& MS_;
    glm::dvec3 sun_;
    cpu::EclipseGeometry g_;
    cpu::EclipseMsTable field_;
    cpu::EclipseGeometry gm_;
};

// The Sky element over the astronomy's keys at an instant (eclipses on or off), rendered to a
// small equirectangular image.
struct EclipseRig {
    SkyVars vars;
    elements::OfflineRenderer r;
    elements::Sky sky{elements::SkyOptions{.quality = 1, .moon = false}};
    Camera cam;
    Image img;
    EclipseRig(const char* iso, bool eclipses, int w = 64, int h = 32, bool hazy = false)
        : vars([&] {
              SkyVars v = test::astronomyAt(iso, kLat, kLon);
              if (!eclipses) {
                  v.set(astro::keys::eclipses, false);
                  astro::updateSkyVars(v);
              }
              return v;
          }()),
          r(vars, test::testLogger()) {
        test::glContext();
        vars.set(atmosphere::kAtmosphere, std::make_shared<const atmosphere::Atmosphere>(hazy ? atmosphere::Atmosphere::earthHazy()
                                                                                                : atmosphere::Atmosphere::earthClear()));
        cam.projection = Projection::Equirect;
        cam.width = w;
        cam.height = h;
        img = r.render(sky, cam);
    }
    ~EclipseRig() {
        sky.release();
        r.release();
    }
    glm::dvec3 px(int x, int y) const { return {img.at(x, y, 0), img.at(x, y, 1), img.at(x, y, 2)}; }
    glm::dvec3 dir(int x, int y) const { return *cam.directionAt({x + 0.5, y + 0.5}); }
    glm::dvec3 horizontal() const { return vars.get(skykeys::horizontalIlluminance); }
};
}  // namespace

TEST_CASE("Eclipse sky: the visible fraction at the observer matches the astronomy's sun.eclipse_fraction", "[cpu][eclipse]") {
    // moon.position_m (the apparent Sun's frame) and the shader's 24-ring fraction give the
    // astronomy's own value at the observer, through the partial phase and at totality.
    for (const char* iso : {"2026-08-12T18:05:00Z", "2026-08-12T18:20:00Z", "2026-08-12T18:27:00Z", kTotality}) {
        const SkyVars v = test::astronomyAt(iso, kLat, kLon);
        const double f = cpu::eclipseAt(geometryOf(v), glm::dvec3(0.0)).x;
        INFO(iso << ": twin " << f << ", astronomy " << v.get(keys::sunEclipseFraction));
        // 24 rings against the astronomy's 512: the ring rule's error, below 0.3 % of the disk
        // (measured < 0.1 %); the Sun's radius from its distance vs the ephemeris' 1e-4 relative.
        CHECK(f == Approx(v.get(keys::sunEclipseFraction)).margin(3e-3));
    }
    CHECK(test::astronomyAt(kTotality, kLat, kLon).get(keys::sunEclipseFraction) == 0.0);  // total at Burgos
    // The ring rule against the 512-ring reference over partial geometries.
    for (double d : {0.0, 0.3, 0.7, 1.0, 1.5, 2.0})
        for (double ro : {0.5, 0.97, 1.03})
            // 24 rings against 512: up to 1.7 % of the disk (measured: annular, ro 0.97, where the
            // Moon's limb cuts few rings); 2 %.
            CHECK(cpu::eclipseFraction(1.0, ro, d) == Approx(astro::eclipseVisibleFraction(1.0, ro, d)).margin(0.02));
    SkyVars off = test::astronomyAt(kTotality, kLat, kLon);
    off.set(astro::keys::eclipses, false);
    astro::updateSkyVars(off);
    CHECK(off.get(keys::sunEclipseFraction) == 1.0);
}

TEST_CASE("Eclipse sky: the visible fraction keeps the thin crescent before second contact", "[cpu][eclipse]") {
    // An independent reference: the limb-darkened disk (u = 0.6) integrated over 200,000 uniform
    // rings, each ring's hidden arc exact. Crescents of 0.5 % down to 1e-5 of the disk (the last
    // ~20 s before C2 at Burgos), a Moon 3.4 % (Burgos) and 0.5 % (a barely total eclipse) larger than the Sun.
    auto fine = [](double R, double D) {
        constexpr int n = 200000;
        double total = 0.0, visible = 0.0;
        for (int i = 0; i < n; ++i) {
            const double r = (i + 0.5) / n, w = (1.0 - 0.6 * (1.0 - std::sqrt(1.0 - r * r))) * r;
            double hidden = 0.0;
            if (D + r <= R) hidden = 1.0;
            else if (!(D >= r + R || R + D <= r)) hidden = std::acos(std::clamp((r * r + D * D - R * R) / (2.0 * r * D), -1.0, 1.0)) / M_PI;
            total += w;
            visible += w * (1.0 - hidden);
        }
        return visible / total;
    };
    for (double R : {1.034, 1.005})
        for (double width : {0.02, 0.005, 0.001}) {  // the crescent's width, in solar radii: D = R - 1 + width
            const double D = R - 1.0 + width, ref = fine(R, D), f = cpu::eclipseFraction(1.0, R, D);
            INFO("R " << R << ", crescent " << width << ": rule " << f << ", reference " << ref);
            REQUIRE(ref > 1e-6);
            // 1 %: the band rule is within 0.1 % of the fraction (24 nodes on the cut band); the
            // uniform 24 rings it replaced gave 0.36x at a 0.02-wide crescent and 0 below.
            CHECK(f == Approx(ref).epsilon(0.01));
        }
}

TEST_CASE("Eclipse sky: at totality over Burgos the ground darkens 1000-fold and the horizon outshines the zenith", "[gl][eclipse]") {
    EclipseRig ecl(kTotality, true), clear(kTotality, false);
    REQUIRE(ecl.sky.eclipsed());
    REQUIRE_FALSE(clear.sky.eclipsed());
    const double eEcl = ecl.horizontal().x, eClear = clear.horizontal().x;
    std::printf("\ntotality over Burgos: ground illuminance %.4g lx (direct %.3g), without the Moon %.4g lx: 1/%.0f\n", eEcl,
                ecl.horizontal().y, eClear, eClear / eEcl);
    CHECK(eClear > 1000.0);  // the Sun ~10 deg up: a bright evening without the Moon
    CHECK(eEcl * 1e3 < eClear);
    CHECK(eEcl > 0.0);
    // Zenith (top row) against the horizon ring (the row just above the horizon), every azimuth.
    double zenith = 0.0, horizon = 0.0, horizonMin = 1e30;
    const int yh = ecl.cam.height / 2 - 1;
    for (int x = 0; x < ecl.cam.width; ++x) {
        zenith += Y(ecl.px(x, 0)) / ecl.cam.width;
        horizon += Y(ecl.px(x, yh)) / ecl.cam.width;
        horizonMin = std::min(horizonMin, Y(ecl.px(x, yh)));
    }
    std::printf("zenith %.3g cd/m^2, horizon mean %.3g (least %.3g); the clear sky's zenith %.3g\n", zenith, horizon, horizonMin,
                Y(clear.px(0, 0)));
    CHECK(horizon > 2.0 * zenith);  // the ring of light from the air outside the umbra
    // (Not checked: every azimuth of the horizon brighter than the zenith. The multiple-scattering
    // model is too dark inside the umbra, docs/eclipse.md: where the horizon ray stays in the umbra
    // both are ~0 in the fp16 table.)
}

TEST_CASE("Eclipse sky: the GPU's eclipse table against the CPU twin at totality", "[gl][eclipse]") {
    // On the renderer's air and on hazy air (where the weight's haze terms run: the shader's text).
    const bool hazy = GENERATE(false, true);
    INFO((hazy ? "Atmosphere::earthHazy()" : "Atmosphere::earthClear()"));
    EclipseRig ecl(kTotality, true, 64, 32, hazy);
    REQUIRE(ecl.sky.eclipsed());
    const SkyModel m = SkyModel::fromVars(ecl.vars);
    const SkyQuality q = SkyQuality::preset(1);
    const Lut2D T = cpu::transmittanceLut(m, q);
    const cpu::MsField MS = cpu::msField(m, q, T);
    const glm::dvec3 sun = glm::normalize(ecl.vars.get(keys::sunDirection));
    const glm::dvec3 E = ecl.vars.get(lightkeys::sunIlluminance);
    cpu::EclipseGeometry g = geometryOf(ecl.vars);
    const cpu::EclipseMsTable field = cpu::eclipseMsTable(g, cpu::eclipseMsLength(g));  // as EclipseSkyLut builds it
    g.ms = &field;
    double worst = 0.0;
    for (auto [x, y] : {std::pair{5, 2}, std::pair{20, 8}, std::pair{40, 12}, std::pair{60, 15}, std::pair{10, 15}, std::pair{33, 5}}) {
        const glm::dvec3 d = ecl.dir(x, y);
        const glm::dvec3 twin = cpu::radiance(m, cpu::integrateEclipse(m, T, MS, 0.0, d, sun, g, 128, false, m.sunAngularRadius), glm::dot(d, sun)) * E;
        const double gpu = Y(ecl.px(x, y)), cpuY = Y(twin);
        INFO("pixel " << x << "," << y << " (alt " << std::asin(d.z) / kDeg << " deg): GPU " << gpu << ", twin " << cpuY);
        // The table (2x the sky view's width over 360 deg, its latitude rows, fp16, 30 steps per
        // ray) against a 128-step march: 8 % (the shadow's steep edge across texels near the horizon),
        // or 1e-5 cd/m^2 where the twin is ~0 in the umbra (starlight's scale, invisible beside the
        // stars; an NVIDIA H100 gave 1.6e-7 where the twin gives 0, llvmpipe 0).
        CHECK(gpu == Approx(cpuY).epsilon(0.08).margin(1e-5));
        if (cpuY > 1e-5) worst = std::max(worst, std::abs(gpu / cpuY - 1.0));
    }
    std::printf("\neclipse table vs CPU twin at totality (%s air): largest difference %.1f %%\n", hazy ? "hazy" : "clear", 100 * worst);
}

TEST_CASE("Eclipse sky: in the partial phase the direct light is the clear sky's times the visible fraction", "[gl][eclipse]") {
    const char* partial = "2026-08-12T18:10:00Z";
    EclipseRig ecl(partial, true, 32, 16), clear(partial, false, 32, 16);
    const double f = ecl.vars.get(keys::sunEclipseFraction);
    std::printf("\npartial phase %s: fraction %.4f, direct %.2f lx vs clear %.2f lx\n", partial, f, ecl.horizontal().y, clear.horizontal().y);
    REQUIRE(f > 0.05);
    REQUIRE(f < 0.95);
    REQUIRE(ecl.sky.eclipsed());
    CHECK(ecl.horizontal().y == Approx(clear.horizontal().y * f).epsilon(0.01));  // the 1 % (float passes, same LUTs)
    CHECK(ecl.horizontal().z < clear.horizontal().z);  // the shadowed air gives less diffuse light too
}

TEST_CASE("Eclipse sky: a day without an eclipse builds no eclipse table", "[gl][eclipse]") {
    EclipseRig day("2026-08-13T18:29:00Z", true, 32, 16);
    CHECK_FALSE(day.sky.eclipsed());
    CHECK(day.vars.get(skykeys::eclipseViewLut).id == 0);
}

TEST_CASE("Eclipse sky: the multiple-scattering model against the eclipse reference at totality", "[cpu][eclipse]") {
    // cpu::integrateEclipse with the multiple-scattering field (what the GPU table follows) against
    // atmosphere::eclipseReferenceRadiance (exact to order 2) at mid-totality over Burgos.
    const SkyVars v = test::astronomyAt(kTotality, kLat, kLon);
    const SkyModel m = SkyModel::fromVars(v);
    const SkyQuality q = SkyQuality::preset(1);
    const Lut2D T = cpu::transmittanceLut(m, q);
    const cpu::MsField MS = cpu::msField(m, q, T);
    const EclipseComparison cmp(v, m, T, MS);
    // Towards the Sun too (beneath it and 45 deg up): this aerosol scatters 23 % of the light at
    // the ground (the renderer's 86 %), so the weight along the axis keeps most of the kernel's
    // average there (cpu::eclipseMsAxisWeight); with sin(angle) alone the model gave 0.13 and 0.47
    // of the reference, measured now 0.89 and 0.70.
    for (auto [daz, alt] : {std::pair{0.0, 90.0}, std::pair{90.0, 45.0}, std::pair{180.0, 2.0}, std::pair{90.0, 2.0}, std::pair{0.0, 2.0},
                            std::pair{0.0, 45.0}}) {
        const EclipseComparison::Point pt = cmp.at(daz, alt);
        const double ref = pt.reference, model = pt.model;
        INFO("azimuth from the Sun " << daz << " deg, altitude " << alt << " deg: model " << model << ", reference " << ref);
        // Within kEclipseModelFactor (above); the old model gave 0 at the zenith (a factor of infinity).
        CHECK(model < ref * kEclipseModelFactor);
        CHECK(model > ref / kEclipseModelFactor);
    }
}

TEST_CASE("Eclipse sky: the model against the eclipse reference at totality on the renderer's atmosphere: towards the Sun", "[cpu][eclipse]") {
    // The case above integrates SkyModel::earthClear() (no atmosphere key: Hillaire's aerosol,
    // clear horizon towards the Sun 0.18 cd/m^2 per lx); the Sky element draws
    // atmosphere::Atmosphere::earthClear() (the key EclipseRig sets: 0.84 there, its aerosol far
    // more forward-scattering). The horizon beneath the Sun is where the two part: the reference's
    // "3.8x" there (5.6e-6 against 1.49e-6 cd/m^2 per lx, docs/eclipse.md) is the atmosphere, not
    // the integrator (welkin bench eclipse --coarse true with and without --plain-model). On the
    // atmosphere the renderer draws, the direction the case above leaves out, beneath the Sun, and
    // the sky above it towards the Sun.
    SkyVars v = test::astronomyAt(kTotality, kLat, kLon);
    v.set(atmosphere::kAtmosphere, std::make_shared<const atmosphere::Atmosphere>(atmosphere::Atmosphere::earthClear()));
    const SkyModel m = SkyModel::fromVars(v);
    const SkyQuality q = SkyQuality::preset(1);
    const Lut2D T = cpu::transmittanceLut(m, q);
    const cpu::MsField MS = cpu::msField(m, q, T);
    const EclipseComparison cmp(v, m, T, MS);
    for (auto [daz, alt] : {std::pair{0.0, 2.0}, std::pair{0.0, 45.0}}) {
        const EclipseComparison::Point pt = cmp.at(daz, alt);
        const double ref = pt.reference, model = pt.model;
        INFO("azimuth from the Sun " << daz << " deg, altitude " << alt << " deg: model " << model << ", reference " << ref
                                     << " (order 2: " << pt.secondOrder / ref << " of it)");
        // Measured 1.21 beneath the Sun and 1.15 at 45 deg (here, 128 steps, as the bench's 256;
        // 1.31 and 1.10 with the weight fitted at Burgos alone); kEclipseModelFactor, the stated
        // accuracy at totality.
        CHECK(model < ref * kEclipseModelFactor);
        CHECK(model > ref / kEclipseModelFactor);
        // The reference there is exact where it matters: its second order, computed exactly,
        // carries most of the light beneath the Sun (measured 0.95; 0.79 on SkyModel::earthClear()).
        if (alt < 10.0) CHECK(pt.secondOrder > 0.75 * ref);
    }
}

TEST_CASE("Eclipse sky: the model against the eclipse reference at totality on hazy air", "[cpu][eclipse]") {
    // Atmosphere::earthHazy() (aerosol optical depth 0.4 at 550 nm, g 0.75): the sunlit ring's
    // light reaches the umbra's air through ~3 km of horizontal extinction length, mostly by the
    // aerosol's forward peak (docs/eclipse.md, "Hazy air"). Before the haze's terms of the weight
    // the model was 2.31 x the reference at the zenith, 4.40 x at 45 deg towards the Sun and
    // 10.3 x on the horizon beneath it (welkin bench eclipse --coarse true --hazy true): this
    // case failed in all three directions.
    SkyVars v = test::astronomyAt(kTotality, kLat, kLon);
    v.set(atmosphere::kAtmosphere, std::make_shared<const atmosphere::Atmosphere>(atmosphere::Atmosphere::earthHazy()));
    const SkyModel m = SkyModel::fromVars(v);
    REQUIRE(cpu::eclipseHaze(m) == Approx(1.0));  // the haze's terms fully on
    const SkyQuality q = SkyQuality::preset(1);
    const Lut2D T = cpu::transmittanceLut(m, q);
    const cpu::MsField MS = cpu::msField(m, q, T);
    const EclipseComparison cmp(v, m, T, MS);
    for (auto [daz, alt] : {std::pair{0.0, 90.0}, std::pair{0.0, 45.0}, std::pair{0.0, 2.0}}) {
        const EclipseComparison::Point pt = cmp.at(daz, alt);
        const double ref = pt.reference, model = pt.model;
        INFO("azimuth from the Sun " << daz << " deg, altitude " << alt << " deg: model " << model << ", reference " << ref
                                     << " (order 2: " << pt.secondOrder / ref << " of it)");
        // Measured (here and the bench) 0.81 at the zenith, 1.27 at 45 deg towards the Sun, 0.74 on
        // the horizon beneath it (the weight fitted on the three places; 1.00, 1.34, 0.66 with its
        // haze terms fitted here alone); kEclipseModelFactor, the stated accuracy at totality.
        CHECK(model < ref * kEclipseModelFactor);
        CHECK(model > ref / kEclipseModelFactor);
        // The reference beneath the Sun is its exact second order (measured 1.00 of it).
        if (alt < 10.0) CHECK(pt.secondOrder > 0.75 * ref);
    }
}

TEST_CASE("Eclipse sky: the multiple-scattering weight on hazy air, and none of it on clear air", "[cpu][eclipse]") {
    // atmosphere.shared.glsl's atm_eclMsWeight()/atm_eclHaze() (run by cpu::eclipseMsWeight and
    // cpu::eclipseHaze) write their constants as literals: here against the C++ constants.
    auto modelOf = [](const atmosphere::Atmosphere& a) {
        SkyVars v = test::astronomyAt(kTotality, kLat, kLon);
        v.set(atmosphere::kAtmosphere, std::make_shared<const atmosphere::Atmosphere>(a));
        return SkyModel::fromVars(v);
    };
    const SkyModel clear = modelOf(atmosphere::Atmosphere::earthClear()), hazy = modelOf(atmosphere::Atmosphere::earthHazy());
    // The haze measure: 0 on the renderer's air and on Hillaire's (whose weight is then unchanged),
    // 1 on the hazy air (4.0 x the clear aerosol's scattering at the ground).
    CHECK(cpu::eclipseHaze(clear) == 0.0);
    CHECK(cpu::eclipseHaze(SkyModel::earthClear()) == 0.0);
    const double ratio = hazy.scatteringMie(0.0).g / cpu::kEclipseHazeClearMie;
    CHECK(cpu::eclipseHaze(hazy) == Approx(std::clamp((ratio - 1.1) / 2.9, 0.0, 1.0)).margin(1e-12));
    CHECK(ratio == Approx(4.0).epsilon(0.01));  // AOD 0.4 against 0.1, the same scale height
    // The Sun's elevation's terms (docs/eclipse.md, "One model at three places"), for a Sun at
    // muS: X = 1 / muS, the column's share G and the umbra's elongation E.
    auto G = [](double muS) { return 1.0 - std::exp(-cpu::kEclipseColumnRate * (1.0 / muS - 1.0)); };
    auto E = [](double muS) {
        const double x = 1.0 / muS - 1.0;
        return x * x / (x * x + cpu::kEclipseRingElongation * cpu::kEclipseRingElongation);
    };
    // The low views' gain (docs/eclipse.md, "The ring of directions"): 1 + gain (1 + haze H)
    // (x e^(1 - x))^power, x = mu / kEclipseLowViewMu: 1 on the horizon's rim (mu = 0) and largest,
    // 1 + gain (1 + haze H), at mu = kEclipseLowViewMu.
    auto gain = [](double mu, double H) {
        const double x = std::max(mu, 0.0) / cpu::kEclipseLowViewMu;
        return 1.0 + cpu::kEclipseLowViewGain * (1.0 + cpu::kEclipseLowViewHaze * H) * std::pow(x * std::exp(1.0 - x), cpu::kEclipseLowViewPower);
    };
    // Clear air, the Sun low (G = 1 to 1e-12 at 10 deg): away from the Sun and across the axis
    // (nu <= 0) no axis term, the gain alone whatever cosRing; the literals against the constants
    // to rounding (1e-12).
    const double low = std::sin(10 * kDeg), F = 1.0;  // Atmosphere::earthClear(): the forward share clamps to 1
    REQUIRE(G(low) == Approx(1.0).margin(1e-12));
    for (double cr : {0.0, 0.7, 1.0}) CHECK(cpu::eclipseMsWeight(clear, 0.187, 0.0, 0.3, low, cr) == Approx(gain(0.3, 0.0)).margin(1e-12));
    CHECK(cpu::eclipseMsWeight(clear, 0.187, -0.5, 0.3, low, 0.0) == Approx(gain(0.3, 0.0)).margin(1e-12));
    // The gain's peak at mu = kEclipseLowViewMu (here away from the Sun: nothing else).
    CHECK(cpu::eclipseMsWeight(clear, 0.187, -0.5, cpu::kEclipseLowViewMu, low, 0.0) == Approx(1.0 + cpu::kEclipseLowViewGain).margin(1e-12));
    // On the horizon's rim (mu = 0) the gain is 1: across the axis the weight is 1.
    CHECK(cpu::eclipseMsWeight(clear, 0.187, 0.0, 0.0, low, 1.0) == Approx(1.0).margin(1e-12));
    // Towards the Sun, 60 deg from it in its vertical at 60 deg elevation: s = sin(60 deg) (the
    // footprint's offset, 0.47 x 0.87 x 5.8 = 2.4, is larger), raised to kEclipseSunwardPower.
    const double s60 = std::pow(std::sqrt(0.75), cpu::kEclipseSunwardPower);
    CHECK(cpu::eclipseMsWeight(clear, 0.187, 0.5, std::sin(60 * kDeg), low, 0.0) ==
          Approx((1.0 - F * (1.0 - s60)) * gain(std::sin(60 * kDeg), 0.0)).margin(1e-12));
    // On the horizon beneath the Sun: the footprint's offset, kEclipseFootprintMu x mu x X, not sin(angle).
    const double mu2 = std::sin(2 * kDeg), off = cpu::kEclipseFootprintMu * mu2 / low;
    CHECK(cpu::eclipseMsWeight(clear, 0.187, std::cos(8 * kDeg), mu2, low, 0.0) ==
          Approx(std::pow(off, cpu::kEclipseSunwardPower) * gain(mu2, 0.0)).margin(1e-12));
    // Off saturation, where the column's rate shows (kEclipseColumnRate, the shared text's literal
    // 23.6): the Sun 80 deg up, X = 1.0154, G = 1 - exp(-0.364) = 0.305 (to the printed digits);
    // towards the Sun, 60 deg from it and 20 deg up, off its vertical (cosRing 0.9: the offset from
    // the footprint exceeds sin 60 deg, so s = sin 60 deg), the axis weight with F x G.
    const double high = std::sin(80 * kDeg), mu20 = std::sin(20 * kDeg);
    REQUIRE(G(high) == Approx(0.305).margin(0.001));
    const double nu60 = std::cos(60 * kDeg);
    CHECK(cpu::eclipseMsWeight(clear, 0.187, nu60, mu20, high, 0.9) ==
          Approx((1.0 - F * G(high) * (1.0 - s60)) * gain(mu20, 0.0)).margin(1e-12));
    // The Sun at or below the horizon: X clamps at 1 / 0.05 (the weight as at muS = 0.05).
    CHECK(cpu::eclipseMsWeight(clear, 0.187, 0.5, 0.3, -0.1, 0.2) ==
          Approx(cpu::eclipseMsWeight(clear, 0.187, 0.5, 0.3, 0.05, 0.2)).margin(1e-15));
    // The Sun at the zenith: no column (G = 0), the weight the gain's (1.14 at the zenith) even looking at the Sun.
    CHECK(cpu::eclipseMsWeight(clear, 0.187, 1.0, 1.0, 1.0, 0.0) == Approx(gain(1.0, 0.0)).margin(1e-12));
    CHECK(gain(1.0, 0.0) < 1.2);
    // Hazy air (H = 1), the Sun at 10 deg: R = share x mix(1, the mean of the HG lobe (asymmetry
    // G) at +-cosRing x 4 pi, E).
    const double g = cpu::kEclipseHazeRingG, A = cpu::kEclipseHazeRingShare;
    auto lobe = [&](double c) { return (1 - g * g) / std::pow(1 + g * g - 2 * g * c, 1.5); };
    auto R = [&](double cr, double muS) { return A * (1.0 + (0.5 * (lobe(cr) + lobe(-cr)) - 1.0) * E(muS)); };
    // Across the axis, horizontal (nu = 0, cosRing = 1): w' = 1, the ring's lobe at 0 and 180 deg, no gain (mu = 0).
    CHECK(cpu::eclipseMsWeight(hazy, 0.187, 0.0, 0.0, low, 1.0) == Approx(R(1.0, low)).epsilon(1e-9));
    // 60 deg towards the Sun in its vertical: F' = 1, s = sin^(power (1 + haze power)), the gain with H = 1.
    const double s60h = std::pow(std::sqrt(0.75), cpu::kEclipseSunwardPower * (1.0 + cpu::kEclipseHazeSunwardPower));
    CHECK(cpu::eclipseMsWeight(hazy, 0.187, 0.5, std::sin(60 * kDeg), low, 0.0) ==
          Approx(s60h * R(0.0, low) * gain(std::sin(60 * kDeg), 1.0)).epsilon(1e-9));
    // The Sun at the zenith: the umbra round on the air, no ring direction (E = 0): R = share.
    CHECK(cpu::eclipseMsWeight(hazy, 0.187, 0.0, 0.0, 1.0, 1.0) == Approx(A).epsilon(1e-9));
}

// The places of docs/eclipse.md at mid-totality (welkin astro --events) and the Sun's elevation
// there: Burgos 8.3 deg, Reykjavik 24.6 deg, Luxor 81.8 deg.
struct EclipsePlace {
    const char* name;
    double lat, lon;
    const char* mid;
};
constexpr EclipsePlace kPlaces[3] = {{"Burgos", kLat, kLon, kTotality},
                                     {"Reykjavik", 64.15, -21.94, "2026-08-12T17:48:36Z"},
                                     {"Luxor", 25.69, 32.64, "2027-08-02T10:05:13Z"}};

// The fit set's directions (docs/eclipse.md, "The ring of directions"), as (azimuth from the Sun,
// altitude) in degrees: the zenith, a ring every 45 deg of azimuth at 2 deg (the horizon), 15 and
// 45 deg, and 30 and 70 deg in a few azimuths: 29 directions.
std::vector<std::pair<double, double>> ringDirections() {
    std::vector<std::pair<double, double>> d = {{0.0, 90.0}};
    for (double alt : {2.0, 15.0, 45.0})
        for (double daz = 0.0; daz < 359.0; daz += 45.0) d.push_back({daz, alt});
    d.insert(d.end(), {{45.0, 30.0}, {135.0, 30.0}, {0.0, 70.0}, {180.0, 70.0}});
    return d;
}

TEST_CASE("Eclipse sky: the model against the eclipse reference at Burgos, Reykjavik and Luxor", "[cpu][eclipse]") {
    // One weight at every Sun's elevation and in every direction (docs/eclipse.md, "One model at
    // three places", "The ring of directions"): at the three places' mid-totality, on the
    // atmosphere the renderer draws and on hazy air, the 29 directions of the fit set (87 points
    // per atmosphere).
    const bool hazy = GENERATE(false, true);
    INFO((hazy ? "Atmosphere::earthHazy()" : "Atmosphere::earthClear()"));
    SkyVars v0 = test::astronomyAt(kTotality, kLat, kLon);
    v0.set(atmosphere::kAtmosphere, std::make_shared<const atmosphere::Atmosphere>(hazy ? atmosphere::Atmosphere::earthHazy()
                                                                                          : atmosphere::Atmosphere::earthClear()));
    const SkyModel m = SkyModel::fromVars(v0);
    const SkyQuality q = SkyQuality::preset(1);
    const Lut2D T = cpu::transmittanceLut(m, q);
    const cpu::MsField MS = cpu::msField(m, q, T);
    // The stated accuracy (docs/eclipse.md, "The ring of directions", welkin bench eclipse --ring
    // true, 256 steps; this case's 128 give the same to ~1 %): on the renderer's air the model is
    // within 0.68-1.83 of the reference over the 87 points (the largest on Burgos' horizon opposite
    // the Sun), rms |ln(model / reference)| 0.200; on hazy air 0.40-2.49 (Reykjavik's horizon 45 deg
    // from the Sun), rms 0.345. The bounds: 2.0 and 2.75 on the worst point, 0.21 and 0.38 on the
    // rms (the measured values plus 5-10 %). The weight before the ring's refit (kernel 36 km)
    // fails the hazy worst (3.68 on Reykjavik's horizon 45 deg from the Sun) and both rms bounds
    // (this case measured 0.229 and 0.413 with it; docs/eclipse.md, "The ring of directions").
    const double factor = hazy ? 2.75 : 2.0, rmsBound = hazy ? 0.38 : 0.21;
    double sum2 = 0.0;
    int n = 0;
    for (const EclipsePlace& pl : kPlaces) {
        const SkyVars v = test::astronomyAt(pl.mid, pl.lat, pl.lon);
        REQUIRE(v.get(keys::sunEclipseFraction) == 0.0);  // total there
        const EclipseComparison cmp(v, m, T, MS);
        for (auto [daz, alt] : ringDirections()) {
            const EclipseComparison::Point pt = cmp.at(daz, alt);
            INFO(pl.name << ", azimuth from the Sun " << daz << " deg, altitude " << alt << " deg: model " << pt.model << ", reference "
                         << pt.reference << " (" << pt.model / pt.reference << ")");
            std::printf("%s %s az %+.0f alt %.0f: model / reference %.3f\n", hazy ? "hazy" : "clear", pl.name, daz, alt, pt.model / pt.reference);
            CHECK(pt.model < pt.reference * factor);
            CHECK(pt.model > pt.reference / factor);
            sum2 += std::pow(std::log(pt.model / pt.reference), 2);
            ++n;
        }
    }
    const double rms = std::sqrt(sum2 / n);
    INFO("rms |ln(model / reference)| over " << n << " points: " << rms);
    std::printf("%s: rms |ln(model / reference)| over %d points %.3f\n", hazy ? "hazy" : "clear", n, rms);
    CHECK(n == 87);
    CHECK(rms < rmsBound);
}

TEST_CASE("Eclipse sky: the model against the eclipse reference in the 99 % phase at Burgos, Reykjavik and Luxor", "[cpu][eclipse]") {
    // The instant 1 % of the Sun is left before second contact at each place (bisection on the
    // astronomy's sun.eclipse_fraction), the renderer's air, the same five directions.
    SkyVars v0 = test::astronomyAt(kTotality, kLat, kLon);
    v0.set(atmosphere::kAtmosphere, std::make_shared<const atmosphere::Atmosphere>(atmosphere::Atmosphere::earthClear()));
    const SkyModel m = SkyModel::fromVars(v0);
    const SkyQuality q = SkyQuality::preset(1);
    const Lut2D T = cpu::transmittanceLut(m, q);
    const cpu::MsField MS = cpu::msField(m, q, T);
    for (const EclipsePlace& pl : kPlaces) {
        const UtcInstant mid = UtcInstant::parse(pl.mid);
        double a = -1800.0, b = 0.0;  // seconds from mid-totality
        for (int i = 0; i < 30; ++i) {
            const double c = 0.5 * (a + b);
            const SkyVars vc = test::astronomyAt(mid.plusSeconds(c).toIso().c_str(), pl.lat, pl.lon);
            (vc.get(keys::sunEclipseFraction) > 0.01 ? a : b) = c;
        }
        const SkyVars v = test::astronomyAt(mid.plusSeconds(a).toIso().c_str(), pl.lat, pl.lon);
        // The phase itself (the instant rounded to the second by toIso(): 5 %).
        REQUIRE(v.get(keys::sunEclipseFraction) == Approx(0.01).epsilon(0.05));
        const EclipseComparison cmp(v, m, T, MS);
        for (auto [daz, alt] : {std::pair{0.0, 90.0}, std::pair{0.0, 45.0}, std::pair{180.0, 45.0}, std::pair{0.0, 2.0}, std::pair{180.0, 2.0}}) {
            const EclipseComparison::Point pt = cmp.at(daz, alt);
            INFO(pl.name << " at 99 %, azimuth from the Sun " << daz << " deg, altitude " << alt << " deg: model " << pt.model
                         << ", reference " << pt.reference);
            std::printf("99 %% %s az %+.0f alt %.0f: model / reference %.3f\n", pl.name, daz, alt, pt.model / pt.reference);
            // Measured 0.92-1.33 (the bench; the largest at Luxor's horizon opposite the Sun, where
            // the clear model alone is 1.13 x the reference); 1.5.
            CHECK(pt.model < pt.reference * 1.5);
            CHECK(pt.model > pt.reference / 1.5);
        }
    }
}

TEST_CASE("Eclipse sky: the model against the eclipse reference in the partial phases (90 %, 99 %, 99.5 %)", "[cpu][eclipse]") {
    // The instants where 10 %, 1 % and 0.5 % of the Sun is left before C2 over Burgos (welkin bench
    // eclipse finds them by bisection), the same coarse reference as at totality.
    const SkyVars v0 = test::astronomyAt(kTotality, kLat, kLon);
    const SkyModel m = SkyModel::fromVars(v0);
    const SkyQuality q = SkyQuality::preset(1);
    const Lut2D T = cpu::transmittanceLut(m, q);
    const cpu::MsField MS = cpu::msField(m, q, T);
    for (auto [iso, fraction] : {std::pair{"2026-08-12T18:27:39Z", 0.005}, std::pair{"2026-08-12T18:27:16Z", 0.01},
                                 std::pair{"2026-08-12T18:22:25Z", 0.1}}) {
        const SkyVars v = test::astronomyAt(iso, kLat, kLon);
        // The phase itself (the bisection's instants rounded to the second: 2 %).
        REQUIRE(v.get(keys::sunEclipseFraction) == Approx(fraction).epsilon(0.02));
        const EclipseComparison cmp(v, m, T, MS);
        for (auto [daz, alt] : {std::pair{0.0, 90.0}, std::pair{90.0, 45.0}, std::pair{0.0, 2.0}, std::pair{90.0, 2.0}}) {
            const EclipseComparison::Point pt = cmp.at(daz, alt);
            const double ref = pt.reference, model = pt.model;
            INFO(iso << ", azimuth from the Sun " << daz << " deg, altitude " << alt << " deg: model " << model << ", reference " << ref);
            // Measured 0.99 to 1.04 at this test's quality 1 (0.91 to 1.59 at the default quality,
            // the bench's table, the largest on the horizon 90 deg from the Sun where the clear
            // model alone is 1.09 x the reference); 1.25. The uniform 24-ring fraction it replaced
            // gave 0.07 towards the Sun at 99.5 % (the crescent's light lost).
            CHECK(model < ref * 1.25);
            CHECK(model > ref / 1.25);
        }
    }
}

TEST_CASE("Eclipse sky: the eclipse table is rebuilt only when the shadow moves, in bands", "[gl][eclipse]") {
    EclipseRig ecl(kTotality, true, 32, 16);
    REQUIRE(ecl.sky.eclipsed());
    std::shared_ptr<EclipseSkyLut> lut = SkyLuts::obtain(ecl.vars).eclipse;
    lut->setTimeSlices(4);
    lut->setFieldPieces(3);  // the field's table in 3 runs of its own before the first band
    const UtcInstant t0 = UtcInstant::parse(kTotality);
    auto at = [&](double seconds) {
        const JulianDate jd = t0.plusSeconds(seconds).julianDate();
        ecl.vars.set(keys::timeJdUtc, glm::dvec2(jd.day, jd.fraction));
        astro::updateSkyVars(ecl.vars);
        ecl.img = ecl.r.render(ecl.sky, ecl.cam);
    };
    const uint32_t id0 = ecl.vars.get(skykeys::eclipseViewLut).id;
    const int n0 = lut->rebuilds();
    // The shadow moves ~0.5-1 km/s over Spain: 0.1 s, below kEclipseRebuildMeters (2 km) now and
    // by the time a rebuild could be shown (3 field runs and 4 bands ahead: ~0.5 km).
    at(0.1);
    CHECK(lut->rebuilds() == n0);
    CHECK(lut->fieldRuns() == 0);
    const int f0 = lut->fieldRuns();
    at(4.0);  // > 2 km: a rebuild starts with the field's table, a third of it per frame, no band yet
    CHECK(lut->fieldRuns() == f0 + 1);
    CHECK(lut->buildingField());
    CHECK(lut->rebuilds() == n0);
    at(4.0);
    at(4.0);  // the field's third piece: finished, still no band
    CHECK(lut->fieldRuns() == f0 + 3);
    CHECK_FALSE(lut->buildingField());
    CHECK(lut->rebuilds() == n0);
    at(4.0);  // then one band per frame; the old table stays shown
    CHECK(lut->rebuilds() == n0 + 1);
    CHECK(lut->fieldRuns() == f0 + 3);
    CHECK(ecl.vars.get(skykeys::eclipseViewLut).id == id0);
    for (int i = 0; i < 3; ++i) at(4.0);
    CHECK(lut->rebuilds() == n0 + 4);
    CHECK(ecl.vars.get(skykeys::eclipseViewLut).id == id0);  // the 4th band rendered, not yet shown
    at(4.0);
    CHECK(lut->rebuilds() == n0 + 4);                        // no band in the swap's frame
    CHECK(ecl.vars.get(skykeys::eclipseViewLut).id != id0);  // the frame after the 4th band: the new table shown
    const int n1 = lut->rebuilds();
    at(300.0);  // a jump (> kEclipseJumpMeters): the whole table at once, shown at once
    CHECK(lut->rebuilds() == n1 + 1);
    CHECK(lut->msTable().n > 0);
}

TEST_CASE("Eclipse sky: the multiple-scattering axis weight and its forward share", "[cpu][eclipse]") {
    // The weight (atmosphere.shared.glsl's atm_eclMsAxisWeight, run by cpu::eclipseMsAxisWeight):
    // w = 1 - F (1 - sin(angle to the Sun)), F = min(1, forward x aerosol share / 0.16). The shared
    // text writes 0.16 as a literal: here it must agree with kEclipseForwardShare, and F must clamp.
    const SkyModel m = SkyModel::earthClear();
    const double sM = m.scatteringMie(0.0).g, sR = m.scatteringRayleigh(0.0).g;
    const double share = sM / (sM + sR);  // the aerosol's share of the scattering at the ground
    const double atOne = cpu::kEclipseForwardShare / share;  // the forward fraction that makes F = 1
    // Across the axis (nu = 0: sin = 1) the weight is 1 whatever F.
    CHECK(cpu::eclipseMsAxisWeight(m, 0.5 * atOne, 0.0) == Approx(1.0).margin(1e-12));
    // Along the axis (nu = 1): w = 1 - F exactly (rounding only, 1e-12).
    CHECK(cpu::eclipseMsAxisWeight(m, atOne, 1.0) == Approx(0.0).margin(1e-12));
    CHECK(cpu::eclipseMsAxisWeight(m, 0.5 * atOne, 1.0) == Approx(0.5).margin(1e-12));
    CHECK(cpu::eclipseMsAxisWeight(m, 3.0 * atOne, 1.0) == Approx(0.0).margin(1e-12));  // F clamped to 1
    // 60 deg from the Sun: sin = 0.866, w = 1 - 0.5 (1 - 0.866) = 0.933.
    CHECK(cpu::eclipseMsAxisWeight(m, 0.5 * atOne, 0.5) == Approx(1.0 - 0.5 * (1.0 - std::sqrt(0.75))).margin(1e-12));
}

TEST_CASE("Eclipse sky: the bands are sized to the frame, and tile the table", "[cpu][eclipse]") {
    // W x H = 384 x 108, the default quality's eclipse table. Large frames: the default 32 bands;
    // small ones: a band holds at most pixels / kEclipseBandPixelsPerTexel texels, up to 512 bands.
    CHECK(EclipseSkyLut::bandsFor(0, 384, 108) == kEclipseTimeSlices);
    CHECK(EclipseSkyLut::bandsFor(1280 * 720, 384, 108) == kEclipseTimeSlices);
    const int n320 = EclipseSkyLut::bandsFor(320 * 180, 384, 108);
    CHECK(n320 > kEclipseTimeSlices);
    CHECK(384.0 * 108.0 / n320 <= 320.0 * 180.0 / kEclipseBandPixelsPerTexel);
    CHECK(EclipseSkyLut::bandsFor(160 * 90, 384, 108) == kEclipseMaxTimeSlices);
    CHECK(EclipseSkyLut::bandsFor(1, 384, 108) == kEclipseMaxTimeSlices);
}

TEST_CASE("Eclipse sky: a small frame's rebuild in thin bands covers the table once", "[gl][eclipse]") {
    EclipseRig ecl(kTotality, true, 32, 16);
    REQUIRE(ecl.sky.eclipsed());
    std::shared_ptr<EclipseSkyLut> lut = SkyLuts::obtain(ecl.vars).eclipse;
    lut->setFramePixels(160 * 90);
    const UtcInstant t0 = UtcInstant::parse(kTotality);
    auto at = [&](double seconds) {
        const JulianDate jd = t0.plusSeconds(seconds).julianDate();
        ecl.vars.set(keys::timeJdUtc, glm::dvec2(jd.day, jd.fraction));
        astro::updateSkyVars(ecl.vars);
        ecl.img = ecl.r.render(ecl.sky, ecl.cam);
    };
    const uint32_t id0 = ecl.vars.get(skykeys::eclipseViewLut).id;
    const int n0 = lut->rebuilds(), f0 = lut->fieldRuns();
    at(4.0);  // > 2 km: a rebuild starts
    const int W = lut->smoothTexture().width(), H = lut->smoothTexture().height();
    const int bands = lut->bandsPerRebuild();
    CHECK(bands == EclipseSkyLut::bandsFor(160 * 90, W, H));
    int frames = 1;
    while (ecl.vars.get(skykeys::eclipseViewLut).id == id0 && frames < 2000) {
        at(4.0);
        ++frames;
    }
    // Work counted: every band rendered once, the last frame swapping without a band; the bands
    // tile the table exactly (their texels sum to W x H) and none exceeds the frame's budget
    // (rounding: one row of a tile more).
    const int done = lut->rebuilds() - n0;
    INFO(bands << " bands asked, " << done << " rendered in " << frames << " frames, largest " << lut->largestBandTexels() << " texels");
    CHECK(done >= bands);
    CHECK(done <= bands + W);  // whole tiles of columns per row band
    // The field's table first, in runs of its own (kEclipseFieldPixels: 24 at 160 x 90), then the
    // bands, then the swap.
    CHECK(lut->fieldPiecesPerRebuild() == EclipseSkyLut::fieldPiecesFor(160 * 90));
    CHECK(lut->fieldPiecesPerRebuild() == 24);
    CHECK(EclipseSkyLut::fieldPiecesFor(320 * 180) == 6);
    CHECK(EclipseSkyLut::fieldPiecesFor(1280 * 720) == 1);
    // (The builder's units make the field take a few runs fewer than asked: a quarter at most, the
    // test of the builder below.)
    const int pieces = lut->fieldPiecesPerRebuild(), fieldRuns = lut->fieldRuns() - f0;
    CHECK(fieldRuns >= pieces - pieces / 4);
    CHECK(fieldRuns <= pieces + 1);
    CHECK(frames == fieldRuns + done + 1);
    CHECK(lut->lastRebuildTexels() == long(W) * long(H));
    CHECK(lut->largestBandTexels() <= long(std::ceil(double(W) * H / bands)) + W);
}

TEST_CASE("Eclipse sky: the field's table built in pieces is the whole build's, bit for bit", "[cpu][eclipse]") {
    // EclipseSkyLut spreads the multiple-scattering field over frames (cpu::EclipseMsTableBuilder);
    // the model's results must not change: the same arithmetic in the same order, so equality is
    // exact, not within a tolerance. At totality over Burgos, and in the 99 % phase (the crescent's
    // penumbra, no umbra).
    const char* instant = GENERATE("2026-08-12T18:29:00Z", "2026-08-12T18:27:15Z");
    INFO(instant);
    const SkyVars v = test::astronomyAt(instant, kLat, kLon);
    const cpu::EclipseGeometry g = geometryOf(v);
    const double L = cpu::eclipseMsLength(g);
    const cpu::EclipseMsTable whole = cpu::eclipseMsTable(g, L);
    for (int pieces : {2, 3, 7, 12, kEclipseMaxFieldPieces}) {
        cpu::EclipseMsTableBuilder b(g, L);
        const double share = b.totalWork() / pieces;
        int runs = 0;
        double largest = 0.0;
        while (!b.finished()) {
            const double before = b.workDone();
            b.advance(share);
            largest = std::max(largest, b.workDone() - before);
            ++runs;
        }
        const cpu::EclipseMsTable t = b.take();
        INFO(pieces << " pieces: " << runs << " runs, the largest " << largest / b.totalWork() << " of the work");
        CHECK(t.n == whole.n);
        CHECK(t.halfExtentMeters == whole.halfExtentMeters);
        CHECK(t.e1 == whole.e1);
        CHECK(t.e2 == whole.e2);
        CHECK(t.centre == whole.centre);
        CHECK(t.d == whole.d);  // exact
        // The work is cut where asked: about as many runs as pieces (a unit's granularity, at most
        // ~4 % of the table, makes a run overshoot its share: a quarter fewer runs at most, or one
        // more), none more than one unit above its share.
        CHECK(runs >= pieces - pieces / 4);
        CHECK(runs <= pieces + 1);
        CHECK(largest <= share + 0.05 * b.totalWork());
    }
    // The D is not trivially zero (the test would pass on an empty table): measured 0.26 at
    // totality, 0.0011 at 99 %.
    CHECK(*std::max_element(whole.d.begin(), whole.d.end()) > 5e-4);
}

TEST_CASE("Eclipse sky: while time runs the table is built for where the shadow will be when shown", "[gl][eclipse]") {
    // The clock running 4 s a frame (240x real time at 60 frames/s: the shadow moves ~3-4 km a
    // frame), 3 field runs and 4 bands: a rebuild is shown 7 frames after it starts and rebuilds
    // follow back to back (a cycle of 8 frames). Without the prediction the table shown lags the
    // shadow by 7 to 15 frames' motion; with it, it is built for the middle of the 8 frames it is
    // shown in: 4 frames' motion ahead at the swap to 4 behind before the next (and the Moon's
    // curvature over those 32 s, < 0.1 km). Measured over 24 frames after the first swap.
    auto offsets = [](bool predict) {
        EclipseRig ecl(kTotality, true, 32, 16);
        REQUIRE(ecl.sky.eclipsed());
        std::shared_ptr<EclipseSkyLut> lut = SkyLuts::obtain(ecl.vars).eclipse;
        lut->setTimeSlices(4);
        lut->setFieldPieces(3);
        lut->setPredict(predict);
        const UtcInstant t0 = UtcInstant::parse(kTotality);
        double clock = 0.0;
        auto frame = [&] {
            clock += 4.0;
            const JulianDate jd = t0.plusSeconds(clock).julianDate();
            ecl.vars.set(keys::timeJdUtc, glm::dvec2(jd.day, jd.fraction));
            astro::updateSkyVars(ecl.vars);
            ecl.img = ecl.r.render(ecl.sky, ecl.cam);
        };
        const uint32_t id0 = ecl.vars.get(skykeys::eclipseViewLut).id;
        int i = 0;
        while (ecl.vars.get(skykeys::eclipseViewLut).id == id0 && i++ < 40) frame();
        REQUIRE(ecl.vars.get(skykeys::eclipseViewLut).id != id0);
        std::vector<double> o;
        for (int k = 0; k < 24; ++k) {
            o.push_back(lut->shownOffsetMeters());
            frame();
        }
        return o;
    };
    const std::vector<double> pred = offsets(true), lag = offsets(false);
    const double maxPred = *std::max_element(pred.begin(), pred.end()), maxLag = *std::max_element(lag.begin(), lag.end());
    const double minLag = *std::min_element(lag.begin(), lag.end());
    INFO("the table shown against the shadow: predicted, largest " << maxPred << " m; not predicted " << minLag << " to " << maxLag << " m");
    // Not predicted: never nearer than the 7 frames of a rebuild's motion (> 15 km at 3-4 km a frame).
    CHECK(minLag > 15e3);
    // Predicted: at most ~4 frames' motion (of the 15 without), a third of the lag's worst.
    CHECK(maxPred < 0.4 * maxLag);
}
