// The cloud-path LUT: GPU texels against the analytic ray-sphere crossing, below, inside and
// above the layer; the mapping's round trip.
#include <catch2/catch.hpp>

#include "clouds/cloud_test_util.hpp"
#include "gl_test_context.hpp"

#include <welkin/generators/cloud_keys.hpp>
#include <welkin/generators/cloud_path_lut.hpp>
#include <welkin/generators/lights.hpp>

#include <cmath>

using namespace welkin;
using namespace welkin::generators;

TEST_CASE("Cloud-path LUT mapping round-trips", "[cpu][clouds]") {
    for (double mu : {-1.0, -0.3, -1e-3, 0.0, 2e-4, 0.5, 1.0}) CHECK(cloudPathMu(cloudPathX(mu)) == Approx(mu).margin(1e-12));
    for (double h : {0.0, 700.0, 1500.0, 2000.0, 3999.0, 4000.0, 30000.0, 54000.0})
        CHECK(cloudPathAltitude(cloudPathY(h, 1500.0, 4000.0), 1500.0, 4000.0) == Approx(h).margin(1e-9));
    // The thirds: the layer's base and top at y = 1/3 and 2/3.
    CHECK(cloudPathY(1500.0, 1500.0, 4000.0) == Approx(1.0 / 3.0));
    CHECK(cloudPathY(4000.0, 1500.0, 4000.0) == Approx(2.0 / 3.0));
}

TEST_CASE("Cloud-path LUT: texels match the analytic crossing below, inside and above", "[gl][clouds]") {
    test::glContext();
    SkyVars vars;
    vars.declare(cloudkeys::bottom, 1500.0);
    vars.declare(cloudkeys::top, 4000.0);
    vars.declare(lightkeys::planetRadius, 6360e3);
    const int W = 64, H = 30;
    CloudPathLut lut(W, H);
    lut.run(vars, test::testLogger(), true);
    const cpu::Image im = test::toImage(lut.texture());
    int below = 0, inside = 0, above = 0, misses = 0;
    double worst = 0;
    for (int j = 0; j < H; ++j)
        for (int i = 0; i < W; ++i) {
            const glm::dvec2 ref = cpu::cloudPathTexel(i, j, W, H, 6360e3, 1500.0, 4000.0);
            const glm::dvec4 g = im.texel(i, j);
            const double h = cloudPathAltitude(double(j) / (H - 1), 1500.0, 4000.0);
            if (ref.y < 0) {
                ++misses;
                CHECK(g.y < 0);
                continue;
            }
            (h < 1500.0 ? below : h <= 4000.0 ? inside : above) += 1;
            // Computed in double on the GPU, stored as float: relative 6e-8 of distances up to
            // ~1000 km (0.06 m); 1e-6 relative + 1 mm is the float storage with margin.
            worst = std::max(worst, std::abs(g.x - ref.x) / (1e-3 + 1e-6 * ref.x));
            worst = std::max(worst, std::abs(g.y - ref.y) / (1e-3 + 1e-6 * ref.y));
        }
    INFO("worst error / tolerance " << worst);
    CHECK(worst <= 1.0);
    CHECK(below > 100);
    CHECK(inside > 100);
    CHECK(above > 100);
    CHECK(misses > 100);  // looking into the ground from below, upwards from above
    // Physical facts, independent of the twin: straight up from the ground the path is the layer
    // itself (1500 m to 4000 m); straight down from the top of the LUT (54 km) it is the layer
    // seen from above: entry 50 000 m, exit 52 500 m.
    CHECK(im.texel(W - 1, 0).x == Approx(1500.0).margin(1e-3));
    CHECK(im.texel(W - 1, 0).y == Approx(4000.0).margin(1e-3));
    CHECK(im.texel(0, H - 1).x == Approx(50000.0).margin(1e-2));
    CHECK(im.texel(0, H - 1).y == Approx(52500.0).margin(1e-2));
}
