// The eye (welkin/eye.hpp, docs/eye.md): the TVI model, the temporal adaptation, the mesopic
// colour and the tone map that applies them, fed with uniform fields of known luminance.
#include <catch2/catch.hpp>

#include "gl_test_context.hpp"
#include "uniform_field.hpp"

#include <welkin/color.hpp>
#include <welkin/eye.hpp>
#include <welkin/gl/shader.hpp>
#include <welkin/keys.hpp>
#include <welkin/processor.hpp>

#include <epoxy/gl.h>

#include <algorithm>
#include <random>
#include <cmath>
#include <cstdio>
#include <vector>

using namespace welkin;

namespace {
using Field = test::UniformField;

Camera smallCamera() {
    Camera c;  // perspective: every pixel weighs in the meter
    c.width = 16;
    c.height = 16;
    return c;
}

double srgbDecode(double v) { return v <= 0.04045 ? v / 12.92 : std::pow((v + 0.055) / 1.055, 2.4); }

// Mean of the decoded (linear) tone-mapped image.
glm::dvec3 meanDisplayed(const SkyProcessor& p) {
    Image img = p.readToneMapped();
    glm::dvec3 s(0.0);
    for (int y = 0; y < img.height; ++y)
        for (int x = 0; x < img.width; ++x)
            for (int c = 0; c < 3; ++c) s[c] += srgbDecode(img.at(x, y, c));
    return s / double(img.width * img.height);
}

const glm::dvec3 kOrange(1.0, 0.35, 0.08);  // a saturated colour, far from both white and the rod hue
}  // namespace

TEST_CASE("Eye: Ferwerda's threshold curves, the Larson scotopic luminance", "[cpu][eye]") {
    // The fit's pieces meet: Ferwerda 1996's published coefficients join within 0.013 log units
    // (the rods' upper knee: (0.405 * -1.44 + 1.6)^2.18 - 2.86 = -1.823 against -1.835).
    for (double l : {-2.6, 1.9}) CHECK(eye::coneThresholdLog10(std::pow(10.0, l - 1e-9)) == Approx(eye::coneThresholdLog10(std::pow(10.0, l + 1e-9))).margin(0.013));
    for (double l : {-3.94, -1.44}) CHECK(eye::rodThresholdLog10(std::pow(10.0, l - 1e-9)) == Approx(eye::rodThresholdLog10(std::pow(10.0, l + 1e-9))).margin(0.013));
    // Weber ranges (threshold proportional to the luminance) and the absolute floors.
    CHECK(eye::coneThresholdLog10(1e3) == Approx(3 - 1.255).margin(1e-12));
    CHECK(eye::rodThresholdLog10(1.0) == Approx(-0.395).margin(1e-12));
    CHECK(eye::coneThresholdLog10(1e-4) == -0.72);
    CHECK(eye::rodThresholdLog10(1e-6) == -2.86);
    CHECK_THROWS_WITH(eye::coneThresholdLog10(0.0), "eye::coneThresholdLog10(): adaptation luminance 0 not > 0");
    // V' of the D65 white by hand from its XYZ (0.95047, 1, 1.08883): 1.33 (1 + 2.08883 / 0.95047)
    // - 1.68 = 2.5729; 1e-3: the sRGB matrix's four-digit rounding.
    CHECK(eye::scotopicPerPhotopicWhite() == Approx(2.5729).epsilon(1e-3));
    // Purkinje: a red light looks darker to the rods than a blue one of equal luminance.
    const glm::dvec3 red(1, 0, 0), blue(0, 0, 1);
    CHECK(eye::scotopicLuminance(red) / color::luminance(red) < eye::scotopicLuminance(blue) / color::luminance(blue));
    CHECK(eye::scotopicLuminance(glm::dvec3(0.0)) == 0.0);
}

TEST_CASE("Eye: darker scenes display darker, daylight exposes as a camera", "[cpu][eye]") {
    const double kappa = eye::scotopicPerPhotopicWhite();
    // The display value of the adaptation luminance itself (before the curve) for a grey scene.
    auto displayed = [&](double L) { return eye::eyeExposure({L, kappa * L}) * L; };
    // Daylight: cones in their Weber range give the camera's log-average exposure (1e-12:
    // the same arithmetic in two orders).
    for (double L : {100.0, 5e3, 1e5}) CHECK(eye::eyeExposure({L, kappa * L}) == Approx(eye::cameraExposure(L)).epsilon(1e-12));
    // Monotonic from below the absolute threshold to daylight: a darker scene is never shown brighter.
    double prev = 0;
    for (double l = -7; l <= 6; l += 0.05) {
        const double d = displayed(std::pow(10.0, l));
        INFO("log10 L = " << l);
        CHECK(d >= prev * (1 - 1e-12));
        prev = d;
    }
    // The ladder of the task: moonless night (~1e-4), moonlit (~1e-3 .. 1e-2), civil twilight
    // (~1), day; each rung at least a stop above the one below.
    CHECK(displayed(1e-3) > 2 * displayed(1e-4));
    CHECK(displayed(1.0) > 2 * displayed(1e-3));
    CHECK(displayed(1e3) > 2 * displayed(1.0));
    // The eye stops adapting below the rods' floor: the exposure is constant there.
    CHECK(eye::eyeExposure({1e-6, 1e-6}) == Approx(eye::eyeExposure({1e-7, 1e-7})).epsilon(1e-12));
    // EV100 round trip.
    CHECK(eye::ev100FromExposure(eye::exposureFromEv100(-3.25)) == Approx(-3.25).margin(1e-12));
}

TEST_CASE("Eye: temporal adaptation reaches 63 % of a step after one time constant", "[cpu][eye]") {
    const double tc = 0.4, tr = 120;
    const double f = 1 - std::exp(-1.0);  // 63.2 %
    auto part = [](double from, double to, double now) { return std::log(now / from) / std::log(to / from); };
    // Darkening (day -> night): cones with their constant, rods with theirs.
    eye::Adaptation day{1e3, 2.5e3}, night{1e-3, 2.5e-3};
    eye::Adaptation a = eye::adapt(day, night, tc, tc, tr);
    CHECK(part(day.cone, night.cone, a.cone) == Approx(f).margin(1e-12));
    a = eye::adapt(day, night, tr, tc, tr);
    CHECK(part(day.rod, night.rod, a.rod) == Approx(f).margin(1e-12));
    // Brightening: light adaptation is fast for both.
    a = eye::adapt(night, day, tc, tc, tr);
    CHECK(part(night.cone, day.cone, a.cone) == Approx(f).margin(1e-12));
    CHECK(part(night.rod, day.rod, a.rod) == Approx(f).margin(1e-12));
    // Ten steps of tau/10 equal one step of tau (frame-rate independent; 1e-9: rounding over
    // the ten exponentials).
    eye::Adaptation s = day;
    for (int i = 0; i < 10; ++i) s = eye::adapt(s, night, tc / 10, tc, tr);
    CHECK(s.cone == Approx(eye::adapt(day, night, tc, tc, tr).cone).epsilon(1e-9));
    // tau = 0 jumps; dt = 0 stays.
    CHECK(eye::adapt(day, night, 0.01, 0, 0).rod == night.rod);
    CHECK(eye::adapt(day, night, 0.0, tc, tr).cone == day.cone);
    CHECK_THROWS_WITH(eye::adapt(day, night, -1, tc, tr), "eye::adapt(): dt -1 not >= 0");
    CHECK_THROWS_WITH(eye::adapt(day, {0, 1}, 1, tc, tr), "eye::adapt(): luminance 0 not a finite value > 0");
}

TEST_CASE("Eye: the mesopic weight and colour (CPU twin)", "[cpu][eye]") {
    const double lo = 1e-3, hi = 3;
    CHECK(eye::rodWeight(1e-5, lo, hi) == 1.0);
    CHECK(eye::rodWeight(lo, lo, hi) == 1.0);
    CHECK(eye::rodWeight(hi, lo, hi) == 0.0);
    CHECK(eye::rodWeight(100, lo, hi) == 0.0);
    CHECK(eye::rodWeight(std::sqrt(lo * hi), lo, hi) == Approx(0.5).margin(1e-12));  // smoothstep's midpoint in log
    // Photopic: unchanged; scotopic: the rod hue at V' / (V'/Y)_white.
    const glm::dvec2 rod(0.25, 0.25);
    CHECK(eye::mesopicColor(kOrange * 10.0, lo, hi, rod) == kOrange * 10.0);
    const glm::dvec3 s = eye::mesopicColor(kOrange * 1e-4, lo, hi, rod);
    const glm::dvec2 xy = color::chromaticity(color::linearSrgbToXyz(s));
    CHECK(xy.x == Approx(0.25).margin(1e-9));
    CHECK(xy.y == Approx(0.25).margin(1e-9));
    CHECK(color::luminance(s) == Approx(eye::scotopicLuminance(kOrange * 1e-4) / eye::scotopicPerPhotopicWhite()).epsilon(1e-9));
    // A grey keeps its luminance through the transition (V'/Y of the white is the normalisation).
    CHECK(color::luminance(eye::mesopicColor(glm::dvec3(1e-4), lo, hi, rod)) == Approx(1e-4).epsilon(1e-9));
}

TEST_CASE("Eye: the tone map's sRGB transfer function without pow (CPU twin)", "[cpu][eye][tonemap]") {
    // The rational stand-in for x^(1/2.4) against the standard's formula on a dense grid: 6e-6 is
    // the fit's largest error (1/650 of an 8-bit step), so no displayed code can move by more than one.
    double worst = 0;
    for (int i = 0; i <= 200000; ++i) {
        const double x = std::pow(10.0, -6.0 + 6.0 * i / 200000.0);  // 1e-6 .. 1, log-spaced
        worst = std::max(worst, std::abs(eye::srgbEncodeFast(x) - eye::srgbEncode(x)));
    }
    CHECK(worst < 6e-6);
    // Continuous at the knee (the linear segment's end, 0.0031308 -> 0.04045) and exact at 0 and 1
    // within the same bound.
    CHECK(eye::srgbEncodeFast(0.0031308) == Approx(0.040450).margin(1e-5));
    CHECK(eye::srgbEncodeFast(1.0) == Approx(1.0).margin(6e-6));
    CHECK(eye::srgbEncodeFast(0.0) == 0.0);
    CHECK(eye::srgbEncode(0.5) == Approx(0.735357).margin(1e-6));  // the standard's value at mid-grey
}

TEST_CASE("Eye: the GPU tone map of a host's HDR texture equals the CPU curves (RGBA32F image and RGBA16F sampler paths)",
          "[gl][eye][tonemap]") {
    test::glContext();
    // A ramp over 11 decades of exposed value, each texel exactly representable in half float
    // (m * 2^e, m in {1, 1.25, 1.5, 1.75}), so both formats hold the same numbers; the channels
    // differ (g = r / 2, b = r / 8) so the per-channel curves and Reinhard's luminance are exercised.
    const int w = 64, h = 2;
    std::vector<float> texels(size_t(w) * h * 4);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const float r = std::ldexp(1.0f + 0.25f * float(x % 4), x / 4 - 14 + 8 * y);  // 2^-14 .. 2^9
            float* t = &texels[(size_t(y) * w + x) * 4];
            t[0] = r, t[1] = r / 2, t[2] = r / 8, t[3] = 1;
        }
    SkyProcessor p(SkyVars::earth(), Logger(), ProcessorOptions{.astronomy = false});
    Camera cam;
    cam.width = w;
    cam.height = h;
    p.setCamera(cam);
    const double ev100 = 3.0;
    p.setExposure({.automatic = false, .ev100 = ev100});
    p.vars().set(eye::keys::mesopic, false);
    const float exposure = float(eye::exposureFromEv100(ev100));  // the shader's uniform is a float
    gl::Texture2D ldr(w, h, GL_RGBA8);
    gl::Framebuffer fbo = gl::Framebuffer::create();
    fbo.attach(GL_COLOR_ATTACHMENT0, ldr);
    for (GLenum format : {GL_RGBA32F, GL_RGBA16F}) {
        gl::Texture2D hdr(w, h, format);
        glTextureSubImage2D(hdr.id(), 0, 0, 0, w, h, GL_RGBA, GL_FLOAT, texels.data());
        for (int curve = 0; curve <= 3; ++curve) {
            p.vars().set(eye::keys::curve, curve);
            p.toneMapInto(fbo.id(), hdr.id());
            std::vector<unsigned char> out(size_t(w) * h * 4);
            glGetTextureImage(ldr.id(), 0, GL_RGBA, GL_UNSIGNED_BYTE, GLsizei(out.size()), out.data());
            int worst = 0;
            for (int i = 0; i < w * h; ++i) {
                const glm::dvec3 x = glm::dvec3(texels[size_t(i) * 4], texels[size_t(i) * 4 + 1], texels[size_t(i) * 4 + 2]) * double(exposure);
                const glm::dvec3 c = curve == 0   ? eye::acesFit(x)
                                     : curve == 1 ? eye::hable(x)
                                     : curve == 2 ? eye::reinhardLuminance(x)
                                                  : glm::clamp(x, 0.0, 1.0);
                for (int k = 0; k < 3; ++k) {
                    const int expected = int(std::lround(eye::srgbEncode(c[k]) * 255.0));
                    worst = std::max(worst, std::abs(int(out[size_t(i) * 4 + k]) - expected));
                }
            }
            INFO((format == GL_RGBA32F ? "RGBA32F" : "RGBA16F") << " curve " << curve);
            // One 8-bit code: float32 arithmetic against double, and the unorm conversion's
            // rounding, can each land a value on the other side of a code boundary; the fit's own
            // error is 1/650 of a code.
            CHECK(worst <= 1);
        }
    }
}

TEST_CASE("Eye: the scotopic shift engages below and disengages above the specified luminances", "[gl][eye]") {
    test::glContext();
    SkyProcessor p(SkyVars::earth(), Logger(), ProcessorOptions{.astronomy = false});
    p.setCamera(smallCamera());
    auto& field = p.emplace<Field>(glm::vec3(kOrange));
    p.vars().set(eye::keys::curve, 3);  // no curve: the displayed value is the exposed colour, clipped
    const glm::dvec2 rodXy = p.vars().get(eye::keys::rodChromaticity);
    const glm::dvec2 orangeXy = color::chromaticity(color::linearSrgbToXyz(kOrange));
    struct Case {
        double Y;
        double rodShare;  // expected position between the orange's chromaticity (0) and the rod hue (1)
    } cases[] = {{30, 0}, {3.0, 0}, {0.5, -1}, {0.05, -1}, {1e-3, 1}, {1e-4, 1}, {1e-5, 1}};
    for (auto c : cases) {
        const glm::dvec3 L = kOrange * (c.Y / color::luminance(kOrange));
        field.setRadiance(glm::vec3(L));
        // Manual exposure: the field's brightest channel at 0.8 on the display, unclipped.
        const glm::dvec3 perceived = eye::mesopicColor(L, 1e-3, 3.0, rodXy);
        const double peak = std::max({perceived.r, perceived.g, perceived.b});
        p.setExposure({.ev100 = eye::ev100FromExposure(0.8 / peak)});
        p.renderFrame();
        const glm::dvec3 shown = meanDisplayed(p);
        const glm::dvec3 want = perceived * eye::exposureFromEv100(p.lastEv100());
        INFO("Y = " << c.Y << " cd/m^2: shown " << shown.r << " " << shown.g << " " << shown.b << ", CPU twin " << want.r << " "
                    << want.g << " " << want.b);
        // GPU against the CPU twin: 8-bit output, 1/255 in sRGB is <= 0.5 % in linear near 0.5;
        // 1 % with the float shader's rounding.
        for (int k = 0; k < 3; ++k) CHECK(shown[k] == Approx(want[k]).epsilon(0.01).margin(2e-3));
        const glm::dvec2 xy = color::chromaticity(color::linearSrgbToXyz(shown));
        const double share = glm::length(xy - orangeXy) / glm::length(rodXy - orangeXy);
        // 0.02 of the orange-to-rod distance (~0.43 in xy): the 8-bit quantisation of the colour.
        if (c.rodShare >= 0) CHECK(share == Approx(c.rodShare).margin(0.02));
        else {  // mesopic: part way, and more so at the lower luminance
            CHECK(share > 0.05);
            CHECK(share < 0.95);
        }
    }
    // Off: the scotopic field keeps its colour.
    p.vars().set(eye::keys::mesopic, false);
    field.setRadiance(glm::vec3(kOrange * 1e-4));
    p.setExposure({.ev100 = eye::ev100FromExposure(0.8 / 1e-4)});
    p.renderFrame();
    const glm::dvec2 xy = color::chromaticity(color::linearSrgbToXyz(meanDisplayed(p)));
    CHECK(glm::length(xy - orangeXy) < 0.01);  // 8-bit quantisation of a saturated colour
    // Limits out of order: one line at the next frame.
    p.vars().set(eye::keys::scotopicBelow, 5.0);
    CHECK_THROWS_WITH(p.renderFrame(), "SkyProcessor: eye.scotopic_cd_m2 5 not below eye.photopic_cd_m2 3");
}

TEST_CASE("Eye: the adaptation follows the frames' animation time; a still render is the steady state", "[gl][eye]") {
    test::glContext();
    const double Lday = 2e3, Lnight = 2e-3;
    // The still render of the night field (animation time fixed: every frame the steady state).
    auto still = [&](double L) {
        SkyProcessor p(SkyVars::earth(), Logger(), ProcessorOptions{.astronomy = false});
        p.setCamera(smallCamera());
        p.emplace<Field>(glm::vec3(L));
        p.setExposure({.automatic = true});
        p.setAnimationTime(0.0);
        p.renderFrame();
        return std::pair{p.lastEv100(), p.adaptationLuminance()};
    };
    auto [evNight, aNight] = still(Lnight);
    // The meter of a uniform grey field is the field (float log-average: 1e-5).
    CHECK(aNight.x == Approx(Lnight).epsilon(1e-5));
    CHECK(aNight.y == Approx(Lnight * eye::scotopicPerPhotopicWhite()).epsilon(1e-3));  // V' in the shader's 4-digit matrix
    // The GPU's state (float, adapt.frag.glsl) against the CPU twin in double: 1e-4 EV.
    CHECK(evNight == Approx(eye::steadyEv100(aNight.x, aNight.y)).epsilon(0).margin(1e-4));
    CHECK(still(Lday).first > evNight + 5);  // daylight exposes far less

    // Day, then night in an animation: 63 % of the way in log after one time constant.
    SkyProcessor p(SkyVars::earth(), Logger(), ProcessorOptions{.astronomy = false});
    p.setCamera(smallCamera());
    auto& field = p.emplace<Field>(glm::vec3(Lday));
    p.setExposure({.automatic = true});
    const double tc = 0.5, tr = 4.0;
    p.vars().set(eye::keys::coneTime, tc);
    p.vars().set(eye::keys::rodTime, tr);
    p.setAnimationTime(10.0);
    p.renderFrame();  // the first frame: steady state in daylight
    const glm::dvec2 a0 = p.adaptationLuminance();
    field.setRadiance(glm::vec3(Lnight));
    p.setAnimationTime(10.0 + tc);
    p.renderFrame();
    glm::dvec2 a = p.adaptationLuminance();
    // 1e-4: the float meter's log-average.
    CHECK(std::log(a.x / a0.x) / std::log(aNight.x / a0.x) == Approx(1 - std::exp(-1.0)).margin(1e-4));
    CHECK(std::log(a.y / a0.y) / std::log(aNight.y / a0.y) == Approx(1 - std::exp(-tc / tr)).margin(1e-4));
    {  // a second tone map of the same frame (into the host's framebuffer) does not advance the eye
        gl::Texture2D target(16, 16, GL_RGBA8);
        gl::Framebuffer fbo = gl::Framebuffer::create();
        fbo.attach(GL_COLOR_ATTACHMENT0, target);
        p.toneMapInto(fbo.id());
        CHECK(p.adaptationLuminance() == a);
        // With the frame's own settings it takes no step at all (ToneMapper::advance() skips
        // it); that is exact because a step with no time passed writes the same texel: one with
        // other settings, then one with the frame's settings again, gives the state and the
        // exposure back bit for bit.
        const double ev = p.lastEv100();
        p.vars().set(eye::keys::compensation, 1.0);
        p.toneMapInto(fbo.id());
        CHECK(p.lastEv100() == Approx(ev - 1.0).margin(1e-5));  // the key applies: one stop more light (float exp2)
        CHECK(p.adaptationLuminance() == a);
        p.vars().set(eye::keys::compensation, 0.0);
        p.toneMapInto(fbo.id());
        CHECK(p.lastEv100() == ev);
        CHECK(p.adaptationLuminance() == a);
    }
    // Long after (30 rod time constants, e^-30): the still render's exposure.
    p.setAnimationTime(10.0 + tc + 30 * tr);
    p.renderFrame();
    CHECK(p.lastEv100() == Approx(evNight).epsilon(0).margin(1e-4));  // float state, e^-30 of the step left
    // A cut: the steady state at once.
    field.setRadiance(glm::vec3(Lday));
    p.resetAdaptation();
    p.setAnimationTime(1000.0);
    p.renderFrame();
    CHECK(p.lastEv100() == Approx(still(Lday).first).epsilon(0).margin(1e-6));  // the same GPU arithmetic
}

TEST_CASE("Eye: the keys are the settings (--var), the camera model stays available", "[gl][eye]") {
    test::glContext();
    SkyProcessor p(SkyVars::earth(), Logger(), ProcessorOptions{.astronomy = false});
    p.setCamera(smallCamera());
    auto& field = p.emplace<Field>(glm::vec3(1e-4f));
    p.setAnimationTime(0.0);  // still renders: every frame the steady state
    p.vars().setFromString("exposure.auto", "true");  // as `welkin render --var exposure.auto=true`
    p.renderFrame();
    const double evEye = p.lastEv100();
    // GPU float state against the CPU twin: 1e-4 EV.
    CHECK(evEye == Approx(eye::steadyEv100(p.adaptationLuminance().x, p.adaptationLuminance().y)).epsilon(0).margin(1e-4));
    p.vars().setFromString("eye.adaptation", "false");  // a camera: the log-average to 0.104 whatever the light
    p.renderFrame();
    CHECK(p.lastEv100() == Approx(std::log2(1e-4 * 100 / 12.5)).margin(1e-4));  // float meter
    // The camera lifts a 1e-4 cd/m^2 night by more than 3 stops over the eye at the default
    // eye.strength 0.6 (the full TVI matching: 6.9 stops; 0.6 of it is 4.1).
    CHECK(p.lastEv100() < evEye - 3);
    p.vars().setFromString("exposure.compensation_ev", "2");
    p.renderFrame();
    CHECK(p.lastEv100() == Approx(std::log2(1e-4 * 100 / 12.5) - 2).margin(1e-4));
    // A frame of NaN: the exposure and the eye stay finite (GLSL leaves NaN comparisons to the
    // driver: the meter either skips the pixels, as unlit ones, or returns NaN, and the eye
    // then stays where it was).
    const double adaptedBefore = p.adaptationLuminance().x;
    field.setRadiance(glm::vec3(std::nanf("")));
    p.renderFrame();
    CHECK(std::isfinite(p.lastEv100()));
    const double a = p.adaptationLuminance().x;
    // 1e-6: the state is float.
    CHECK((a == Approx(eye::Defaults::adaptationMin).epsilon(1e-6) || a == Approx(adaptedBefore).epsilon(1e-6)));
    CHECK_THROWS_WITH(p.vars().setFromString("exposure.curve", "4"), Catch::Contains("'4' is not one of aces, hable, reinhard, none"));
    CHECK_THROWS_WITH(p.vars().setFromString("eye.rod_time_s", "-1"), Catch::Contains("not in [0, 3600]"));
}

TEST_CASE("Eye: the display's slope bound (what an element under it cannot show) holds and is tight", "[cpu][eye][tonemap]") {
    // Each curve through the sRGB encoding, sampled densely: the largest slope stays under the
    // bound and within 1 % of it (the bound is the sampled maximum rounded up).
    auto display = [](int curve, double x) {
        const glm::dvec3 v(x);
        const double c = curve == 0 ? eye::acesFit(v).x : curve == 1 ? eye::hable(v).x : std::clamp(x, 0.0, 1.0);
        return eye::srgbEncode(c);
    };
    for (int curve : {0, 1, 3}) {
        double best = 0.0;
        for (double x = 0.0; x < 0.05; x += 2e-6) best = std::max(best, (display(curve, x + 2e-6) - display(curve, x)) / 2e-6);
        for (double x = 0.05; x < 100.0; x *= 1.0005) best = std::max(best, (display(curve, x * 1.0005) - display(curve, x)) / (x * 0.0005));
        const double bound = eye::displaySlopeBound(curve, false, 1e-3, 3.0, {0.25, 0.25});
        CAPTURE(curve, best, bound);
        CHECK(best <= bound * (1.0 + 1e-9));  // 1e-9: the difference quotient's rounding on the linear segment (12.92 exactly)
        CHECK(best >= 0.99 * bound);
    }
    // Reinhard on luminance, one channel raised: no displayed channel moves by more than the bound.
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    {
        const double bound = eye::displaySlopeBound(2, false, 1e-3, 3.0, {0.25, 0.25});
        double best = 0.0;
        for (int i = 0; i < 20000; ++i) {
            const glm::dvec3 c = glm::dvec3(u(rng), u(rng), u(rng)) * std::pow(10.0, 4.0 * u(rng) - 3.0);
            for (int k = 0; k < 3; ++k) {
                glm::dvec3 d = c;
                const double h = 1e-7 * (c.r + c.g + c.b + 1e-3);
                d[k] += h;
                const glm::dvec3 a = eye::reinhardLuminance(c), b = eye::reinhardLuminance(d);
                for (int j = 0; j < 3; ++j) best = std::max(best, std::abs(eye::srgbEncode(b[j]) - eye::srgbEncode(a[j])) / h);
            }
        }
        CAPTURE(best, bound);
        CHECK(best <= bound);
    }
    // The mesopic colour: random non-negative colours over the whole ramp (1e-5 to 1e2 cd/m^2)
    // plus a small non-negative radiance d: |M(c + d) - M(c)| <= |d| x the bound / the curve's slope.
    const double lo = eye::Defaults::scotopicBelow, hi = eye::Defaults::photopicAbove;
    const glm::dvec2 rod(eye::Defaults::rodX, eye::Defaults::rodY);
    const double g = eye::displaySlopeBound(3, true, lo, hi, rod) / eye::displaySlopeBound(3, false, lo, hi, rod);
    double best = 0.0;
    for (int i = 0; i < 200000; ++i) {
        glm::dvec3 c(u(rng), u(rng), u(rng));
        if (i % 4 == 0) c[i / 4 % 3] = 0.0;  // the gamut's faces, where the Jacobian is largest
        c *= std::pow(10.0, 7.0 * u(rng) - 5.0);
        const glm::dvec3 d = glm::dvec3(u(rng), u(rng), u(rng)) * 1e-6 * (c.r + c.g + c.b);
        const double dMax = std::max({d.r, d.g, d.b});
        const glm::dvec3 m = eye::mesopicColor(c + d, lo, hi, rod) - eye::mesopicColor(c, lo, hi, rod);
        best = std::max(best, std::max({std::abs(m.r), std::abs(m.g), std::abs(m.b)}) / dMax);
    }
    std::printf("eye: the mesopic map's largest growth %.3f, its bound %.3f (4.84 on a fine grid, x 1.1)\n", best, g);
    CHECK(best <= g);
    CHECK(best >= 0.6 * g);  // tight enough to be useful: random directions rarely hit the worst one
    CHECK(g == Approx(1.1 * 4.84).epsilon(0.02));  // the grid's 4.84 (the README's figure), x 1.1
    // Other limits: recomputed, and a wider ramp (a gentler weight) gives a smaller bound.
    CHECK(eye::displaySlopeBound(3, true, 1e-5, 30.0, rod) < eye::displaySlopeBound(3, true, lo, hi, rod));
    CHECK_THROWS_WITH(eye::displaySlopeBound(0, true, 3.0, 1e-3, rod), Catch::Contains("not 0 < lo < hi"));
}
