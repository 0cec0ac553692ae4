// The night sky's image reuse (issue 22, README "Reusing the image"): in displayed frames the
// pass's image, drawn first over the processor's black target, is kept and copied back instead of
// drawn while every input is the same and the sky's rotation moved no screen direction by more
// than nightsky.reuse_tolerance_px. The flags (NightSky::lastReused, the counters) say which path
// ran, so no check below compares a path with itself; the fresh images come from a second
// processor with the reuse off.
#include <catch2/catch.hpp>

#include "gl_test_context.hpp"
#include "malta_night.hpp"

#include <welkin/astro/astro_keys.hpp>
#include <welkin/elements/nightsky.hpp>
#include <welkin/gl/objects.hpp>
#include <welkin/keys.hpp>
#include <welkin/processor.hpp>

#include <epoxy/gl.h>
#include <glm/gtc/matrix_transform.hpp>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <memory>
#include <numbers>

using namespace welkin;

namespace {
constexpr double kDeg = std::numbers::pi / 180.0;
constexpr double kEarthRate = 7.2921159e-5;  // rad per s of UT: how fast the sky turns (15.04 arcsec/s)

// 20 deg over 180 rows: 0.11 deg pixels under the panorama's 0.18 deg texels, so the pass samples
// level 0 everywhere (the fast path's fixed level): the bound below is for that level.
Camera view(double azimuthDeg = 180.0) {
    Camera cam;
    cam.projection = Projection::Perspective;
    cam.azimuthRad = azimuthDeg * kDeg;
    cam.altitudeRad = 30 * kDeg;
    cam.verticalFovRad = 20 * kDeg;
    cam.width = 320;
    cam.height = 180;
    return cam;
}

struct Night {
    std::unique_ptr<SkyProcessor> p;
    elements::NightSky* n = nullptr;
    int frame = 0;
};

// The night sky alone over Malta, displayed frames (render.interactive) with a manual exposure
// that shows it (EV100 -8: the skip's bound is far above half a code).
Night make(bool reuse, bool interactive = true) {
    Night s;
    s.p = std::make_unique<SkyProcessor>();
    test::atMalta(*s.p, view());
    s.p->vars().set(keys::interactive, interactive);
    s.p->setExposure({.automatic = false, .ev100 = -8});
    auto n = std::make_unique<elements::NightSky>();
    s.n = n.get();
    s.p->add(std::move(n));
    s.p->vars().set(elements::nightkeys::reuse, reuse);
    return s;
}

Image frameAt(Night& s, double seconds) {
    s.p->setTime(test::kMaltaNight.plusSeconds(seconds));
    s.p->setAnimationTime(0.05 * s.frame++);
    s.p->renderFrame();
    return s.p->readHdr();
}

glm::dmat3 rotationOf(const Night& s) { return s.p->vars().get(astro::keys::starFrameRotation); }

// The angle of the rotation a -> b, from its trace (independent of the element's Frobenius form).
double angleBetween(const glm::dmat3& a, const glm::dmat3& b) {
    const glm::dmat3 d = b * glm::transpose(a);
    return std::acos(std::clamp((d[0][0] + d[1][1] + d[2][2] - 1.0) / 2.0, -1.0, 1.0));
}

// The pinhole's largest scale, pixels per radian: f / cos^2 at the corner, f = (H/2) / tan(fov/2)
// and tan^2 of the corner's off-axis angle t^2 (1 + aspect^2).
double cornerPixelsPerRadian(const Camera& c) {
    const double t = std::tan(0.5 * c.verticalFovRad), a = double(c.width) / c.height;
    return 0.5 * c.height / t * (1.0 + t * t * (1.0 + a * a));
}

bool identical(const Image& a, const Image& b) {
    return a.pixels.size() == b.pixels.size() && std::memcmp(a.pixels.data(), b.pixels.data(), a.pixels.size() * sizeof(float)) == 0;
}
}  // namespace

TEST_CASE("NightSky: the kept image is reused only while its inputs hold, within the derived bound", "[gl][nightsky][display]") {
    test::glContext();
    Night a = make(true);
    Night fresh = make(false);

    // Nothing changed: the first frame draws (nothing to compare with), the second draws and keeps
    // (the same inputs as the first), the third copies; it is a fresh draw's image bit for bit.
    frameAt(a, 0);
    CHECK_FALSE(a.n->lastReused());
    CHECK(a.n->reuseKeeps() == 0);
    frameAt(a, 0);
    CHECK_FALSE(a.n->lastReused());
    CHECK(a.n->reuseKeeps() == 1);
    const Image reused = frameAt(a, 0);
    REQUIRE(a.n->lastReused());
    CHECK(a.n->reuseHits() == 1);
    CHECK(a.p->stats()["nightsky"]["reused"].get<bool>());
    CHECK(a.n->reuseBytes() == size_t(320) * 180 * 16);  // one RGBA32F image of the target's size
    const Image drawn = frameAt(fresh, 0);
    CHECK_FALSE(fresh.n->lastReused());
    CHECK(fresh.n->reuseBytes() == 0);  // the key off: no memory held
    CHECK(identical(reused, drawn));

    // The sky turned by less than the tolerance (0.05 px by default): 0.5 s of Earth rotation is
    // 3.6e-5 rad, 0.021 px at the corner's 576 px/rad: reused, and within the bound.
    const glm::dmat3 r0 = rotationOf(a);
    const Image shifted = frameAt(a, 0.5);
    const glm::dmat3 r1 = rotationOf(a);
    const double theta = angleBetween(r0, r1), ppr = cornerPixelsPerRadian(view());
    CAPTURE(theta, ppr, theta * ppr);
    CHECK(theta == Approx(0.5 * kEarthRate).epsilon(0.01));  // the frame's rotation is the Earth's (precession is slower)
    CHECK(elements::NightSky::rotationAngle(r0, r1) == Approx(theta).epsilon(1e-6));
    CHECK(elements::NightSky::maxPixelsPerRadian(view()) == Approx(1.01 * ppr).epsilon(1e-9));  // its 1 % margin
    REQUIRE(theta * ppr < 0.05);
    CHECK(a.n->lastReused());
    CHECK(a.n->reuseHits() == 2);
    // The fresh image at 0.5 s, its folded panorama built at 0 s as the kept one's (the Sun's
    // 0.5 s moves no rebuild; a fresh processor would build it for 0.5 s: another zodiacal light).
    const Image moved = frameAt(fresh, 0.5);
    CHECK_FALSE(fresh.n->lastReused());
    {
        // The bound (README): the pass is 1e-4 x the folded panorama's bilinear interpolation B at
        // the pixel's J2000 direction, plus terms of the horizon frame (airglow, light pollution,
        // extinction <= 1) that the rotation does not change. Between two texel coordinates
        // |dB| <= Gx |dx| + Gy |dy|, Gx and Gy the largest differences between neighbouring texels
        // along each axis around the two points (B is bilinear in each cell). dx, dy from the two
        // rotations in double (milkyWayTexCoord), each widened by kSlack texels for the shader's
        // float coordinates in both images (u, v ~0.5 in float: 1.2e-4 texels a rounding; atan,
        // acos and the float rotation a few more; measured: without it 113 of 172,800 values
        // exceed, up to 2.5x). llvmpipe filters float textures with float weights; a GPU whose
        // weights have GL's minimum 8 bits of sub-texel precision would need 1/256 more.
        constexpr double kSlack = 1e-3;
        const std::vector<float> fold = a.n->readFolded(0);  // bottom row first = the panorama's top (t = 0)
        const int W = 2048, H = 1024;
        REQUIRE(fold.size() == size_t(W) * H * 4);
        auto texel = [&](int i, int j, int c) {
            i = ((i % W) + W) % W;
            j = std::clamp(j, 0, H - 1);
            return double(fold[(size_t(j) * W + i) * 4 + c]);
        };
        const Camera cam = view();
        double worst = 0.0, maxDiff = 0.0, maxBound = 0.0;
        size_t differing = 0;
        for (int y = 0; y < cam.height; ++y)
            for (int x = 0; x < cam.width; ++x) {
                const glm::dvec3 d = *cam.directionAt({x + 0.5, y + 0.5});
                const glm::dvec2 uv0 = elements::milkyWayTexCoord(glm::transpose(r0) * d), uv1 = elements::milkyWayTexCoord(glm::transpose(r1) * d);
                double du = std::abs(uv1.x - uv0.x);
                du = std::min(du, 1.0 - du);  // across the seam
                const double dx = du * W + kSlack, dy = std::abs(uv1.y - uv0.y) * H + kSlack;
                const int i0 = int(std::floor(uv0.x * W - 0.5)), j0 = int(std::floor(uv0.y * H - 0.5));
                for (int c = 0; c < 3; ++c) {
                    double gx = 0.0, gy = 0.0;
                    for (int j = j0 - 1; j <= j0 + 2; ++j)
                        for (int i = i0 - 1; i <= i0 + 2; ++i) {
                            gx = std::max(gx, std::abs(texel(i + 1, j, c) - texel(i, j, c)));
                            gy = std::max(gy, std::abs(texel(i, j + 1, c) - texel(i, j, c)));
                        }
                    const double bound = 1e-4 * (gx * dx + gy * dy);  // kMwStorageScale
                    const double diff = std::abs(double(shifted.at(x, y, c)) - double(moved.at(x, y, c)));
                    maxDiff = std::max(maxDiff, diff);
                    maxBound = std::max(maxBound, bound);
                    worst = std::max(worst, diff / std::max(bound, 1e-30));
                    differing += diff > 0.0;
                    CHECK(diff <= bound);
                }
            }
        double gAll = 0.0, brightest = 0.0;  // the panorama's largest neighbour difference and texel, cd/m^2
        for (int j = 0; j < H; ++j)
            for (int i = 0; i < W; ++i)
                for (int c = 0; c < 3; ++c) {
                    brightest = std::max(brightest, 1e-4 * texel(i, j, c));
                    gAll = std::max({gAll, 1e-4 * std::abs(texel(i + 1, j, c) - texel(i, j, c)), 1e-4 * std::abs(texel(i, j + 1, c) - texel(i, j, c))});
                }
        std::printf("nightsky reuse: the folded panorama's largest neighbouring-texel difference %.3g cd/m^2, brightest texel %.3g cd/m^2\n", gAll,
                    brightest);
        std::printf("nightsky reuse, 0.5 s of rotation (%.3f px): reused against fresh max |diff| %.3g cd/m^2, bound there up to %.3g, "
                    "largest diff / bound %.3f, %zu of %zu values differ\n",
                    theta * ppr, maxDiff, maxBound, worst, differing, shifted.pixels.size());
        CHECK(differing > 0);  // the fresh image did move: the reused one is not the same draw
    }

    // Above the tolerance: 3 s (0.126 px) redraws, and the redrawn image is the fresh one exactly.
    const Image redrawn = frameAt(a, 3.0);
    CHECK_FALSE(a.n->lastReused());
    CHECK(identical(redrawn, frameAt(fresh, 3.0)));
    frameAt(a, 3.0);  // the same inputs twice: kept
    CHECK_FALSE(a.n->lastReused());
    frameAt(a, 3.0);
    CHECK(a.n->lastReused());

    // A key: another Milky Way scale redraws (and refolds the panorama).
    a.p->vars().set(elements::nightkeys::milkyWayScale, 2.0);
    frameAt(a, 3.0);
    CHECK_FALSE(a.n->lastReused());
    frameAt(a, 3.0);
    frameAt(a, 3.0);
    CHECK(a.n->lastReused());
    // The camera: a degree to the east redraws.
    a.p->setCamera(view(181.0));
    frameAt(a, 3.0);
    CHECK_FALSE(a.n->lastReused());
    frameAt(a, 3.0);
    frameAt(a, 3.0);
    CHECK(a.n->lastReused());
    // The exposure's skip: at a daylight exposure the pass is skipped; back at the night's, it is
    // drawn again, not copied, though every other input is the kept image's.
    a.p->setExposure({.automatic = false, .ev100 = 15});
    frameAt(a, 3.0);
    CHECK(a.n->lastSkippedInvisible());
    CHECK_FALSE(a.n->lastReused());
    a.p->setExposure({.automatic = false, .ev100 = -8});
    frameAt(a, 3.0);
    CHECK_FALSE(a.n->lastSkippedInvisible());
    CHECK_FALSE(a.n->lastReused());
    frameAt(a, 3.0);
    frameAt(a, 3.0);
    CHECK(a.n->lastReused());
    // Tolerance 0: reused only at the identical rotation.
    a.p->vars().set(elements::nightkeys::reuseTolerancePx, 0.0);
    frameAt(a, 3.0);
    CHECK(a.n->lastReused());
    frameAt(a, 3.1);
    CHECK_FALSE(a.n->lastReused());
    // A turning camera: every frame drawn, none kept (no copy paid for nothing).
    a.p->vars().set(elements::nightkeys::reuseTolerancePx, 0.05);
    const int keeps = a.n->reuseKeeps();
    for (int i = 0; i < 4; ++i) {
        a.p->setCamera(view(182.0 + i));
        frameAt(a, 3.0);
        CHECK_FALSE(a.n->lastReused());
    }
    CHECK(a.n->reuseKeeps() == keeps);
}

TEST_CASE("NightSky: no reuse over a host's target, in offline frames or with the key off", "[gl][nightsky][display]") {
    test::glContext();
    // The host's renderInto(): something may be behind the sky, the pass blends: never kept.
    {
        Night s = make(true);
        const Camera cam = view();
        gl::Texture2D colour(cam.width, cam.height, GL_RGBA32F);
        auto fbo = gl::Framebuffer::create();
        fbo.attach(GL_COLOR_ATTACHMENT0, colour);
        fbo.checkComplete("test host target");
        for (int i = 0; i < 4; ++i) {
            s.p->setAnimationTime(0.05 * i);
            fbo.bind();
            const float black[4] = {0, 0, 0, 1};
            glClearBufferfv(GL_COLOR, 0, black);
            s.p->renderInto({.framebuffer = fbo.id(), .width = cam.width, .height = cam.height});
            CHECK(s.n->drawn());
            CHECK_FALSE(s.n->lastReused());
        }
        glBindFramebuffer(GL_FRAMEBUFFER, 0);
        CHECK(s.n->reuseKeeps() == 0);
        CHECK(s.n->reuseBytes() == 0);
    }
    // welkin render (render.interactive false) and the key off: never kept, no memory held.
    for (int which = 0; which < 2; ++which) {
        Night s = which == 0 ? make(true, false) : make(false);
        for (int i = 0; i < 4; ++i) {
            frameAt(s, 0);
            CHECK(s.n->drawn());
            CHECK_FALSE(s.n->lastReused());
        }
        CHECK(s.n->reuseKeeps() == 0);
        CHECK(s.n->reuseBytes() == 0);
    }
}

TEST_CASE("NightSky: the reuse's largest pixels per radian bounds the camera's scale over the image", "[cpu][nightsky]") {
    // Camera::pixelScale (the projection's own Jacobian) sampled over a 65 x 65 grid of pixel
    // positions, edges and corners included: never above the bound, and the bound not loose
    // (within its 1 % margin of the largest sample, which a pinhole has at a corner).
    auto sampled = [](const Camera& c) {
        double best = 0.0;
        for (int j = 0; j <= 64; ++j)
            for (int i = 0; i <= 64; ++i) {
                const auto d = c.directionAt({c.width * i / 64.0, c.height * j / 64.0});
                if (!d) continue;
                if (const auto s = c.pixelScale(*d)) best = std::max(best, (*s)[1]);
            }
        return best;
    };
    const glm::dvec3 fwd = glm::normalize(glm::dvec3(0.4, 0.3, -1.0));
    const glm::dmat4 hostView = glm::lookAt(glm::dvec3(0.0), fwd, glm::dvec3(0, 1, 0));
    const Camera host = Camera::fromViewProjection(hostView, glm::frustum(-0.3, 0.7, -0.2, 0.4, 0.5, 100.0), enuFromYUp(), 640, 384);
    Camera wide = view();
    wide.verticalFovRad = 120 * kDeg;
    Camera bench = view();
    bench.verticalFovRad = 60 * kDeg;
    bench.width = 1280;
    bench.height = 720;
    for (const Camera& c : {view(), wide, bench, host}) {
        const double bound = elements::NightSky::maxPixelsPerRadian(c), seen = sampled(c);
        CAPTURE(c.width, c.height, c.verticalFovRad, bool(c.host), bound, seen);
        CHECK(seen <= bound);
        CHECK(seen >= bound / 1.01 * (1.0 - 1e-9));  // the corner is sampled: the bound is the largest scale
    }
    // bench display's view: f / cos^2 at the corner, 623.5 x 2.387 = 1488 px/rad.
    CHECK(elements::NightSky::maxPixelsPerRadian(bench) / 1.01 == Approx(cornerPixelsPerRadian(bench)).epsilon(1e-9));
    CHECK(cornerPixelsPerRadian(bench) == Approx(1488.3).epsilon(1e-4));
    // The fisheye: largest along the horizon, R = min(size) / 2 (pixelScale at altitude 0).
    const Camera fish = test::fisheye(512);
    const double fb = elements::NightSky::maxPixelsPerRadian(fish);
    CHECK(fb == Approx(1.01 * 256.0));
    CHECK(sampled(fish) <= fb);
    for (double az = 0; az < 360; az += 45) CHECK((*fish.pixelScale(directionFromAzAlt(az * kDeg, 0.0)))[1] == Approx(256.0).epsilon(1e-6));
    // Equirect and cube faces: no bound (reused only at the identical rotation).
    Camera eq = view();
    eq.projection = Projection::Equirect;
    CHECK(std::isinf(elements::NightSky::maxPixelsPerRadian(eq)));
    Camera cube = view();
    cube.projection = Projection::CubeFace;
    CHECK(std::isinf(elements::NightSky::maxPixelsPerRadian(cube)));
}
