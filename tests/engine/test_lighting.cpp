// SkyLighting (welkin/lighting.hpp): the SH irradiance against a brute-force double-precision
// projection of the same environment (an equirect rendered by the same processor), a uniform sky,
// the truncation error of nine coefficients (printed for docs/lighting.md), the specular cube's
// mip 0 against the sky's own cube-face render and its roughest mip against a brute-force GGX
// convolution, the axis lights against the exact cosine integral, the clouds and eclipses in the
// directional lights, and that nothing runs when nothing changed.
#include <catch2/catch.hpp>

#include "astronomy_at.hpp"
#include "elements_present.hpp"
#include "gl_test_context.hpp"
#include "uniform_field.hpp"

#include <epoxy/gl.h>

#include <welkin/astro/astro_keys.hpp>
#include <welkin/astro/bodies.hpp>
#include <welkin/color.hpp>
#include <welkin/elements/registry.hpp>
#include <welkin/generators/lights.hpp>
#include <welkin/generators/sky_luts.hpp>
#include <welkin/keys.hpp>
#include <welkin/lighting.hpp>
#include <welkin/processor.hpp>

#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdio>
#include <numbers>

using namespace welkin;

namespace {
constexpr double kPi = std::numbers::pi;
constexpr double kDeg = kPi / 180;

glm::dvec3 azAlt(double az, double alt) { return {std::cos(alt) * std::sin(az), std::cos(alt) * std::cos(az), std::sin(alt)}; }

// A processor with the Sky element only (no astronomy: the Sun where the test puts it, the Moon
// below the horizon), lighting on with small cube faces.
std::unique_ptr<SkyProcessor> skyAt(double sunAltRad, double sunAzRad = 180 * kDeg, int cubeSize = 32) {
    auto p = std::make_unique<SkyProcessor>(SkyVars::earth(), test::testLogger(), ProcessorOptions{.astronomy = false});
    p->add(elements::makeElement("sky"));
    p->vars().set(keys::sunDirection, azAlt(sunAzRad, sunAltRad));
    p->vars().set(keys::moonDirection, glm::dvec3(0, 0, -1));
    p->setLighting(LightingOptions{.cubeSize = cubeSize});
    p->setAnimationTime(0.0);
    return p;
}

// The environment as an equirect of the same processor, with each pixel's direction and exact
// solid angle.
struct Environment {
    std::vector<glm::dvec3> dir, L;
    std::vector<double> omega;
};
Environment equirect(SkyProcessor& p, int w, int h) {
    Camera cam;
    cam.projection = Projection::Equirect;
    cam.width = w;
    cam.height = h;
    p.setCamera(cam);
    p.renderFrame();
    const Image img = p.readHdr();
    Environment env;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const double alt0 = kPi / 2 - kPi * y / h, alt1 = kPi / 2 - kPi * (y + 1) / h;
            env.dir.push_back(*cam.directionAt({x + 0.5, y + 0.5}));
            env.omega.push_back(2 * kPi / w * (std::sin(alt0) - std::sin(alt1)));
            env.L.push_back({img.at(x, y, 0), img.at(x, y, 1), img.at(x, y, 2)});
        }
    return env;
}
std::array<glm::dvec3, 9> project(const Environment& env) {
    std::array<glm::dvec3, 9> c{};
    for (size_t i = 0; i < env.dir.size(); ++i) {
        const auto y = sh::basis(env.dir[i]);
        for (int k = 0; k < 9; ++k) c[size_t(k)] += env.L[i] * y[size_t(k)] * env.omega[i];
    }
    return c;
}
glm::dvec3 shIrradiance(const std::array<glm::dvec3, 9>& L, const glm::dvec3& n) {
    SkyLighting s;
    s.sh9Radiance = L;
    return s.irradiance(n);
}
glm::dvec3 exactIrradiance(const Environment& env, const glm::dvec3& n) {
    glm::dvec3 e(0.0);
    for (size_t i = 0; i < env.dir.size(); ++i) e += env.L[i] * std::max(glm::dot(n, env.dir[i]), 0.0) * env.omega[i];
    return e;
}

// One face of a cube texture's level, RGBA float, GL rows (row 0: t = -1).
std::vector<float> readFace(const TextureRef& t, int level, int face) {
    const int n = std::max(t.width >> level, 1);
    std::vector<float> px(size_t(n) * n * 4);
    glGetTextureSubImage(t.id, level, 0, 0, face, n, n, 1, GL_RGBA, GL_FLOAT, GLsizei(px.size() * sizeof(float)), px.data());
    return px;
}
Camera cubeCamera(int face, int n) {
    Camera c;
    c.projection = Projection::CubeFace;
    c.cubeFace = face;
    c.width = c.height = n;
    return c;
}
// Exact solid angle of texel (i, j) of a face of n texels (double precision).
double texelSolidAngle(int i, int j, int n) {
    auto A = [](double x, double y) { return std::atan2(x * y, std::sqrt(x * x + y * y + 1)); };
    const double x0 = 2.0 * i / n - 1, x1 = 2.0 * (i + 1) / n - 1, y0 = 2.0 * j / n - 1, y1 = 2.0 * (j + 1) / n - 1;
    return A(x0, y0) - A(x0, y1) - A(x1, y0) + A(x1, y1);
}
double relErr(const glm::dvec3& a, const glm::dvec3& b) { return std::abs(color::luminance(a) - color::luminance(b)) / std::max(color::luminance(b), 1e-30); }

const std::vector<std::pair<const char*, glm::dvec3>> kNormals = {
    {"up", {0, 0, 1}}, {"north", {0, 1, 0}}, {"east", {1, 0, 0}}, {"south", {0, -1, 0}}, {"west", {-1, 0, 0}}};
}  // namespace

TEST_CASE("SkyLighting: the SH irradiance equals a brute-force projection of the same sky; truncation measured", "[gl][lighting]") {
    test::glContext();
    std::printf("\nSH irradiance vs brute-force projection (equirect 256x128) and vs the exact cosine integral, Sun at azimuth 180 deg:\n");
    std::printf("| Sun altitude | normal | E exact (lx) | SH (code) vs projection | SH (9 coefficients) vs exact |\n|---|---|---|---|---|\n");
    for (double alt : {5.0, 30.0, 60.0}) {
        auto p = skyAt(alt * kDeg);
        const Environment env = equirect(*p, 256, 128);
        const SkyLighting& l = p->lighting();
        const auto reference = project(env);
        std::vector<std::pair<const char*, glm::dvec3>> normals = kNormals;
        normals.push_back({"down", {0, 0, -1}});  // the ground's light (the Sun in the south: "north" faces away from it)
        for (auto& [name, n] : normals) {
            const glm::dvec3 code = l.irradiance(n), bf = shIrradiance(reference, n), exact = exactIrradiance(env, n);
            const double e1 = relErr(code, bf), e2 = (color::luminance(code) - color::luminance(exact)) / color::luminance(exact);
            std::printf("| %.0f deg | %s | %.4g | %+.2f %% | %+.1f %% |\n", alt, name, color::luminance(exact), 100 * (color::luminance(code) - color::luminance(bf)) / color::luminance(bf),
                        100 * e2);
            INFO("Sun at " << alt << " deg, normal " << name);
            // 2 %: the capture (a 32-texel cube) and the equirect (256 x 128) sample the same sky at
            // different resolutions; the rest is float accumulation (1e-6).
            CHECK(e1 < 0.02);
            // The truncation of nine coefficients is the method's (Ramamoorthi & Hanrahan: a few %
            // on average): measured up to 12 % on the up and horizontal normals (facing away from
            // a Sun at 5 deg) and 54 % facing down at sunrise (a dark ground under a bright sky
            // band: the l <= 2 lobes spill the sky into the nadir); the bands are those, rounded
            // up by a third, so that the documented table (docs/lighting.md) stays true.
            CHECK(std::abs(e2) < (n.z < -0.5 ? 0.75 : 0.16));
        }
    }
}

TEST_CASE("SkyLighting: a uniform sky gives pi L on every normal, and its radiance in every specular mip", "[gl][lighting]") {
    test::glContext();
    const glm::vec3 L(100.0f, 200.0f, 50.0f);
    SkyProcessor p(SkyVars::earth(), test::testLogger(), ProcessorOptions{.astronomy = false});
    p.emplace<test::UniformField>(L);
    p.setLighting(LightingOptions{.cubeSize = 16, .specularMips = 4});
    Camera cam;
    cam.width = 32;
    cam.height = 16;
    p.setCamera(cam);
    p.renderFrame();
    const SkyLighting& l = p.lighting();
    for (auto& [name, n] : kNormals) {
        INFO(name);
        for (int c = 0; c < 3; ++c) CHECK(l.irradiance(n)[c] == Approx(kPi * L[c]).epsilon(0.01));  // 1 %: the target; float sums of 1536 texels
    }
    CHECK(l.irradiance({0, 0, -1}).g == Approx(kPi * L.g).epsilon(0.01));
    // The axis lights: each half of the light map's texels, L |d . axis| Omega summed: pi L up to
    // the centre-direction weighting of 22.5 x 11.25 deg texels (cos averaged over a texel vs at
    // its centre: < 1 %).
    for (int a = 0; a < 6; ++a) CHECK(l.axisLights[size_t(a)].g == Approx(kPi * L.g).epsilon(0.01));
    for (int m = 0; m < l.specularMips; ++m) {
        const std::vector<float> px = readFace(l.specularCube, m, m % 6);
        for (size_t i = 0; i < px.size(); i += 4) REQUIRE(px[i + 1] == Approx(L.g).epsilon(1e-4));  // weights normalised: float rounding only
    }
}

TEST_CASE("SkyLighting: specular mip 0 is the sky's radiance; the roughest mip a brute-force GGX convolution", "[gl][lighting]") {
    test::glContext();
    const int n = 32;
    auto p = skyAt(30 * kDeg, 150 * kDeg, n);
    p->setCamera(cubeCamera(0, n));
    p->renderFrame();
    const SkyLighting& l = p->lighting();
    REQUIRE(l.specularMips == 5);
    // Mip 0, face by face, against the same processor rendering the face with the CubeFace camera
    // (its image top row first is GL's row 0, t = -1).
    std::vector<std::vector<float>> level0;
    for (int f = 0; f < 6; ++f) {
        level0.push_back(readFace(l.specularCube, 0, f));
        p->setCamera(cubeCamera(f, n));
        p->renderFrame();
        const Image img = p->readHdr();
        double worst = 0;
        for (int y = 0; y < n; ++y)
            for (int x = 0; x < n; ++x) {
                const double a = color::luminance({level0[size_t(f)][size_t(4 * (y * n + x))], level0[size_t(f)][size_t(4 * (y * n + x) + 1)],
                                            level0[size_t(f)][size_t(4 * (y * n + x) + 2)]});
                const double b = color::luminance({img.at(x, y, 0), img.at(x, y, 1), img.at(x, y, 2)});
                worst = std::max(worst, std::abs(a - b) / std::max(b, 1e-6));
            }
        INFO("face " << f);
        CHECK(worst < 0.01);  // 1 %: the same passes, the same texels; float rounding only
    }
    // Every prefiltered mip against the double-precision sum over every texel of level 0 with
    // the split-sum weight D(h)/4 (n.l) Omega; the roughest (roughness 1, GGX alpha 1) must be
    // within 3 % (the target); the others are printed for docs/lighting.md (mip 1 sums level 1).
    for (int mip = 1; mip < l.specularMips; ++mip) {
        const int m = n >> mip;
        const double r = double(mip) / (l.specularMips - 1), a2 = r * r * r * r;
        double worst = 0, sumErr = 0;
        for (int f = 0; f < 6; ++f) {
            const std::vector<float> px = readFace(l.specularCube, mip, f);
            for (int j = 0; j < m; ++j)
                for (int i = 0; i < m; ++i) {
                    const glm::dvec3 nrm = *cubeCamera(f, m).directionAt({i + 0.5, j + 0.5});
                    glm::dvec3 sum(0.0);
                    double wsum = 0;
                    for (int sf = 0; sf < 6; ++sf)
                        for (int sj = 0; sj < n; ++sj)
                            for (int si = 0; si < n; ++si) {
                                const glm::dvec3 d = *cubeCamera(sf, n).directionAt({si + 0.5, sj + 0.5});
                                const double nl = glm::dot(nrm, d);
                                if (nl <= 0) continue;
                                const double nh = glm::dot(nrm, glm::normalize(nrm + d));
                                const double q = nh * nh * (a2 - 1) + 1, D = a2 / (kPi * q * q);
                                const double w = D / 4 * nl * texelSolidAngle(si, sj, n);
                                const size_t o = size_t(4 * (sj * n + si));
                                sum += w * glm::dvec3(level0[size_t(sf)][o], level0[size_t(sf)][o + 1], level0[size_t(sf)][o + 2]);
                                wsum += w;
                            }
                    const glm::dvec3 ref = sum / wsum;
                    const glm::dvec3 got(px[size_t(4 * (j * m + i))], px[size_t(4 * (j * m + i) + 1)], px[size_t(4 * (j * m + i) + 2)]);
                    worst = std::max(worst, relErr(got, ref));
                    sumErr += relErr(got, ref);
                }
        }
        std::printf("specular mip %d (roughness %.2f, %dx%d) vs brute-force GGX over level 0 (double): mean %.3f %%, worst %.3f %%\n", mip, r, m, m,
                    100 * sumErr / (6 * m * m), 100 * worst);
        if (mip == l.specularMips - 1) CHECK(worst < 0.03);  // 3 %: the target; it sums level 0 too, in float
    }
}

TEST_CASE("SkyLighting: the six axis lights are the irradiance along the axes", "[gl][lighting]") {
    test::glContext();
    auto p = skyAt(20 * kDeg, 120 * kDeg);
    const Environment env = equirect(*p, 256, 128);
    const SkyLighting& l = p->lighting();
    const glm::dvec3 axes[6] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
    std::printf("\naxis lights vs the exact cosine integral (Sun at 20 deg, azimuth 120 deg):\n");
    for (int a = 0; a < 6; ++a) {
        const glm::dvec3 exact = exactIrradiance(env, axes[a]);
        const double e = (color::luminance(l.axisLights[size_t(a)]) - color::luminance(exact)) / color::luminance(exact);
        std::printf("  axis %d: %.4g lx, exact %.4g lx, %+.2f %%, SH %+.2f %%\n", a, color::luminance(l.axisLights[size_t(a)]), color::luminance(exact), 100 * e,
                    100 * (color::luminance(l.irradiance(axes[a])) - color::luminance(exact)) / color::luminance(exact));
        INFO("axis " << a);
        // 3 %: SevenSky's light map weights each 22.5 x 11.25 deg texel's mean radiance by the
        // cosine at its centre; where the radiance varies across a texel (the aureole, the
        // horizon), the mean of L cos differs from mean L x cos(centre): measured up to 1.7 %.
        CHECK(std::abs(e) < 0.03);
    }
}

#ifdef WELKIN_HAS_ELEMENT_clouds  // the Clouds element, by name
TEST_CASE("SkyLighting: overcast clouds lower the Sun's light", "[gl][lighting][clouds]") {
    test::glContext();
    auto sunLux = [](const char* preset) {
        auto p = skyAt(40 * kDeg, 180 * kDeg, 16);
        p->add(elements::makeElement("clouds"));
        p->vars().setFromString("clouds.preset", preset);
        Camera cam;
        cam.width = 32;
        cam.height = 16;
        p->setCamera(cam);
        p->renderFrame();
        return std::pair{p->lighting().sun.illuminanceLux, p->vars().getOr(keys::sunCloudTransmittance, -1.0)};
    };
    const auto [clear, clearT] = sunLux("clear");
    const auto [overcast, overcastT] = sunLux("overcast");
    std::printf("\nSun's illuminance: clear %.4g lx (cloud T %.3f), overcast %.4g lx (cloud T %.3g)\n", clear, clearT, overcast, overcastT);
    CHECK(clear > 5e4);          // a Sun 40 deg high through a clear air: ~7e4 lx
    CHECK(clearT == 1.0);        // no cloud on the ray
    CHECK(overcast < 0.1 * clear);  // a stratocumulus deck: optical depth > 10 on the ray
    CHECK(overcast == Approx(clear * overcastT).epsilon(1e-9));  // exactly the photometry's transmittance
}
#endif

TEST_CASE("Eclipses: the Sun's visible fraction and the sunlight reaching the Moon", "[cpu][lighting][astro]") {
    // Geometry alone: concentric equal disks hide everything; disjoint ones nothing; a uniform
    // disk half covered by a straight edge (a huge occulter) keeps half.
    CHECK(astro::eclipseVisibleFraction(1e-3, 1e-3, 0.0) == Approx(0.0).margin(1e-12));
    CHECK(astro::eclipseVisibleFraction(1e-3, 1e-3, 2.01e-3) == 1.0);
    CHECK(astro::eclipseVisibleFraction(1e-3, 1e3, 1e3, 0.0) == Approx(0.5).margin(2e-3));  // ring quadrature: ~1/512
    // Limb darkening: the disk's centre is brighter, so a central occulter of half the radius
    // hides more than its area's quarter: analytic for I = 1 - u (1 - mu), u = 0.6:
    // hidden = int_0^0.5 (1 - u + u sqrt(1 - r^2)) r dr / int_0^1 (...) r dr.
    const double u = 0.6;
    auto F = [&](double r) { return (1 - u) * r * r / 2 - u * std::pow(1 - r * r, 1.5) / 3; };
    const double hidden = (F(0.5) - F(0.0)) / (F(1.0) - F(0.0));
    CHECK(astro::eclipseVisibleFraction(1e-3, 0.5e-3, 0.0) == Approx(1 - hidden).margin(1e-5));

    auto at = [](const char* iso, double latDeg, double lonDeg) {
        const SkyVars v = test::astronomyAt(iso, latDeg, lonDeg);
        return std::pair{v.get(keys::sunEclipseFraction), v.get(keys::moonEclipseFactor)};
    };
    // The total solar eclipse of 2026-08-12 near Burgos (Spain), 18:29 UTC: near-total.
    const auto [sunEclipse, moonDuringSolar] = at("2026-08-12T18:29:00Z", 42.34, -3.70);
    std::printf("\nsolar eclipse 2026-08-12 18:29 UTC, 42.34 N 3.70 W: sun.eclipse_fraction %.4f\n", sunEclipse);
    CHECK(sunEclipse < 0.01);
    CHECK(moonDuringSolar == 1.0);
    CHECK(at("2026-08-13T18:29:00Z", 42.34, -3.70).first == 1.0);  // a day later: an ordinary Sun
    // The total lunar eclipse of 2025-09-07, 18:12 UTC (greatest eclipse 18:11): the Moon deep in
    // the umbra; four hours later it is out of the penumbra.
    const auto [sunDuringLunar, moonEclipse] = at("2025-09-07T18:12:00Z", 0.0, 60.0);
    std::printf("lunar eclipse 2025-09-07 18:12 UTC: moon.eclipse_factor %.4f\n", moonEclipse);
    CHECK(moonEclipse < 0.02);
    CHECK(sunDuringLunar == 1.0);
    CHECK(at("2025-09-07T23:30:00Z", 0.0, 60.0).second == 1.0);
}

TEST_CASE("Eclipses: a lunar eclipse dims lights.moon_illuminance by moon.eclipse_factor", "[gl][lighting][astro]") {
    test::glContext();
    auto moonLux = [](const char* iso) {
        SkyProcessor p(SkyVars::earth(), test::testLogger());
        p.addGenerator(generators::AtmosphereLights::obtain(p.vars()));
        p.setObserver({.latitudeRad = 0.0, .longitudeRad = 60 * kDeg, .heightMeters = 0});
        p.setTime(UtcInstant::parse(iso));
        p.update();
        const double magnitudeLux = astro::magnitude::illuminanceLux(p.vars().get(astro::keys::moonMagnitude));
        return std::tuple{color::luminance(p.vars().get(keys::moonIlluminance)), magnitudeLux, p.vars().get(keys::moonEclipseFactor)};
    };
    const auto [eclipsed, magEclipsed, factor] = moonLux("2025-09-07T18:12:00Z");
    const auto [full, magFull, factorFull] = moonLux("2025-09-07T23:30:00Z");
    std::printf("\nMoon's illuminance above the air: eclipsed %.3g lx (factor %.4f), 5 h later %.3g lx\n", eclipsed, factor, full);
    CHECK(factorFull == 1.0);
    CHECK(full == Approx(magFull).epsilon(1e-9));           // the magnitude law's illuminance (colour of luminance 1)
    CHECK(eclipsed == Approx(factor * magEclipsed).epsilon(1e-9));  // exactly the factor applied
    CHECK(eclipsed < 1e-2 * full);  // the issue's: more than 10^2 darker at mid-totality
    CHECK(eclipsed > 1e-6 * full);  // not black: the refracted light (2e-5 .. 1e-4, astro/eclipses.hpp)
}

TEST_CASE("SkyLighting: nothing runs when nothing changed; time-sliced in the interactive path", "[gl][lighting]") {
    test::glContext();
    auto p = skyAt(30 * kDeg, 180 * kDeg, 16);
    Camera cam;
    cam.width = 32;
    cam.height = 16;
    p->setCamera(cam);
    auto faces = [&] { return p->stats()["lighting"]["faces_captured"].get<int>(); };
    p->renderFrame();
    const int first = faces();
    CHECK(first >= 6);
    const uint64_t revision = p->lighting().revision;
    for (int i = 0; i < 3; ++i) p->renderFrame();
    CHECK(faces() == first);                      // no key changed: no capture, no reduction
    CHECK(p->lighting().revision == revision);    // and no output changed
    p->vars().set(keys::sunDirection, azAlt(180 * kDeg, 35 * kDeg));
    p->renderFrame();
    CHECK(faces() == first + 6);                  // an offline frame: the whole refresh at once
    CHECK(p->lighting().revision > revision);

    // Interactive: one slice per frame (6 faces, the reductions, 4 prefiltered mips = 11 frames).
    p->vars().set(keys::interactive, true);
    p->renderFrame();  // the interactive flag is itself a key: its change starts a refresh
    for (int i = 0; i < 12; ++i) p->renderFrame();
    const int settled = faces();
    p->vars().set(keys::sunDirection, azAlt(180 * kDeg, 40 * kDeg));
    p->renderFrame();
    CHECK(faces() == settled + 1);
    CHECK(p->stats()["lighting"]["refreshing"].get<bool>());
    for (int i = 0; i < 10; ++i) p->renderFrame();
    CHECK(faces() >= settled + 6);  // the whole refresh, a slice a frame
    // The interactive Sky goes on building its keyframe tables in the background after the
    // light's change (sky.keyframe_budget parts a frame, a few hundred frames at medium) but
    // re-mixes its shown table only when a table it shows changes (the light's exact table when
    // complete), so the lighting settles after that table's parts and one more refresh: 36 frames
    // measured here. 100 bounds it with room for the quality's part counts; a Sky re-mixing
    // through the whole fill (as it did before, 332 frames) fails.
    int still = 0, frames = 0;
    for (int last = faces(); still < 5 && frames < 1000; ++frames) {
        p->renderFrame();
        still = faces() == last && !p->stats()["lighting"]["refreshing"].get<bool>() ? still + 1 : 0;
        last = faces();
    }
    INFO("frames to settle: " << frames);
    CHECK(still == 5);  // settled: five frames in a row with no capture and no refresh running
    CHECK(frames < 100);
}

TEST_CASE("SkyLighting: options are checked at the API boundary", "[cpu][lighting]") {
    SkyProcessor p(SkyVars::earth(), test::testLogger(), ProcessorOptions{.astronomy = false});
    CHECK_THROWS_WITH(p.setLighting(LightingOptions{.cubeSize = 3}), "SkyProcessor::setLighting(): cubeSize 3 not in [8, 1024]");
    CHECK_THROWS_WITH(p.setLighting(LightingOptions{.cubeSize = 48}), "SkyProcessor::setLighting(): cubeSize 48 is not a power of two");
    CHECK_THROWS_WITH(p.setLighting(LightingOptions{.cubeSize = 16, .specularMips = 6}),
                      "SkyProcessor::setLighting(): specularMips 6 not in [1, 5]");
    CHECK_FALSE(p.vars().get(keys::lightingEnabled));  // off by default; a failed call changes nothing
    p.setLighting(LightingOptions{});
    CHECK(p.vars().get(keys::lightingEnabled));
    p.setLighting(std::nullopt);
    CHECK_FALSE(p.vars().get(keys::lightingEnabled));
}

TEST_CASE("SkyLighting: the host's GLSL chunks shade with the same SH and specular cube", "[gl][lighting]") {
    test::glContext();
    auto p = skyAt(25 * kDeg, 200 * kDeg, 16);
    Camera cam;
    cam.width = 32;
    cam.height = 16;
    p->setCamera(cam);
    p->renderFrame();
    const SkyLighting& l = p->lighting();
    // A host's own program (no ProgramBuilder), Y-up world with -z north: pixel i shades the
    // world normal u_n[i]; pixel 6 reads the specular cube towards world +x (east), roughness 0.
    std::string fs = "#version 450 core\n";
    for (auto& [name, text] : lightingGlslChunks()) fs += text + "\n";
    fs += "uniform vec3 u_n[6]; out vec4 o;\n"
          "void main() { int i = int(gl_FragCoord.x);\n"
          "  o = vec4(i < 6 ? welkin_shIrradiance(welkin_toEnu(u_n[i])) : welkin_specularRadiance(welkin_toEnu(vec3(1, 0, 0)), 0.0), 1.0); }\n";
    const char* vs = "#version 450 core\nvoid main() { vec2 p = vec2((gl_VertexID & 1) * 4 - 1, (gl_VertexID & 2) * 2 - 1); gl_Position = vec4(p, 0, 1); }\n";
    auto compile = [](GLenum type, const std::string& src) {
        GLuint s = glCreateShader(type);
        const char* c = src.c_str();
        glShaderSource(s, 1, &c, nullptr);
        glCompileShader(s);
        GLint ok = 0;
        glGetShaderiv(s, GL_COMPILE_STATUS, &ok);
        char log[2048] = {};
        glGetShaderInfoLog(s, sizeof log, nullptr, log);
        INFO(log);
        REQUIRE(ok);
        return s;
    };
    GLuint prog = glCreateProgram();
    GLuint v = compile(GL_VERTEX_SHADER, vs), f = compile(GL_FRAGMENT_SHADER, fs);
    glAttachShader(prog, v);
    glAttachShader(prog, f);
    glLinkProgram(prog);
    GLint linked = 0;
    glGetProgramiv(prog, GL_LINK_STATUS, &linked);
    REQUIRE(linked);
    const glm::dmat3 enuFromYUp(glm::dvec3(1, 0, 0), glm::dvec3(0, 0, 1), glm::dvec3(0, -1, 0));
    const glm::vec3 worldNormals[6] = {{0, 1, 0}, {0, -1, 0}, {1, 0, 0}, {-1, 0, 0}, {0, 0, -1}, {0, 0, 1}};  // up, down, E, W, N, S
    glProgramUniform3fv(prog, glGetUniformLocation(prog, "u_n"), 6, &worldNormals[0].x);
    bindLighting(prog, l, 5, enuFromYUp);
    gl::Texture2D target(7, 1, GL_RGBA32F);
    auto fbo = gl::Framebuffer::create();
    fbo.attach(GL_COLOR_ATTACHMENT0, target);
    fbo.bind();
    glViewport(0, 0, 7, 1);
    glUseProgram(prog);
    GLuint vao = 0;
    glCreateVertexArrays(1, &vao);
    glBindVertexArray(vao);
    glDisable(GL_BLEND);
    glDisable(GL_DEPTH_TEST);
    glDrawArrays(GL_TRIANGLE_STRIP, 0, 4);
    const std::vector<float> px = target.readRgbaFloat();
    glBindVertexArray(0);
    glDeleteVertexArrays(1, &vao);
    glUseProgram(0);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    glBindTextureUnit(5, 0);
    glDeleteProgram(prog);
    glDeleteShader(v);
    glDeleteShader(f);
    for (int i = 0; i < 6; ++i) {
        const glm::dvec3 want = l.irradiance(enuFromYUp * glm::dvec3(worldNormals[i]));
        INFO("normal " << i);
        // float uniforms and a float sum of nine terms against double: 1e-4
        for (int c = 0; c < 3; ++c) CHECK(px[size_t(4 * i + c)] == Approx(want[c]).epsilon(1e-4));
    }
    // East is face +X's centre: bilinear between its four central texels at mip 0.
    const std::vector<float> face = readFace(l.specularCube, 0, 0);
    const int n = l.specularCube.width, a = n / 2 - 1, b = n / 2;
    for (int c = 0; c < 3; ++c) {
        const double mean = 0.25 * (face[size_t(4 * (a * n + a) + c)] + face[size_t(4 * (a * n + b) + c)] + face[size_t(4 * (b * n + a) + c)] +
                                    face[size_t(4 * (b * n + b) + c)]);
        CHECK(px[size_t(24 + c)] == Approx(mean).epsilon(1e-3));  // the sampler's 8-bit bilinear weights: exact at the centre
    }
}

TEST_CASE("SkyLighting: the library's bodies and overlays stay out of the environment, the rest is in it", "[cpu][lighting]") {
    // The convention of docs/writing-an-element.md: Layer::Bodies (the Sun's and Moon's disks, the
    // directional lights) and Layer::Overlay (not light) say setContributesToLighting(false).
    for (const ElementDescriptor* d : elements::descriptors()) {
        INFO(d->name << " (" << toString(d->layer) << ")");
        const bool expected = d->layer != Layer::Bodies && d->layer != Layer::Overlay;
        CHECK(d->make()->contributesToLighting() == expected);
    }
}
