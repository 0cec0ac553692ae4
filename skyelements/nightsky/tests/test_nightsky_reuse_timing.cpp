// Hidden timing (not run by CI: `welkin_tests "[night_reuse_timing]"`): the night sky's pass with
// its image reuse (README "Reusing the image") against the pass drawn every frame, at 1280x720 in
// the view (south, 30 deg up, 60 deg), displayed frames (render.interactive) 1/30 s apart,
// under an element that attenuates and draws nothing (the default scene's case without the Sky's
// cost). Each row's frames alternate with every other row's; the night sky's cost is its element
// time (update + render, wall clock with glFinish around it: the processor's timing, as `welkin
// bench display`'s frame budget), as a ratio to a trivial pass (a uniform field) timed the same way
// in the same rounds; the process CPU time of the whole frame is printed beside it.
#include <catch2/catch.hpp>

#include "cpu_timing.hpp"
#include "gl_test_context.hpp"
#include "uniform_field.hpp"

#include <welkin/elements/nightsky.hpp>
#include <welkin/keys.hpp>
#include <welkin/processor.hpp>
#include <welkin/time.hpp>

#include <epoxy/gl.h>
#include <nlohmann/json.hpp>

#include <cstdio>
#include <functional>
#include <memory>
#include <numbers>
#include <numeric>
#include <string>
#include <vector>

using namespace welkin;

TEST_CASE("Night reuse timing: still, time at 1x, a turning camera", "[.][night_reuse_timing]") {
    test::glContext();
    constexpr double kDeg = std::numbers::pi / 180.0;
    const UtcInstant t0 = UtcInstant::parse("2026-08-12T22:00:00Z");
    const int frames = 92, warm = 2;  // 3 s of display at 30 fps after the warm-up
    auto view = [&](double azDeg) {
        Camera cam;
        cam.azimuthRad = azDeg * kDeg;
        cam.altitudeRad = 30 * kDeg;
        cam.verticalFovRad = 60 * kDeg;
        cam.width = 1280;
        cam.height = 720;
        return cam;
    };
    struct Row {
        std::string what;
        std::unique_ptr<SkyProcessor> p;
        std::function<void(SkyProcessor&, int)> step;  // time and camera of frame i
        std::string element;                           // the timed element
        std::vector<double> ms, cpu;
        elements::NightSky* night = nullptr;
    };
    auto make = [&](bool night, bool reuse) {
        auto p = std::make_unique<SkyProcessor>(SkyVars::earth(), Logger(), ProcessorOptions{.timing = true});
        p->setObserver({.latitudeRad = 35.9 * kDeg, .longitudeRad = 14.5 * kDeg, .heightMeters = 50});
        p->setTime(t0);
        p->setCamera(view(180));
        p->vars().set(keys::interactive, true);
        p->setExposure({.automatic = true});
        elements::NightSky* n = nullptr;
        if (night) {
            auto e = std::make_unique<elements::NightSky>();
            n = e.get();
            p->add(std::move(e));
            p->add(std::make_unique<test::Attenuator>());
            p->vars().set(elements::nightkeys::reuse, reuse);
        } else {
            p->add(std::make_unique<test::UniformField>(glm::vec3(1e-3f)));
        }
        return std::make_pair(std::move(p), n);
    };
    auto still = [](SkyProcessor& p, int i) { p.setAnimationTime(i / 30.0); };
    auto realTime = [&](SkyProcessor& p, int i) {
        p.setAnimationTime(i / 30.0);
        p.setTime(t0.plusSeconds(i / 30.0));
    };
    auto turning = [&](SkyProcessor& p, int i) {  // 15 deg/s, a slow pan
        p.setAnimationTime(i / 30.0);
        p.setCamera(view(180 + 0.5 * i));
    };
    std::vector<Row> rows;
    auto add = [&](std::string what, bool night, bool reuse, std::function<void(SkyProcessor&, int)> step) {
        auto [p, n] = make(night, reuse);
        rows.push_back({std::move(what), std::move(p), std::move(step), night ? "nightsky" : "field", {}, {}, n});
    };
    add("trivial pass (uniform field)", false, false, still);
    add("nightsky drawn every frame, still (reuse off)", true, false, still);
    add("nightsky reuse, still", true, true, still);
    add("nightsky drawn every frame, time 1x (reuse off)", true, false, realTime);
    add("nightsky reuse, time 1x", true, true, realTime);
    add("nightsky drawn every frame, camera turning (reuse off)", true, false, turning);
    add("nightsky reuse, camera turning", true, true, turning);
    for (int f = 0; f < frames; ++f)
        for (Row& r : rows) {
            r.step(*r.p, f);
            glFinish();
            const double c0 = test::cpuMs();
            r.p->renderFrame();
            glFinish();
            const double cpu = test::cpuMs() - c0;
            if (f < warm) continue;  // programs, tables, the folded panorama
            const nlohmann::json st = r.p->stats();  // held: the loop below refers into it
            for (const auto& e : st["elements"])
                if (e["name"].get<std::string>() == r.element) r.ms.push_back(e["update_ms"].get<double>() + e["render_ms"].get<double>());
            r.cpu.push_back(cpu);
        }
    for (const Row& r : rows) REQUIRE(r.ms.size() == size_t(frames - warm));
    auto mean = [](const std::vector<double>& v) { return std::accumulate(v.begin(), v.end(), 0.0) / double(v.size()); };
    const double trivial = test::medianOf(rows[0].ms);
    std::printf("night reuse timing, 1280x720, %d frames 1/30 s apart after %d warm-up, trivial pass %.2f ms (element wall time, median):\n",
                frames - warm, warm, trivial);
    for (const Row& r : rows) {
        std::string counts;
        if (r.night) counts = ", reused " + std::to_string(r.night->reuseHits()) + ", kept " + std::to_string(r.night->reuseKeeps());
        std::printf("  %-58s median %6.2f, mean %6.2f, worst %6.2f x trivial; frame CPU median %6.2f ms%s\n", r.what.c_str(), test::medianOf(r.ms) / trivial,
                    mean(r.ms) / trivial, *std::max_element(r.ms.begin(), r.ms.end()) / trivial, test::medianOf(r.cpu), counts.c_str());
    }
    CHECK(trivial > 0.0);
    CHECK(rows[2].night->reuseHits() > 0);
}
