// The night sky's cheaper programs (issue 22, README "Cost"): with a pinhole camera whose pixels
// are all smaller than the panorama's texels the level of detail is fixed at 0, and as the first
// pass over the processor's black target it writes without blending. Both must give the
// general program's pixels, the blended composite over black.
#include <catch2/catch.hpp>

#include "elements_present.hpp"
#include "gl_test_context.hpp"
#include "malta_night.hpp"

#include <welkin/elements/nightsky.hpp>
#include <welkin/elements/registry.hpp>
#include <welkin/gl/objects.hpp>
#include <welkin/processor.hpp>

#include <epoxy/gl.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>

using namespace welkin;

namespace {
constexpr double kDeg = std::numbers::pi / 180.0;

// The view (south, 30 deg up: the Milky Way in Sagittarius and Scutum) at `fovDeg`.
Camera southView(double fovDeg, int w, int h) {
    Camera cam;
    cam.projection = Projection::Perspective;
    cam.azimuthRad = std::numbers::pi;
    cam.altitudeRad = 30 * kDeg;
    cam.verticalFovRad = fovDeg * kDeg;
    cam.width = w;
    cam.height = h;
    return cam;
}

struct Diff {
    double maxAbs = 0, meanAbs = 0, mean = 0;
};
Diff compare(const Image& a, const Image& b) {
    Diff d;
    for (size_t i = 0; i < a.pixels.size(); ++i) {
        const double e = std::abs(double(a.pixels[i]) - b.pixels[i]);
        d.maxAbs = std::max(d.maxAbs, e);
        d.meanAbs += e;
        d.mean += b.pixels[i];
    }
    d.meanAbs /= double(a.pixels.size());
    d.mean /= double(a.pixels.size());
    return d;
}

// The frame through the processor's own target (renderFrame: the first element has nothing
// behind it) or through a host's RGBA32F target cleared to black (renderInto: every element
// blended), with the night sky's fast paths on or off.
Image render(const Camera& cam, bool fast, bool hostTarget, bool withSky) {
    SkyProcessor p;
    test::atMalta(p, cam);
    auto n = std::make_unique<elements::NightSky>();
    n->setFastPaths(fast);
    p.add(std::move(n));
#ifdef WELKIN_HAS_ELEMENT_sky
    if (withSky) p.add(elements::makeElement("sky"));
#else
    (void)withSky;
#endif
    Image img;
    if (!hostTarget) {
        p.renderFrame();
        img = p.readHdr();
    } else {
        gl::Texture2D colour(cam.width, cam.height, GL_RGBA32F);
        auto fbo = gl::Framebuffer::create();
        fbo.attach(GL_COLOR_ATTACHMENT0, colour);
        fbo.checkComplete("test host target");
        fbo.bind();
        const float black[4] = {0, 0, 0, 1};
        glClearBufferfv(GL_COLOR, 0, black);
        p.renderInto({.framebuffer = fbo.id(), .width = cam.width, .height = cam.height});
        const std::vector<float> rgba = colour.readRgbaFloat();  // bottom row first
        img.width = cam.width;
        img.height = cam.height;
        img.pixels.resize(size_t(cam.width) * cam.height * 3);
        for (int y = 0; y < cam.height; ++y)
            for (int x = 0; x < cam.width; ++x)
                for (int c = 0; c < 3; ++c) img.at(x, y, c) = rgba[(size_t(cam.height - 1 - y) * cam.width + x) * 4 + c];
        glBindFramebuffer(GL_FRAMEBUFFER, 0);
    }
    return img;
}

struct Flags {
    bool levelFixed = false, unblended = false;
};
Flags flagsOf(const Camera& cam, bool fast, bool hostTarget) {
    SkyProcessor p;
    test::atMalta(p, cam);
    auto n = std::make_unique<elements::NightSky>();
    n->setFastPaths(fast);
    elements::NightSky* night = n.get();
    p.add(std::move(n));
    gl::Texture2D colour(cam.width, cam.height, GL_RGBA32F);
    auto fbo = gl::Framebuffer::create();
    fbo.attach(GL_COLOR_ATTACHMENT0, colour);
    if (hostTarget) p.renderInto({.framebuffer = fbo.id(), .width = cam.width, .height = cam.height});
    else p.renderFrame();
    return {night->lastLevelFixed(), night->lastUnblended()};
}
}  // namespace

TEST_CASE("NightSky: the fixed level of detail and the unblended pass give the general program's pixels", "[gl][nightsky][display]") {
    test::glContext();
    // 20 deg over 180 rows: 0.11 deg pixels against the panorama's 0.18 deg texels (the
    // condition's 0.64 <= 0.9: the level is 0 everywhere); 60 deg over 180 rows: 0.33 deg pixels
    // (1.9 > 0.9: minified, the general program).
    const Camera magnified = southView(20, 320, 180), minified = southView(60, 320, 180);
    {
        const Flags f = flagsOf(magnified, true, false);
        CHECK(f.levelFixed);
        CHECK(f.unblended);
        const Flags g = flagsOf(minified, true, false);
        CHECK_FALSE(g.levelFixed);
        CHECK(g.unblended);
        const Flags h = flagsOf(magnified, true, true);  // over a host's target: blended
        CHECK(h.levelFixed);
        CHECK_FALSE(h.unblended);
        const Flags o = flagsOf(magnified, false, false);
        CHECK_FALSE(o.levelFixed);
        CHECK_FALSE(o.unblended);
        const Flags fish = flagsOf(test::fisheye(128), true, false);  // not a pinhole
        CHECK_FALSE(fish.levelFixed);
    }
    for (bool withSky : {false, true}) {
        for (const Camera* cam : {&magnified, &minified}) {
            CAPTURE(withSky, cam->verticalFovRad / kDeg);
            // New: renderFrame() with the fast paths. Old: the general program, blended over a
            // black host target (the path every element took before).
            const Image fast = render(*cam, true, false, withSky);
            const Image general = render(*cam, false, true, withSky);
            const Diff d = compare(fast, general);
            std::printf("nightsky fast paths%s, %.0f deg over %d rows: max |diff| %.3g, mean |diff| %.3g cd/m^2 (image mean %.3g)\n",
                        withSky ? " under the Sky" : "", cam->verticalFovRad / kDeg, cam->height, d.maxAbs, d.meanAbs, d.mean);
            CHECK(d.mean > 1e-4);  // the night sky is there (a dark site's ~3e-4 cd/m^2)
            // The same arithmetic on the same texels: the fixed level selects level 0, which the
            // general program's max(log2(...), 0) gives at every pixel of the magnified view; the
            // blend over black adds 0 and multiplies 0. Measured bit-identical (0); the bound
            // allows one float rounding of the pixel (1e-6 relative of ~1e-3 cd/m^2).
            CHECK(d.maxAbs <= 1e-9);
        }
    }
}
