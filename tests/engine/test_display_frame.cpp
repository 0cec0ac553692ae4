// The displayed frame (issue 22, docs/eye.md "Cost"): renderFrame() composites and advances the
// eye, and leaves the tone map's per-pixel pass for readToneMapped() (or the host's
// toneMapInto()), so a viewer that shows the frame with toneMapInto(0) pays one tone map, not
// two. The image readToneMapped() returns is the one renderFrame() drew at once before.
#include <catch2/catch.hpp>

#include "gl_test_context.hpp"

#include <welkin/element.hpp>
#include <welkin/gl/objects.hpp>
#include <welkin/gl/shader.hpp>
#include <welkin/keys.hpp>
#include <welkin/processor.hpp>

#include <epoxy/gl.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cstdio>
#include <cmath>
#include <vector>

using namespace welkin;

namespace {
// Radiance over twelve decades across the image (1e-6 cd/m^2 at the left to 1e6 at the right)
// and a colour that changes down it: the scotopic, mesopic and photopic ranges, the curve's toe
// and shoulder, all in one frame.
class Ramp final : public SkyElement {
public:
    Ramp() : SkyElement("ramp") {}

private:
    void doInit(InitContext&) override {
        program_ = gl::ProgramBuilder("Ramp")
                       .fullscreenVertex()
                       .fragment("engine/composite.glsl", gl::engineShader("composite.glsl"))
                       .fragment("ramp.frag",
                                 "uniform vec2 u_size;\n"
                                 "void main() {\n"
                                 "    vec2 f = gl_FragCoord.xy / u_size;\n"
                                 "    welkin_output(pow(10.0, 12.0 * f.x - 6.0) * vec3(1.0, 0.4 + 0.6 * f.y, 1.4 - f.y), vec3(0.0));\n"
                                 "}\n")
                       .build();
    }
    void doRender(const FrameContext& ctx) override {
        program_.use();
        program_.set("u_size", glm::vec2(ctx.camera.width, ctx.camera.height));
        ctx.drawFullscreen();
    }
    void doRelease() override { program_ = {}; }
    gl::Program program_;
};

// Largest absolute difference between an Image (top row first) and a texture's RGBA floats
// (bottom row first), over RGB.
double maxDifference(const Image& img, const std::vector<float>& rgbaBottomUp) {
    double d = 0.0;
    for (int y = 0; y < img.height; ++y)
        for (int x = 0; x < img.width; ++x)
            for (int c = 0; c < 3; ++c)
                d = std::max(d, std::abs(double(img.at(x, y, c)) - rgbaBottomUp[(size_t(img.height - 1 - y) * img.width + x) * 4 + c]));
    return d;
}

// A processor drawing the Ramp alone into w x h, at EV100 3 (manual or automatic exposure).
void setUpRamp(SkyProcessor& p, int w, int h, bool automatic) {
    Camera cam;
    cam.width = w;
    cam.height = h;
    p.setCamera(cam);
    p.setAnimationTime(0.0);
    p.setExposure({.automatic = automatic, .ev100 = 3.0});
    p.add(std::make_unique<Ramp>());
}

double maxDifference(const Image& a, const Image& b) {
    double d = 0.0;
    for (size_t i = 0; i < a.pixels.size(); ++i) d = std::max(d, std::abs(double(a.pixels[i]) - b.pixels[i]));
    return d;
}
}  // namespace

TEST_CASE("The displayed frame: readToneMapped() draws renderFrame()'s tone map when asked, as toneMapInto() does",
          "[gl][tonemap][display]") {
    test::glContext();
    const int w = 96, h = 24;
    for (bool automatic : {false, true}) {
        CAPTURE(automatic);
        SkyProcessor p;
        setUpRamp(p, w, h, automatic);
        gl::Texture2D shown(w, h, GL_RGBA8);
        auto fbo = gl::Framebuffer::create();
        fbo.attach(GL_COLOR_ATTACHMENT0, shown);
        fbo.checkComplete("test display target");

        // A viewer's frame: renderFrame(), then the tone map into its own target.
        p.renderFrame();
        p.toneMapInto(fbo.id());
        const std::vector<float> viewer = shown.readRgbaFloat();
        const Image own = p.readToneMapped();  // drawn now, from the same HDR frame and eye state
        // The ramp spans black to white: the image is not trivially equal.
        float lo = 1.0f, hi = 0.0f;
        for (float v : own.pixels) lo = std::min(lo, v), hi = std::max(hi, v);
        CHECK(lo < 0.05f);
        CHECK(hi > 0.95f);
        // The same program with the same uniforms and, with the automatic exposure, the same
        // eye state (a second tone map of a frame with its own settings takes no adaptation
        // step: ToneMapper::advance()): bit for bit.
        CHECK(maxDifference(own, viewer) == 0.0);
        // Below: the late draw against frames of their own (the eye steps between them).
        const double tolerance = automatic ? 1.0 / 255.0 + 1e-6 : 0.0;

        // The frame's own settings: a key changed after renderFrame() reaches the next frame,
        // not the tone map of this one that readToneMapped() draws late.
        p.renderFrame();
        const Image first = p.readToneMapped();
        p.renderFrame();
        p.vars().set(keys::exposureEv100, 10.0);  // 7 stops darker for a manual exposure
        const Image late = p.readToneMapped();
        CHECK(maxDifference(late, first) <= tolerance);
        CHECK(maxDifference(p.readToneMapped(), late) == 0.0);  // read again: the same target, not drawn again
        p.renderFrame();
        const Image next = p.readToneMapped();
        if (!automatic) CHECK(maxDifference(next, first) > 0.3);  // the new exposure shows from the next frame
        else CHECK(maxDifference(next, first) <= tolerance);       // the automatic exposure ignores ev100
    }
}

TEST_CASE("The displayed frame: into an sRGB target the framebuffer encodes on write, within one 8-bit code of the shader's encoding",
          "[gl][tonemap][display]") {
    test::glContext();
    const int w = 96, h = 24;
    // The raw stored bytes of an RGBA8-class texture, bottom row first (a view as RGBA8: no sRGB
    // decoding on the read).
    auto rawBytes = [](const gl::Texture2D& t) {
        GLuint view = 0;
        glGenTextures(1, &view);
        glTextureView(view, GL_TEXTURE_2D, t.id(), GL_RGBA8, 0, 1, 0, 1);
        std::vector<unsigned char> out(size_t(t.width()) * t.height() * 4);
        glPixelStorei(GL_PACK_ALIGNMENT, 1);
        glGetTextureImage(view, 0, GL_RGBA, GL_UNSIGNED_BYTE, GLsizei(out.size()), out.data());
        glDeleteTextures(1, &view);
        return out;
    };
    for (bool automatic : {false, true}) {
        CAPTURE(automatic);
        SkyProcessor p;
        setUpRamp(p, w, h, automatic);
        gl::Texture2D linear(w, h, GL_RGBA8), srgb(w, h, GL_SRGB8_ALPHA8);
        auto linearFbo = gl::Framebuffer::create(), srgbFbo = gl::Framebuffer::create();
        linearFbo.attach(GL_COLOR_ATTACHMENT0, linear);
        srgbFbo.attach(GL_COLOR_ATTACHMENT0, srgb);
        p.renderFrame();
        p.toneMapInto(linearFbo.id());
        CHECK_FALSE(p.stats()["tonemap_srgb_target"].get<bool>());  // RGBA8: the shader encodes
        p.toneMapInto(srgbFbo.id());
        CHECK(p.stats()["tonemap_srgb_target"].get<bool>());  // SRGB8_ALPHA8: the framebuffer does
        CHECK_FALSE(glIsEnabled(GL_FRAMEBUFFER_SRGB));        // and the state is as it was
        const std::vector<unsigned char> a = rawBytes(linear), b = rawBytes(srgb);
        int maxCodes = 0, lo = 255, hi = 0;
        size_t differing = 0;
        for (size_t i = 0; i < a.size(); ++i) {
            if (i % 4 == 3) continue;
            maxCodes = std::max(maxCodes, std::abs(int(a[i]) - int(b[i])));
            differing += a[i] != b[i];
            lo = std::min(lo, int(b[i])), hi = std::max(hi, int(b[i]));
        }
        std::printf("tone map into SRGB8_ALPHA8 (encoded on write) against RGBA8 (encoded in the shader): max %d codes, %zu of %zu values differ\n",
                    maxCodes, differing, a.size() / 4 * 3);
        CHECK(lo == 0);  // the ramp spans black to white: the comparison covers every code range
        CHECK(hi == 255);
        // The shader's encoding is within 6e-6 of the standard (docs/eye.md); the driver's
        // conversion on write rounds its own way: one code apart at most.
        CHECK(maxCodes <= 1);
    }
}
