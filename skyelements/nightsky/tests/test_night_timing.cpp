// Hidden timing (not run by CI: `welkin_tests "[night_timing]"`): the CPU time per frame of the
// night sky's cube map against its per-pixel reference, and of the Sky at night with and without
// the Sun's term, at 1280x720, against a trivial fullscreen pass. Process CPU time (llvmpipe's
// threads run in the process), not wall time: on a machine shared with other jobs the wall time
// of a frame swings by 2-5x, the CPU time it uses much less.
#include <catch2/catch.hpp>

#include "cpu_timing.hpp"
#include "gl_test_context.hpp"
#include "uniform_field.hpp"

#include <epoxy/gl.h>

#include <welkin/elements/nightsky.hpp>
#include <welkin/elements/registry.hpp>
#include <welkin/keys.hpp>
#include <welkin/processor.hpp>
#include <welkin/time.hpp>

#include <algorithm>
#include <cstdio>
#include <ctime>
#include <functional>
#include <vector>

using namespace welkin;

namespace {
Camera issueView() {
    Camera cam;
    cam.projection = Projection::Perspective;
    cam.azimuthRad = M_PI;
    cam.altitudeRad = 30 * M_PI / 180;
    cam.verticalFovRad = 60 * M_PI / 180;
    cam.width = 1280;
    cam.height = 720;
    return cam;
}
}  // namespace

TEST_CASE("Night timing: cube map vs per-pixel lookup, Sky with and without the Sun's term", "[.][night_timing]") {
    test::glContext();
    const Camera cam = issueView();
    auto make = [&](std::function<void(SkyProcessor&)> add, bool astronomy = true) {
        auto p = std::make_unique<SkyProcessor>(SkyVars::earth(), Logger(), ProcessorOptions{.astronomy = astronomy});
        if (astronomy) {
            p->setObserver({.latitudeRad = 35.9 * M_PI / 180, .longitudeRad = 14.5 * M_PI / 180, .heightMeters = 0});
            p->setTime(UtcInstant::parse("2026-08-12T22:00:00Z"));
        }
        p->setCamera(cam);
        add(*p);
        return p;
    };
    std::vector<std::pair<std::string, std::unique_ptr<SkyProcessor>>> ps;
    ps.emplace_back("empty (clear + tone map)", make([](SkyProcessor&) {}));
    ps.emplace_back("trivial pass (uniform field)", make([](SkyProcessor& p) { p.add(std::make_unique<test::UniformField>(glm::vec3(1e-3f))); }));
    ps.emplace_back("nightsky, per-pixel lookup", make([](SkyProcessor& p) {
        auto n = std::make_unique<elements::NightSky>();
        n->setDirectLookup(true);
        p.add(std::move(n));
    }));
    ps.emplace_back("nightsky, cube maps", make([](SkyProcessor& p) { p.add(std::make_unique<elements::NightSky>()); }));
    auto sky = [](double sunAltDeg) {
        return [sunAltDeg](SkyProcessor& p) {
            p.vars().set(keys::sunDirection, glm::dvec3(0.0, -std::cos(sunAltDeg * M_PI / 180), std::sin(sunAltDeg * M_PI / 180)));
            p.vars().set(keys::moonDirection, glm::dvec3(0, 0, -1));
            p.add(std::make_unique<test::UniformField>(glm::vec3(1e-3f)));
            p.add(elements::makeElement("sky"));  // by name: no other folder's header
        };
    };
    ps.emplace_back("uniform field + sky, Sun -20.9 deg (Sun's term drawn)", make(sky(-20.9), false));
    ps.emplace_back("uniform field + sky, Sun -21.1 deg (skipped)", make(sky(-21.1), false));
    // The night sky as under a Sky (FrameContext::attenuatedLater: no extinction of its own, the
    // default scene's case) without the Sky's cost: a later element that declares it attenuates
    // and draws nothing. The night sky's cost is the difference of these two frames.
    ps.emplace_back("attenuator alone (draws nothing)", make([](SkyProcessor& p) { p.add(std::make_unique<test::Attenuator>(false)); }));
    ps.emplace_back("nightsky per-pixel, attenuated later", make([](SkyProcessor& p) {
        auto n = std::make_unique<elements::NightSky>();
        n->setDirectLookup(true);
        p.add(std::move(n));
        p.add(std::make_unique<test::Attenuator>(false));
    }));
    std::vector<std::vector<double>> ms(ps.size());
    for (int f = 0; f < 9; ++f)
        for (size_t i = 0; i < ps.size(); ++i) {
            const double t0 = test::cpuMs();
            ps[i].second->renderFrame();
            glFinish();
            if (f >= 2) ms[i].push_back(test::cpuMs() - t0);  // 2 warm-up frames: programs, tables, cubes
        }
    const double empty = test::medianOf(ms[0]), trivial = test::medianOf(ms[1]) - empty;
    std::printf("night timing, 1280x720, process CPU ms per frame (median of 7), trivial pass %.2f ms:\n", trivial);
    for (size_t i = 0; i < ps.size(); ++i)
        std::printf("  %-55s %8.2f ms frame, %8.2f ms over the empty frame = %.2f x trivial\n", ps[i].first.c_str(), test::medianOf(ms[i]), test::medianOf(ms[i]) - empty,
                    (test::medianOf(ms[i]) - empty) / trivial);
    const size_t n = ps.size();
    std::printf("  nightsky attenuated later: %.2f ms = %.2f x trivial\n", test::medianOf(ms[n - 1]) - test::medianOf(ms[n - 2]),
                (test::medianOf(ms[n - 1]) - test::medianOf(ms[n - 2])) / trivial);
    CHECK(trivial > 0.0);
}
