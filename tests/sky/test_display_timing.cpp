// Hidden timing (not run by CI: `welkin_tests "[display_timing]"`): issue 22's displayed frame
// at 1280x720 with each of this revision's cuts on and off, in one process, frames alternated,
// process CPU time (llvmpipe's threads are the process's; on a machine shared with other jobs
// the wall time swings by 2-5x, the CPU time much less). Each row is a ratio to a trivial
// fullscreen pass (a uniform field composited, minus the empty frame) timed in the same rounds.
#include <catch2/catch.hpp>

#include "elements_present.hpp"
#include "cpu_timing.hpp"
#include "gl_test_context.hpp"
#include "uniform_field.hpp"

#include <epoxy/gl.h>

#include <welkin/elements/registry.hpp>
#include <welkin/gl/objects.hpp>
#include <welkin/keys.hpp>
#include <welkin/processor.hpp>
#include <welkin/time.hpp>
#ifdef WELKIN_HAS_ELEMENT_nightsky
#include <welkin/elements/nightsky.hpp>
#endif

#include <algorithm>
#include <cstdio>
#include <ctime>
#include <functional>
#include <memory>
#include <numbers>
#include <string>
#include <vector>

using namespace welkin;

namespace {
// Draws nothing without saying so: the elements after it are composited as before this revision
// (the Sky blended, with its transmittance, after a night sky that skipped its pass by day).
class Silent final : public SkyElement {
public:
    Silent() : SkyElement("silent") {}

private:
    void doInit(InitContext&) override {}
    void doRender(const FrameContext&) override {}
    void doRelease() override {}
};
}  // namespace

#if defined(WELKIN_HAS_ELEMENT_nightsky) && defined(WELKIN_HAS_ELEMENT_stars) && defined(WELKIN_HAS_ELEMENT_planet)
TEST_CASE("Display timing: the night sky's fast paths, the Sky unblended by day, one tone map per displayed frame", "[.][display_timing]") {
    test::glContext();
    constexpr double kDeg = std::numbers::pi / 180.0;
    const int w = 1280, h = 720;
    Camera cam;
    cam.azimuthRad = std::numbers::pi;  // the bench display's view: south, 30 deg up, 60 deg
    cam.altitudeRad = 30 * kDeg;
    cam.verticalFovRad = 60 * kDeg;
    cam.width = w;
    cam.height = h;
    gl::Texture2D display(w, h, GL_RGBA8), ldr(w, h, GL_RGBA8);
    auto displayFbo = gl::Framebuffer::create(), ldrFbo = gl::Framebuffer::create();
    displayFbo.attach(GL_COLOR_ATTACHMENT0, display);
    ldrFbo.attach(GL_COLOR_ATTACHMENT0, ldr);

    auto make = [&](const char* when, std::function<void(SkyProcessor&)> add) {
        auto p = std::make_unique<SkyProcessor>();
        p->setObserver({.latitudeRad = 35.9 * kDeg, .longitudeRad = 14.5 * kDeg, .heightMeters = 50});
        p->setTime(UtcInstant::parse(when));
        p->setCamera(cam);
        p->setAnimationTime(0.0);
        p->setExposure({.automatic = true});
        add(*p);
        return p;
    };
    auto defaults = [](SkyProcessor& p) {
        for (const char* e : {"nightsky", "stars", "planet", "sky"}) p.add(elements::makeElement(e));
    };
    auto night = [](bool fast) {
        return [fast](SkyProcessor& p) {
            auto n = std::make_unique<elements::NightSky>();
            n->setFastPaths(fast);
            p.add(std::move(n));
            p.add(std::make_unique<test::Attenuator>());  // under a Sky, without the Sky's cost
        };
    };
    const char* kDay = "2026-06-21T10:00:00Z";
    const char* kNight = "2026-08-12T22:00:00Z";
    struct Row {
        std::string what;
        std::unique_ptr<SkyProcessor> p;
        std::function<void(SkyProcessor&)> frame;
        std::vector<double> ms;
    };
    auto renderFrame = [](SkyProcessor& p) { p.renderFrame(); };
    auto displayed = [&](SkyProcessor& p) {
        p.renderFrame();
        p.toneMapInto(displayFbo.id());
    };
    auto displayedTwice = [&](SkyProcessor& p) {  // the viewer before: renderFrame's own tone map, then the window's
        p.renderFrame();
        p.toneMapInto(ldrFbo.id());
        p.toneMapInto(displayFbo.id());
    };
    std::vector<Row> rows;
    rows.push_back({"empty (clear, meter)", make(kNight, [](SkyProcessor&) {}), renderFrame, {}});
    rows.push_back({"trivial (uniform field)", make(kNight, [](SkyProcessor& p) { p.add(std::make_unique<test::UniformField>(glm::vec3(1e-3f))); }), renderFrame, {}});
    rows.push_back({"attenuator alone", make(kNight, [](SkyProcessor& p) { p.add(std::make_unique<test::Attenuator>()); }), renderFrame, {}});
    rows.push_back({"nightsky, general (before)", make(kNight, night(false)), renderFrame, {}});
    rows.push_back({"nightsky, fast paths (after)", make(kNight, night(true)), renderFrame, {}});
    rows.push_back({"day, default elements, the Sky blended (before)", make(kDay, [&](SkyProcessor& p) {
                        p.add(std::make_unique<Silent>());
                        defaults(p);
                    }),
                    renderFrame, {}});
    rows.push_back({"day, default elements, renderFrame (after)", make(kDay, defaults), renderFrame, {}});
    rows.push_back({"day, displayed: renderFrame + two tone maps (before)", make(kDay, defaults), displayedTwice, {}});
    rows.push_back({"day, displayed: renderFrame + one tone map (after)", make(kDay, defaults), displayed, {}});
    rows.push_back({"moonless, displayed: two tone maps (before)", make(kNight, defaults), displayedTwice, {}});
    rows.push_back({"moonless, displayed: one tone map (after)", make(kNight, defaults), displayed, {}});
    for (int f = 0; f < 11; ++f)
        for (Row& r : rows) {
            glFinish();
            const double t0 = test::cpuMs();
            r.frame(*r.p);
            glFinish();
            if (f >= 2) r.ms.push_back(test::cpuMs() - t0);  // 2 warm-up frames: programs, tables
        }
    const double empty = test::medianOf(rows[0].ms), trivial = test::medianOf(rows[1].ms) - empty, attenuator = test::medianOf(rows[2].ms);
    std::printf("display timing, %dx%d, process CPU ms per frame (median of 9), trivial pass %.2f ms:\n", w, h, trivial);
    for (const Row& r : rows)
        std::printf("  %-62s %8.2f ms = %6.2f x trivial\n", r.what.c_str(), test::medianOf(r.ms), test::medianOf(r.ms) / trivial);
    std::printf("  nightsky pass (over the attenuator frame): general %.2f, fast %.2f x trivial\n", (test::medianOf(rows[3].ms) - attenuator) / trivial,
                (test::medianOf(rows[4].ms) - attenuator) / trivial);
    CHECK(trivial > 0.0);
}
#endif
