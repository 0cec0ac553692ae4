// Hidden timing (not run by CI: `welkin_tests "[tonemap_timing]"`): the tone map's per-pixel pass
// (engine/shaders/tonemap.frag.glsl, as the displayed frame runs it: RGBA32F frame read by
// imageLoad, the mesopic colour, the ACES fit, an SRGB8_ALPHA8 target encoding on write) against
// other shapes of the same work, each timed in alternation with a trivial fullscreen pass (a
// constant of gl_FragCoord arithmetic into RGBA32F, as `welkin bench frame`'s), process CPU time
// (llvmpipe's threads are the process's; the wall time of a shared machine swings by 2-5x).
// Issue 22's target: the tone map <= 2x that trivial pass (docs/eye.md).
#include <catch2/catch.hpp>

#include "cpu_timing.hpp"
#include "gl_test_context.hpp"
#include "uniform_field.hpp"

#include <welkin/gl/objects.hpp>
#include <welkin/gl/shader.hpp>
#include <welkin/keys.hpp>
#include <welkin/processor.hpp>

#include <nlohmann/json.hpp>

#include <epoxy/gl.h>

#include <chrono>
#include <cmath>
#include <memory>
#include <cstdio>
#include <functional>
#include <string>
#include <vector>

using namespace welkin;

namespace {
// A night frame's radiance: every pixel a different colour, luminance from 1e-5 to 10 cd/m^2 (the
// scotopic, mesopic and low photopic ranges: the mesopic colour's whole ramp).
// The meter's per-sample work (log luminance, its weight, log scotopic luminance), shared by the
// timing cases below.
const char* kLogLumSample =
    "vec3 logLum(vec2 uv) {\n"
    "  vec3 c = textureLod(u_hdr, uv, 0.0).rgb;\n"
    "  float X = dot(c, vec3(0.4124, 0.3576, 0.1805)); float Y = dot(c, vec3(0.2126, 0.7152, 0.0722));\n"
    "  float Z = dot(c, vec3(0.0193, 0.1192, 0.9505));\n"
    "  float V = X > 0.0 ? Y * (1.33 * (1.0 + (Y + Z) / X) - 1.68) : 0.0;\n"
    "  float wt = Y > 1e-7 ? 1.0 : 0.0;\n"
    "  return vec3(wt * log(max(Y, 1e-7)), wt, wt * log(max(V, 1e-7)));\n}\n";

// A timed processor (no astronomy) of w x h pixels drawing one uniform field (cd/m^2), with the
// automatic exposure: what the meter's timing cases measure.
std::unique_ptr<SkyProcessor> meteredProcessor(int w, int h, glm::vec3 field) {
    auto p = std::make_unique<SkyProcessor>(SkyVars::earth(), Logger(), ProcessorOptions{.timing = true, .astronomy = false});
    Camera cam;
    cam.width = w;
    cam.height = h;
    p->setCamera(cam);
    p->emplace<test::UniformField>(field);
    p->setExposure({.automatic = true});
    return p;
}

const char* kFillFrag =
    "out vec4 o;\n"
    "void main() {\n"
    "  vec2 p = gl_FragCoord.xy;\n"
    "  float h = fract(sin(dot(p, vec2(12.9898, 78.233))) * 43758.5453);\n"
    "  float Y = exp2(mix(-16.6, 3.3, fract(p.x / 1280.0 + 0.37 * h)));\n"
    "  o = vec4(Y * vec3(0.5 + h, 1.0, 1.5 - h), 1.0);\n"
    "}\n";

// The shapes' common uniforms (set like ToneMapper::display(): the default keys).
void setToneUniforms(gl::Program& p) {
    p.use();
    p.set("u_exposure", 1.0f / (1.2f * 0.01f));  // EV100 -6.6: a moonless night's exposure
    const float lo = std::log2(1e-3f), span = std::log2(3.0f) - lo;
    p.set("u_rodRamp", glm::vec2(1.0f / span, lo / span));
    p.set("u_rodColor", glm::vec3(0.33f, 0.39f, 0.62f));
}
}  // namespace

TEST_CASE("Tone map timing: the displayed pass against other shapes and the trivial pass", "[.][tonemap_timing]") {
    test::glContext();
    const int w = 1280, h = 720;
    auto vao = gl::VertexArray::create();
    gl::Texture2D hdr(w, h, GL_RGBA32F), scratch(w, h, GL_RGBA32F), srgb(w, h, GL_SRGB8_ALPHA8), rgba8(w, h, GL_RGBA8);
    auto hdrFbo = gl::Framebuffer::create(), scratchFbo = gl::Framebuffer::create(), srgbFbo = gl::Framebuffer::create();
    hdrFbo.attach(GL_COLOR_ATTACHMENT0, hdr);
    scratchFbo.attach(GL_COLOR_ATTACHMENT0, scratch);
    srgbFbo.attach(GL_COLOR_ATTACHMENT0, srgb);
    auto fill = gl::ProgramBuilder("fill").fullscreenVertex().fragment("fill.frag", kFillFrag).build();
    hdrFbo.bind();
    glViewport(0, 0, w, h);
    vao.bind();
    fill.use();
    glDrawArrays(GL_TRIANGLES, 0, 3);

    auto trivial = gl::ProgramBuilder("trivial")
                       .fullscreenVertex()
                       .fragment("trivial.frag", "out vec4 o; void main() { o = vec4(gl_FragCoord.xy * 1e-3, 1.0, 1.0); }")
                       .build();
    auto toneMap = [&](bool mesopic) {
        gl::ProgramBuilder b("tone map");
        b.define("WELKIN_TONEMAP_IMAGE").define("WELKIN_TONEMAP_CURVE", 0).define("WELKIN_TONEMAP_SRGB_TARGET");
        if (mesopic) b.define("WELKIN_TONEMAP_MESOPIC");
        return b.vertex("engine/tonemap.vert.glsl", gl::engineShader("tonemap.vert.glsl"))
            .fragment("engine/tonemap.frag.glsl", gl::engineShader("tonemap.frag.glsl"))
            .build();
    };
    gl::Program current = toneMap(true), noMesopic = toneMap(false);
    auto copy = gl::ProgramBuilder("copy")
                    .fullscreenVertex()
                    .fragment("copy.frag", "layout(binding = WELKIN_BINDING_HDR_IMAGE, rgba32f) readonly uniform image2D u_hdrImage;\n"
                                           "out vec4 o; void main() { o = vec4(imageLoad(u_hdrImage, ivec2(gl_FragCoord.xy)).rgb * 1e-3, 1.0); }")
                    .build();
    // The same arithmetic as a compute pass over 8x8 tiles into an RGBA8 image (no encoding: an
    // sRGB image cannot be stored to, so this is a lower bound of a compute tone map).
    auto computeCopy = gl::ProgramBuilder("tone map compute")
                           .compute("tm.comp", "layout(local_size_x = 8, local_size_y = 8) in;\n"
                                               "layout(binding = 0, rgba32f) readonly uniform image2D u_in;\n"
                                               "layout(binding = 1, rgba8) writeonly uniform image2D u_out;\n"
                                               "uniform float u_exposure;\n"
                                               "void main() { ivec2 p = ivec2(gl_GlobalInvocationID.xy);\n"
                                               "vec3 x = 0.6 * u_exposure * imageLoad(u_in, p).rgb;\n"
                                               "imageStore(u_out, p, vec4((x * (2.51 * x + 0.03)) / (x * (2.43 * x + 0.59) + 0.14), 1.0)); }")
                           .build();
    // Candidate arithmetic: Larson's V' = Y (1.33 (X + Y + Z) - 1.68 X) / X with the bracket one dot
    // product, the exposure and the ACES fit's 0.6 folded into the blend's two weights.
    auto candidate = [&](const char* name, const char* tail, const char* def = nullptr) {
        gl::ProgramBuilder b(name);
        if (def) b.define(def);
        return b
            .fullscreenVertex()
            .fragment(name, std::string("layout(binding = WELKIN_BINDING_HDR_IMAGE, rgba32f) readonly uniform image2D u_hdrImage;\n"
                                        "uniform float u_exposure; uniform vec2 u_rodRamp; uniform vec3 u_rodColor; out vec4 o_color;\n"
                                        "void main() {\n"
                                        "  vec3 c = imageLoad(u_hdrImage, ivec2(gl_FragCoord.xy)).rgb;\n"
                                        "  float Y = dot(c, vec3(0.2126, 0.7152, 0.0722));\n"
                                        "  float X = dot(c, vec3(0.4124, 0.3576, 0.1805));\n"
                                        "  float D = dot(c, vec3(0.164087, 0.984592, 1.297016));\n"
                                        "#ifdef NO_DIV\n  float V = Y * D;\n#else\n  float V = X > 0.0 ? Y * D / X : 0.0;\n#endif\n"
                                        "  int bits = floatBitsToInt(Y);\n"
                                        "  float m = intBitsToFloat((bits & 0x007fffff) | 0x3f800000) - 1.0;\n"
                                        "  float l = float((bits >> 23) - 127) + m * (1.4246257 + m * (-0.5894235 + m * 0.1656103));\n"
                                        "#ifdef LIN_LOG\n  l = float(bits) * 1.1920929e-7 - 127.0;\n#endif\n#ifdef BUILTIN_LOG\n  l = log2(Y);\n#endif\n  float t = clamp(l * u_rodRamp.x - u_rodRamp.y, 0.0, 1.0);\n"
                                        "  float w = Y > 0.0 ? 1.0 - t * t * (3.0 - 2.0 * t) : 1.0;\n#ifdef NO_LOG\n  w = clamp(Y * u_rodRamp.x, 0.0, 1.0);\n#endif\n"
                                        "  float s = 0.6 * u_exposure;\n"
                                        "  vec3 x = c * (s - s * w) + u_rodColor * (s * w * V);\n"
                                        "  vec3 r = (x * (2.51 * x + 0.03)) / (x * (2.43 * x + 0.59) + 0.14);\n") +
                                tail + "}\n")
            .build();
    };
    gl::Program folded = candidate("folded.frag", "o_color = vec4(min(r, 1.0), 1.0);\n");
    gl::Program foldedNoClamp = candidate("folded_noclamp.frag", "o_color = vec4(r, 1.0);\n");
    gl::Program noDiv = candidate("nodiv.frag", "o_color = vec4(r, 1.0);\n", "NO_DIV");
    gl::Program noLog = candidate("nolog.frag", "o_color = vec4(r, 1.0);\n", "NO_LOG");
    gl::Program linLog = candidate("linlog.frag", "o_color = vec4(r, 1.0);\n", "LIN_LOG");
    gl::Program builtinLog = candidate("builtinlog.frag", "o_color = vec4(r, 1.0);\n", "BUILTIN_LOG");
    gl::Program noSmooth = candidate("nosmooth.frag", "o_color = vec4(r, 1.0);\n", "NO_SMOOTH");
    setToneUniforms(linLog);
    setToneUniforms(builtinLog);
    setToneUniforms(noSmooth);
    setToneUniforms(noDiv);
    setToneUniforms(noLog);
    setToneUniforms(folded);
    setToneUniforms(foldedNoClamp);
    setToneUniforms(current);
    setToneUniforms(noMesopic);
    computeCopy.use();
    computeCopy.set("u_exposure", 1.0f / (1.2f * 0.01f));

    auto into = [&](const gl::Framebuffer& fbo, gl::Program& p, bool srgbWrite) {
        return [&, srgbWrite] {
            fbo.bind();
            glViewport(0, 0, w, h);
            vao.bind();
            glBindImageTexture(0, hdr.id(), 0, GL_FALSE, 0, GL_READ_ONLY, GL_RGBA32F);
            if (srgbWrite) glEnable(GL_FRAMEBUFFER_SRGB);
            p.use();
            glDrawArrays(GL_TRIANGLES, 0, 3);
            if (srgbWrite) glDisable(GL_FRAMEBUFFER_SRGB);
        };
    };
    struct Shape {
        const char* what;
        std::function<void()> draw;
    };
    std::vector<Shape> shapes = {
        {"trivial pass into RGBA32F (the unit)", into(scratchFbo, trivial, false)},
        {"copy imageLoad RGBA32F -> SRGB8_ALPHA8 (encoded on write)", into(srgbFbo, copy, true)},
        {"tone map as displayed (mesopic, ACES, SRGB8 target)", into(srgbFbo, current, true)},
        {"the same without the mesopic colour", into(srgbFbo, noMesopic, true)},
        {"folded: one dot for V', the exposure in the blend's weights, min(r, 1)", into(srgbFbo, folded, true)},
        {"folded, no clamp (the UNORM target clamps on write)", into(srgbFbo, foldedNoClamp, true)},
        {"(bisect) folded, no clamp, V' without the division", into(srgbFbo, noDiv, true)},
        {"(bisect) folded, no clamp, the weight without log2 and smoothstep", into(srgbFbo, noLog, true)},
        {"(bisect) folded, no clamp, log2 as the float's bits (exponent + linear mantissa)", into(srgbFbo, linLog, true)},
        {"(bisect) folded, no clamp, builtin log2", into(srgbFbo, builtinLog, true)},
        {"(bisect) folded, no clamp, no smoothstep (w = 1 - t)", into(srgbFbo, noSmooth, true)},
        {"compute 8x8: imageLoad, ACES, imageStore RGBA8 (no mesopic, no encoding)",
         [&] {
             computeCopy.use();
             glBindImageTexture(0, hdr.id(), 0, GL_FALSE, 0, GL_READ_ONLY, GL_RGBA32F);
             glBindImageTexture(1, rgba8.id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA8);
             glDispatchCompute(GLuint((w + 7) / 8), GLuint((h + 7) / 8), 1);
             glMemoryBarrier(GL_ALL_BARRIER_BITS);
         }},
    };
    for (auto& s : shapes) s.draw();  // JIT at the first draw of each state
    std::vector<std::vector<double>> ms(shapes.size());
    for (int round = 0; round < 21; ++round)
        for (size_t k = 0; k < shapes.size(); ++k) {
            glFinish();
            const double t0 = test::cpuMs();
            shapes[k].draw();
            glFinish();
            ms[k].push_back(test::cpuMs() - t0);
        }
    const double unit = test::medianOf(ms[0]);
    std::printf("tone map shapes, 1280x720, medians of 21 (process CPU), x trivial pass (%.2f ms):\n", unit);
    for (size_t k = 0; k < shapes.size(); ++k) std::printf("  %-80s %5.2f\n", shapes[k].what, test::medianOf(ms[k]) / unit);
    CHECK(unit > 0.0);  // the clock advanced: a timing of nothing would print zeros
}

// What the automatic exposure adds to a displayed frame: the eye's meter (a 128x128 log-luminance
// pass, its mip chain and the one-texel adaptation pass, with the state's copy for the next
// frame), timed as `welkin bench display` does (the processor's glFinish-bracketed tonemap_ms of
// renderFrame(), wall clock) and in process CPU time, against the trivial pass timed alternately.
TEST_CASE("Tone map timing: the eye's meter in renderFrame()", "[.][tonemap_timing]") {
    test::glContext();
    const int w = 1280, h = 720;
    const auto held = meteredProcessor(w, h, glm::vec3(1e-3f));
    SkyProcessor& p = *held;
    auto vao = gl::VertexArray::create();
    gl::Texture2D scratch(w, h, GL_RGBA32F);
    auto scratchFbo = gl::Framebuffer::create();
    scratchFbo.attach(GL_COLOR_ATTACHMENT0, scratch);
    auto trivial = gl::ProgramBuilder("trivial")
                       .fullscreenVertex()
                       .fragment("trivial.frag", "out vec4 o; void main() { o = vec4(gl_FragCoord.xy * 1e-3, 1.0, 1.0); }")
                       .build();
    double seconds = 0;
    p.setAnimationTime(seconds);
    p.renderFrame();
    std::vector<double> trivialWall, trivialCpu, meterWall, frameCpu, manualCpu;
    for (int round = 0; round < 21; ++round) {
        glFinish();
        auto t0 = std::chrono::steady_clock::now();
        double c0 = test::cpuMs();
        scratchFbo.bind();
        glViewport(0, 0, w, h);
        vao.bind();
        trivial.use();
        glDrawArrays(GL_TRIANGLES, 0, 3);
        glFinish();
        trivialCpu.push_back(test::cpuMs() - c0);
        trivialWall.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
        for (bool automatic : {true, false}) {
            p.setExposure({.automatic = automatic});
            seconds += 1.0 / 30.0;  // a displayed frame: the eye adapts, the meter runs
            p.setAnimationTime(seconds);
            glFinish();
            c0 = test::cpuMs();
            p.renderFrame();
            glFinish();
            (automatic ? frameCpu : manualCpu).push_back(test::cpuMs() - c0);
            if (automatic) meterWall.push_back(p.stats()["tonemap_ms"].get<double>());
        }
    }
    const double tw = test::medianOf(trivialWall), tc = test::medianOf(trivialCpu);
    std::printf("eye's meter, 1280x720, medians of 21: trivial pass %.2f ms wall, %.2f ms CPU\n", tw, tc);
    std::printf("  meter (renderFrame's tonemap_ms, wall)            %.2f ms = %.2f x trivial\n", test::medianOf(meterWall), test::medianOf(meterWall) / tw);
    std::printf("  renderFrame automatic - manual (CPU)              %.2f ms = %.2f x trivial\n",
                test::medianOf(frameCpu) - test::medianOf(manualCpu), (test::medianOf(frameCpu) - test::medianOf(manualCpu)) / tc);
    CHECK(tw > 0.0);  // the clock advanced
}

// The meter's two shapes side by side (standalone, the same sample math without the camera's
// fisheye test): a 128x128 fragment pass + its mip chain + a one-texel pass reading the top level
// (the meter before 2026-11-27 evening), against one compute dispatch of 1 or 4x4 work groups
// writing the means + the one-texel pass; wall clock and process CPU, alternated.
TEST_CASE("Tone map timing: the meter as a mip chain or one compute dispatch", "[.][tonemap_timing]") {
    test::glContext();
    const int w = 1280, h = 720;
    auto vao = gl::VertexArray::create();
    gl::Texture2D hdr(w, h, GL_RGBA32F), one(1, 1, GL_RGBA32F), chain(128, 128, GL_RGBA32F, 8), m1(1, 1, GL_RGBA32F), m16(4, 4, GL_RGBA32F);
    hdr.setFilter(GL_LINEAR);
    auto hdrFbo = gl::Framebuffer::create(), oneFbo = gl::Framebuffer::create(), chainFbo = gl::Framebuffer::create();
    hdrFbo.attach(GL_COLOR_ATTACHMENT0, hdr);
    oneFbo.attach(GL_COLOR_ATTACHMENT0, one);
    chainFbo.attach(GL_COLOR_ATTACHMENT0, chain);
    auto fill = gl::ProgramBuilder("fill").fullscreenVertex().fragment("fill.frag", kFillFrag).build();
    hdrFbo.bind();
    glViewport(0, 0, w, h);
    vao.bind();
    fill.use();
    glDrawArrays(GL_TRIANGLES, 0, 3);
    const std::string sample = kLogLumSample;
    auto frag = gl::ProgramBuilder("loglum")
                    .fullscreenVertex()
                    .fragment("loglum.frag", "layout(binding = 0) uniform sampler2D u_hdr; in vec2 v_ndc; out vec4 o;\n" + sample +
                                                 "void main() { o = vec4(logLum(0.5 * v_ndc + 0.5), 1.0); }")
                    .build();
    auto comp = [&](int perInvocation, int block) {
        return gl::ProgramBuilder("meter")
            .compute("meter.comp", "layout(local_size_x = 16, local_size_y = 16) in;\n"
                                   "layout(binding = 0) uniform sampler2D u_hdr; layout(binding = 1, rgba32f) writeonly uniform image2D u_m;\n"
                                   "shared vec3 s[256];\n" +
                                       sample + "void main() { uint k = gl_LocalInvocationIndex; vec3 sum = vec3(0.0);\n"
                                       "ivec2 f = ivec2(gl_WorkGroupID.xy) * " + std::to_string(block) + " + ivec2(gl_LocalInvocationID.xy) * " +
                                       std::to_string(perInvocation) + ";\n"
                                       "for (int j = 0; j < " + std::to_string(perInvocation) + "; ++j) for (int i = 0; i < " +
                                       std::to_string(perInvocation) + "; ++i) sum += logLum((vec2(f + ivec2(i, j)) + 0.5) / 128.0);\n"
                                       "s[k] = sum; for (uint st = 128u; st > 0u; st >>= 1) { barrier(); if (k < st) s[k] += s[k + st]; }\n"
                                       "if (k == 0u) imageStore(u_m, ivec2(gl_WorkGroupID.xy), vec4(s[0], 1.0)); }")
            .build();
    };
    auto comp1 = comp(8, 128), comp16 = comp(2, 32);
    auto readOne = gl::ProgramBuilder("read")
                       .fullscreenVertex()
                       .fragment("read.frag", "layout(binding = 1) uniform sampler2D u_m; uniform int u_level; uniform int u_n; out vec4 o;\n"
                                              "void main() { vec4 m = vec4(0.0); for (int j = 0; j < u_n; ++j) for (int i = 0; i < u_n; ++i)\n"
                                              "m += texelFetch(u_m, ivec2(i, j), u_level); o = exp(m * 1e-6); }")
                       .build();
    auto readInto = [&](const gl::Texture2D& t, int level, int n) {
        oneFbo.bind();
        glViewport(0, 0, 1, 1);
        glBindTextureUnit(1, t.id());
        readOne.use();
        readOne.set("u_level", level);
        readOne.set("u_n", n);
        glDrawArrays(GL_TRIANGLES, 0, 3);
    };
    unsigned pack = 0;
    glCreateBuffers(1, &pack);
    glNamedBufferStorage(pack, 4 * sizeof(float), nullptr, 0);
    GLsync fence = nullptr;
    std::vector<std::pair<const char*, std::function<void()>>> shapes = {
        {"128x128 fragment pass + mip chain + one-texel pass", [&] {
             chainFbo.bind();
             glViewport(0, 0, 128, 128);
             vao.bind();
             glBindTextureUnit(0, hdr.id());
             frag.use();
             glDrawArrays(GL_TRIANGLES, 0, 3);
             chain.generateMipmaps();
             readInto(chain, 7, 1);
         }},
        {"one compute work group + one-texel pass", [&] {
             glBindTextureUnit(0, hdr.id());
             glBindImageTexture(1, m1.id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA32F);
             comp1.use();
             glDispatchCompute(1, 1, 1);
             glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT);
             readInto(m1, 0, 1);
         }},
        {"one compute work group alone (no one-texel pass)", [&] {
             glBindTextureUnit(0, hdr.id());
             glBindImageTexture(1, m1.id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA32F);
             comp1.use();
             glDispatchCompute(1, 1, 1);
             glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT);
         }},
        {"one compute work group + one-texel pass + its texel packed into a buffer, fenced", [&] {
             glBindTextureUnit(0, hdr.id());
             glBindImageTexture(1, m1.id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA32F);
             comp1.use();
             glDispatchCompute(1, 1, 1);
             glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT);
             readInto(m1, 0, 1);
             // as ToneMapper::advance() copies the eye's state for previousExposure()
             glBindBuffer(GL_PIXEL_PACK_BUFFER, pack);
             glGetTextureImage(one.id(), 0, GL_RGBA, GL_FLOAT, GLsizei(4 * sizeof(float)), nullptr);
             glBindBuffer(GL_PIXEL_PACK_BUFFER, 0);
             if (fence) glDeleteSync(fence);
             fence = glFenceSync(GL_SYNC_GPU_COMMANDS_COMPLETE, 0);
         }},
        {"4x4 compute work groups + one-texel pass (16 fetches)", [&] {
             glBindTextureUnit(0, hdr.id());
             glBindImageTexture(1, m16.id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA32F);
             comp16.use();
             glDispatchCompute(4, 4, 1);
             glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT);
             readInto(m16, 0, 4);
         }},
    };
    for (auto& s : shapes) s.second();
    std::vector<std::vector<double>> wall(shapes.size()), cpu(shapes.size());
    for (int round = 0; round < 41; ++round)
        for (size_t k = 0; k < shapes.size(); ++k) {
            hdrFbo.bind();  // the frame just drawn, as after the elements
            glViewport(0, 0, w, h);
            vao.bind();
            fill.use();
            glDrawArrays(GL_TRIANGLES, 0, 3);
            glFinish();
            const auto t0 = std::chrono::steady_clock::now();
            const double c0 = test::cpuMs();
            glFlush();
            shapes[k].second();
            glFinish();
            cpu[k].push_back(test::cpuMs() - c0);
            wall[k].push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
        }
    std::printf("the meter's shapes, medians of 41, ms (wall / process CPU):\n");
    for (size_t k = 0; k < shapes.size(); ++k)
        std::printf("  %-60s %5.3f / %5.3f\n", shapes[k].first, test::medianOf(wall[k]), test::medianOf(cpu[k]));
    if (fence) glDeleteSync(fence);
    glDeleteBuffers(1, &pack);
    CHECK(test::medianOf(wall[0]) > 0.0);  // the clock advanced
}

// The meter spread over several work groups (issue 22, session 21): one work group runs on one of
// llvmpipe's threads; G groups of 256/G invocations each sum the same 8x8 sample blocks as the one
// group's invocations (invocation k of the 16x16 grid, wherever it runs), write them to a buffer,
// and the last group to finish (an atomic counter) reduces the 256 block sums by the one group's
// tree, in its order: the same float sums. Against one group, wall clock and CPU, alternated.
TEST_CASE("Tone map timing: the meter over several work groups", "[.][tonemap_timing]") {
    test::glContext();
    const int w = 1280, h = 720;
    auto vao = gl::VertexArray::create();
    gl::Texture2D hdr(w, h, GL_RGBA32F), m1(1, 1, GL_RGBA32F);
    hdr.setFilter(GL_LINEAR);
    auto hdrFbo = gl::Framebuffer::create();
    hdrFbo.attach(GL_COLOR_ATTACHMENT0, hdr);
    auto fill = gl::ProgramBuilder("fill").fullscreenVertex().fragment("fill.frag", kFillFrag).build();
    const std::string sample = kLogLumSample;
    auto program = [&](int groups, int per) {
        const int rows = 16 / groups;
        const std::string n = std::to_string(groups), p = std::to_string(per);
        return gl::ProgramBuilder("meter groups")
            .compute("meter_groups.comp",
                     "layout(local_size_x = 16, local_size_y = " + std::to_string(rows) + ") in;\n"
                     "layout(binding = 0) uniform sampler2D u_hdr; layout(binding = 1, rgba32f) writeonly uniform image2D u_m;\n"
                     "layout(std430, binding = 4) coherent buffer Partials { uint counter; uint pad[3]; vec4 partial[256]; };\n"
                     "shared vec3 s[256]; shared bool s_last;\n" + sample +
                     "void main() {\n"
                     "  uint k = gl_GlobalInvocationID.y * 16u + gl_GlobalInvocationID.x; vec3 sum = vec3(0.0);\n"
                     "  ivec2 f = ivec2(gl_GlobalInvocationID.xy) * " + p + ";\n"
                     "  for (int j = 0; j < " + p + "; ++j) for (int i = 0; i < " + p + "; ++i) sum += logLum((vec2(f + ivec2(i, j)) + 0.5) / " + std::to_string(16 * per) + ".0);\n"
                     "  uint l = gl_LocalInvocationIndex; const uint size = " + std::to_string(16 * rows) + "u;\n"
                     "#if " + n + " == 1\n"
                     "  s[k] = sum;\n"
                     "#else\n"
                     "  partial[k] = vec4(sum, 0.0);\n"
                     "  memoryBarrierBuffer(); barrier();\n"
                     "  if (l == 0u) s_last = atomicAdd(counter, 1u) == " + n + "u - 1u;\n"
                     "  barrier();\n"
                     "  if (!s_last) return;\n"
                     "  memoryBarrierBuffer();\n"
                     "  for (uint i = l; i < 256u; i += size) s[i] = partial[i].xyz;\n"
                     "#endif\n"
                     "  for (uint st = 128u; st > 0u; st >>= 1) { barrier(); for (uint i = l; i < st; i += size) s[i] += s[i + st]; }\n"
                     "  if (l == 0u) {\n"
                     "#if " + n + " != 1\n    counter = 0u;\n#endif\n"
                     "    imageStore(u_m, ivec2(0), vec4(s[0] / 16384.0, 1.0)); }\n"
                     "}\n")
            .build();
    };
    unsigned ssbo = 0;
    glCreateBuffers(1, &ssbo);
    std::vector<unsigned char> zeros(16 + 256 * 16, 0);
    glNamedBufferStorage(ssbo, GLsizeiptr(zeros.size()), zeros.data(), 0);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 4, ssbo);
    struct Shape {
        std::string what;
        gl::Program p;
        int groups;
    };
    std::vector<Shape> shapes;
    shapes.push_back({"1 group of 16x16, 8x8 samples each (today)", program(1, 8), 1});
    shapes.push_back({"2 groups of 16x8, the last reduces", program(2, 8), 2});
    shapes.push_back({"4 groups of 16x4, the last reduces", program(4, 8), 4});
    shapes.push_back({"8 groups of 16x2, the last reduces", program(8, 8), 8});
    shapes.push_back({"16 groups of 16x1, the last reduces", program(16, 8), 16});
    const size_t exactShapes = shapes.size();
    shapes.push_back({"64x64 samples: 1 group", program(1, 4), 1});
    shapes.push_back({"64x64 samples: 2 groups", program(2, 4), 2});
    shapes.push_back({"64x64 samples: 4 groups", program(4, 4), 4});
    auto run = [&](Shape& s) {
        glBindTextureUnit(0, hdr.id());
        glBindImageTexture(1, m1.id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA32F);
        s.p.use();
        glDispatchCompute(1, GLuint(s.groups), 1);
        glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_SHADER_STORAGE_BARRIER_BIT);
    };
    hdrFbo.bind();
    glViewport(0, 0, w, h);
    vao.bind();
    fill.use();
    glDrawArrays(GL_TRIANGLES, 0, 3);
    std::vector<std::vector<float>> results;
    for (auto& s : shapes) {
        run(s);
        results.push_back(m1.readRgbaFloat());
    }
    for (size_t k = 1; k < exactShapes; ++k)
        for (int c = 0; c < 3; ++c) CHECK(results[k][size_t(c)] == results[0][size_t(c)]);  // the same sums in the same order
    std::printf("64x64 against 128x128 on this frame: mean ln Y %.6f against %.6f\n", results[exactShapes][0] / results[exactShapes][1], results[0][0] / results[0][1]);  // the same sums in the same order
    auto trivial = gl::ProgramBuilder("trivial")
                       .fullscreenVertex()
                       .fragment("trivial.frag", "out vec4 o; void main() { o = vec4(gl_FragCoord.xy * 1e-3, 1.0, 1.0); }")
                       .build();
    gl::Texture2D scratch(w, h, GL_RGBA32F);
    auto scratchFbo = gl::Framebuffer::create();
    scratchFbo.attach(GL_COLOR_ATTACHMENT0, scratch);
    std::vector<std::vector<double>> wall(shapes.size() + 1), cpu(shapes.size() + 1);
    for (int round = 0; round < 41; ++round)
        for (size_t k = 0; k <= shapes.size(); ++k) {
            hdrFbo.bind();
            glViewport(0, 0, w, h);
            vao.bind();
            fill.use();
            glDrawArrays(GL_TRIANGLES, 0, 3);
            glFinish();
            const auto t0 = std::chrono::steady_clock::now();
            const double c0 = test::cpuMs();
            if (k == shapes.size()) {
                scratchFbo.bind();
                trivial.use();
                glDrawArrays(GL_TRIANGLES, 0, 3);
            } else {
                run(shapes[k]);
            }
            glFinish();
            cpu[k].push_back(test::cpuMs() - c0);
            wall[k].push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
        }
    const double tw = test::medianOf(wall.back()), tc = test::medianOf(cpu.back());
    std::printf("the meter over work groups, medians of 41, ms wall / CPU (x trivial pass %.3f / %.3f ms):\n", tw, tc);
    for (size_t k = 0; k < shapes.size(); ++k)
        std::printf("  %-50s %6.3f / %6.3f   (%5.2f / %5.2f)\n", shapes[k].what.c_str(), test::medianOf(wall[k]), test::medianOf(cpu[k]),
                    test::medianOf(wall[k]) / tw, test::medianOf(cpu[k]) / tc);
    glDeleteBuffers(1, &ssbo);
    CHECK(tw > 0.0);  // the clock advanced
}

// `welkin bench display`'s "tone map" row as it measures it (wall clock between glFinish: the
// processor's tonemap_ms of renderFrame(), the eye's meter, plus that of toneMapInto() into an
// SRGB8_ALPHA8 target, the displayed pass), with the trivial pass timed in the same rounds, and
// the bare floor (a copy imageLoad RGBA32F -> SRGB8_ALPHA8) beside it; process CPU too.
TEST_CASE("Tone map timing: bench display's tone map row and its parts", "[.][tonemap_timing]") {
    test::glContext();
    const int w = 1280, h = 720;
    const auto held = meteredProcessor(w, h, glm::vec3(2e-2f, 3e-2f, 4e-2f));  // mesopic: the mesopic colour's whole arithmetic runs
    SkyProcessor& p = *held;
    p.vars().set(keys::interactive, true);
    auto vao = gl::VertexArray::create();
    gl::Texture2D scratch(w, h, GL_RGBA32F), srgb(w, h, GL_SRGB8_ALPHA8), srgb2(w, h, GL_SRGB8_ALPHA8);
    auto scratchFbo = gl::Framebuffer::create(), srgbFbo = gl::Framebuffer::create(), srgb2Fbo = gl::Framebuffer::create();
    scratchFbo.attach(GL_COLOR_ATTACHMENT0, scratch);
    srgbFbo.attach(GL_COLOR_ATTACHMENT0, srgb);
    srgb2Fbo.attach(GL_COLOR_ATTACHMENT0, srgb2);
    auto trivial = gl::ProgramBuilder("trivial")
                       .fullscreenVertex()
                       .fragment("trivial.frag", "out vec4 o; void main() { o = vec4(gl_FragCoord.xy * 1e-3, 1.0, 1.0); }")
                       .build();
    auto copy = gl::ProgramBuilder("copy")
                    .fullscreenVertex()
                    .fragment("copy.frag", "layout(binding = WELKIN_BINDING_HDR_IMAGE, rgba32f) readonly uniform image2D u_hdrImage;\n"
                                           "out vec4 o; void main() { o = vec4(imageLoad(u_hdrImage, ivec2(gl_FragCoord.xy)).rgb * 1e-3, 1.0); }")
                    .build();
    double seconds = 0;
    for (int i = 0; i < 3; ++i) {
        p.setAnimationTime(seconds += 1.0 / 30.0);
        p.renderFrame();
        p.toneMapInto(srgbFbo.id());
    }
    std::vector<double> trivialWall, trivialCpu, meterWall, displayWall, rowCpu, copyWall, copyCpu;
    for (int round = 0; round < 31; ++round) {
        for (int k = 0; k < 2; ++k) {
            glFinish();
            auto t0 = std::chrono::steady_clock::now();
            double c0 = test::cpuMs();
            (k == 0 ? scratchFbo : srgb2Fbo).bind();
            glViewport(0, 0, w, h);
            vao.bind();
            if (k == 0) {
                trivial.use();
            } else {
                glBindImageTexture(0, p.hdrTexture().id(), 0, GL_FALSE, 0, GL_READ_ONLY, GL_RGBA32F);
                glEnable(GL_FRAMEBUFFER_SRGB);
                copy.use();
            }
            glDrawArrays(GL_TRIANGLES, 0, 3);
            glFinish();
            if (k == 1) glDisable(GL_FRAMEBUFFER_SRGB);
            (k == 0 ? trivialCpu : copyCpu).push_back(test::cpuMs() - c0);
            (k == 0 ? trivialWall : copyWall).push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
        }
        p.setAnimationTime(seconds += 1.0 / 30.0);
        p.renderFrame();
        const double meter = p.stats()["tonemap_ms"].get<double>();
        glFinish();
        const double c0 = test::cpuMs();
        p.toneMapInto(srgbFbo.id());
        rowCpu.push_back(test::cpuMs() - c0);
        meterWall.push_back(meter);
        displayWall.push_back(p.stats()["tonemap_ms"].get<double>());
    }
    const double tw = test::medianOf(trivialWall), tc = test::medianOf(trivialCpu);
    std::vector<double> row;
    for (size_t i = 0; i < meterWall.size(); ++i) row.push_back(meterWall[i] + displayWall[i]);
    std::printf("bench display's tone map row, 1280x720, medians of 31: trivial pass %.3f ms wall, %.3f ms CPU\n", tw, tc);
    std::printf("  meter (renderFrame's tonemap_ms, wall)        %6.3f ms = %5.2f x trivial\n", test::medianOf(meterWall), test::medianOf(meterWall) / tw);
    std::printf("  display (toneMapInto's tonemap_ms, wall)      %6.3f ms = %5.2f x trivial\n", test::medianOf(displayWall), test::medianOf(displayWall) / tw);
    std::printf("  the row (meter + display, wall)               %6.3f ms = %5.2f x trivial\n", test::medianOf(row), test::medianOf(row) / tw);
    std::printf("  toneMapInto (CPU)                             %6.3f ms = %5.2f x trivial CPU\n", test::medianOf(rowCpu), test::medianOf(rowCpu) / tc);
    std::printf("  floor: copy imageLoad -> SRGB8 (wall / CPU)   %6.3f / %6.3f ms = %5.2f / %5.2f x trivial\n", test::medianOf(copyWall),
                test::medianOf(copyCpu), test::medianOf(copyWall) / tw, test::medianOf(copyCpu) / tc);
    CHECK(tw > 0.0);  // the clock advanced
}
