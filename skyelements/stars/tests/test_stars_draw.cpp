// The Stars' draw (README "Cost", 2026-11-27): one indexed draw of 4 vertices per star
// instead of an instance per star. The same triangles in the same order: the same pixels. And a
// hidden timing (`welkin_tests "[display_timing]"`) of where the Stars' cost at the moonless
// view goes: process CPU time per frame at 1280x720, each draw alternated in one process.
#include <catch2/catch.hpp>

#include "cpu_timing.hpp"
#include "gl_test_context.hpp"
#include "uniform_field.hpp"

#include <epoxy/gl.h>
#include <nlohmann/json.hpp>

#include <welkin/astro/stars.hpp>
#include <welkin/elements/stars.hpp>
#include <welkin/processor.hpp>
#include <welkin/time.hpp>

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <ctime>
#include <filesystem>
#include <functional>
#include <memory>
#include <numbers>
#include <string>
#include <vector>

using namespace welkin;

namespace {
constexpr double kDeg = std::numbers::pi / 180.0;

Camera view(Projection proj, int w, int h) {
    Camera cam;
    cam.projection = proj;
    cam.azimuthRad = std::numbers::pi;  // the bench display's view: south, 30 deg up, 60 deg
    cam.altitudeRad = 30 * kDeg;
    cam.verticalFovRad = 60 * kDeg;
    cam.width = w;
    cam.height = h;
    return cam;
}

std::unique_ptr<SkyProcessor> starsAt(const Camera& cam, bool instanced, double magnitudeLimit = 30) {
    auto p = std::make_unique<SkyProcessor>();
    p->setObserver({.latitudeRad = 35.9 * kDeg, .longitudeRad = 14.5 * kDeg, .heightMeters = 50});
    p->setTime(UtcInstant::parse("2026-08-12T22:00:00Z"));
    p->setCamera(cam);
    p->setAnimationTime(0.0);
    auto s = std::make_unique<elements::Stars>();
    s->setInstancedDraw(instanced);
    p->add(std::move(s));
    p->vars().set(elements::starkeys::magnitudeLimit, magnitudeLimit);
    return p;
}

}  // namespace

TEST_CASE("Stars: one indexed draw of 4 vertices per star gives the instanced draw's pixels", "[gl][stars]") {
    if (!std::filesystem::exists(astro::kKStarsCatalogue)) FAIL("no " << astro::kKStarsCatalogue << " (Debian: kstars-data): install it (a missing file fails, never skips)");
    test::glContext();
    // The moonless view (perspective) and the equirect view (two copies of each star: the seam's
    // twin, the instance index's other use).
    for (Projection proj : {Projection::Perspective, Projection::Equirect}) {
        CAPTURE(toString(proj));
        const Camera cam = view(proj, proj == Projection::Equirect ? 512 : 320, proj == Projection::Equirect ? 256 : 180);
        auto a = starsAt(cam, false), b = starsAt(cam, true);
        a->renderFrame();
        b->renderFrame();
        const int drawn = a->stats()["stars"]["drawn"].get<int>();
        CHECK(drawn > 1000);  // a dark night's thousands of stars (limit ~6.2)
        CHECK(b->stats()["stars"]["drawn"].get<int>() == drawn);
        const Image ia = a->readHdr(), ib = b->readHdr();
        REQUIRE(ia.pixels.size() == ib.pixels.size());
        double sum = 0;
        for (float v : ia.pixels) sum += v;
        CHECK(sum > 0.0);  // stars were drawn into the image
        // The same vertices in the same order, each shaded by the same code: bit for bit.
        CHECK(std::memcmp(ia.pixels.data(), ib.pixels.data(), ia.pixels.size() * sizeof(float)) == 0);
    }
}

TEST_CASE("Display timing: the Stars at the moonless view, instanced and single draw", "[.][display_timing]") {
    test::glContext();
    const Camera cam = view(Projection::Perspective, 1280, 720);
    struct Row {
        std::string what;
        std::unique_ptr<SkyProcessor> p;
        std::vector<double> ms;
    };
    std::vector<Row> rows;
    auto empty = std::make_unique<SkyProcessor>();
    empty->setCamera(cam);
    rows.push_back({"empty (clear, meter)", std::move(empty), {}});
    auto trivial = std::make_unique<SkyProcessor>();
    trivial->setCamera(cam);
    trivial->add(std::make_unique<test::UniformField>(glm::vec3(1e-3f)));
    rows.push_back({"trivial (uniform field)", std::move(trivial), {}});
    rows.push_back({"stars, instanced (before)", starsAt(cam, true), {}});
    rows.push_back({"stars, indexed single draw (after)", starsAt(cam, false), {}});
    rows.push_back({"stars to magnitude 3, indexed", starsAt(cam, false, 3.0), {}});
    rows.push_back({"stars to magnitude 0, indexed", starsAt(cam, false, 0.0), {}});
    for (int f = 0; f < 11; ++f)
        for (Row& r : rows) {
            glFinish();
            const double t0 = test::cpuMs();
            r.p->renderFrame();
            glFinish();
            if (f >= 2) r.ms.push_back(test::cpuMs() - t0);
        }
    const double e = test::medianOf(rows[0].ms), t = test::medianOf(rows[1].ms) - e;
    std::printf("stars timing, 1280x720, process CPU ms per frame over the empty frame (median of 9), trivial pass %.2f ms:\n", t);
    for (const Row& r : rows) {
        const int drawn = r.p->stats().contains("stars") ? r.p->stats()["stars"]["drawn"].get<int>() : 0;
        std::printf("  %-40s %6d stars %8.2f ms = %6.2f x trivial\n", r.what.c_str(), drawn, test::medianOf(r.ms) - e, (test::medianOf(r.ms) - e) / t);
    }
    CHECK(t > 0.0);
}
