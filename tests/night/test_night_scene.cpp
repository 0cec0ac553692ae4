// The whole night scene (the default elements: nightsky, stars, planet, sky; plus the
// constellations) at 4096x4096 and 1x1 (issue 10 item 7's size clause): fisheye (FOV 180 deg),
// equirect (the whole sphere) and perspective at 0.5 deg on the Moon; every pixel finite and
// non-negative. A 4096^2 RGBA32F read-back is 256 MB and seconds on llvmpipe, so the pixels are
// classified on the GPU by a compute pass (bit tests, immune to fast-math NaN folding) that counts
// non-finite, negative and positive channel values; the counter is itself checked against a
// texture with known bad values and against the CPU read-back of the same scene at 256x256.
#include <catch2/catch.hpp>

#include "elements_present.hpp"
// The scene and its data checks need the Constellations and the Planet (their data files' paths):
// compiled where both folders are.
#if defined(WELKIN_HAS_ELEMENT_constellations) && defined(WELKIN_HAS_ELEMENT_planet)

#include "gl_test_context.hpp"

#include <welkin/astro/stars.hpp>
#include <welkin/elements/constellations.hpp>
#include <welkin/elements/planet.hpp>
#include <welkin/elements/registry.hpp>
#include <welkin/gl/shader.hpp>
#include <welkin/gl/text.hpp>
#include <welkin/keys.hpp>
#include <welkin/processor.hpp>
#include <welkin/time.hpp>

#include <epoxy/gl.h>

#include <array>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <limits>
#include <numbers>
#include <string>
#include <vector>

using namespace welkin;

namespace {
constexpr double kDeg = std::numbers::pi / 180.0;

struct ChannelCounts {
    unsigned nonFinite = 0, negative = 0, positive = 0;
};

// Counts the RGB channel values of an RGBA32F texture (alpha ignored, as Image/readHdr does):
// non-finite (exponent all ones: NaN or infinity), negative (sign set, not -0), positive (> 0).
ChannelCounts classifyOnGpu(const gl::Texture& texture, int width, int height) {
    gl::Program program = gl::ProgramBuilder("finite check")
                              .compute("finite_check.comp", R"(
layout(local_size_x = 16, local_size_y = 16) in;
layout(binding = 0, rgba32f) readonly uniform image2D img;
layout(std430, binding = 0) buffer Counts { uint nonFinite; uint negative; uint positive; };
void main() {
    ivec2 p = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(p, imageSize(img)))) return;
    vec3 v = imageLoad(img, p).rgb;
    uint bad = 0u, neg = 0u, pos = 0u;
    for (int c = 0; c < 3; ++c) {
        uint b = floatBitsToUint(v[c]);
        if ((b & 0x7f800000u) == 0x7f800000u) bad++;
        else if ((b & 0x80000000u) != 0u && (b & 0x7fffffffu) != 0u) neg++;
        else if ((b & 0x7fffffffu) != 0u) pos++;
    }
    if (bad > 0u) atomicAdd(nonFinite, bad);
    if (neg > 0u) atomicAdd(negative, neg);
    if (pos > 0u) atomicAdd(positive, pos);
}
)")
                              .build();
    const std::array<unsigned, 3> zero{0, 0, 0};
    gl::Buffer counts(sizeof zero, zero.data());
    counts.bindBase(GL_SHADER_STORAGE_BUFFER, 0);
    glBindImageTexture(0, texture.id(), 0, GL_FALSE, 0, GL_READ_ONLY, GL_RGBA32F);
    program.use();
    glDispatchCompute(GLuint((width + 15) / 16), GLuint((height + 15) / 16), 1);
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    std::array<unsigned, 3> out{};
    glGetNamedBufferSubData(counts.id(), 0, sizeof out, out.data());
    glBindImageTexture(0, 0, 0, GL_FALSE, 0, GL_READ_ONLY, GL_RGBA32F);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, 0);
    glUseProgram(0);
    return {out[0], out[1], out[2]};
}

ChannelCounts classifyOnCpu(const Image& img) {
    ChannelCounts c;
    for (float v : img.pixels) {
        if (!std::isfinite(v)) ++c.nonFinite;
        else if (v < 0) ++c.negative;
        else if (v > 0) ++c.positive;
    }
    return c;
}

// The data the night scene reads: scripts/setup.sh installs it, so a missing file fails the test
// (never a silent skip).
void requireNightData() {
    for (const char* f : {astro::kKStarsCatalogue, elements::kConstellationLinesFile, elements::kConstellationNamesFile,
                          gl::kDefaultFontPath, elements::kMoonTexturePath, elements::kMoonNormalsPath,
                          "/usr/share/stellarium/textures/milkyway.png"})
        if (!std::filesystem::exists(f))
            FAIL("no " << f << " (kstars-data, stellarium-data, fonts-dejavu-core: scripts/setup.sh installs them)");
}
}  // namespace

TEST_CASE("Night scene: the GPU finiteness counter counts what the CPU counts", "[gl][night]") {
    test::glContext();
    // 4x4 texels (RGB used, alpha ignored): two NaNs, one +inf, one -inf, two negatives, one -0
    // (not negative, not positive), the rest positive or zero.
    const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
    std::vector<float> texels(4 * 4 * 4, 0.0f);
    for (size_t i = 0; i < texels.size(); ++i) texels[i] = float(i % 5);  // 0,1,2,3,4,...
    texels[0] = nan, texels[5] = -nan, texels[9] = inf, texels[14] = -inf;  // RGB channels
    texels[20] = -1.0f, texels[33] = -1e-3f, texels[40] = -0.0f;
    texels[3] = nan, texels[7] = -5.0f;  // alpha: ignored
    gl::Texture2D tex(4, 4, GL_RGBA32F);
    glTextureSubImage2D(tex.id(), 0, 0, 0, 4, 4, GL_RGBA, GL_FLOAT, texels.data());
    Image ref;
    ref.width = ref.height = 4;
    ref.channels = 3;
    for (size_t i = 0; i < texels.size(); ++i)
        if (i % 4 != 3) ref.pixels.push_back(texels[i]);
    const ChannelCounts cpu = classifyOnCpu(ref), gpu = classifyOnGpu(tex, 4, 4);
    CHECK(cpu.nonFinite == 4);
    CHECK(cpu.negative == 2);
    CHECK(gpu.nonFinite == cpu.nonFinite);
    CHECK(gpu.negative == cpu.negative);
    CHECK(gpu.positive == cpu.positive);
}

TEST_CASE("Night scene: every pixel finite and non-negative at 4096x4096 (default elements + constellations)", "[gl][night]") {
    requireNightData();
    test::glContext();
    // Malta, 2026-08-24 20:30 UTC: Sun -30.8 deg, a waxing gibbous Moon (89 % lit) 29 deg up in the
    // south, Saturn rising, the Milky Way overhead: every night element has something to draw.
    SkyProcessor p;
    p.setObserver({.latitudeRad = 35.9 * kDeg, .longitudeRad = 14.5 * kDeg, .heightMeters = 0});
    p.setTime(UtcInstant::parse("2026-08-24T20:30:00Z"));
    p.setExposure({.automatic = true});
    p.setAnimationTime(0.0);
    std::vector<std::string> names = elements::defaultElements();
    names.push_back("constellations");
    for (const std::string& n : names) p.add(elements::makeElement(n));
    Camera cam;
    cam.projection = Projection::Fisheye;

    // 256x256 first: the GPU counter against the CPU read-back of the same frame.
    cam.width = cam.height = 256;
    p.setCamera(cam);
    p.renderFrame();
    const ChannelCounts cpu = classifyOnCpu(p.readHdr()), gpu256 = classifyOnGpu(p.hdrTexture(), 256, 256);
    CHECK(cpu.nonFinite == 0);
    CHECK(cpu.negative == 0);
    CHECK(gpu256.nonFinite == cpu.nonFinite);
    CHECK(gpu256.negative == cpu.negative);
    CHECK(gpu256.positive == cpu.positive);

    // Then 4096x4096 (and 1x1) at FOV 180 deg (fisheye), the whole sphere (equirect: the ground,
    // the poles, the seam) and 0.5 deg on the Moon (perspective: the Moon's shading fills the frame).
    const glm::dvec3 moon = p.vars().get(keys::moonDirection);
    struct Case {
        Projection proj;
        int size;
    };
    for (Case k : {Case{Projection::Fisheye, 4096}, Case{Projection::Equirect, 4096}, Case{Projection::Perspective, 4096},
                   Case{Projection::Fisheye, 1}, Case{Projection::Perspective, 1}}) {
        cam.projection = k.proj;
        cam.width = cam.height = k.size;
        cam.azimuthRad = std::atan2(moon.x, moon.y);
        cam.altitudeRad = std::asin(moon.z);
        cam.verticalFovRad = 0.5 * kDeg;
        p.setCamera(cam);
        const auto t0 = std::chrono::steady_clock::now();
        p.renderFrame();
        const ChannelCounts c = classifyOnGpu(p.hdrTexture(), k.size, k.size);
        const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        const double channels = 3.0 * k.size * k.size;
        INFO(toString(k.proj) << " " << k.size << "x" << k.size << ": frame and check " << seconds << " s, " << c.positive
                              << " positive channels of " << channels);
        CHECK(c.nonFinite == 0);
        CHECK(c.negative == 0);
        if (k.size == 1) continue;
        // Lit everywhere it looks at the sky (airglow, the Milky Way's floor, the moonlit sky) or
        // the Moon: the fisheye's image circle is pi/4 = 78.5 % of the square (75 %: less its
        // rim); the upper half of the equirect (45 %: less the horizon's row and the ground's
        // darkness); the Moon's disk fills the 0.5-deg frame (90 %).
        const double minLit = k.proj == Projection::Fisheye ? 0.75 : k.proj == Projection::Equirect ? 0.45 : 0.9;
        CHECK(double(c.positive) > minLit * channels);
    }
}
#endif
