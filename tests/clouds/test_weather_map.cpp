// The weather map: GPU map against its CPU twin, seamless tiling, the flow's advection (a solid
// rotation), determinism, the artist's image and its errors.
#include <catch2/catch.hpp>

#include "clouds/cloud_test_util.hpp"
#include "gl_test_context.hpp"

#include <welkin/error.hpp>
#include <welkin/generators/cloud_keys.hpp>
#include <welkin/generators/weather_map.hpp>
#include <welkin/image.hpp>
#include <welkin/keys.hpp>

#include <cmath>
#include <filesystem>

using namespace welkin;
using namespace welkin::generators;

namespace {
constexpr int kSize = 64;          // texels: small, llvmpipe draws it in milliseconds
constexpr double kExtent = 20000;  // m

SkyVars makeVars(int seed, int count = 12) {
    SkyVars vars;
    vars.declare(cloudkeys::seed, seed);
    vars.declare(cloudkeys::weatherExtent, kExtent);
    vars.declare(cloudkeys::cloudCount, count);
    vars.declare(cloudkeys::cloudSizeMin, 800.0);
    vars.declare(cloudkeys::cloudSizeMax, 3000.0);
    vars.declare(cloudkeys::flowFile, std::string());
    vars.declare(cloudkeys::flowScale, 10.0);
    vars.declare(keys::timeJdUtc, glm::dvec2(2461000.0, 0.25));
    return vars;
}

cpu::Image runMap(WeatherMap& wm, SkyVars& vars) {
    wm.run(vars, test::testLogger(), true);
    REQUIRE(vars.get(cloudkeys::weatherMap).id == wm.texture().id());
    return test::toImage(wm.texture());
}
}  // namespace

TEST_CASE("Weather map: GPU map matches the CPU twin and tiles seamlessly", "[gl][clouds]") {
    test::glContext();
    SkyVars vars = makeVars(5);
    WeatherMap wm(kSize);
    // A cloud straddling the map's corner: it must continue across both borders.
    const CloudShape corner{.centre = {100.0, 19900.0}, .semiAxes = {2500.0, 1500.0}, .rotation = 0.4, .density = 0.9,
                            .baseFraction = 0.1, .topFraction = 0.8, .rain = 0.5, .seed = 99};
    wm.add(corner);
    const cpu::Image im = runMap(wm, vars);
    REQUIRE(wm.clouds().size() == 13);  // the added one, then 12 generated
    int cloudy = 0, bad = 0;
    double worst = 0;
    for (int j = 0; j < kSize; ++j)
        for (int i = 0; i < kSize; ++i) {
            const glm::dvec4 ref = cpu::weatherTexel(wm.clouds(), i, j, kSize, kExtent);
            const glm::dvec4 g = im.texel(i, j);
            cloudy += ref.r > 0.1;
            // Half floats (11-bit mantissa: 5e-4 relative) and the rasteriser's float local
            // coordinates: 2e-3. G and B jump from 0 where a cloud's fade crosses 1e-3: a texel
            // right on that edge may differ (count them; fewer than 0.5 % allowed).
            const glm::dvec4 ad = glm::abs(g - ref);
            const double e = std::max(std::max(ad.x, ad.y), std::max(ad.z, ad.w));
            if (e > 2e-3) ++bad;
            else worst = std::max(worst, e);
        }
    INFO("cloudy texels " << cloudy << ", worst " << worst << ", off " << bad);
    CHECK(cloudy > 100);
    CHECK(bad <= kSize * kSize / 200);
    // Seamless: the corner cloud covers texels on both sides of each border, and the step
    // across a border is like the step between neighbours inside (no seam).
    CHECK(im.texel(0, kSize - 1).r > 0.3);
    CHECK(im.texel(kSize - 1, kSize - 1).r > 0.1);
    CHECK(im.texel(0, 0).r > 0.1);
    double inside = 0, border = 0;
    for (int k = 0; k < kSize; ++k) {
        inside += std::abs(im.texel(kSize / 2, k).r - im.texel(kSize / 2 - 1, k).r) + std::abs(im.texel(k, kSize / 2).r - im.texel(k, kSize / 2 - 1).r);
        border += std::abs(im.texel(0, k).r - im.texel(kSize - 1, k).r) + std::abs(im.texel(k, 0).r - im.texel(k, kSize - 1).r);
    }
    INFO("mean step inside " << inside << ", across the borders " << border);
    // The twin's continuation is exact: texel -1 (one period on) equals texel N-1.
    for (int k = 0; k < kSize; k += 7) CHECK(cpu::weatherTexel(wm.clouds(), -1, k, kSize, kExtent).r == Approx(cpu::weatherTexel(wm.clouds(), kSize - 1, k, kSize, kExtent).r).margin(1e-9));
    // Same statistics across a border as inside (sum of |steps| over two lines of 64 texels:
    // 2x covers the sampling noise of different lines; a seam would add steps of ~0.5 each).
    CHECK(border < 2.0 * inside + 0.05);
}

TEST_CASE("Weather map: a rotation field carries a cloud along its arc", "[gl][clouds]") {
    test::glContext();
    SkyVars vars = makeVars(1, 0);
    WeatherMap wm(kSize);
    const glm::dvec2 c(kExtent / 2, kExtent / 2);
    const double omega = 2e-4;  // rad/s: a quarter turn in ~2.2 h
    wm.setClouds({CloudShape{.centre = c + glm::dvec2(5000.0, 0.0), .semiAxes = {1500.0, 1500.0}, .density = 1.0, .seed = 3}});
    // v = omega x r around the map's centre (counter-clockwise seen from above).
    wm.setFlow([&](glm::dvec2 p, double) { return omega * glm::dvec2(-(p.y - c.y), p.x - c.x); });
    const cpu::Image before = runMap(wm, vars);
    const double T = 3600.0;  // s: 0.72 rad
    vars.set(keys::timeJdUtc, glm::dvec2(2461000.0, 0.25 + T / 86400.0));
    const cpu::Image after = runMap(wm, vars);
    CHECK(wm.elapsedSeconds() == Approx(T).margin(1e-3));  // jd fraction in double: ~1e-6 s
    const glm::dvec2 p = wm.clouds()[0].centre - c;
    // RK4 in 30 s steps: error ~ (omega h)^5 / 120 x r per step, < 1e-12 m; the angle and
    // radius are exact to 1e-6 relative (jd's double resolution gives 1e-6 s of time).
    CHECK(glm::length(p) == Approx(5000.0).epsilon(1e-6));
    CHECK(std::atan2(p.y, p.x) == Approx(omega * T).epsilon(1e-6));
    // And the map moved with it: the cloud's density peak is now near the rotated centre
    // (the texel of the new centre is cloudy, the old one clear).
    auto texelOf = [&](glm::dvec2 m) { return glm::ivec2(glm::floor(m / kExtent * double(kSize))); };
    const glm::ivec2 oldT = texelOf(c + glm::dvec2(5000.0, 0.0)), newT = texelOf(wm.clouds()[0].centre);
    CHECK(before.texel(oldT.x, oldT.y).r > 0.5);
    CHECK(after.texel(newT.x, newT.y).r > 0.5);
    CHECK(after.texel(oldT.x, oldT.y).r == 0.0);
}

TEST_CASE("Weather map: wind moves the offset, same seed same map, another seed differs", "[gl][clouds]") {
    test::glContext();
    SkyVars a = makeVars(11), b = makeVars(11), c = makeVars(12);
    WeatherMap wa(kSize), wb(kSize), wc(kSize);
    const cpu::Image ia = runMap(wa, a), ib = runMap(wb, b), ic = runMap(wc, c);
    CHECK(ia.rgba == ib.rgba);
    CHECK(ia.rgba != ic.rgba);
    // Wind: offset = offset at the first run - wind x elapsed time (east wind: map slides east).
    a.set(cloudkeys::wind, glm::dvec2(10.0, -5.0));
    a.set(keys::timeJdUtc, glm::dvec2(2461000.0, 0.25 + 600.0 / 86400.0));
    wa.run(a, test::testLogger(), true);
    const glm::dvec2 off = a.get(cloudkeys::weatherOffset);
    CHECK(off.x == Approx(-6000.0).margin(1e-3));  // 10 m/s x 600 s (time in double days: ~1e-5 s)
    CHECK(off.y == Approx(3000.0).margin(1e-3));
    // The cirrus follows the same wind unless it has its own.
    CHECK(a.get(cloudkeys::cirrusOffset).x == Approx(-6000.0).margin(1e-3));
    a.set(cloudkeys::cirrusWind, glm::dvec2(30.0, 0.0));
    wa.run(a, test::testLogger(), true);
    CHECK(a.get(cloudkeys::cirrusOffset).x == Approx(-18000.0).margin(1e-3));
    CHECK(a.get(cloudkeys::cirrusOffset).y == Approx(0.0).margin(1e-3));
    CHECK(a.get(cloudkeys::weatherOffset).x == Approx(-6000.0).margin(1e-3));
}

TEST_CASE("Weather map: an artist's image round-trips, bad files fail in one line", "[gl][clouds]") {
    test::glContext();
    namespace fs = std::filesystem;
    const fs::path dir = fs::temp_directory_path() / "welkin_weather_test";
    fs::create_directories(dir);
    Image img{.width = 8, .height = 4, .channels = 4, .pixels = {}};
    img.pixels.resize(8 * 4 * 4);
    for (size_t i = 0; i < img.pixels.size(); ++i) img.pixels[i] = float(test::hashUnit(uint32_t(i)));
    const std::string path = (dir / "weather.exr").string();
    writeImage(img, path);
    SkyVars vars = makeVars(1);
    vars.declare(cloudkeys::weatherFile, path);
    WeatherMap wm(kSize);
    const cpu::Image im = runMap(wm, vars);
    REQUIRE(im.w == 8);
    REQUIRE(im.h == 4);
    // GL row j is the image's row 3 - j (the image's top row is the map's north edge); half
    // floats keep 11 bits: 1e-3 relative on [0, 1].
    for (int y = 0; y < 4; ++y)
        for (int x = 0; x < 8; ++x)
            for (int ch = 0; ch < 4; ++ch) CHECK(im.texel(x, 3 - y)[ch] == Approx(img.at(x, y, ch)).margin(1e-3));

    // Three channels: A = 0.
    Image rgb{.width = 2, .height = 2, .channels = 3, .pixels = std::vector<float>(12, 0.5f)};
    const std::string p3 = (dir / "weather3.exr").string();
    writeImage(rgb, p3);
    vars.set(cloudkeys::weatherFile, p3);
    const cpu::Image i3 = runMap(wm, vars);
    CHECK(i3.texel(1, 1).a == 0.0);
    CHECK(i3.texel(1, 1).g == Approx(0.5).margin(1e-3));

    // A missing file and a one-channel image: one line naming the key and the file.
    WeatherMap bad(kSize);
    vars.set(cloudkeys::weatherFile, (dir / "missing.png").string());
    try {
        bad.run(vars, test::testLogger(), true);
        FAIL("no error for a missing file");
    } catch (const Error& e) {
        const std::string msg = e.what();
        CHECK(msg.find("clouds.weather_map_file") != std::string::npos);
        CHECK(msg.find("missing.png") != std::string::npos);
        CHECK(msg.find('\n') == std::string::npos);
    }
    Image grey{.width = 2, .height = 2, .channels = 1, .pixels = std::vector<float>(4, 0.5f)};
    const std::string p1 = (dir / "grey.exr").string();
    writeImage(grey, p1);
    vars.set(cloudkeys::weatherFile, p1);
    CHECK_THROWS_WITH(bad.run(vars, test::testLogger(), true), Catch::Contains("clouds.weather_map_file") && Catch::Contains("needs 3 or 4"));
    fs::remove_all(dir);
}

TEST_CASE("Weather map: a flow image advects the clouds; a bad one fails in one line", "[gl][clouds]") {
    test::glContext();
    namespace fs = std::filesystem;
    const fs::path dir = fs::temp_directory_path() / "welkin_flow_test";
    fs::create_directories(dir);
    // Uniform field R = 0.75, G = 0.25: v = (2 x 0.75 - 1, 2 x 0.25 - 1) x 10 m/s = (5, -5) m/s.
    Image flow{.width = 4, .height = 4, .channels = 3, .pixels = {}};
    for (int i = 0; i < 16; ++i) flow.pixels.insert(flow.pixels.end(), {0.75f, 0.25f, 0.0f});
    const std::string path = (dir / "flow.exr").string();
    writeImage(flow, path);
    SkyVars vars = makeVars(1, 0);
    vars.set(cloudkeys::flowFile, path);
    WeatherMap wm(kSize);
    wm.setClouds({CloudShape{.centre = {5000.0, 5000.0}, .semiAxes = {1000.0, 1000.0}, .seed = 1}});
    wm.run(vars, test::testLogger(), true);
    vars.set(keys::timeJdUtc, glm::dvec2(2461000.0, 0.25 + 200.0 / 86400.0));
    wm.run(vars, test::testLogger(), true);
    // 200 s at (5, -5) m/s: (+1000, -1000) m (time from double days: ~1e-5 s -> 1e-4 m).
    CHECK(wm.clouds()[0].centre.x == Approx(6000.0).margin(1e-2));
    CHECK(wm.clouds()[0].centre.y == Approx(4000.0).margin(1e-2));
    Image grey{.width = 2, .height = 2, .channels = 1, .pixels = std::vector<float>(4, 0.5f)};
    const std::string p1 = (dir / "grey.exr").string();
    writeImage(grey, p1);
    WeatherMap bad(kSize);
    vars.set(cloudkeys::flowFile, p1);
    CHECK_THROWS_WITH(bad.run(vars, test::testLogger(), true), Catch::Contains("clouds.flow_file") && Catch::Contains("needs 2"));
    fs::remove_all(dir);
}

TEST_CASE("Weather map: a clock tick without motion does not republish the map", "[gl][clouds]") {
    test::glContext();
    SkyVars vars = makeVars(2, 4);
    WeatherMap wm(kSize);
    wm.run(vars, test::testLogger(), true);
    const uint64_t v0 = vars.version(cloudkeys::weatherMap), o0 = vars.version(cloudkeys::weatherOffset);
    vars.set(keys::timeJdUtc, glm::dvec2(2461000.0, 0.26));
    wm.run(vars, test::testLogger(), true);
    CHECK(vars.version(cloudkeys::weatherMap) == v0);   // no flow, no edit: same map
    CHECK(vars.version(cloudkeys::weatherOffset) == o0);  // no wind: same offset
    wm.move(0, {100.0, 0.0});
    wm.run(vars, test::testLogger(), true);
    CHECK(vars.version(cloudkeys::weatherMap) > v0);  // an edit redraws and republishes
}
