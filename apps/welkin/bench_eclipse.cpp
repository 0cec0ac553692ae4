// welkin bench eclipse: the solar eclipse's sky (issue 21 item 1, docs/eclipse.md). (1) Frame
// cost: the whole frame (astronomy, the sky's tables, the Sky pass; perspective 1280x720 towards
// the Sun) at mid-totality over Burgos (2026-08-12 18:29 UTC) with the eclipse on and off
// (astro.eclipses), time running 1 s per frame so the eclipse's table is rebuilt every frame;
// frames alternated so machine load hits both alike. Target: <= 1.5x. (2) Accuracy at
// mid-totality: the real-time model (CPU twin, cpu::integrateEclipse, which the GPU pass follows)
// and the GPU's table (the rendered sky) against the reference integrator extended to the eclipse
// (atmosphere::eclipseReferenceRadiance), luminance per lux of the Sun, for directions around the
// sky; and the same directions without the eclipse (the model's clear-sky error, for scale).
#include "bench_util.hpp"
#include "command.hpp"

#include <welkin/astro/astro_keys.hpp>
#include <welkin/elements/sky.hpp>
#include <welkin/error.hpp>
#include <welkin/generators/eclipse_reference.hpp>
#include <welkin/generators/lights.hpp>
#include <welkin/generators/sky_luts.hpp>
#include <welkin/gl/context.hpp>
#include <welkin/keys.hpp>
#include <welkin/processor.hpp>
#include <welkin/time.hpp>

#include <epoxy/gl.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

namespace welkin::cli {
namespace {

constexpr double kDeg = M_PI / 180;

struct EclipseBenchOptions {
    int repeats = 10;
    int width = 1280, height = 720;
    bool accuracy = true;
    std::string sweep;  // comma list of multiple-scattering disk radii (km) to compare (model tuning)
};

double Y(const glm::dvec3& c) { return 0.2126 * c.r + 0.7152 * c.g + 0.0722 * c.b; }

int run(const EclipseBenchOptions& o) {
    if (o.repeats < 1 || o.repeats > 1000) throw Error("--repeats " + std::to_string(o.repeats) + " not in [1, 1000]");
    if (o.width < 16 || o.width > 8192 || o.height < 16 || o.height > 8192) throw Error("--width/--height not in [16, 8192]");
    Logger log;
    auto ctx = gl::HeadlessContext::create({}, log);
    std::printf("welkin bench eclipse (%s)\n\n", ctx->description().c_str());
    const UtcInstant t0 = UtcInstant::parse("2026-08-12T18:29:00Z");
    auto makeProcessor = [&](bool eclipses) {
        auto p = std::make_unique<SkyProcessor>(SkyVars::earth(), log, ProcessorOptions{.timing = false});
        p->setObserver({.latitudeRad = 42.34 * kDeg, .longitudeRad = -3.70 * kDeg, .heightMeters = 0});
        p->setTime(t0);
        p->vars().set(astro::keys::eclipses, eclipses);
        Camera cam;
        cam.projection = Projection::Perspective;
        cam.width = o.width;
        cam.height = o.height;
        cam.verticalFovRad = 60 * kDeg;
        p->add(std::make_unique<elements::Sky>());
        p->renderFrame();
        const glm::dvec3 s = p->vars().get(keys::sunDirection);
        cam.azimuthRad = std::atan2(s.x, s.y);
        cam.altitudeRad = std::asin(s.z);
        p->setCamera(cam);
        for (int i = 0; i < 3; ++i) p->renderFrame();  // programs, tables
        return p;
    };
    // (1) Frame cost.
    auto on = makeProcessor(true), off = makeProcessor(false);
    int frame = 0;
    auto step = [&](SkyProcessor& p) {
        p.setTime(t0.plusSeconds(double(frame / 2)));
        ++frame;
        p.renderFrame();
    };
    const std::vector<double> ms = alternatedMedianMs(o.repeats, {[&] { step(*off); }, [&] { step(*on); }});
    const bool drew = on->vars().get(generators::skykeys::eclipseViewLut).id != 0;
    std::printf("| frame (%dx%d, perspective 60 deg towards the Sun) | ms |\n|---|---|\n", o.width, o.height);
    std::printf("| normal sky (astro.eclipses=false) | %.2f |\n| eclipse sky (mid-totality, table rebuilt every frame%s) | %.2f |\n", ms[0],
                drew ? "" : ", NOT DRAWN", ms[1]);
    const double ratio = ms[1] / ms[0];
    std::printf("| ratio | %.2f (target <= 1.5: %s) |\n\n", ratio, ratio <= 1.5 ? "met" : "NOT met");
    if (!o.accuracy) return 0;
    // (2) Accuracy at mid-totality.
    SkyVars& v = on->vars();
    using namespace generators;
    const SkyModel m = SkyModel::fromVars(v);
    const SkyQuality q = SkyQuality::preset(effectiveQuality(v));
    const Lut2D T = cpu::transmittanceLut(m, q);
    const cpu::MsField MS = cpu::msField(m, q, T);
    const glm::dvec3 sun = glm::normalize(v.get(keys::sunDirection));
    cpu::EclipseGeometry g{.moonPos = v.get(astro::keys::moonPosition), .moonRadius = astro::keys::kMoonRadiusMeters,
                           .sunPos = sun * v.get(astro::keys::sunDistance), .sunRadius = kSunRadiusMeters, .msRadius = kEclipseMsRadiusMeters};
    std::printf("mid-totality: sun.eclipse_fraction %.5f, Sun at %.2f deg altitude; reference: eclipseReferenceRadiance (defaults)\n\n",
                v.get(keys::sunEclipseFraction), std::asin(sun.z) / kDeg);
    std::printf("| direction (az from the Sun, altitude) | reference, eclipse (cd/m^2 per lx) | model / reference, eclipse | "
                "reference, no eclipse | model / reference, no eclipse | eclipse / no eclipse (reference) |\n|---|---|---|---|---|---|\n");
    const double sunAz = std::atan2(sun.x, sun.y);
    double worst = 0.0, worstClear = 0.0;
    for (auto [daz, alt] : {std::pair{0.0, 90.0}, std::pair{0.0, 2.0}, std::pair{90.0, 2.0}, std::pair{180.0, 2.0}, std::pair{0.0, 30.0},
                            std::pair{180.0, 30.0}, std::pair{90.0, 45.0}}) {
        const glm::dvec3 dir = directionFromAzAlt(sunAz + daz * kDeg, alt * kDeg);
        atmosphere::EclipseReferenceOptions ro;
        const double ref = Y(atmosphere::eclipseReferenceRadiance(m, T, MS, 0.0, dir, sun, g, ro).radiance);
        ro.eclipse = false;
        const double refClear = Y(atmosphere::eclipseReferenceRadiance(m, T, MS, 0.0, dir, sun, g, ro).radiance);
        const double model = Y(cpu::radiance(m, cpu::integrateEclipse(m, T, MS, 0.0, dir, sun, g, 256, false, m.sunAngularRadius),
                                             glm::dot(dir, sun)));
        cpu::EclipseGeometry far = g;
        far.moonPos = -g.moonPos;  // the Moon on the far side: no shadow
        const double modelClear = Y(cpu::radiance(m, cpu::integrateEclipse(m, T, MS, 0.0, dir, sun, far, 256, false, m.sunAngularRadius),
                                                  glm::dot(dir, sun)));
        std::printf("| %+.0f, %.0f deg | %.3g | %.3f | %.3g | %.3f | %.2e |", daz, alt, ref, model / ref, refClear, modelClear / refClear,
                    ref / refClear);
        for (size_t a = 0, b; a < o.sweep.size(); a = b + 1) {
            b = o.sweep.find(',', a);
            if (b == std::string::npos) b = o.sweep.size();
            cpu::EclipseGeometry gs = g;
            gs.msRadius = std::stod(o.sweep.substr(a, b - a)) * 1e3;
            const double ms = Y(cpu::radiance(m, cpu::integrateEclipse(m, T, MS, 0.0, dir, sun, gs, 256, false, m.sunAngularRadius),
                                              glm::dot(dir, sun)));
            std::printf(" l=%s km: %.3f |", o.sweep.substr(a, b - a).c_str(), ms / ref);
        }
        std::printf("\n");
        std::fflush(stdout);
        worst = std::max(worst, std::abs(model / ref - 1.0));
        worstClear = std::max(worstClear, std::abs(modelClear / refClear - 1.0));
    }
    std::printf("\nlargest |model / reference - 1|: eclipse %.1f %%, no eclipse %.1f %%\n", 100 * worst, 100 * worstClear);
    return 0;
}

BenchRegistrar reg("eclipse", "the solar eclipse's sky: frame cost against a normal sky, and its error against the reference", [](CLI::App& sub) {
    auto* o = new EclipseBenchOptions();
    sub.add_option("--repeats", o->repeats, "timed frames per configuration (median reported), [1, 1000]")->capture_default_str();
    sub.add_option("--width", o->width, "frame width, px, [16, 8192]")->capture_default_str();
    sub.add_option("--height", o->height, "frame height, px, [16, 8192]")->capture_default_str();
    sub.add_option("--ms-radius-sweep", o->sweep, "also the model / reference for these multiple-scattering disk radii, km (comma list)");
    sub.add_option("--accuracy", o->accuracy, "also measure the error against the reference (minutes on the CPU)")->capture_default_str();
    return [o]() { return run(*o); };
});

}  // namespace
}  // namespace welkin::cli
