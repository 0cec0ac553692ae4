// The clouds' shadow on the atmosphere's in-scattering (generators/clouds/cloud_sky_shadow.hpp,
// the Sky element's shadow variant): no clouds changes nothing, bit for bit; under a full
// overcast the Sun's single scattering below the deck is gone (against the sky view's own
// single-scattering table); one cloud darkens exactly the directions whose rays cross its shadow.
#include <catch2/catch.hpp>

#include "cloud_test_textures.hpp"
#include "elements_present.hpp"
#include "gl_test_context.hpp"

#include <epoxy/gl.h>

#include <welkin/camera.hpp>
#include <welkin/elements/registry.hpp>
#include <welkin/elements/sky.hpp>
#include <welkin/elements/sky_offline.hpp>
#include <welkin/generators/atmosphere.hpp>
#include <welkin/generators/cloud_shadow.hpp>
#include <welkin/generators/cloud_sky_shadow.hpp>
#include <welkin/generators/lights.hpp>
#include <welkin/generators/sky_luts.hpp>
#include <welkin/gl/objects.hpp>
#include <welkin/keys.hpp>
#include <welkin/processor.hpp>

#include <algorithm>
#include <cmath>

using namespace welkin;
using namespace welkin::generators;

namespace {
constexpr double kPi = 3.14159265358979323846;
constexpr double kDeg = kPi / 180.0;

double lum(const Image& im, int x, int y) { return 0.2126 * im.at(x, y, 0) + 0.7152 * im.at(x, y, 1) + 0.0722 * im.at(x, y, 2); }

// A weather map over `extentM` (offset extent / 2: ENU (0, 0) reads its centre) holding one round
// cumulus of radius `radiusM` centred at ENU `centre` (base and top at the layer's: G = 0, B = 1;
// a 400 m cosine edge), or density 1 everywhere (overcast), or nothing (radius 0).
cpu::Image weather(int n, double extentM, glm::dvec2 centre, double radiusM, bool everywhere) {
    cpu::Image w{n, n, 1, std::vector<float>(size_t(n) * size_t(n) * 4, 0.0f)};
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            const glm::dvec2 xy = (glm::dvec2(i + 0.5, j + 0.5) / double(n) - 0.5) * extentM;
            const double d = everywhere ? 1.0 : std::clamp((radiusM - glm::length(xy - centre)) / 400.0 + 0.5, 0.0, 1.0);
            const double s = everywhere ? 1.0 : 0.5 - 0.5 * std::cos(kPi * d);
            float* t = &w.rgba[(size_t(j) * size_t(n) + size_t(i)) * 4];
            if (s > 0.0) t[0] = float(s), t[1] = 0.0f, t[2] = 1.0f;
        }
    return w;
}

gl::Texture upload(const cpu::Image& im, bool is3D) { return test::uploadCloudTexture(im, is3D); }

std::vector<float> readRgba(TextureRef ref) {
    std::vector<float> px(size_t(ref.width) * size_t(ref.height) * 4);
    glGetTextureImage(ref.id, 0, GL_RGBA, GL_FLOAT, GLsizei(px.size() * sizeof(float)), px.data());
    return px;
}

// The Sky element (medium quality, Sun only) rendered offline as an equirect image, with the
// clouds' shadow generators run by hand between the sky's LUTs and the draw: the Sky element
// reads sky.shadow_loss_lut from the SkyVars when it exists.
struct Rig {
    SkyVars vars = SkyVars::earth();
    elements::OfflineRenderer r{vars, test::testLogger()};
    elements::Sky sky{elements::SkyOptions{.quality = 1, .moon = false}};
    std::shared_ptr<CloudShadowMap> map = std::make_shared<CloudShadowMap>();
    std::shared_ptr<CloudSkyShadow> loss = std::make_shared<CloudSkyShadow>();
    std::vector<gl::Texture> textures;
    Camera cam;
    Rig(glm::dvec3 sun, double observerHeightM) {
        test::glContext();
        vars.set(atmosphere::kAtmosphere, std::make_shared<const atmosphere::Atmosphere>(atmosphere::Atmosphere::earthClear()));
        vars.set(keys::sunDirection, glm::normalize(sun));
        vars.set(keys::moonDirection, glm::dvec3(0, 0, -1));
        vars.set(keys::observerHeight, observerHeightM);
        cam.projection = Projection::Equirect;
        cam.width = 96;
        cam.height = 48;
    }
    Image render() { return r.render(sky, cam); }
    // The clouds' shadow for `w` over `extentM` (the layer 2-3 km, sigma 0.05 /m: opaque), then
    // the loss table; the next render() subtracts it.
    void clouds(const cpu::Image& w, double extentM, int mapResolution) {
        map->declareKeys(vars);
        loss->declareKeys(vars);
        textures.clear();
        textures.push_back(upload(w, false));
        vars.set(cloudkeys::weatherMap, textures.back().ref());
        textures.push_back(upload(cpu::Image{1, 1, 1, {1.0f, 0.5f, 0.5f, 0.5f}}, true));  // R = 1: the shape is the map's
        vars.set(cloudkeys::noiseBase, textures.back().ref());
        vars.set(cloudkeys::weatherExtent, extentM);
        vars.set(cloudkeys::weatherOffset, glm::dvec2(extentM / 2));
        vars.set(cloudkeys::bottom, 2000.0);
        vars.set(cloudkeys::top, 3000.0);
        vars.set(cloudkeys::coverage, 1.0);
        vars.set(cloudkeys::scattering, 0.05);
        vars.set(cloudkeys::cirrusCoverage, 0.0);
        vars.set(cloudkeys::cirrusHeight, 9000.0);
        vars.set(lightkeys::planetRadius, 6360e3);
        vars.set(cloudkeys::shadowExtent, extentM);
        vars.set(cloudkeys::shadowResolution, mapResolution);
        map->run(vars, test::testLogger());
        loss->run(vars, test::testLogger());
    }
    ~Rig() {
        loss->releaseGl();
        map->release();
        sky.release();
        r.release();
    }
};
}  // namespace

TEST_CASE("Clouds' shadow on the sky: no clouds leaves the sky bit for bit", "[gl][clouds][shadow]") {
    Rig rig(directionFromAzAlt(200 * kDeg, 25 * kDeg), 0.0);
    const Image plain = rig.render();  // no sky.shadow_loss_lut: the sky's own program
    REQUIRE_FALSE(rig.vars.has(skykeys::shadowLossLut));
    // The clouds' generators present, but the layer holds no cloud (an empty weather map): the
    // shadow map is exp(-0) = 1, the loss exactly 0, and the shadow variant subtracts 0.
    rig.clouds(weather(32, 40e3, {0, 0}, 0.0, false), 40e3, 32);
    REQUIRE(rig.vars.has(skykeys::shadowLossLut));
    for (float x : readRgba(rig.vars.get(skykeys::shadowLossLut))) REQUIRE((x == 0.0f || x == 1.0f));  // alpha is 1
    for (float x : readRgba(rig.vars.get(skykeys::shadowLossMieLut))) REQUIRE((x == 0.0f || x == 1.0f));
    const Image shadowed = rig.render();
    REQUIRE(shadowed.pixels.size() == plain.pixels.size());
    size_t differ = 0;
    for (size_t i = 0; i < plain.pixels.size(); ++i) differ += plain.pixels[i] != shadowed.pixels[i];
    CHECK(differ == 0);
}

TEST_CASE("Clouds' shadow on the sky: under a full overcast the single scattering below the deck is gone", "[gl][clouds][shadow]") {
    // The Sun at the zenith (the sky view and the loss table are then the same along every
    // azimuth), the observer 1 km up under an opaque deck at 2-3 km covering 400 km (every ray
    // down to the ground, <= 113 km long from 1 km, lies below the base and inside the map).
    // Looking down, all the Sun's single scattering is shadowed: the loss table's Mie part must
    // equal the sky view's Mie table (pure single scattering, sky_luts.hpp) row by row, and the
    // Rayleigh + ground loss may not exceed the sky view's smooth part (single Rayleigh + multiple
    // scattering + the lit ground), whose remainder is the unshadowed multiple scattering.
    Rig rig(glm::dvec3(0, 0, 1), 1000.0);
    const Image plain = rig.render();
    rig.clouds(weather(16, 400e3, {0, 0}, 0.0, true), 400e3, 16);
    const TextureRef lossRef = rig.vars.get(skykeys::shadowLossLut), view = rig.vars.get(skykeys::sunViewMieLut);
    REQUIRE(lossRef.height == view.height);
    const std::vector<float> lossM = readRgba(rig.vars.get(skykeys::shadowLossMieLut)), lossR = readRgba(lossRef);
    const std::vector<float> viewM = readRgba(view), viewS = readRgba(rig.vars.get(skykeys::sunViewLut));
    const int H = view.height, Wl = lossRef.width, Wv = view.width;
    double worst = 0.0, worstR = -1.0;
    for (int j = 1; j < H / 2; ++j)  // the ground half (row 0: the nadir)
        for (int c = 0; c < 3; ++c) {
            const double a = lossM[(size_t(j) * size_t(Wl) + size_t(Wl / 3)) * 4 + size_t(c)];
            const double b = viewM[(size_t(j) * size_t(Wv) + size_t(Wv / 2)) * 4 + size_t(c)];
            REQUIRE(b > 0.0);
            worst = std::max(worst, std::abs(a / b - 1.0));
            const double s = viewS[(size_t(j) * size_t(Wv) + size_t(Wv / 2)) * 4 + size_t(c)];
            const double r = lossR[(size_t(j) * size_t(Wl) + size_t(Wl / 3)) * 4 + size_t(c)];
            worstR = std::max(worstR, r / s);
        }
    INFO("largest |Mie loss / sky view Mie - 1| " << worst << "; largest (Rayleigh + ground loss) / sky view smooth " << worstR);
    // The two marches of the same integral: 32 uniform midpoint steps over the segment against the
    // sky view's 30 quadratically spaced ones (the float delta-M transmittance is the same
    // formula): their quadrature errors on the smooth exponential integrand stay below 0.5 %
    // (measured 2e-4 on llvmpipe).
    CHECK(worst < 0.005);
    // The lit ground's direct term and single Rayleigh are most of the smooth part looking down;
    // the rest (multiple scattering, the sky's light on the ground) is > 10 % of it: the loss stays
    // below 0.95 of the smooth part, and is not trivially small (> 0.3).
    CHECK(worstR < 0.95);
    CHECK(worstR > 0.3);
    // The rendered sky: darker everywhere below the horizon, never negative, never black (the
    // multiple scattering stays).
    const Image dark = rig.render();
    for (int y = rig.cam.height / 2 + 1; y < rig.cam.height; y += 3)
        for (int x = 0; x < rig.cam.width; x += 7) {
            INFO("pixel " << x << ", " << y);
            CHECK(lum(dark, x, y) < 0.9 * lum(plain, x, y));
            CHECK(lum(dark, x, y) > 0.02 * lum(plain, x, y));
        }
}

TEST_CASE("Clouds' shadow on the sky: one cloud darkens the directions through its shadow, only those", "[gl][clouds][shadow]") {
    // The Sun 20 deg up in the south; one opaque cumulus (radius 1.5 km, 2-3 km) 6 km north of the
    // observer. Its shadow column leans north: below the base it covers the ground from
    // 6 + 2 / tan 20 = 11.5 km to 6 + 3 / tan 20 = 14.2 km north (+- 1.5 km). A ray due north 3 deg
    // up is 0.6-0.75 km high there: it crosses the column, so that direction darkens. A ray due
    // south (away from the cloud and its shadow) never meets shadowed air: its loss is exactly 0.
    Rig rig(directionFromAzAlt(180 * kDeg, 20 * kDeg), 0.0);
    const Image plain = rig.render();
    rig.clouds(weather(128, 40e3, {0, 6000}, 1500.0, false), 40e3, 256);
    const Image shadowed = rig.render();
    // Equirect 96 x 48: x = W az / 2 pi (az from north through east), y = H (pi/2 - alt) / pi.
    auto pixel = [&](double azDeg, double altDeg) {
        std::optional<glm::dvec2> p = rig.cam.pixelOf(directionFromAzAlt(azDeg * kDeg, altDeg * kDeg));
        REQUIRE(p);
        return glm::ivec2(int(p->x), int(p->y));
    };
    const glm::ivec2 north = pixel(0.0, 3.0), south = pixel(180.0, 3.0), southUp = pixel(180.0, 40.0);
    const double n0 = lum(plain, north.x, north.y), n1 = lum(shadowed, north.x, north.y);
    INFO("north 3 deg: " << n0 << " -> " << n1 << " cd/m2");
    // The shadowed segment (~3 km of the ray's ~100 km of low, dense air) carries a few % of the
    // direction's radiance: at least 1 % must go.
    CHECK(n1 < 0.99 * n0);
    CHECK(n1 > 0.5 * n0);  // the multiple scattering and the rest of the ray stay
    for (glm::ivec2 p : {south, southUp})
        for (int c = 0; c < 3; ++c) CHECK(shadowed.at(p.x, p.y, c) == plain.at(p.x, p.y, c));  // loss exactly 0: bit for bit
}

TEST_CASE("Clouds' shadow on the sky: the GPU loss table against its double CPU twin", "[gl][clouds][shadow]") {
    // Two opaque cumulus (north and east-south-east), the Sun 8 deg up in the west-south-west,
    // the observer 300 m up: shafts in several azimuths, rays up and down. The twin marches in
    // double with the CPU transmittance LUT and reads the GPU's shadow map (read back) bilinearly.
    Rig rig(directionFromAzAlt(250 * kDeg, 8 * kDeg), 300.0);
    rig.render();
    cpu::Image w = weather(128, 40e3, {0, 7000}, 2000.0, false);
    const cpu::Image w2 = weather(128, 40e3, {6000, -3000}, 1500.0, false);
    for (size_t i = 0; i < w.rgba.size(); i += 4)
        if (w2.rgba[i] > w.rgba[i]) std::copy(&w2.rgba[i], &w2.rgba[i] + 4, &w.rgba[i]);
    rig.clouds(w, 40e3, 256);
    const TextureRef mapRef = rig.vars.get(cloudkeys::shadowMap);
    const std::vector<float> map = readRgba(mapRef);
    const int n = mapRef.width;
    auto texel = [&](int x, int y) { return double(map[(size_t(std::clamp(y, 0, n - 1)) * size_t(n) + size_t(std::clamp(x, 0, n - 1))) * 4]); };
    auto sampler = [&](glm::dvec2 uv) {  // GL_LINEAR, clamp to edge
        const double x = uv.x * n - 0.5, y = uv.y * n - 0.5;
        const int x0 = int(std::floor(x)), y0 = int(std::floor(y));
        const double fx = x - x0, fy = y - y0;
        return (1 - fy) * ((1 - fx) * texel(x0, y0) + fx * texel(x0 + 1, y0)) + fy * ((1 - fx) * texel(x0, y0 + 1) + fx * texel(x0 + 1, y0 + 1));
    };
    const SkyModel& m = rig.loss->model();
    const SkyQuality& q = rig.loss->quality();
    const Lut2D T = cpu::transmittanceLut(m, q);
    const double deltaM = cpu::phaseMoments(m, q.shBands).forward;
    const TextureRef lossRef = rig.vars.get(skykeys::shadowLossLut);
    const std::vector<float> gR = readRgba(lossRef), gM = readRgba(rig.vars.get(skykeys::shadowLossMieLut));
    const int W = lossRef.width, H = lossRef.height;
    double maxR = 0, maxM = 0, errR = 0, errM = 0;
    int compared = 0;
    for (int j = 1; j < H; j += 4)
        for (int i = 0; i < W; i += 5) {
            const glm::dvec2 uv((i + 0.5) / W, (j + 0.5) / H);
            const double mu = skyViewMuAz(m, rig.loss->inputs().observerHeightM, uv, W, H).x, az = 2 * kPi * uv.x;
            const double sv = std::sqrt(std::max(1 - mu * mu, 0.0));
            const auto [R, M] = cpu::skyShadowLoss(m, T, deltaM, rig.loss->inputs(), m.sunAngularRadius, {sv * std::sin(az), sv * std::cos(az), mu},
                                                   j < H / 2, sampler);
            for (int c = 0; c < 3; ++c) {
                const size_t k = (size_t(j) * size_t(W) + size_t(i)) * 4 + size_t(c);
                maxR = std::max(maxR, R[c]), maxM = std::max(maxM, M[c]);
                errR = std::max(errR, std::abs(gR[k] / kLutScale - R[c]));
                errM = std::max(errM, std::abs(gM[k] / kLutScale - M[c]));
            }
            ++compared;
        }
    INFO(compared << " texels: largest Rayleigh loss " << maxR << ", |GPU - CPU| " << errR << "; Mie " << maxM << ", " << errM);
    REQUIRE(maxR > 0.0);
    REQUIRE(maxM > 0.0);
    // 1 % of the largest loss: float against double along rays of up to ~60 km (the midpoint
    // positions and heights in float: ~1e-6 relative), the GPU's transmittance LUT against the
    // CPU's twin (float storage), and the GPU's bilinear weights (8 fractional bits in the GL
    // minimum) on the shadows' sharp edges, where one step can cross a 0-to-1 edge.
    CHECK(errR < 0.01 * maxR);
    CHECK(errM < 0.01 * maxM);
}

#ifdef WELKIN_HAS_ELEMENT_clouds  // the Clouds element, by name (the registry)
TEST_CASE("Clouds' shadow on the sky: the Clouds element switches it on, clouds.sky_shadow off", "[gl][clouds][shadow]") {
    // The whole chain in a processor (Sky + Clouds, default weather and noise, a tiny fisheye):
    // the Clouds element adds the shadow map and the loss table, the Sky renders a finite,
    // non-negative image; with clouds.sky_shadow = false neither table exists.
    test::glContext();
    for (bool on : {true, false}) {
        SkyProcessor p{SkyVars::earth(), test::testLogger(), ProcessorOptions{.astronomy = false}};
        p.vars().set(atmosphere::kAtmosphere, std::make_shared<const atmosphere::Atmosphere>(atmosphere::Atmosphere::earthClear()));
        p.vars().set(keys::sunDirection, directionFromAzAlt(250 * kDeg, 10 * kDeg));
        p.vars().set(keys::moonDirection, glm::dvec3(0, 0, -1));
        Camera cam;
        cam.projection = Projection::Fisheye;
        cam.width = 24;
        cam.height = 24;
        p.setCamera(cam);
        p.add(std::make_unique<elements::Sky>(elements::SkyOptions{.quality = 0}));
        p.add(elements::makeElement("clouds"));
        p.vars().setFromString("clouds.samples", "8");  // few samples: llvmpipe
        p.vars().setFromString("clouds.light_samples", "2");
        p.vars().setFromString("clouds.sky_shadow", on ? "true" : "false");
        p.setExposure({.automatic = false, .ev100 = 12});
        p.renderFrame();
        const Image img = p.readHdr();
        INFO("clouds.sky_shadow " << on);
        CHECK(p.vars().has(skykeys::shadowLossLut) == on);
        CHECK(p.vars().has(cloudkeys::shadowMap) == on);
        CHECK(static_cast<elements::Sky&>(*p.elements().front()).shadowed() == on);
        for (float x : img.pixels) REQUIRE((std::isfinite(x) && x >= 0.0f));
        p.release();
    }
}
#endif

TEST_CASE("Clouds' shadow on the sky: a moving light's map and loss table rebuilt over clouds.shadow_slices frames", "[gl][clouds][shadow]") {
    // One opaque cumulus north of the observer, the Sun 20 deg up in the south; both tables built
    // whole first. Then, interactive with 4 slices, the Sun moves to 21 deg and stays: each
    // generator draws one part per frame (never more), the map and its light stay the old ones
    // until the new map is complete, and once both settle (the map over frames 1-4, the loss
    // table over 1-4 with the old map and again over 5-8 with the new one) they equal tables
    // built whole with the same inputs.
    Rig rig(directionFromAzAlt(180 * kDeg, 20 * kDeg), 0.0);
    rig.render();  // the sky's LUTs
    rig.clouds(weather(64, 40e3, {0, 6000}, 1500.0, false), 40e3, 64);
    const glm::dvec3 oldLight = rig.vars.get(cloudkeys::shadowLight);
    rig.vars.set(keys::interactive, true);
    rig.vars.set(cloudkeys::shadowSlices, 4);
    rig.vars.set(keys::sunDirection, directionFromAzAlt(180 * kDeg, 21 * kDeg));
    const Logger& log = test::testLogger();
    int frames = 0;
    for (; frames < 20 && (rig.map->isDue(rig.vars) || rig.loss->isDue(rig.vars)); ++frames) {
        const int m0 = rig.map->slicesBuilt(), l0 = rig.loss->slicesBuilt();
        rig.map->runIfDue(rig.vars, log);
        rig.loss->runIfDue(rig.vars, log);
        CHECK(rig.map->slicesBuilt() - m0 <= 1);
        CHECK(rig.loss->slicesBuilt() - l0 <= 1);
        if (frames < 3) CHECK(rig.vars.get(cloudkeys::shadowLight) == oldLight);  // the old map, whole, until the new one is
    }
    CHECK(frames == 8);
    CHECK(rig.map->slicesBuilt() == 4);
    CHECK(rig.loss->slicesBuilt() == 8);
    const glm::dvec3 newLight = rig.vars.get(cloudkeys::shadowLight);
    CHECK(newLight.z == Approx(std::sin(21 * kDeg)).margin(1e-12));
    const std::vector<float> mapSliced = readRgba(rig.vars.get(cloudkeys::shadowMap));
    const std::vector<float> lossSliced = readRgba(rig.vars.get(skykeys::shadowLossLut));
    const std::vector<float> mieSliced = readRgba(rig.vars.get(skykeys::shadowLossMieLut));
    // Whole: one slice (a change of the key reruns both), the same light, offset and layer.
    rig.vars.set(cloudkeys::shadowSlices, 1);
    rig.map->runIfDue(rig.vars, log);
    rig.loss->runIfDue(rig.vars, log);
    CHECK(rig.map->slicesBuilt() == 4);
    CHECK(rig.loss->slicesBuilt() == 8);
    // The same shader on the same inputs, only scissored by rows: equal to float rounding (1e-6
    // of the table's largest value allows another driver's reassociation).
    auto worst = [](const std::vector<float>& a, const std::vector<float>& b) {
        float mx = 0, d = 0;
        for (size_t i = 0; i < b.size(); ++i) mx = std::max(mx, std::abs(b[i])), d = std::max(d, std::abs(a[i] - b[i]));
        return mx > 0 ? d / mx : d;
    };
    CHECK(worst(mapSliced, readRgba(rig.vars.get(cloudkeys::shadowMap))) <= 1e-6);
    CHECK(worst(lossSliced, readRgba(rig.vars.get(skykeys::shadowLossLut))) <= 1e-6);
    CHECK(worst(mieSliced, readRgba(rig.vars.get(skykeys::shadowLossMieLut))) <= 1e-6);
    // And the map is not trivially flat: the cloud's shadow is in it.
    float darkest = 1.0f;
    for (size_t i = 0; i < mapSliced.size(); i += 4) darkest = std::min(darkest, mapSliced[i]);  // R: the transmittance
    CHECK(darkest < 0.5f);
}
