// The sky's LUT generators: each GPU pass against its CPU double-precision twin (same math, same
// parameterisation, same bilinear lookups), on tiny LUTs (llvmpipe). The twins are themselves
// checked against physics in test_sky_element.cpp and test_stability.cpp.
#include <catch2/catch.hpp>

#include "gl_test_context.hpp"
#include "lut_readback.hpp"

#include <epoxy/gl.h>

#include <welkin/generators/atmosphere.hpp>
#include <welkin/generators/sky_luts.hpp>
#include <welkin/keys.hpp>

#include <cmath>
#include <cstdio>

using namespace welkin;
using namespace welkin::generators;

namespace {
constexpr double kDeg = M_PI / 180;

using test::readLut;
using test::relErr;

struct Rig {
    SkyVars vars = [] {
        SkyVars v = SkyVars::earth();
        v.set(generators::skykeys::aerialVolume, true);  // these tests look at the aerial volume too
        return v;
    }();
    SkyLuts luts;
    SkyQuality q = SkyQuality::tiny();
    SkyModel m;
    explicit Rig(double sunAltDeg, double h = 0.0, int shIterations = 0, int shBands = 4) {
        q.shIterations = shIterations;
        q.shBands = shBands;
        test::glContext();
        vars.set(atmosphere::kAtmosphere, std::make_shared<const atmosphere::Atmosphere>(atmosphere::Atmosphere::earthClear()));
        vars.set(keys::sunDirection, directionFromAzAlt(1.0, sunAltDeg * kDeg));
        vars.set(keys::moonDirection, directionFromAzAlt(4.0, 30 * kDeg));
        vars.set(keys::observerHeight, h);
        m = SkyModel::fromVars(vars);
        vars.set(lightkeys::sunIlluminance, m.solarIlluminance);
        vars.set(lightkeys::moonIlluminance, m.solarIlluminance * 2e-6);
        luts = SkyLuts::obtain(vars);
        for (SkyGenerator* g : {(SkyGenerator*)luts.transmittance.get(), (SkyGenerator*)luts.multiScattering.get(), (SkyGenerator*)luts.sh.get(),
                                (SkyGenerator*)luts.sunView.get(), (SkyGenerator*)luts.moonView.get(),
                                (SkyGenerator*)luts.aerial.get(), (SkyGenerator*)luts.irradiance.get()})
            g->setFixedQuality(q);
    }
    void runAll() {
        const Logger& log = test::testLogger();
        luts.lightZenith->runIfDue(vars, log);  // the lights' cos zenith, read by the sky views
        luts.transmittance->runIfDue(vars, log);
        luts.multiScattering->runIfDue(vars, log);
        luts.sh->runIfDue(vars, log);
        luts.sunView->runIfDue(vars, log);
        luts.moonView->runIfDue(vars, log);
        luts.aerial->runIfDue(vars, log);
        luts.irradiance->runIfDue(vars, log);
        gl::checkError("sky LUT test");
    }
    ~Rig() { luts.releaseGl(); }
};
}  // namespace

TEST_CASE("Sky LUTs: GPU passes match their CPU double twins", "[gl][sky]") {
    const double h = 500.0;  // above the ground, so that rays below the horizon have a path too
    // The forms of the directional field: one SH pass, l <= 4 (low, medium), two passes with
    // l <= 4, and two with l <= 6 (high, reference).
    const auto [shIterations, shBands] = GENERATE(std::pair{0, 4}, std::pair{1, 4}, std::pair{0, 6}, std::pair{1, 6});
    INFO("SkyQuality::shIterations " << shIterations << ", shBands " << shBands);
    Rig rig(20.0, h, shIterations, shBands);
    rig.runAll();
    const SkyModel& m = rig.m;
    const SkyQuality& q = rig.q;

    // Transmittance: float optical depth of up to ~40 accumulated in 24 steps; 1e-3 relative on
    // the transmittance (optical depths agree to ~1e-4 absolute in float) plus 1e-6 absolute
    // where it underflows towards 0 along rays grazing the ground.
    Lut2D Tcpu = cpu::transmittanceLut(m, q);
    Lut2D Tgpu = readLut(rig.luts.transmittance->texture());
    REQUIRE(Tgpu.width == q.transmittanceW);
    double worstT = 0;
    for (size_t i = 0; i < Tcpu.texels.size(); ++i) worstT = std::max(worstT, relErr(Tgpu.texels[i], Tcpu.texels[i], 1e-6 / 1e-3));
    INFO("worst transmittance relative error " << worstT);
    CHECK(worstT < 1e-3);

    // Multiple scattering: sums of ~16 x 8 float terms through the same LUT lookups; 3e-3
    // (llvmpipe: 1.1e-3; an NVIDIA H100, driver 580, 2.2e-3 with its own exp/log approximations
    // and fused multiply-adds in the float sums).
    cpu::MsField MScpu = cpu::msField(m, q, Tcpu);
    Lut2D MSgpu = readLut(rig.luts.multiScattering->texture());
    double worstMS = 0;
    for (size_t i = 0; i < MScpu.psi.texels.size(); ++i) worstMS = std::max(worstMS, relErr(MSgpu.texels[i], MScpu.psi.texels[i], 1e-9));
    INFO("worst multiple-scattering relative error " << worstMS);
    CHECK(worstMS < 3e-3);

    // Directional multiple scattering (SH l <= L: 15 or 28 layers): each coefficient against the
    // twin, relative to the layer's largest magnitude: 5e-3 (the l = 2 layers are sums of terms of
    // both signs that cancel to ~1/10 of their parts, so float rounding is amplified ~10x).
    {
        const int nc = cpu::shCoefficients(q.shBands);
        REQUIRE(int(MScpu.sh.size()) == nc);
        const int layers = nc + 1;  // + the ground-irradiance layer
        REQUIRE(rig.luts.sh->texture().depth() == layers);
        std::vector<float> px(size_t(q.multiScatteringMuS) * q.multiScatteringSize * layers * 4);
        glGetTextureImage(rig.luts.sh->texture().id(), 0, GL_RGBA, GL_FLOAT, GLsizei(px.size() * sizeof(float)), px.data());
        const size_t layer = size_t(q.multiScatteringMuS) * q.multiScatteringSize;
        for (int k = 0; k < nc; ++k) {
            double big = 0, worst = 0;
            for (auto& t : MScpu.sh[k].texels) big = std::max(big, std::abs(t.g));
            for (size_t i = 0; i < layer; ++i) {
                glm::dvec3 g(px[(k * layer + i) * 4], px[(k * layer + i) * 4 + 1], px[(k * layer + i) * 4 + 2]);
                worst = std::max(worst, glm::length(g - MScpu.sh[k].texels[i]) / big);
            }
            INFO("SH layer " << k << ": worst error " << worst << " of the layer's largest " << big);
            CHECK(big > 0.0);
            CHECK(worst < 5e-3);
        }
        // Last layer, row 0: the sky's irradiance on the ground over mu_s, relative per texel where
        // it exceeds 1e-4 of its largest (deep below the horizon it falls by decades): 2e-3.
        double big = 0, worst = 0;
        for (auto& t : MScpu.ground.texels) big = std::max(big, t.g);
        for (int i = 0; i < q.multiScatteringMuS; ++i) {
            const size_t at = (size_t(nc) * layer + i) * 4;
            glm::dvec3 g(px[at], px[at + 1], px[at + 2]);
            if (MScpu.ground.texels[i].g > 1e-4 * big) worst = std::max(worst, relErr(g, MScpu.ground.texels[i], 1e-9));
        }
        INFO("ground irradiance layer: worst relative error " << worst << "; largest " << big);
        CHECK(big > 0.0);
        CHECK(worst < 2e-3);
    }

    // Sky view (Sun at 20 deg, observer at 500 m): every texel, both textures; 3e-3 relative
    // (float march of 12 steps, LUT lookups at float texture coordinates) over a floor of 1e-3 of
    // the LUT's largest value (the nearly-black ground rows seen against the Sun).
    Lut2D Scpu{q.skyViewW, q.skyViewH, {}}, Mcpu{q.skyViewW, q.skyViewH, {}};
    Scpu.texels.resize(size_t(q.skyViewW) * q.skyViewH);
    Mcpu.texels = Scpu.texels;
    double muS = std::sin(20 * kDeg);
    for (int y = 0; y < q.skyViewH; ++y)
        for (int x = 0; x < q.skyViewW; ++x) {
            auto t = cpu::skyViewTexel(m, q, Tcpu, MScpu, h, muS, {(x + 0.5) / q.skyViewW, (y + 0.5) / q.skyViewH},
                                       m.sunAngularRadius);
            Scpu.at(x, y) = t.smooth;
            Mcpu.at(x, y) = t.mie;
        }
    Lut2D Sgpu = readLut(rig.luts.sunView->smoothTexture(), 1.0 / kLutScale);
    Lut2D Mgpu = readLut(rig.luts.sunView->mieTexture(), 1.0 / kLutScale);
    double maxS = 0, maxM = 0;
    for (auto& t : Scpu.texels) maxS = std::max(maxS, t.g);
    for (auto& t : Mcpu.texels) maxM = std::max(maxM, t.g);
    double worstS = 0, worstM = 0;
    for (size_t i = 0; i < Scpu.texels.size(); ++i) {
        worstS = std::max(worstS, relErr(Sgpu.texels[i], Scpu.texels[i], 1e-3 * maxS));
        worstM = std::max(worstM, relErr(Mgpu.texels[i], Mcpu.texels[i], 1e-3 * maxM));
    }
    INFO("worst sky-view relative errors " << worstS << " (smooth), " << worstM << " (Mie)");
    CHECK(worstS < 3e-3);
    CHECK(worstM < 3e-3);
    // The total texture: smooth + Mie x phase at the texel's own angle to the Sun (baked-phase
    // presets). The Sun's vertical plane is at azimuth 0 of the parameterisation.
    {
        Lut2D Tgpu = readLut(rig.luts.sunView->totalTexture(), 1.0 / kLutScale);
        Lut2D want{q.skyViewW, q.skyViewH, Scpu.texels};
        double worstT = 0, maxT = 0;
        for (int y = 0; y < q.skyViewH; ++y)
            for (int x = 0; x < q.skyViewW; ++x) {
                glm::dvec2 ma = skyViewMuAz(m, h, {(x + 0.5) / q.skyViewW, (y + 0.5) / q.skyViewH}, q.skyViewW, q.skyViewH);
                double sinV = std::sqrt(std::max(1.0 - ma.x * ma.x, 0.0)), sinS = std::sqrt(1.0 - muS * muS);
                double nu = std::clamp(sinV * sinS * std::cos(ma.y) + ma.x * muS, -1.0, 1.0);
                want.at(x, y) += Mcpu.at(x, y) * miePhase(nu, m.mieG, m.miePhase);
                maxT = std::max(maxT, want.at(x, y).g);
            }
        for (size_t i = 0; i < want.texels.size(); ++i) worstT = std::max(worstT, relErr(Tgpu.texels[i], want.texels[i], 1e-3 * maxT));
        INFO("worst total-texture relative error " << worstT);
        CHECK(maxT > maxS);  // the aureole adds to the smooth part
        CHECK(worstT < 3e-3);
    }

    // Aerial perspective: sample texels (directions above and below the horizon, near and far
    // slices); same tolerance reasoning as the sky view.
    std::vector<float> inAll = rig.luts.aerial->inscatter().readRgbaFloat();
    std::vector<float> trAll = rig.luts.aerial->transmittance().readRgbaFloat();
    const int n = q.aerialSize;
    for (auto [i, j, k] : {std::tuple{1, 1, 0}, {3, 6, 3}, {6, 2, 7}, {0, 7, 5}, {7, 4, 1}}) {
        auto c = cpu::aerialTexel(m, q, Tcpu, MScpu, h, muS, i, j, k);
        size_t idx = (size_t(k) * n * n + size_t(j) * n + i) * 4;
        glm::dvec3 gin(inAll[idx], inAll[idx + 1], inAll[idx + 2]), gtr(trAll[idx], trAll[idx + 1], trAll[idx + 2]);
        INFO("aerial texel " << i << "," << j << "," << k << ": gpu " << gin.g / kLutScale << " cpu " << c.inscatter.g);
        CHECK(c.inscatter.g > 0.0);  // in-scattering along any non-empty segment
        CHECK(c.transmittance.g < 1.0);
        CHECK(relErr(gin / kLutScale, c.inscatter, 1e-12) < 3e-3);
        CHECK(relErr(gtr, c.transmittance, 1e-6) < 1e-3);
    }

    // Irradiance: the GPU hemisphere quadrature over the GPU sky-view LUT against the same
    // quadrature over the CPU LUT; 3e-3 (the LUTs agree to that).
    glm::dvec3 E = m.solarIlluminance;
    glm::dvec3 sunDir = directionFromAzAlt(1.0, 20 * kDeg);
    glm::dvec3 cpuDiffuse = cpuDiffuseIrradiance(m, q, h, muS, [&](double mu, double az, double nu) {
        return cpu::skyViewSample(m, Scpu, Mcpu, h, mu, az, nu);
    }) * E;
    glm::dvec3 gpuDiffuse = rig.luts.irradiance->sunDiffuse();
    INFO("diffuse " << gpuDiffuse.g << " vs " << cpuDiffuse.g);
    CHECK(relErr(gpuDiffuse, cpuDiffuse, 1e-9) < 3e-3);
    // The same quadrature (atmosphere.shared.glsl's atm_irradianceSample(), atm_cosViewLight(),
    // atm_irradianceWeight(): one text for the pass and cpuDiffuseIrradiance()) summed in double over
    // the GPU's own sky-view LUT: what differs is the order of the sum (the pass's 64 x
    // SKY_IRRADIANCE_GROUPS strided partial sums in float, added on the CPU), float arithmetic and
    // the texture unit's bilinear weights.
    const glm::dvec3 sameLut = cpuDiffuseIrradiance(m, q, h, muS, [&](double mu, double az, double nu) {
        return cpu::skyViewSample(m, Sgpu, Mgpu, h, mu, az, nu);
    }) * E;
    std::printf("\nsky irradiance (green): pass %.9g lux, double sum over the pass's LUT %.9g (relative %.3g), over the CPU's LUT %.9g\n",
                gpuDiffuse.g, sameLut.g, relErr(gpuDiffuse, sameLut, 1e-9), cpuDiffuse.g);
    // Measured 2.4e-6 to 2.8e-6 (2026-11-27, llvmpipe): 3e-5 leaves 10x for another GPU's float
    // order and filter weights; a sample or weight not shared would be off by far more (the
    // half-texel shift of a sample moves the sum by ~1e-3).
    CHECK(relErr(gpuDiffuse, sameLut, 1e-9) < 3e-5);
    // Direct: E T mu_s with T from the LUT.
    glm::dvec3 hv = rig.vars.get(skykeys::horizontalIlluminance);
    glm::dvec3 direct = cpu::transmittanceToLight(m, Tcpu, h, sunDir.z, m.sunAngularRadius) * sunDir.z * E;
    double Yd = 0.2126 * direct.r + 0.7152 * direct.g + 0.0722 * direct.b;
    CHECK(hv.y == Approx(Yd + 0.0).epsilon(2e-3).margin(0.1));  // + the Moon's direct (Moon at 30 deg, 2e-6 of the Sun)
}

TEST_CASE("Sky LUTs: generators run only when their inputs change", "[gl][sky]") {
    Rig rig(30.0);
    rig.runAll();
    int t = rig.luts.transmittance->runCount(), v = rig.luts.sunView->runCount();
    rig.runAll();
    CHECK(rig.luts.transmittance->runCount() == t);
    CHECK(rig.luts.sunView->runCount() == v);
    rig.vars.set(keys::sunDirection, directionFromAzAlt(1.0, 31 * kDeg));  // the Sun moved
    rig.runAll();
    CHECK(rig.luts.transmittance->runCount() == t);      // atmosphere unchanged
    CHECK(rig.luts.multiScattering->runCount() == 1);
    CHECK(rig.luts.sunView->runCount() == v + 1);
    rig.vars.set(atmosphere::kAtmosphere,
                 std::make_shared<const atmosphere::Atmosphere>(atmosphere::Atmosphere::earthHazy()));
    rig.runAll();
    CHECK(rig.luts.transmittance->runCount() == t + 1);
    CHECK(rig.luts.multiScattering->runCount() == 2);
}

TEST_CASE("Sky SH basis: orthonormal to l = 6, and the closed forms", "[cpu][sky]") {
    // Closed forms of the real SH (no Condon-Shortley phase; standard tables) against the
    // recurrence in cpu::shBasis(): to 1e-6 (the tables' constants have 6-7 digits).
    for (auto [x, z] : {std::pair{0.3, 0.5}, {-0.7, 0.1}, {0.0, -0.9}, {0.6, 0.8}}) {
        const double y2 = 1 - x * x - z * z, z2 = z * z;
        const auto Y = cpu::shBasis(x, z);
        const std::pair<int, double> closed[] = {
            {0, 0.282095},
            {2, 0.488603 * x},
            {4, 1.092548 * x * z},
            {5, 0.546274 * (x * x - y2)},
            {9, 0.590044 * x * (x * x - 3 * y2)},
            {10, 0.105786 * (35 * z2 * z2 - 30 * z2 + 3)},
            {14, 0.625836 * (x * x * x * x - 6 * x * x * y2 + y2 * y2)},
            {15, 0.116950 * z * (63 * z2 * z2 - 70 * z2 + 15)},
            {21, 0.063569 * (231 * z2 * z2 * z2 - 315 * z2 * z2 + 105 * z2 - 5)},
            {27, 0.683184 * (std::pow(x, 6) - 15 * std::pow(x, 4) * y2 + 15 * x * x * y2 * y2 - y2 * y2 * y2)},
        };
        for (auto [k, v] : closed) {
            INFO("x " << x << " z " << z << " coefficient " << k);
            CHECK(Y[size_t(k)] == Approx(v).margin(2e-6).epsilon(2e-6));
        }
    }
    // Orthonormality over the sphere: the products are polynomials of degree <= 12 in z times
    // trigonometric polynomials of degree <= 12 in phi. 32 equally spaced phi integrate the latter
    // exactly; the midpoint rule in z errs as 1/nz^2 (5.7e-4 with 400 cells, so ~6e-6 with 4000).
    const int nz = 4000, nphi = 32;
    std::array<std::array<double, cpu::kShMaxCoefficients>, cpu::kShMaxCoefficients> gram{};
    for (int i = 0; i < nz; ++i) {
        double z = -1 + 2 * (i + 0.5) / nz, s = std::sqrt(1 - z * z);
        for (int j = 0; j < nphi; ++j) {
            double phi = 2 * M_PI * (j + 0.5) / nphi;
            auto Y = cpu::shBasis(s * std::cos(phi), z);
            for (int a = 0; a < cpu::kShMaxCoefficients; ++a)
                for (int b = 0; b <= a; ++b) gram[size_t(a)][size_t(b)] += Y[size_t(a)] * Y[size_t(b)];
        }
    }
    const double w = 4 * M_PI / (double(nz) * nphi);
    double worst = 0;
    for (int a = 0; a < cpu::kShMaxCoefficients; ++a)
        for (int b = 0; b <= a; ++b) worst = std::max(worst, std::abs(gram[size_t(a)][size_t(b)] * w - (a == b ? 1.0 : 0.0)));
    INFO("worst Gram-matrix deviation from the identity " << worst);
    CHECK(worst < 2e-5);
}
