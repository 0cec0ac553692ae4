// The host example (examples/host, issue 18): its scene library's BRDF table, and its headless
// frame at noon: finite, non-negative HDR; the buildings brighter on the Sun's side than on the
// shaded side; a far building's face nearer the sky's colour than a near one's (aerial perspective).
#include <catch2/catch.hpp>

#include "gl_test_context.hpp"

#include <welkin_host/host_app.hpp>
#include <welkin_host/renderer.hpp>

#include <welkin/time.hpp>

#include <cmath>

using namespace welkin;

namespace {

// Mean HDR radiance over a (2r+1)^2 box of pixels about a world point's pixel (top row first).
glm::dvec3 radianceAt(const host::HostApp& app, const Image& hdr, const glm::dvec3& world, int r) {
    const glm::dvec4 clip = app.viewProjection() * glm::dvec4(world, 1.0);
    REQUIRE(clip.w > 0.0);
    const int px = int(std::floor((clip.x / clip.w + 1.0) * 0.5 * hdr.width));
    const int py = int(std::floor((1.0 - clip.y / clip.w) * 0.5 * hdr.height));
    REQUIRE(px - r >= 0);
    REQUIRE(px + r < hdr.width);
    REQUIRE(py - r >= 0);
    REQUIRE(py + r < hdr.height);
    glm::dvec3 sum(0.0);
    for (int y = py - r; y <= py + r; ++y)
        for (int x = px - r; x <= px + r; ++x) sum += glm::dvec3(hdr.at(x, y, 0), hdr.at(x, y, 1), hdr.at(x, y, 2));
    return sum / double((2 * r + 1) * (2 * r + 1));
}

double luminance(const glm::dvec3& c) { return 0.2126 * c.r + 0.7152 * c.g + 0.0722 * c.b; }
// rg chromaticity (r, b fractions of r + g + b).
glm::dvec2 chroma(const glm::dvec3& c) { return glm::dvec2(c.r, c.b) / (c.r + c.g + c.b); }

}  // namespace

// The directional albedo of the GGX lobe with F0 = 1 (scale + bias of the split-sum table) by
// brute force: a midpoint rule over the hemisphere of light directions, n x 2n cells.
double albedoBruteForce(double NoV, double roughness, int n) {
    const double a2 = roughness * roughness * roughness * roughness, pi = 3.14159265358979;
    const glm::dvec3 v(std::sqrt(1.0 - NoV * NoV), 0.0, NoV);
    double sum = 0.0;
    for (int i = 0; i < n; ++i) {
        const double th = (i + 0.5) / n * pi / 2;
        for (int j = 0; j < 2 * n; ++j) {
            const double ph = (j + 0.5) / (2 * n) * 2 * pi;
            const glm::dvec3 l(std::sin(th) * std::cos(ph), std::sin(th) * std::sin(ph), std::cos(th));
            const double NoH = glm::normalize(v + l).z, NoL = l.z;
            const double d = NoH * NoH * (a2 - 1.0) + 1.0, D = a2 / (pi * d * d);
            const double vis = 0.5 / (NoL * std::sqrt(NoV * NoV * (1 - a2) + a2) + NoV * std::sqrt(NoL * NoL * (1 - a2) + a2));
            sum += D * vis * NoL * std::sin(th) * (pi / 2 / n) * (pi / n);
        }
    }
    return sum;
}

TEST_CASE("Host example: the split-sum BRDF table", "[cpu][host]") {
    const int n = 64;
    const auto table = host::computeBrdfTable(n, 512);
    auto at = [&](int i, int j) { return table[size_t(j * n + i)]; };  // i: n.v, j: roughness
    for (const glm::vec2& ab : table) {
        CHECK(ab.x >= 0.0f);
        CHECK(ab.y >= 0.0f);
        // A passive surface reflects at most what it receives (F0 = 1: scale + bias <= 1).
        // 0.02: the 512-sample estimate's error at grazing n.v, measured up to 0.013.
        CHECK(ab.x + ab.y <= 1.02f);
    }
    // Against the brute-force integral where a 300 x 600 grid resolves the lobe (roughness
    // >= 0.5, n.v >= 0.25). 0.02: the 512-sample estimate's error there, measured up to 0.0094.
    for (int j = 32; j < n; j += 5)
        for (int i = 16; i < n; i += 5) {
            const glm::vec2 ab = at(i, j);
            const double ref = albedoBruteForce((i + 0.5) / n, (j + 0.5) / n, 300);
            INFO("n.v " << (i + 0.5) / n << ", roughness " << (j + 0.5) / n);
            CHECK(ab.x + ab.y == Approx(ref).margin(0.02));
        }
    // A smooth mirror (roughness 1/128, the first texel) seen head-on reflects all of F0 = 1.
    // 1e-3: the Smith masking of the residual roughness and the estimate's error.
    const glm::vec2 mirror = at(n - 1, 0);
    CHECK(mirror.x + mirror.y == Approx(1.0f).margin(1e-3f));
}

TEST_CASE("Host example: the noon frame lights the buildings by the Sun and veils the far ones", "[gl][host]") {
    test::glContext();
    host::HostApp app({.assetsDir = WELKIN_SOURCE_DIR "/examples/host/assets"}, test::testLogger());
    app.sky().setAnimationTime(0.0);
    // Malta at the March equinox, near true solar noon (11:09 UTC): the Sun 54 deg up in the south.
    const host::FlyCamera camera;  // the default view: 8 m up, looking west over the village
    app.render(UtcInstant::parse("2026-03-20T11:10:00Z"), camera, 640, 360);
    const Image hdr = app.readHdr();

    SECTION("finite, non-negative HDR") {
        size_t bad = 0;
        for (float v : hdr.pixels) bad += !(std::isfinite(v) && v >= 0.0f);
        CHECK(bad == 0);
    }

    const host::SceneNode* north = app.scene().findNode("house_n1");  // north of the view: its south wall faces us
    const host::SceneNode* south = app.scene().findNode("house_s1");  // south of the view: its north wall faces us
    const host::SceneNode* keep = app.scene().findNode("keep_far");   // 2.4 km west, on the ridge
    REQUIRE(north);
    REQUIRE(south);
    REQUIRE(keep);
    // A wall's centre: the bounds' face (the roof's 0.4 m overhang puts it that far out), a third
    // of the way up from the foundation (below the eaves).
    auto wall = [](const host::Bounds& b, glm::dvec3 axis, bool maxSide) {
        glm::dvec3 p = 0.5 * (glm::dvec3(b.min) + glm::dvec3(b.max));
        p.y = b.min.y + 0.35 * (b.max.y - b.min.y);
        for (int k : {0, 2})
            if (axis[k] != 0.0) p[k] = maxSide ? b.max[k] : b.min[k];
        return p;
    };

    SECTION("brighter on the Sun's side") {
        const glm::dvec3 sunny = radianceAt(app, hdr, wall(north->worldBounds, {0, 0, 1}, true), 1);     // south wall
        const glm::dvec3 shaded = radianceAt(app, hdr, wall(south->worldBounds, {0, 0, 1}, false), 1);   // north wall
        INFO("sunny south wall " << luminance(sunny) << " cd/m^2, shaded north wall " << luminance(shaded) << " cd/m^2");
        // The south wall gets the Sun's E cos(54 deg) ~ 0.59 E besides the sky's light that both
        // walls get (about a tenth of E on a vertical wall): several times brighter. 2x leaves
        // room for the sky's anisotropy and the ground's bounce on the north wall.
        CHECK(luminance(sunny) > 2.0 * luminance(shaded));
    }

    SECTION("fading towards the sky's colour with distance") {
        // Both east walls face the camera and get no sunlight at noon (the Sun is south).
        const glm::dvec3 near = radianceAt(app, hdr, wall(north->worldBounds, {1, 0, 0}, true), 1);
        const glm::dvec3 far = radianceAt(app, hdr, wall(keep->worldBounds, {1, 0, 0}, true), 0);
        // The sky 8 deg above the western horizon (above every hill of the 6 km terrain), 5 deg
        // south of the keep.
        const double az = 265.0 * 3.14159265358979 / 180.0, alt = 8.0 * 3.14159265358979 / 180.0;
        const glm::dvec3 dir(std::sin(az) * std::cos(alt), std::sin(alt), -std::cos(az) * std::cos(alt));
        const glm::dvec3 sky = radianceAt(app, hdr, camera.position + 1e5 * dir, 1);
        INFO("near wall " << near.r << " " << near.g << " " << near.b << "; far wall " << far.r << " " << far.g << " " << far.b
                          << "; sky " << sky.r << " " << sky.g << " " << sky.b);
        // Chromaticity: the sandstone's warm colour gives way to the air's blue.
        CHECK(glm::length(chroma(far) - chroma(sky)) < glm::length(chroma(near) - chroma(sky)));
        // Luminance: the veil of in-scattered light brings the wall's towards the sky's.
        CHECK(std::abs(std::log(luminance(far) / luminance(sky))) < std::abs(std::log(luminance(near) / luminance(sky))));
    }
}
