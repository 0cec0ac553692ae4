// welkin bench cloud-reference: the real-time clouds against the path-traced reference
// (generators/reference/reference_clouds.hpp) on fixed scenes, at a small size. For each scene the
// real-time frame (the default Sky element plus Clouds, no reprojection, the element's own
// samples; astronomy off, the Sun placed by sun.direction) is rendered and read back (cd/m^2);
// the clouds' textures it used (weather map, base, detail and curl noise) are read back too and
// the path tracer renders the same camera rays through the density function's CPU twin, lit by
// the Sun above the cloud layer (lights.sun_illuminance x the reference sky's transmittance at the
// layer's middle), the sky (the reference integrator's clear-sky radiance seen from the ground,
// tabulated) and the ground (the atmosphere's albedo). Over the cloud pixels (the path-traced
// camera ray's cloud transmittance < 0.5) it prints the luminance error of the real-time frame:
//   RMS = sqrt(mean (Y_rt - Y_ref)^2) / mean Y_ref (also with the reference's own variance
//   sigma^2 subtracted from each squared difference), p95 = 95th percentile of |Y_rt / Y_ref - 1|,
//   bias = mean Y_rt / mean Y_ref,  noise = the reference's mean relative standard error.
// Both images include the sky behind the clouds and, in the fair field's scenes, the air between
// the camera and the clouds (aerial perspective): the reference adds it from the reference sky at
// each ray's mean scattering distance (--no-reference-air: left out, as before 2026-11-27; the
// single cumulus 4 km away and the decks never have it in the reference). Writes a side-by-side PNG per scene (--out DIR:
// reference left, real time right, one exposure) and the table as CSV.
#include "bench_util.hpp"

#include <CLI/CLI.hpp>
#include <welkin/bench.hpp>
#include <welkin/camera.hpp>
#include <welkin/csv.hpp>
#include <welkin/elements/clouds.hpp>
#include <welkin/elements/sky.hpp>
#include <welkin/error.hpp>
#include <welkin/generators/atmosphere.hpp>
#include <welkin/generators/cloud_density.hpp>
#include <welkin/generators/cloud_keys.hpp>
#include <welkin/generators/reference_clouds.hpp>
#include <welkin/generators/reference_sky.hpp>
#include <welkin/gl/context.hpp>
#include <welkin/gl/objects.hpp>
#include <welkin/image.hpp>
#include <welkin/keys.hpp>
#include <welkin/processor.hpp>

#include <epoxy/gl.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

namespace welkin::cli {
namespace {

constexpr double kDeg = M_PI / 180.0;
namespace ck = generators::cloudkeys;
namespace ek = elements::cloudelemkeys;

struct CloudReferenceOptions {
    int width = 64, height = 36;  // both images' size, px
    int paths = 16;               // path-traced paths per pixel
    int threads = 2;              // path tracer's threads (the result does not depend on them)
    uint64_t seed = 1;
    std::string scenes = "deck,cumulus-side";  // any of kScenes' names
    std::string qualities = "default";          // any of low, default, high (kQualities)
    std::string costSize = "320x180";           // the frame whose cost is timed against the trivial pass (empty: none)
    int repeats = 3;                            // timed frame pairs per row (median)
    std::string out;              // directory for the side-by-side PNGs (empty: none)
    std::string csv = "bench_cloud_reference.csv";
    long slabPhotons = 0;         // > 0: first the slab table (path tracer against adding-doubling)
    long maxScatterings = 1000000;  // the path tracer's scattering orders kept (1: single scattering; cloudref::Scene)
    double truncateDeg = 0;       // > 0: the droplet phase's forward peak truncated at this angle (cloudref::truncatePhase), deg
    bool referenceAir = true;     // the air between the camera and the clouds added to the reference (as the real-time frame has it)
    double groundAlbedo = -1;     // >= 0: the atmosphere's ground albedo (Atmosphere::withGroundAlbedo), for both images; < 0: the default atmosphere's
};

/// A GL texture (by name) read back as the density twin's image, level 0.
generators::cpu::Image readBack(const TextureRef& r) {
    if (r.id == 0) throw Error("bench cloud-reference: a cloud texture is missing");
    generators::cpu::Image im;
    im.w = r.width;
    im.h = r.height;
    im.d = std::max(r.depth, 1);
    im.rgba.resize(size_t(im.w) * im.h * im.d * 4);
    glGetTextureImage(r.id, 0, GL_RGBA, GL_FLOAT, GLsizei(im.rgba.size() * sizeof(float)), im.rgba.data());
    return im;
}

/// A texture of n x n (x n) texels from f, repeating, linear.
gl::Texture makeTexture(int n, bool is3D, const std::function<glm::vec4(double, double)>& f) {
    gl::Texture tex = is3D ? gl::Texture(gl::Texture3D(n, n, n, GL_RGBA32F)) : gl::Texture(gl::Texture2D(n, n, GL_RGBA32F));
    std::vector<float> px;
    const int depth = is3D ? n : 1;
    for (int z = 0; z < depth; ++z)
        for (int y = 0; y < n; ++y)
            for (int x = 0; x < n; ++x) {
                const glm::vec4 c = f((x + 0.5) / n, (y + 0.5) / n);
                px.insert(px.end(), {c.r, c.g, c.b, c.a});
            }
    tex.upload(GL_RGBA, GL_FLOAT, px.data());
    tex.setFilter(GL_LINEAR);
    tex.setWrap(GL_REPEAT);
    return tex;
}

double lum(const glm::dvec3& c) { return 0.2126 * c.r + 0.7152 * c.g + 0.0722 * c.b; }
// The cloud pixels' regions (the per-region error line).
const char* const kRegionNames[4] = {"edge", "base", "sunlit", "shaded"};

// The fixed scenes (skyelements/clouds/README.md, "The real-time clouds against the reference"). Sun and camera
// azimuths from north towards east, degrees.
enum class SceneKind { Deck, Blob, Preset };
struct SceneDef {
    const char* name;
    SceneKind kind;
    const char* preset;       // Preset scenes: clouds.preset
    double sunAz, sunAlt;     // deg
    double camAz, camAlt, fov;  // deg
    double camHeight = 0.5;     // m above the ground (the real-time observer's height; 0.5: on the ground)
};
const SceneDef kScenes[] = {
    // A uniform deck of tau = 10 between 1 and 2 km, the Sun at the zenith, seen from below.
    {"deck", SceneKind::Deck, "", 0, 90, 0, 60, 60},
    // One cumulus (1.5-3.5 km, 4 km north): lit from the side (Sun 30 deg up in the east, 90 deg
    // from the view), from behind (Sun 30 deg up in the north, behind the cloud's middle), from
    // above (Sun 80 deg up).
    {"cumulus-side", SceneKind::Blob, "", 90, 30, 0, 28, 36},
    {"cumulus-behind", SceneKind::Blob, "", 0, 30, 0, 28, 36},
    {"cumulus-above", SceneKind::Blob, "", 90, 80, 0, 28, 36},
    // The fair preset's field (its generated weather map and noise): noon (Sun 70 deg up in the
    // south, looking north-east 20 deg up) and sunset (Sun 4 deg up in the west-north-west,
    // looking south-west 12 deg up, the clouds lit from the side and behind).
    {"fair-noon", SceneKind::Preset, "fair", 180, 70, 30, 20, 50},
    {"fair-sunset", SceneKind::Preset, "fair", 290, 4, 220, 12, 50},
    // The overcast preset's deck, Sun 60 deg up in the south, looking north 45 deg up.
    {"overcast", SceneKind::Preset, "overcast", 180, 60, 0, 45, 60},
    // Seen from above (an aircraft at 6 km): the single cumulus 4 km north, looked down on 35 deg,
    // the Sun 60 deg up in the east. From inside: the uniform deck of tau = 10 with the camera in its
    // middle (1.5 km), looking north along the horizon, the Sun at the zenith.
    {"cumulus-from-above", SceneKind::Blob, "", 90, 60, 0, -35, 50, 6000.0},
    {"deck-inside", SceneKind::Deck, "", 0, 90, 0, 0, 60, 1500.0},
};
std::string sceneNames() {
    std::string n;
    for (const SceneDef& d : kScenes) n += (n.empty() ? "" : ", ") + std::string(d.name);
    return n;
}
// The qualities: view samples and light samples (clouds.samples, clouds.light_samples; the
// element's defaults are `default`). The clouds have no quality key of their own: these are the
// two keys' values the table reports.
struct QualityDef {
    const char* name;
    int samples, lightSamples;
};
const QualityDef kQualities[] = {{"low", 16, 3}, {"default", 48, 6}, {"high", 128, 12}};

struct Row {
    std::string scene, quality;
    int samples = 0, lightSamples = 0;
    int pixels = 0;
    double rms = 0, rmsDenoised = 0, p95 = 0, bias = 0, noise = 0, meanRef = 0, meanRt = 0, refSeconds = 0;
    double frameMs = NAN, trivialMs = NAN, ratioTrivial = NAN;
    double edgeRef = NAN, edgeRt = NAN;  // silhouette over inside luminance, reference and real time
};

int run(const CloudReferenceOptions& o) {
    if (o.width < 8 || o.width > 1024) throw Error("--width " + std::to_string(o.width) + " not in [8, 1024]");
    if (o.height < 8 || o.height > 1024) throw Error("--height " + std::to_string(o.height) + " not in [8, 1024]");
    if (o.paths < 1 || o.paths > 65536) throw Error("--paths " + std::to_string(o.paths) + " not in [1, 65536]");
    if (o.threads < 1 || o.threads > 64) throw Error("--threads " + std::to_string(o.threads) + " not in [1, 64]");
    if (!o.out.empty() && !std::filesystem::is_directory(o.out)) throw Error("--out '" + o.out + "': not an existing directory");
    checkOutputDirectory("--csv", o.csv);
    if (o.slabPhotons < 0 || o.slabPhotons > 100000000) throw Error("--slab-photons " + std::to_string(o.slabPhotons) + " not in [0, 1e8]");
    if (!(o.truncateDeg >= 0 && o.truncateDeg <= 20)) {
        char buf[48];
        std::snprintf(buf, sizeof buf, "%g", o.truncateDeg);
        throw Error(std::string("--truncate-deg ") + buf + " not in [0, 20]");
    }
    if (!(o.groundAlbedo == -1 || (o.groundAlbedo >= 0 && o.groundAlbedo <= 1))) {
        char buf[48];
        std::snprintf(buf, sizeof buf, "%g", o.groundAlbedo);
        throw Error(std::string("--ground-albedo ") + buf + " not in [0, 1]");
    }
    std::vector<const SceneDef*> scenes;
    if (!o.scenes.empty()) {
        std::stringstream ss(o.scenes);
        for (std::string s; std::getline(ss, s, ',');) {
            const SceneDef* f = nullptr;
            for (const SceneDef& d : kScenes)
                if (s == d.name) f = &d;
            if (!f) throw Error("--scenes: '" + s + "' not one of " + sceneNames());
            scenes.push_back(f);
        }
    }
    std::vector<const QualityDef*> qualities;
    {
        std::stringstream ss(o.qualities);
        for (std::string s; std::getline(ss, s, ',');) {
            const QualityDef* f = nullptr;
            for (const QualityDef& q : kQualities)
                if (s == q.name) f = &q;
            if (!f) throw Error("--qualities: '" + s + "' not one of low, default, high");
            qualities.push_back(f);
        }
        if (qualities.empty()) throw Error("--qualities: empty; give one or more of low, default, high");
    }
    int costW = 0, costH = 0;
    if (!o.costSize.empty()) {
        char x = 0;
        std::stringstream ss(o.costSize);
        if (!(ss >> costW >> x >> costH) || x != 'x' || !ss.eof() || costW < 8 || costH < 8 || costW > 4096 || costH > 4096)
            throw Error("--cost-size '" + o.costSize + "': not WxH with W and H in [8, 4096] (empty: no timing)");
    }
    if (o.repeats < 1 || o.repeats > 1000) throw Error("--repeats " + std::to_string(o.repeats) + " not in [1, 1000]");
    if (o.maxScatterings < 1 || o.maxScatterings > 1000000)
        throw Error("--max-scatterings " + std::to_string(o.maxScatterings) + " not in [1, 1000000]");
    if (o.slabPhotons > 0) {
        // HG g = 0.85, conservative scattering, black ground: the photon tracer against adding-doubling.
        std::printf("slabs, HG g = 0.85, %ld photons a case: transmission (direct + diffuse), fractions of the incident flux\n", o.slabPhotons);
        std::printf("| tau | mu0 | R adding-doubling | T adding-doubling | T path tracer | difference / sigma |\n|---|---|---|---|---|---|\n");
        const cloudref::HenyeyGreenstein hg(0.85);
        const auto m = cloudref::hgMoments(0.85, 300);
        for (double tau : {1.0, 10.0, 50.0, 100.0})
            for (double mu0 : {1.0, 0.5}) {
                const cloudref::SlabMedium slab(0.0, 1000.0, tau / 1000.0);
                cloudref::Scene s;
                s.medium = &slab;
                s.phase = &hg;
                const cloudref::SlabFluxes f = cloudref::slabFluxes(s, {std::sqrt(1.0 - mu0 * mu0), 0.0, -mu0}, o.slabPhotons, o.seed);
                const cloudref::SlabSolution a = cloudref::addingDoubling(tau, 1.0, m, mu0);
                std::printf("| %g | %g | %.4f | %.4f | %.4f ± %.4f | %.1f |\n", tau, mu0, a.reflection, a.transmission, f.transmission,
                            f.transmissionSigma, std::abs(f.transmission - a.transmission) / f.transmissionSigma);
                std::fflush(stdout);
            }
    }
    if (scenes.empty()) return 0;
    Logger log;
    auto ctx = gl::HeadlessContext::create({}, log);
    std::printf("welkin bench cloud-reference: %s, %dx%d, %d paths per pixel\n", ctx->description().c_str(), o.width, o.height, o.paths);
    const auto atm = std::make_shared<const atmosphere::Atmosphere>(o.groundAlbedo >= 0 ? atmosphere::Atmosphere::earthClear().withGroundAlbedo(o.groundAlbedo)
                                                                                         : atmosphere::Atmosphere::earthClear());
    const atmosphere::ReferenceSky refSky(*atm, atmosphere::ReferenceOptions::fast());
    std::vector<Row> rows;
    for (const SceneDef* sd : scenes) {
        const std::string name = sd->name;
        const bool deck = sd->kind == SceneKind::Deck;
        // The scene: the Sun, the camera, the layer.
        const glm::dvec3 sun = sd->sunAlt >= 90 ? glm::dvec3(0.0, 0.0, 1.0) : directionFromAzAlt(sd->sunAz * kDeg, sd->sunAlt * kDeg);
        Camera cam;
        cam.projection = Projection::Perspective;
        cam.width = o.width;
        cam.height = o.height;
        cam.azimuthRad = sd->camAz * kDeg;
        cam.altitudeRad = sd->camAlt * kDeg;
        cam.verticalFovRad = sd->fov * kDeg;

        SkyProcessor p(SkyVars::earth(), log, ProcessorOptions{.astronomy = false});
        p.vars().set(atmosphere::kAtmosphere, atm);
        p.vars().set(keys::sunDirection, sun);
        p.vars().set(keys::moonDirection, glm::dvec3(0.0, 0.0, -1.0));
        if (sd->camHeight > 0.5) p.setObserver({.heightMeters = sd->camHeight});  // the processor writes observer.height_m from it
        const glm::dvec3 camOrigin(0.0, 0.0, sd->camHeight);  // the path tracer's camera
        p.setCamera(cam);
        p.add(std::make_unique<elements::Sky>());
        p.add(std::make_unique<elements::Clouds>());
        p.setAnimationTime(0.0);
        p.setExposure({.automatic = false, .ev100 = 14});
        p.vars().set(ek::reprojection, false);
        p.vars().set(ck::cirrusCoverage, 0.0);  // the reference has no cirrus
        std::vector<gl::Texture> own;  // textures this bench made (kept alive through the frame)
        if (sd->kind == SceneKind::Preset) {
            p.vars().setFromString("clouds.preset", sd->preset);
        } else {
            p.vars().set(ck::bottom, deck ? 1000.0 : 1500.0);
            p.vars().set(ck::top, deck ? 2000.0 : 3500.0);
            p.vars().set(ck::weatherExtent, 20000.0);
            p.vars().set(ck::weatherOffset, glm::dvec2(0.0));
        }
        const double bottom = 1000.0, top = 2000.0;  // the deck's
        if (deck) {
            // The uniform deck of tau = 10 (the element's own test): weather R = 1, base 0, top 1; noise
            // of 1; no erosion; the stratocumulus sheet; scattering from the profile's integral.
            own.push_back(makeTexture(8, false, [](double, double) { return glm::vec4(1, 0, 1, 0); }));
            own.push_back(makeTexture(4, true, [](double, double) { return glm::vec4(1.0f); }));
            own.push_back(makeTexture(8, false, [](double, double) { return glm::vec4(1.0f); }));
            p.vars().set(ck::weatherMap, TextureRef{own[0].id(), GL_TEXTURE_2D, 8, 8, 0});
            p.vars().set(ck::noiseBase, TextureRef{own[1].id(), GL_TEXTURE_3D, 4, 4, 4});
            p.vars().set(ck::noiseDetail, TextureRef{own[1].id(), GL_TEXTURE_3D, 4, 4, 4});
            p.vars().set(ck::curlNoise, TextureRef{own[2].id(), GL_TEXTURE_2D, 8, 8, 0});
            p.vars().set(ck::coverage, 1.0);
            p.vars().set(ck::detailScale, 0.0);
            p.vars().set(ck::cloudType, 0.0);
            const generators::cpu::Image w{1, 1, 1, {1, 0, 1, 0}}, one3{1, 1, 1, {1, 1, 1, 1}};
            const generators::cpu::CloudTextures t{w, one3, one3, one3};
            const auto b = generators::CloudLayerBlock::make(6360e3, bottom, top, 1.0, 0.0, 1.0, 9000.0, 0.0, 20000.0, {0.0, 0.0},
                                                             {0.0, 0.0, 0.0}, generators::kDefaultNoiseBasePeriodM,
                                                             generators::kDefaultNoiseDetailPeriodM, generators::kDefaultCurlPeriodM,
                                                             std::nullopt, 0.0);
            double integral = 0.0;
            for (int i = 0; i < 20000; ++i)
                integral += generators::cpu::cloudDensity(b, t, {0.0, 0.0, bottom + (top - bottom) * (i + 0.5) / 20000},
                                                          generators::CloudLod::Full) * (top - bottom) / 20000;
            p.vars().set(ck::scattering, 10.0 / integral);
        } else if (sd->kind == SceneKind::Blob) {
            // One cumulus 4 km north of the camera, ~2.4 km across: a Gaussian blob on the weather map
            // (20 km square, the camera at its centre), base at the layer's bottom, top at 90 %.
            own.push_back(makeTexture(128, false, [](double u, double v) {
                const double x = (u - 0.5) * 20000.0, y = (v - 0.5) * 20000.0 - 4000.0;
                const double r2 = (x * x + y * y) / (1200.0 * 1200.0);
                return glm::vec4(float(std::exp(-r2 * r2)), 0.0f, 0.9f, 0.0f);
            }));
            p.vars().set(ck::weatherMap, TextureRef{own[0].id(), GL_TEXTURE_2D, 128, 128, 0});
            // The weather map's uv = (xy + offset) / extent: the blob's centre at the origin's uv 0.5.
            p.vars().set(ck::weatherOffset, glm::dvec2(10000.0, 10000.0));
            p.vars().set(ck::coverage, 1.0);
            p.vars().set(ck::cloudType, 1.0);
        }
        p.vars().set(ek::samples, qualities[0]->samples);
        p.vars().set(ek::lightSamples, qualities[0]->lightSamples);
        p.renderFrame();  // the generators run: the textures the path tracer reads back exist
        const SkyVars& v = p.vars();
        const auto block = generators::CloudLayerBlock::from(v);
        const generators::cpu::Image w = readBack(v.get(ck::weatherMap)), nb = readBack(v.get(ck::noiseBase)),
                                     nd = readBack(v.get(ck::noiseDetail)), cn = readBack(v.get(ck::curlNoise));
        const generators::cpu::CloudTextures tex{w, nb, nd, cn};
        const cloudref::CloudFieldMedium medium(block, tex);
        // With --truncate-deg, the peak's fraction f of the scattering treated as unscattered: the
        // truncated phase in a medium of extinction x (1 - f). The cloud pixels are chosen by the
        // full medium's transmittance either way.
        const cloudref::TabulatedPhase mie = cloudref::cloudDropletPhase();
        const cloudref::TruncatedPhase cut = o.truncateDeg > 0 ? cloudref::truncatePhase(mie, o.truncateDeg * kDeg) : cloudref::TruncatedPhase{mie, 0.0};
        auto scaledBlock = block;
        scaledBlock.shape[2] *= float(1.0 - cut.removedFraction);
        const cloudref::CloudFieldMedium scaledMedium(scaledBlock, tex);
        const cloudref::TabulatedPhase& phase = cut.phase;

        // The lights: the Sun above the layer, the clear sky (tabulated from the ground), the ground.
        const glm::dvec3 e0 = v.get(keys::sunIlluminance);
        const double layerMid = 0.5 * (v.get(ck::bottom) + v.get(ck::top));
        const glm::dvec3 sunE = e0 * refSky.transmittance(layerMid, sun);
        const int na = 72, nz = 24;
        std::vector<glm::dvec3> skyTab(size_t(na) * nz);
        for (int j = 0; j < nz; ++j)
            for (int i = 0; i < na; ++i)
                skyTab[size_t(j) * na + i] = refSky.radiance(0.0, directionFromAzAlt(2.0 * M_PI * (i + 0.5) / na, 0.5 * M_PI * (j + 0.5) / nz), sun);
        cloudref::Scene s;
        s.medium = &scaledMedium;
        s.phase = &phase;
        s.maxScatterings = o.maxScatterings;
        const glm::dvec3 ga = atm->rgb().groundAlbedo;
        s.ground = {cloudref::Ground::Kind::Sphere, 0.0, 6360e3, (ga.r + ga.g + ga.b) / 3.0};
        s.lights.sunDirection = sun;
        s.lights.sunIrradiance = sunE;
        s.lights.sky = [&](const glm::dvec3& d) {
            const double az = std::atan2(d.x, d.y), alt = std::asin(std::clamp(d.z, 0.0, 1.0));
            const int i = std::clamp(int(std::floor((az < 0 ? az + 2.0 * M_PI : az) / (2.0 * M_PI) * na)), 0, na - 1);
            const int j = std::clamp(int(std::floor(alt / (0.5 * M_PI) * nz)), 0, nz - 1);
            return skyTab[size_t(j) * na + i];
        };
        // The reference image along the camera's own pixel rays.
        std::vector<glm::dvec3> ref(size_t(o.width) * o.height, glm::dvec3(0.0));
        std::vector<double> sig(ref.size(), 0.0), trans(ref.size(), 1.0);
        const auto t0 = std::chrono::steady_clock::now();
        {
            std::atomic<size_t> next{0};
            auto work = [&] {
                for (size_t i = next++; i < ref.size(); i = next++) {
                    const int x = int(i % o.width), y = int(i / o.width);
                    const auto d = cam.directionAt({x + 0.5, y + 0.5});
                    if (!d) continue;
                    const cloudref::Estimate e = cloudref::radiance(s, camOrigin, *d, o.paths, o.seed, i);
                    ref[i] = e.mean;
                    sig[i] = lum(e.sigma);
                    cloudref::Rng rng(o.seed + 7, i);
                    double tr = 0.0;
                    for (int k = 0; k < 4; ++k) tr += 0.25 * cloudref::ratioTrackingTransmittance(medium, camOrigin, *d, 1e7, rng);
                    trans[i] = tr;
                }
            };
            std::vector<std::thread> pool;
            for (int k = 1; k < o.threads; ++k) pool.emplace_back(work);
            work();
            for (auto& th : pool) th.join();
        }
        // The air between the camera and the clouds (on unless --no-reference-air), as the real-time
        // frame has it: the path tracer's clouds have no air in front of them. Along each camera ray
        // the cloud's transmittance T_c and its transmittance-weighted mean scattering distance d
        // are marched (the full medium, 25 m steps or 4000 per interval, to 100 km); the clear sky's
        // light in front of the cloud is the reference sky's radiance from the camera less the
        // share it sees beyond d, L_front = L_sky(camera) - T_seg L_sky(d) (single and multiple
        // scattering, exact for the clear air; the cloud's shadow on that air is not in it), T_seg
        // the air's transmittance over [0, d]. The pixel becomes
        // (1 - T_c) L_front + T_seg (L_ref - T_c L_tab) + T_c L_tab, L_tab the sky behind the cloud
        // that the path tracer added (its table: unchanged, its air is already in it). Only for the
        // fair field's scenes (clouds 5-60 km away, the Sun not behind them): behind a single
        // cumulus the air in front lies in the cloud's own shadow, under a deck in the deck's, and
        // this clear-sky in-scatter (the aureole's, near the Sun) would be far too bright there;
        // the 4 km to the single cumulus and the decks overhead keep the reference without air.
        // Since 2026-11-27 afternoon also the cumulus seen from 6 km above: the air between the
        // aircraft and the cloud is sunlit (the cloud below it), and the real-time frame has it.
        const bool field = sd->kind == SceneKind::Preset && std::string(sd->preset) == "fair";
        const bool fromAbove = std::string(sd->name) == "cumulus-from-above";
        if (o.referenceAir && (field || fromAbove)) {
            const double R = medium.planetRadiusM();
            const glm::dvec3 origin(0.0, 0.0, std::max(0.5, sd->camHeight));
            for (size_t i = 0; i < ref.size(); ++i) {
                const int x = int(i % o.width), y = int(i / o.width);
                const auto d = cam.directionAt({x + 0.5, y + 0.5});
                if (!d) continue;
                cloudref::Interval iv[4];
                const int n = medium.support(origin, *d, 1e5, iv);
                double T = 1.0, wSum = 0.0, wd = 0.0;
                for (int k = 0; k < n; ++k) {
                    const double len = iv[k].t1 - iv[k].t0;
                    const int steps = std::clamp(int(std::ceil(len / 25.0)), 1, 4000);
                    const double dt = len / steps;
                    for (int j = 0; j < steps; ++j) {
                        const double t = iv[k].t0 + (j + 0.5) * dt;
                        const double a = std::exp(-medium.extinctionPerM(origin + t * *d) * dt);
                        wSum += T * (1.0 - a);
                        wd += T * (1.0 - a) * t;
                        T *= a;
                    }
                }
                if (wSum < 1e-4) continue;  // no cloud on this ray: the sky's table has its air
                const double dm = wd / wSum;
                const glm::dvec3 pc = glm::dvec3(0.0, 0.0, R) + origin + dm * *d;
                const double r = glm::length(pc), h = r - R;
                const glm::dvec3 up = pc / r;
                // The view and the Sun in the local frame at the point (same zenith angles and angle between them).
                const double mu = std::clamp(glm::dot(up, *d), -1.0, 1.0), mus = std::clamp(glm::dot(up, sun), -1.0, 1.0), nu = glm::dot(*d, sun);
                const double sv = std::sqrt(std::max(1.0 - mu * mu, 1e-12));
                const glm::dvec3 dl(sv, 0.0, mu);
                const double ax = (nu - mu * mus) / sv;
                const glm::dvec3 sl(ax, std::sqrt(std::max(0.0, 1.0 - mus * mus - ax * ax)), mus);
                // The segment's transmittance as the ratio of two rays to the top of the atmosphere:
                // looking down (the transmittance of a ray that meets the ground is 0) the reversed
                // rays, from the point and from the camera upwards.
                const bool down = d->z < 0.0;
                const glm::dvec3 t0v = down ? refSky.transmittance(h, -dl) : refSky.transmittance(origin.z, *d);
                const glm::dvec3 t1v = down ? refSky.transmittance(origin.z, -*d) : refSky.transmittance(h, dl);
                glm::dvec3 tSeg(1.0);
                for (int c = 0; c < 3; ++c) tSeg[c] = t1v[c] > 1e-12 ? std::clamp(t0v[c] / t1v[c], 0.0, 1.0) : 0.0;
                const glm::dvec3 front = glm::max(refSky.radiance(origin.z, *d, sun) - tSeg * refSky.radiance(h, dl, sl), glm::dvec3(0.0));
                const glm::dvec3 tab = s.lights.sky(*d);
                ref[i] = (1.0 - T) * front + tSeg * (ref[i] - T * tab) + T * tab;
                sig[i] *= lum(tSeg);  // the cloud's own light is what is noisy; lum(1, 1, 1) = 1
            }
        }
        const double refSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();

        // Where the error is: each cloud pixel's region, from the density's CPU twin (the full
        // medium). The visible point is where the camera ray's optical depth reaches 1 (the last
        // cloud sample if it never does); its depth towards the Sun is marched in 20 m steps over at
        // most 5 km. Regions, first match: edge (a clear pixel among the 8 neighbours, as the
        // edge/inside ratio), base (the visible point in the lowest 10 % of the layer), sunlit (the
        // depth towards the Sun < 2), shaded (the rest).
        std::vector<int> region(ref.size(), -1);
        {
            const double R = medium.planetRadiusM(), bottomM = v.get(ck::bottom), topM = v.get(ck::top);
            const glm::dvec3 origin = camOrigin;
            auto clear = [&](int x, int y) { return x >= 0 && y >= 0 && x < o.width && y < o.height && trans[size_t(y) * o.width + x] >= 0.5; };
            for (size_t i = 0; i < ref.size(); ++i) {
                if (trans[i] >= 0.5) continue;
                const int x = int(i % o.width), y = int(i / o.width);
                bool edge = false;
                for (int j = -1; j <= 1; ++j)
                    for (int k = -1; k <= 1; ++k) edge = edge || clear(x + k, y + j);
                if (edge) {
                    region[i] = 0;
                    continue;
                }
                const auto d = cam.directionAt({x + 0.5, y + 0.5});
                if (!d) continue;
                cloudref::Interval iv[4];
                const int n = medium.support(origin, *d, 1e5, iv);
                double tau = 0.0;
                glm::dvec3 pv = origin;
                for (int k = 0; k < n && tau < 1.0; ++k)
                    for (double t = iv[k].t0 + 5.0; t < iv[k].t1 && tau < 1.0; t += 10.0) {
                        const glm::dvec3 q = origin + t * *d;
                        const double e = medium.extinctionPerM(q);
                        if (e > 0) pv = q;
                        tau += e * 10.0;
                    }
                const double h = glm::length(pv + glm::dvec3(0.0, 0.0, R)) - R;
                double tauSun = 0.0;
                for (double t = 10.0; t < 5000.0 && tauSun < 2.0; t += 20.0) tauSun += medium.extinctionPerM(pv + t * sun) * 20.0;
                region[i] = h < bottomM + 0.1 * (topM - bottomM) ? 1 : tauSun < 2.0 ? 2 : 3;
            }
        }

        // Per quality: the real-time frame at the reference's size, its error over the cloud pixels
        // (the path-traced camera ray's cloud transmittance < 0.5, farther than 3 deg from the Sun:
        // the real-time frame has the solar disk, the reference's Sun is a delta light), and the
        // frame's cost at --cost-size against the trivial pass, timed alternately.
        const double cosSunCut = std::cos(3.0 * kDeg);
        for (const QualityDef* q : qualities) {
        p.vars().set(ek::samples, q->samples);
        p.vars().set(ek::lightSamples, q->lightSamples);
        p.setCamera(cam);
        p.renderFrame();
        p.renderFrame();
        const Image rt = p.readHdr();
        Row r;
        r.scene = name;
        r.quality = q->name;
        r.samples = q->samples;
        r.lightSamples = q->lightSamples;
        r.refSeconds = refSeconds;
        std::vector<double> rel;
        double se = 0.0, sRef = 0.0, sRt = 0.0, sNoise = 0.0, sVar = 0.0;
        struct RegionSums {
            double se = 0, var = 0, ref = 0, rt = 0;
            int n = 0;
            std::vector<double> rel;
        };
        std::vector<RegionSums> regions(4);
        for (size_t i = 0; i < ref.size(); ++i) {
            if (trans[i] >= 0.5) continue;
            const int x = int(i % o.width), y = int(i / o.width);
            const auto d = cam.directionAt({x + 0.5, y + 0.5});
            if (d && glm::dot(*d, sun) > cosSunCut) continue;
            const double yr = lum(ref[i]);
            const double yt = 0.2126 * rt.at(x, y, 0) + 0.7152 * rt.at(x, y, 1) + 0.0722 * rt.at(x, y, 2);
            se += (yt - yr) * (yt - yr);
            sRef += yr;
            sRt += yt;
            sNoise += yr > 0 ? sig[i] / yr : 0.0;
            sVar += sig[i] * sig[i];
            rel.push_back(yr > 0 ? std::abs(yt / yr - 1.0) : 0.0);
            ++r.pixels;
            if (region[i] >= 0) {
                RegionSums& g = regions[size_t(region[i])];
                g.se += (yt - yr) * (yt - yr), g.var += sig[i] * sig[i], g.ref += yr, g.rt += yt, ++g.n;
                g.rel.push_back(yr > 0 ? std::abs(yt / yr - 1.0) : 0.0);
            }
        }
        std::printf("%-14s %-7s by region:", name.c_str(), q->name);
        for (size_t k = 0; k < regions.size(); ++k) {
            RegionSums& g = regions[k];
            if (g.n == 0) {
                std::printf("  %s none", kRegionNames[k]);
                continue;
            }
            std::sort(g.rel.begin(), g.rel.end());
            std::printf("  %s %d px bias %.2f RMS %.0f %% p95 %.0f %%", kRegionNames[k], g.n, g.rt / g.ref,
                        100 * std::sqrt(std::max(0.0, g.se - g.var) / g.n) / (g.ref / g.n), 100 * g.rel[std::min(g.rel.size() - 1, size_t(0.95 * double(g.rel.size())))]);
        }
        std::printf("\n");
        if (r.pixels == 0) throw Error("bench cloud-reference: scene " + name + " has no cloud pixels");
        // The silhouette against the inside: the mean luminance of the cloud pixels next to a clear
        // one (8-neighbourhood) over that of the pixels >= 3 px from any clear one, in each image
        // (a silver lining when > 1; the Sun's 3 deg excluded as above).
        {
            auto isCloud = [&](int x, int y) { return x >= 0 && y >= 0 && x < o.width && y < o.height && trans[size_t(y) * o.width + x] < 0.5; };
            double eRef = 0, eRt = 0, cRef = 0, cRt = 0;
            int ne = 0, nc = 0;
            for (int y = 0; y < o.height; ++y)
                for (int x = 0; x < o.width; ++x) {
                    if (!isCloud(x, y)) continue;
                    const auto d = cam.directionAt({x + 0.5, y + 0.5});
                    if (d && glm::dot(*d, sun) > cosSunCut) continue;
                    int dist = 1;
                    for (bool inside = true; inside && dist <= 3; dist += inside ? 1 : 0)
                        for (int j = -dist; j <= dist && inside; ++j)
                            for (int i = -dist; i <= dist && inside; ++i)
                                if (!isCloud(x + i, y + j) && x + i >= 0 && y + j >= 0 && x + i < o.width && y + j < o.height) inside = false;
                    const double yr = lum(ref[size_t(y) * o.width + x]);
                    const double yt = 0.2126 * rt.at(x, y, 0) + 0.7152 * rt.at(x, y, 1) + 0.0722 * rt.at(x, y, 2);
                    if (dist == 1) eRef += yr, eRt += yt, ++ne;
                    else if (dist > 3) cRef += yr, cRt += yt, ++nc;
                }
            if (ne > 0 && nc > 0) {
                r.edgeRef = (eRef / ne) / (cRef / nc);
                r.edgeRt = (eRt / ne) / (cRt / nc);
            }
        }
        std::sort(rel.begin(), rel.end());
        r.meanRef = sRef / r.pixels;
        r.meanRt = sRt / r.pixels;
        r.rms = std::sqrt(se / r.pixels) / r.meanRef;
        // E[(Y_rt - Y_ref)^2] = (Y_rt - Y_true)^2 + sigma^2: the reference's variance removed.
        r.rmsDenoised = std::sqrt(std::max(0.0, se - sVar) / r.pixels) / r.meanRef;
        r.p95 = rel[std::min(rel.size() - 1, size_t(0.95 * double(rel.size())))];
        r.bias = r.meanRt / r.meanRef;
        r.noise = sNoise / r.pixels;
        if (costW > 0) {
            Camera big = cam;
            big.width = costW;
            big.height = costH;
            p.setCamera(big);
            TrivialPass trivial(costW, costH);
            p.renderFrame();  // the targets at this size exist before the timing
            std::vector<double> fms, tms, ratio;
            for (int k = 0; k < o.repeats; ++k) {
                const double t = medianMs(1, [&] { trivial.draw(); });
                const double f = medianMs(1, [&] { p.renderFrame(); });
                tms.push_back(t), fms.push_back(f), ratio.push_back(f / t);
            }
            r.frameMs = median(fms);
            r.trivialMs = median(tms);
            r.ratioTrivial = median(ratio);
        }
        rows.push_back(r);
        std::printf("%-14s %-7s cloud px %5d  mean Y ref %9.0f rt %9.0f cd/m^2  bias %.3f  RMS %5.1f %% (noise removed %5.1f %%)  p95 %5.1f %%  ref noise %4.1f %%  (ref %.0f s)  frame %.1f ms = %.1fx trivial  edge/inside ref %.2f rt %.2f\n",
                    name.c_str(), r.quality.c_str(), r.pixels, r.meanRef, r.meanRt, r.bias, 100 * r.rms, 100 * r.rmsDenoised, 100 * r.p95, 100 * r.noise, refSeconds,
                    r.frameMs, r.ratioTrivial, r.edgeRef, r.edgeRt);
        std::fflush(stdout);
        if (!o.out.empty() && q == qualities.front()) {
            // Side by side, one exposure: 1 - exp(-L / (the reference cloud pixels' mean Y)), sRGB-encoded.
            const int gap = 2;
            Image sbs{.width = 2 * o.width + gap, .height = o.height, .channels = 3, .pixels = {}};
            sbs.pixels.assign(size_t(sbs.width) * sbs.height * 3, 1.0f);
            auto enc = [&](double L) {
                const double c = 1.0 - std::exp(-L / (1.5 * r.meanRef));
                const double s8 = c <= 0.0031308 ? 12.92 * c : 1.055 * std::pow(c, 1.0 / 2.4) - 0.055;
                return float(std::clamp(s8, 0.0, 1.0));
            };
            for (int y = 0; y < o.height; ++y)
                for (int x = 0; x < o.width; ++x)
                    for (int c = 0; c < 3; ++c) {
                        sbs.at(x, y, c) = enc(ref[size_t(y) * o.width + x][c]);
                        sbs.at(x + o.width + gap, y, c) = enc(rt.at(x, y, c));
                    }
            const std::string path = (std::filesystem::path(o.out) / ("cloud_reference_" + name + ".png")).string();
            writeImage(sbs, path);
            std::printf("wrote %s\n", path.c_str());
        }
        }
    }
    if (!o.csv.empty()) {
        CsvWriter f(o.csv, {"scene", "quality", "samples", "light_samples", "cloud_pixels", "mean_ref_cd_m2", "mean_rt_cd_m2", "bias", "rms_rel",
                            "rms_rel_noise_removed", "p95_rel", "ref_noise_rel", "ref_seconds", "frame_ms", "trivial_ms", "ratio_trivial", "edge_inside_ref",
                            "edge_inside_rt"});
        f.comment("welkin bench cloud-reference, " + std::to_string(o.width) + "x" + std::to_string(o.height) + ", " +
                  std::to_string(o.paths) + " paths per pixel, seed " + std::to_string(o.seed) + ", " +
                  (o.referenceAir ? "the air in front of the fair field's clouds in the reference, " : "no air in front of the reference's clouds, ") + ctx->description());
        for (const Row& r : rows)
            f.row(r.scene, r.quality, r.samples, r.lightSamples, r.pixels, r.meanRef, r.meanRt, r.bias, r.rms, r.rmsDenoised, r.p95, r.noise,
                  r.refSeconds, r.frameMs, r.trivialMs, r.ratioTrivial, r.edgeRef, r.edgeRt);
        f.close();
        std::printf("wrote %s\n", o.csv.c_str());
    }
    return 0;
}

bench::CommandBenchRegistrar reg({"cloud-reference", "the real-time clouds against the path-traced reference: RMS and 95th-percentile luminance error",
                   [](CLI::App& sub) {
                       auto o = std::make_shared<CloudReferenceOptions>();  // the action below owns it
                       sub.add_option("--width", o->width, "image width, px, [8, 1024]")->capture_default_str();
                       sub.add_option("--height", o->height, "image height, px, [8, 1024]")->capture_default_str();
                       sub.add_option("--paths", o->paths, "path-traced paths per pixel, [1, 65536]")->capture_default_str();
                       sub.add_option("--threads", o->threads, "path tracer threads, [1, 64] (results do not depend on it)")->capture_default_str();
                       sub.add_option("--seed", o->seed, "path tracer seed")->capture_default_str();
                       sub.add_option("--scenes", o->scenes, "comma list of " + sceneNames() + " (empty: none)")->capture_default_str();
                       sub.add_option("--qualities", o->qualities, "comma list of low (16 samples, 3 light samples), default (48, 6), high (128, 12)")->capture_default_str();
                       sub.add_option("--cost-size", o->costSize, "WxH at which each quality's frame is timed against a trivial pass (empty: not timed)")->capture_default_str();
                       sub.add_option("--max-scatterings", o->maxScatterings, "the path tracer's scattering orders kept (1: single scattering), [1, 1e6]")->capture_default_str();
                       sub.add_option("--repeats", o->repeats, "timed frame pairs per row (median), [1, 1000]")->capture_default_str();
                       sub.add_option("--out", o->out, "directory for the side-by-side PNGs (empty: none)")->capture_default_str();
                       sub.add_option("--truncate-deg", o->truncateDeg, "the path tracer's droplet phase: its forward peak truncated at this angle, the medium's extinction scaled (delta-M; less noise), [0, 20], 0: the full phase")->capture_default_str();
                       sub.add_option("--ground-albedo", o->groundAlbedo, "the atmosphere's ground albedo for both images (the real-time clouds' bases and the path tracer's ground), [0, 1]; default: the default atmosphere's (0.1)");
                       sub.add_flag("!--no-reference-air", o->referenceAir, "leave the air between the camera and the clouds out of the path-traced reference of the fair field's scenes and cumulus-from-above (the real-time frame keeps it)");
                       sub.add_option("--csv", o->csv, "write the table as CSV (empty: none)")->capture_default_str();
                       sub.add_option("--slab-photons", o->slabPhotons, "> 0: first print the slab table (path tracer against adding-doubling) with this many photons a case, [0, 1e8]")
                           ->capture_default_str();
                       return [o]() { return run(*o); };
                   },
                   // The table `welkin bench all` writes into docs/BENCHMARKS.md from this bench.
                   {{.element = "clouds",
                     .title = "Clouds: accuracy and cost against the path tracer, by scene and quality",
                     .what = "The real-time clouds (per-pixel march) against the Monte Carlo path tracer on the fixed scenes of "
                             "skyelements/clouds/README.md (a uniform deck, one cumulus lit from the side, from behind and from above, the fair "
                             "field at noon and at sunset, the overcast deck, the cumulus seen from 6 km above, the deck from inside): RMS and 95th-percentile luminance error over the cloud "
                             "pixels, at 40x22 px (the reference's own noise included), and each quality's frame at 320x180 against a "
                             "trivial pass. Qualities: low 16 samples and 3 light samples, default 48 and 6, high 128 and 12.",
                     .args = {"--scenes", "deck,cumulus-side,cumulus-behind,cumulus-above,fair-noon,fair-sunset,overcast,cumulus-from-above,deck-inside", "--qualities",
                              "low,default,high", "--width", "40", "--height", "22", "--paths", "64", "--truncate-deg", "3", "--cost-size",
                              "320x180", "--repeats", "3"},
                     .quickArgs = {"--scenes", "cumulus-side", "--qualities", "default", "--width", "24", "--height", "14", "--paths", "16",
                                   "--truncate-deg", "3", "--cost-size", "160x90", "--repeats", "1"},
                     .columns = {"scene", "quality", "cloud_pixels:cloud px", "bias", "rms_rel*100:RMS error %",
                                 "rms_rel_noise_removed*100:RMS, noise removed %", "p95_rel*100:p95 error %", "ref_noise_rel*100:reference noise %",
                                 "ratio_trivial:x trivial pass"}}}});

}  // namespace
}  // namespace welkin::cli
