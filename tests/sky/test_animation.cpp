// The sky while time runs: the Sun-dependent tables depend on the Sun's elevation only, are built
// as keyframes over several frames (double-buffered) and blended (light_keyframes.hpp).
#include <catch2/catch.hpp>

#include "gl_test_context.hpp"

#include <welkin/generators/atmosphere.hpp>
#include <welkin/generators/light_keyframes.hpp>
#include <welkin/generators/sky_luts.hpp>
#include <welkin/keys.hpp>

#include <epoxy/gl.h>

#include <algorithm>
#include <cmath>
#include <map>

using namespace welkin;
using namespace welkin::generators;

namespace {
constexpr double kDeg = M_PI / 180;

// Which chunks of which slot the plans have built so far (slot -> chunks, -1 when restarted).
struct BuildLog {
    std::map<int, int> built;
    std::map<int, double> muS;
    void apply(const LightKeyframes::Plan& p) {
        if (p.build < 0) return;
        if (p.chunkBegin == 0) built[p.build] = 0;
        REQUIRE(built[p.build] == p.chunkBegin);  // chunks in order, none skipped
        built[p.build] = p.chunkEnd;
        muS[p.build] = p.buildMuS;
    }
};
}  // namespace

TEST_CASE("LightKeyframes: only complete tables are shown, bracketing the light", "[cpu][sky]") {
    const LightKeyframes::Options o{.stepRad = 1 * kDeg, .chunks = 4, .slots = 4, .stillMuS = 2e-5};
    LightKeyframes kf(o);
    BuildLog log;
    // First run: a table at exactly the light's elevation, built whole.
    auto p = kf.plan(std::sin(10 * kDeg));
    log.apply(p);
    CHECK(p.exact);
    CHECK(p.b < 0);
    CHECK(p.chunkEnd - p.chunkBegin == 4);
    // The Sun sets at 0.1 deg per run from 10 deg to -5 deg, then rises again.
    int blended = 0, extrapolated = 0;
    for (int i = 1; i <= 300; ++i) {
        double e = (i <= 150 ? 10.0 - 0.1 * i : -5.0 + 0.1 * (i - 150)) * kDeg;
        p = kf.plan(std::sin(e));
        log.apply(p);
        INFO("run " << i << " e " << e / kDeg);
        // Never a partially built table: every slot shown has all its chunks.
        REQUIRE(p.a >= 0);
        CHECK(log.built[p.a] == 4);
        if (p.b >= 0) {
            CHECK(log.built[p.b] == 4);
            double ea = std::asin(log.muS[p.a]), eb = std::asin(log.muS[p.b]);
            // The mix reproduces the light's elevation (interpolated or extrapolated).
            CHECK(ea + p.t * (eb - ea) == Approx(e).margin(1e-9));
            CHECK(std::abs(eb - ea) <= 2.5 * o.stepRad + 1e-12);
            if (p.t >= 0 && p.t <= 1) ++blended;
        }
        if (!p.exact && !(p.b >= 0 && p.t >= 0 && p.t <= 1)) ++extrapolated;
    }
    // At 0.1 deg per run and 1 deg steps of 4 chunks the builder keeps ahead: the light stays
    // bracketed but for the first runs (the first grid tables) and after the turn (the slots
    // kept were those below it). Measured: 19 of 300.
    CHECK(blended > 250);
    CHECK(extrapolated <= 30);
    // The light stops: a table at exactly its elevation within `chunks` runs, then nothing to do.
    const double still = std::sin(10 * kDeg + 0.37 * kDeg);
    log.apply(kf.plan(std::sin(10 * kDeg + 0.3 * kDeg)));
    int runs = 0;
    do {
        p = kf.plan(still);
        log.apply(p);
        ++runs;
    } while (!p.exact && runs < 20);
    CHECK(runs <= 2 * 4);  // the build in progress (one chunk per run while still) finishes first
    CHECK(p.exact);
    CHECK(log.muS[p.a] == Approx(still).margin(1e-12));
    CHECK_FALSE(kf.pending());
    // A jump: no table within two steps: one built whole at once.
    p = kf.plan(std::sin(40 * kDeg));
    CHECK(p.exact);
    CHECK(p.chunkBegin == 0);
    CHECK(p.chunkEnd == 4);
    CHECK_THROWS_WITH(kf.plan(1.5), "LightKeyframes::plan(): cos zenith 1.5 not in [-1, 1]");
    CHECK_THROWS_AS(LightKeyframes({.stepRad = 0.0}), Error);
}

namespace {
struct AnimRig {
    SkyVars vars = SkyVars::earth();
    SkyLuts luts;
    SkyQuality q = SkyQuality::tiny();
    explicit AnimRig(double sunAltDeg, double stepDeg = 1.0, int chunks = 3) {
        test::glContext();
        q.keyframeStepRad = stepDeg * kDeg;
        q.keyframeChunks = chunks;
        vars.set(atmosphere::kAtmosphere, std::make_shared<const atmosphere::Atmosphere>(atmosphere::Atmosphere::earthClear()));
        setSun(1.0, sunAltDeg);
        vars.set(keys::moonDirection, directionFromAzAlt(4.0, -40 * kDeg));
        vars.set(keys::observerHeight, 0.0);
        const SkyModel m = SkyModel::fromVars(vars);
        vars.set(lightkeys::sunIlluminance, m.solarIlluminance);
        vars.set(lightkeys::moonIlluminance, glm::dvec3(0.0));
        luts = SkyLuts::obtain(vars);
        for (SkyGenerator* g : {(SkyGenerator*)luts.transmittance.get(), (SkyGenerator*)luts.multiScattering.get(),
                                (SkyGenerator*)luts.sh.get(), (SkyGenerator*)luts.sunView.get(), (SkyGenerator*)luts.moonView.get(),
                                (SkyGenerator*)luts.aerial.get(), (SkyGenerator*)luts.irradiance.get()})
            g->setFixedQuality(q);
    }
    void setSun(double azRad, double altDeg) { vars.set(keys::sunDirection, directionFromAzAlt(azRad, altDeg * kDeg)); }
    void runAll() {
        const Logger& log = test::testLogger();
        for (Generator* g : {(Generator*)luts.lightZenith.get(), (Generator*)luts.transmittance.get(), (Generator*)luts.multiScattering.get(),
                             (Generator*)luts.sh.get(), (Generator*)luts.sunView.get(), (Generator*)luts.moonView.get(),
                             (Generator*)luts.aerial.get(), (Generator*)luts.irradiance.get()})
            g->runIfDue(vars, log);
        gl::checkError("animation test");
    }
    ~AnimRig() { luts.releaseGl(); }
};

std::vector<float> pixels(const gl::Texture& t) { return t.readRgbaFloat(); }

// Worst relative difference of the RGB channels (floor: `floor` x the table's largest value).
double worstRel(const std::vector<float>& a, const std::vector<float>& b, double floorFrac = 1e-3) {
    float mx = 0;
    for (size_t i = 0; i < b.size(); ++i)
        if (i % 4 != 3) mx = std::max(mx, std::abs(b[i]));
    double w = 0;
    for (size_t i = 0; i < a.size(); ++i)
        if (i % 4 != 3) w = std::max(w, std::abs(double(a[i]) - b[i]) / (std::abs(b[i]) + floorFrac * mx));
    return w;
}
}  // namespace

TEST_CASE("Sky animation: a pure azimuth change rebuilds no Sun table; an elevation change does", "[gl][sky]") {
    AnimRig rig(20.0);
    rig.runAll();
    const int v = rig.luts.sunView->runCount(), a = rig.luts.aerial->runCount(), i = rig.luts.irradiance->runCount();
    const int t = rig.luts.transmittance->runCount(), s = rig.luts.sh->runCount();
    // The Sun swings 2 rad in azimuth at the same elevation: nothing Sun-dependent runs.
    rig.setSun(3.0, 20.0);
    rig.runAll();
    CHECK(rig.luts.sunView->runCount() == v);
    CHECK(rig.luts.aerial->runCount() == a);
    CHECK(rig.luts.irradiance->runCount() == i);
    // Within the tolerance (cos zenith 2e-5): nothing either.
    glm::dvec3 d = directionFromAzAlt(3.0, 20.0 * kDeg);
    double mu = d.z + 0.5 * kCosZenithTolerance, rho = std::sqrt(1 - mu * mu) / std::hypot(d.x, d.y);
    rig.vars.set(keys::sunDirection, glm::dvec3(d.x * rho, d.y * rho, mu));
    rig.runAll();
    CHECK(rig.luts.sunView->runCount() == v);
    // Beyond it: the sky view and the aerial perspective run (and the Sun-independent ones do not).
    rig.setSun(3.0, 20.3);
    rig.runAll();
    CHECK(rig.luts.sunView->runCount() == v + 1);
    CHECK(rig.luts.aerial->runCount() == a + 1);
    CHECK(rig.luts.irradiance->runCount() == i + 1);
    CHECK(rig.luts.transmittance->runCount() == t);
    CHECK(rig.luts.sh->runCount() == s);
}

TEST_CASE("Sky animation: keyframed tables against a fresh rebuild, and exact once the Sun stops", "[gl][sky]") {
    // The Sun sets from 6 deg to 2 deg at 0.1 deg per frame (keyframes every 1 deg, 3 chunks).
    AnimRig rig(6.0);
    AnimRig fresh(2.0, 1.0, 3);
    rig.runAll();
    const int v0 = rig.luts.sunView->runCount();
    for (int i = 1; i <= 40; ++i) {
        rig.setSun(1.0, 6.0 - 0.1 * i);
        rig.runAll();
        // Shown: a finite, non-negative table at every frame (never a half-built one, whose
        // rows would still hold another elevation or nothing).
        std::vector<float> px = pixels(rig.luts.sunView->totalTexture());
        bool ok = std::all_of(px.begin(), px.end(), [](float x) { return std::isfinite(x) && x >= 0; });
        REQUIRE(ok);
    }
    CHECK(rig.luts.sunView->runCount() == v0 + 40);
    fresh.runAll();
    // At 2.0 deg the grid has a table: shown as is, so it must equal the fresh one up to float
    // rounding of the blend pass (1e-5).
    {
        const auto& p = rig.luts.sunView->lastPlan();
        INFO("t " << p.t << " a " << p.a << " b " << p.b);
        double w = worstRel(pixels(rig.luts.sunView->smoothTexture()), pixels(fresh.luts.sunView->smoothTexture()));
        CHECK(w < 1e-3);
    }
    // Between grid points: 2.45 deg blended from the 2 and 3 deg tables, against a fresh table
    // at 2.45 deg. Measured worst texel 3.5 % (sky view) and 5.5 % (aerial volume), log-linear in
    // elevation over 1 deg near the horizon (tiny preset): 6 % and 10 % allow for another
    // driver's rounding.
    for (int i = 1; i <= 5; ++i) {
        rig.setSun(1.0, 2.0 + 0.09 * i);
        rig.runAll();
    }
    fresh.setSun(1.0, 2.45);
    fresh.luts.sunView->resetKeyframes();  // a table built at exactly 2.45 deg
    fresh.luts.aerial->resetKeyframes();
    fresh.runAll();
    const auto& p = rig.luts.sunView->lastPlan();
    REQUIRE(p.b >= 0);
    double wBlend = worstRel(pixels(rig.luts.sunView->smoothTexture()), pixels(fresh.luts.sunView->smoothTexture()));
    double wAerial = worstRel(pixels(rig.luts.aerial->inscatter()), pixels(fresh.luts.aerial->inscatter()));
    INFO("blend worst " << wBlend << ", aerial " << wAerial);
    CHECK(wBlend < 0.06);
    CHECK(wAerial < 0.10);
    // The Sun stops at 2.45 deg: within `chunks` (+ the one in progress) frames the shown tables
    // are built at exactly 2.45 deg and equal the fresh ones to float rounding.
    for (int i = 0; i < 8 && rig.luts.sunView->isDue(rig.vars); ++i) rig.runAll();
    CHECK_FALSE(rig.luts.sunView->isDue(rig.vars));
    CHECK(rig.luts.sunView->lastPlan().exact);
    CHECK(worstRel(pixels(rig.luts.sunView->totalTexture()), pixels(fresh.luts.sunView->totalTexture())) < 1e-4);
    CHECK(worstRel(pixels(rig.luts.aerial->inscatter()), pixels(fresh.luts.aerial->inscatter())) < 1e-4);
}
