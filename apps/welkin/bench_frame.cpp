// welkin bench frame: cost of the compositing pipeline itself on this machine: a trivial
// fullscreen pass into RGBA32F and RGBA16F targets, the tone map (manual and automatic
// exposure; on a mesopic frame with eye.mesopic off and on) and the Grid element (on the tiles
// near its lines and, for comparison, as a fullscreen pass), and the floor under any tone map
// (the "floor" rows: write formats, copies by each fetch instruction and source format, blended
// passes, the tone map's other shapes (compute, in place by framebuffer fetch, blit), the Sky's
// parts (atan, 1-D row, multiply-only blend), log2; docs/eye.md, skyelements/sky/README.md), and
// the Sky's pass at `bench display`'s twilight and moonless views (the "Sky pass" rows). CPU-timed with glFinish (GL timer
// queries mean nothing on llvmpipe): elapsed time, or with --clock cpu the process's CPU time
// (steady on a machine other jobs load). Prints a Markdown table; --csv writes the same rows.
#include "bench_util.hpp"
#include "command.hpp"
#include "scene_options.hpp"

#include <welkin/csv.hpp>
#if __has_include(<welkin/embedded/sky_shaders.hpp>)
#include <welkin/embedded/sky_shaders.hpp>
#endif
#include <welkin/elements/registry.hpp>
#include <welkin/error.hpp>
#include <welkin/eye.hpp>
#include <welkin/gl/context.hpp>
#include <welkin/gl/shader.hpp>
#include <welkin/processor.hpp>

#include <epoxy/gl.h>

#include <algorithm>
#include <chrono>
#include <ctime>
#include <cstdio>
#include <functional>
#include <memory>
#include <vector>

namespace welkin::cli {
namespace {

/// A colour target: a texture of the frame's size and the framebuffer that draws into it.
struct ColorTarget {
    gl::Texture2D texture;
    gl::Framebuffer fbo;
    ColorTarget(int w, int h, GLenum format) : texture(w, h, format), fbo(gl::Framebuffer::create()) {
        fbo.attach(GL_COLOR_ATTACHMENT0, texture);
    }
};

struct FrameBenchOptions {
    std::string size = "1280x720";
    int repeats = 10;
    std::string csv;
    std::string clock = "wall";  ///< "wall" (steady clock) or "cpu" (the process's CPU time, llvmpipe's threads included)
};

bool gCpuClock = false;  // --clock cpu

double nowMs() {
    if (!gCpuClock) return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now().time_since_epoch()).count();
    timespec t{};
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
    return t.tv_sec * 1e3 + t.tv_nsec * 1e-6;
}

// medianMs() and alternatedMedianMs() of bench_util.hpp on the clock --clock chose: with "cpu" the
// work the passes cost (llvmpipe's rasterizer threads are this process's), steady when other jobs
// load the machine's cores.
double medianOn(int repeats, const std::function<void()>& fn) {
    std::vector<double> t;
    for (int i = 0; i < std::max(repeats, 1); ++i) {
        glFinish();
        const double t0 = nowMs();
        fn();
        glFinish();
        t.push_back(nowMs() - t0);
    }
    std::sort(t.begin(), t.end());
    return t[t.size() / 2];
}

std::vector<double> alternatedOn(int repeats, const std::vector<std::function<void()>>& fns) {
    std::vector<std::vector<double>> t(fns.size());
    for (int i = 0; i < std::max(repeats, 1); ++i)
        for (size_t k = 0; k < fns.size(); ++k) {
            glFinish();
            const double t0 = nowMs();
            fns[k]();
            glFinish();
            t[k].push_back(nowMs() - t0);
        }
    std::vector<double> medians;
    for (auto& v : t) {
        std::sort(v.begin(), v.end());
        medians.push_back(v[v.size() / 2]);
    }
    return medians;
}

int run(const FrameBenchOptions& o) {
    int w = 0, h = 0;
    std::sscanf(o.size.c_str(), "%dx%d", &w, &h);
    if (w < 1 || h < 1 || w > 8192 || h > 8192) throw Error("--size '" + o.size + "' not WIDTHxHEIGHT in [1, 8192]");
    if (o.repeats < 1 || o.repeats > 1000) throw Error("--repeats " + std::to_string(o.repeats) + " not in [1, 1000]");
    if (o.clock != "wall" && o.clock != "cpu") throw Error("--clock '" + o.clock + "' not one of wall, cpu");
    gCpuClock = o.clock == "cpu";
    // The grid's rows reach it by name: without skyelements/grid, one line before any GL work.
    if (!elements::findDescriptor("grid")) throw Error("needs the element 'grid' (no skyelements/grid in this build)");
    Logger log;
    auto ctx = gl::HeadlessContext::create({}, log);
    auto vao = gl::VertexArray::create();
    auto trivial = gl::ProgramBuilder("trivial")
                       .fullscreenVertex()
                       .fragment("trivial.frag", "out vec4 o; void main() { o = vec4(gl_FragCoord.xy * 1e-3, 1.0, 1.0); }")
                       .build();
    struct Row {
        std::string what;
        double ms;
    };
    std::vector<Row> rows;
    std::vector<Row> alternated;  // (what, ratio to the trivial pass timed in alternation with it)
    std::vector<double> copyRatio;  // the same rows' ratio to the copy pass (the tone map's memory floor)
    auto blended = gl::ProgramBuilder("trivial blended")
                       .fullscreenVertex()
                       .fragment("engine/composite.glsl", gl::engineShader("composite.glsl"))
                       .fragment("blended.frag", "void main() { welkin_output(vec3(gl_FragCoord.xy * 1e-3, 1.0), vec3(0.5)); }")
                       .build();
    for (GLenum fmt : {GL_RGBA32F, GL_RGBA16F}) {  // a compositing pass: dual-source blending
        gl::Texture2D target(w, h, fmt);
        auto fbo = gl::Framebuffer::create();
        fbo.attach(GL_COLOR_ATTACHMENT0, target);
        fbo.checkComplete("bench");
        rows.push_back({fmt == GL_RGBA32F ? "blended (dual-source) pass, RGBA32F" : "blended (dual-source) pass, RGBA16F",
                        medianOn(o.repeats, [&] {
                            fbo.bind();
                            glViewport(0, 0, w, h);
                            vao.bind();
                            blended.use();
                            glEnable(GL_BLEND);
                            glBlendFuncSeparate(GL_ONE, GL_SRC1_COLOR, GL_ZERO, GL_ONE);
                            glDrawArrays(GL_TRIANGLES, 0, 3);
                            glDisable(GL_BLEND);
                        })});
    }
    for (GLenum fmt : {GL_RGBA32F, GL_RGBA16F, GL_RGBA8}) {
        gl::Texture2D target(w, h, fmt);
        auto fbo = gl::Framebuffer::create();
        fbo.attach(GL_COLOR_ATTACHMENT0, target);
        fbo.checkComplete("bench");
        const char* name = fmt == GL_RGBA32F ? "trivial pass, RGBA32F" : fmt == GL_RGBA16F ? "trivial pass, RGBA16F" : "trivial pass, RGBA8";
        rows.push_back({name, medianOn(o.repeats, [&] {
                            fbo.bind();
                            glViewport(0, 0, w, h);
                            vao.bind();
                            trivial.use();
                            glDrawArrays(GL_TRIANGLES, 0, 3);
                        })});
    }
    {
        SkyProcessor sky(SkyVars::earth(), log);
        Camera cam;
        cam.width = w;
        cam.height = h;
        sky.setCamera(cam);
        sky.add(elements::makeElement("grid"));  // by name: options through its keys (grid.tiled)
        sky.renderFrame();
        rows.push_back({"grid element + tone map (renderFrame)", medianOn(o.repeats, [&] { sky.renderFrame(); })});
        const ColorTarget ldr(w, h, GL_RGBA8);
        const gl::Framebuffer& ldrFbo = ldr.fbo;
        // The tone map against the trivial pass and a copy pass (fetch the HDR texel, write RGBA8:
        // the memory traffic any tone map has), timed in alternation: the ratio is the tone map's
        // own arithmetic, steady on a loaded machine.
        ColorTarget trivialColor(w, h, GL_RGBA32F);
        gl::Texture2D& trivialTarget = trivialColor.texture;
        const gl::Framebuffer& trivialFbo = trivialColor.fbo;
        auto copy = gl::ProgramBuilder("copy")
                        .fullscreenVertex()
                        .fragment("copy.frag", "layout(binding = 0) uniform sampler2D u_hdr; out vec4 o;\n"
                                               "void main() { o = vec4(texelFetch(u_hdr, ivec2(gl_FragCoord.xy), 0).rgb * 1e-3, 1.0); }")
                        .build();
        auto drawTrivial = [&] {
            trivialFbo.bind();
            glViewport(0, 0, w, h);
            vao.bind();
            trivial.use();
            glDrawArrays(GL_TRIANGLES, 0, 3);
        };
        auto drawCopy = [&] {
            ldrFbo.bind();
            glViewport(0, 0, w, h);
            vao.bind();
            glBindTextureUnit(0, trivialTarget.id());
            copy.use();
            glDrawArrays(GL_TRIANGLES, 0, 3);
        };
        {
            // The grid drawn on the tiles near its lines (the default) and as a fullscreen pass
            // (grid.tiled=false: its cost before 2026-11-26), each renderFrame() with manual
            // exposure, in alternation with the trivial and copy passes.
            sky.setExposure({.automatic = false});
            auto gridFrame = [&](bool tiled) {
                return [&, tiled] {
                    sky.vars().setFromString("grid.tiled", tiled ? "true" : "false");
                    sky.renderFrame();
                };
            };
            gridFrame(false)();
            const std::vector<double> ms = alternatedOn(o.repeats, {drawTrivial, drawCopy, gridFrame(true), gridFrame(false)});
            sky.vars().setFromString("grid.tiled", "true");
            rows.push_back({"grid element + tone map, lines' tiles (renderFrame)", ms[2]});
            rows.push_back({"grid element + tone map, fullscreen grid (renderFrame)", ms[3]});
            rows.push_back({"  alternated with them: trivial pass RGBA32F", ms[0]});
            alternated.push_back({"grid element + tone map, lines' tiles", ms[2] / ms[0]});
            copyRatio.push_back(ms[2] / ms[1]);
            alternated.push_back({"grid element + tone map, fullscreen grid", ms[3] / ms[0]});
            copyRatio.push_back(ms[3] / ms[1]);
        }
        for (bool automatic : {false, true}) {
            sky.setExposure({.automatic = automatic});
            sky.toneMapInto(ldrFbo.id());
            const std::vector<double> ms =
                alternatedOn(o.repeats, {drawTrivial, drawCopy, [&] { sky.toneMapInto(ldrFbo.id()); }});
            const std::string what = automatic ? "automatic exposure" : "manual exposure";
            rows.push_back({"tone map, " + what, ms[2]});
            rows.push_back({"  alternated with it: trivial pass RGBA32F", ms[0]});
            rows.push_back({"  alternated with it: copy pass RGBA32F -> RGBA8", ms[1]});
            alternated.push_back({"tone map, " + what, ms[2] / ms[0]});
            copyRatio.push_back(ms[2] / ms[1]);
        }
        // The mesopic colour (docs/eye.md): a frame of constant-cost radiance between 0 and ~1.3
        // cd/m^2 (the trivial element: mesopic luminances, so the per-pixel mesopic path runs),
        // automatic exposure, eye.mesopic off and on, both timed in alternation with the trivial
        // pass.
        {
            SkyProcessor night(SkyVars::earth(), log, ProcessorOptions{.astronomy = false});
            night.setCamera(cam);
            night.add(std::make_unique<TrivialElement>());
            night.setExposure({.automatic = true});
            night.renderFrame();
            auto toneMap = [&](bool mesopic) {
                return [&, mesopic] {
                    night.vars().set(eye::keys::mesopic, mesopic);
                    night.toneMapInto(ldrFbo.id());
                };
            };
            toneMap(false)();
            toneMap(true)();
            const std::vector<double> ms = alternatedOn(o.repeats, {drawTrivial, drawCopy, toneMap(false), toneMap(true)});
            rows.push_back({"tone map, mesopic frame, eye.mesopic off", ms[2]});
            rows.push_back({"tone map, mesopic frame, eye.mesopic on", ms[3]});
            rows.push_back({"  alternated with them: trivial pass RGBA32F", ms[0]});
            rows.push_back({"  alternated with them: copy pass RGBA32F -> RGBA8", ms[1]});
            for (int m = 0; m < 2; ++m) {
                alternated.push_back({m ? "tone map, mesopic frame, eye.mesopic on" : "tone map, mesopic frame, eye.mesopic off", ms[2 + m] / ms[0]});
                copyRatio.push_back(ms[2 + m] / ms[1]);
            }
            night.release();
        }
        // The floor under any tone map on this machine: what reading the HDR texel and writing the
        // display format cost by themselves, each variant in alternation with the trivial pass.
        {
            const ColorTarget half(w, h, GL_RGBA16F), floatOut(w, h, GL_RGBA32F);
            auto prog = [](const char* name, const char* src) {
                return gl::ProgramBuilder(name).fullscreenVertex().fragment(name, src).build();
            };
            auto constant8 = prog("const.frag", "out vec4 o; void main() { o = vec4(0.25, 0.5, 0.75, 1.0); }");
            auto image8 = prog("image.frag", "layout(binding = 0, rgba32f) readonly uniform image2D u_img; out vec4 o;\n"
                                             "void main() { o = vec4(imageLoad(u_img, ivec2(gl_FragCoord.xy)).rgb * 1e-3, 1.0); }");
            auto fetchNoScale = prog("fetch.frag", "layout(binding = 0) uniform sampler2D u_hdr; out vec4 o;\n"
                                                  "void main() { o = texelFetch(u_hdr, ivec2(gl_FragCoord.xy), 0); }");
            auto sampled = prog("sampled.frag", "layout(binding = 0) uniform sampler2D u_hdr; uniform vec2 u_inv; out vec4 o;\n"
                                                "void main() { o = vec4(textureLod(u_hdr, gl_FragCoord.xy * u_inv, 0.0).rgb * 1e-3, 1.0); }");
            auto pass = [&](const gl::Framebuffer& fbo, gl::Program& p, unsigned tex, bool image) {
                return [&, tex, image] {
                    fbo.bind();
                    glViewport(0, 0, w, h);
                    vao.bind();
                    if (image)
                        glBindImageTexture(0, tex, 0, GL_FALSE, 0, GL_READ_ONLY, GL_RGBA32F);
                    else
                        glBindTextureUnit(0, tex);
                    p.use();
                    if (&p == &sampled) p.set("u_inv", glm::vec2(1.0f / w, 1.0f / h));
                    glDrawArrays(GL_TRIANGLES, 0, 3);
                };
            };
            const ColorTarget srgb8(w, h, GL_SRGB8_ALPHA8), rgb10(w, h, GL_RGB10_A2);
            auto trivialInto = [&](const gl::Framebuffer& fbo) {
                return [&] {
                    fbo.bind();
                    glViewport(0, 0, w, h);
                    vao.bind();
                    trivial.use();
                    glDrawArrays(GL_TRIANGLES, 0, 3);
                };
            };
            auto trivial8 = trivialInto(ldrFbo);
            trivialTarget.setFilter(GL_NEAREST);
            // fill the half-float source once
            half.fbo.bind();
            glViewport(0, 0, w, h);
            vao.bind();
            trivial.use();
            glDrawArrays(GL_TRIANGLES, 0, 3);
            auto blendedPass = [&](bool dualSource) {
                return [&, dualSource] {
                    trivialFbo.bind();
                    glViewport(0, 0, w, h);
                    vao.bind();
                    glEnable(GL_BLEND);
                    if (dualSource) {
                        blended.use();
                        glBlendFuncSeparate(GL_ONE, GL_SRC1_COLOR, GL_ZERO, GL_ONE);
                    } else {
                        trivial.use();
                        glBlendFunc(GL_ONE, GL_ONE);
                    }
                    glDrawArrays(GL_TRIANGLES, 0, 3);
                    glDisable(GL_BLEND);
                };
            };
            // What an element's pass pays for a texture read (issue 22: the night sky reads a
            // 2048x1024 RGBA16F panorama, mipmapped, magnified at 1280x720 and a 60 deg field, and
            // a 256x128 R32F table): the level 0 given as a constant, the level per pixel (as
            // max(log2(...), 0): 0 here too), the small table, and one texel of a 1x1 texture
            // per pixel (the automatic exposure's state, before it became a flat varying).
            gl::Texture2D panorama(2048, 1024, GL_RGBA16F, 12), table(256, 128, GL_R32F), one(1, 1, GL_RGBA32F);
            {
                std::vector<float> px(size_t(2048) * 1024 * 4);
                for (size_t i = 0; i < px.size(); ++i) px[i] = float((i * 2654435761u) % 1000u) * 1e-3f;
                glTextureSubImage2D(panorama.id(), 0, 0, 0, 2048, 1024, GL_RGBA, GL_FLOAT, px.data());
                panorama.generateMipmaps();
                panorama.setFilter(GL_LINEAR_MIPMAP_LINEAR, GL_LINEAR);
                glTextureSubImage2D(table.id(), 0, 0, 0, 256, 128, GL_RED, GL_FLOAT, px.data());
                table.setFilter(GL_LINEAR);
                glTextureSubImage2D(one.id(), 0, 0, 0, 1, 1, GL_RGBA, GL_FLOAT, px.data());
            }
            // u_uvPerPx: texture coordinates per pixel (0.45 of a panorama texel: magnified).
            auto fetchPass = [&](const char* name, const char* body) {
                return prog(name, (std::string("layout(binding = 0) uniform sampler2D u_tex; uniform vec2 u_uvPerPx; out vec4 o;\n"
                                               "void main() { vec2 uv = gl_FragCoord.xy * u_uvPerPx + vec2(0.1, 0.2);\n") +
                                   body + " }")
                                      .c_str());
            };
            auto panoLevel0 = fetchPass("pano_lod0.frag", "o = vec4(textureLod(u_tex, uv, 0.0).rgb * 1e-3, 1.0);");
            auto panoLevelPx = fetchPass("pano_lodpx.frag",
                                         "float lod = max(log2(max(length(dFdx(uv * 2048.0)), length(dFdy(uv * 2048.0)))), 0.0);\n"
                                         "o = vec4(textureLod(u_tex, uv, lod).rgb * 1e-3, 1.0);");
            auto tableFetch = fetchPass("table.frag", "o = vec4(vec3(textureLod(u_tex, uv, 0.0).r * 1e-3), 1.0);");
            auto oneTexel = fetchPass("one.frag", "o = vec4(uv * texelFetch(u_tex, ivec2(0), 0).z, 0.5, 1.0);");
            auto sampledPass = [&](gl::Program& p, const gl::Texture2D& tex, float texelsWide) {
                return [&, texelsWide] {
                    trivialFbo.bind();
                    glViewport(0, 0, w, h);
                    vao.bind();
                    glBindTextureUnit(0, tex.id());
                    p.use();
                    p.set("u_uvPerPx", glm::vec2(0.45f / texelsWide, 0.45f / texelsWide * 2.0f));
                    glDrawArrays(GL_TRIANGLES, 0, 3);
                };
            };
            // The HDR frame read through framebuffer fetch (EXT_shader_framebuffer_fetch, which
            // Mesa's llvmpipe has): the frame as colour attachment 0 (read, writes masked), the
            // display format as attachment 1.
            const bool fbFetch = epoxy_has_gl_extension("GL_EXT_shader_framebuffer_fetch");
            gl::Program fbFetchCopy;
            gl::Framebuffer fbFetchFbo = gl::Framebuffer::create();
            if (fbFetch) {
                fbFetchCopy = prog("fbfetch.frag", "#extension GL_EXT_shader_framebuffer_fetch : require\n"
                                                   "layout(location = 0) inout vec4 hdr; layout(location = 1) out vec4 o;\n"
                                                   "void main() { o = vec4(hdr.rgb * 1e-3, 1.0); }");
                fbFetchFbo.attach(GL_COLOR_ATTACHMENT0, trivialTarget);
                fbFetchFbo.attach(GL_COLOR_ATTACHMENT1, ldr.texture);
                const GLenum bufs[2] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1};
                glNamedFramebufferDrawBuffers(fbFetchFbo.id(), 2, bufs);
                fbFetchFbo.checkComplete("bench frame framebuffer fetch");
            }
            auto fbFetchPass = [&] {
                if (!fbFetch) return;
                fbFetchFbo.bind();
                glViewport(0, 0, w, h);
                vao.bind();
                fbFetchCopy.use();
                // A dual-source blend function left set (blending off) still limits the draw to
                // one colour buffer: INVALID_OPERATION with two.
                glBlendFunc(GL_ONE, GL_ZERO);
                glColorMaski(0, GL_FALSE, GL_FALSE, GL_FALSE, GL_FALSE);
                glDrawArrays(GL_TRIANGLES, 0, 3);
                glColorMaski(0, GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
            };
            // What the Sky's pass pays for its parts (skyelements/sky/README.md "Cost"): an atan per
            // pixel (the eclipse table's absolute azimuth), a bilinear 1-D RGBA16F row (the view
            // transmittance), and the night's multiply-only blend (dst = T dst, no radiance) against
            // the dual-source one (dst = L + T dst).
            gl::Texture1D row1d(256, GL_RGBA16F);
            {
                std::vector<float> px(256 * 4);
                for (size_t i = 0; i < px.size(); ++i) px[i] = float(i % 97) * 1e-2f;
                glTextureSubImage1D(row1d.id(), 0, 0, 256, GL_RGBA, GL_FLOAT, px.data());
                glTextureParameteri(row1d.id(), GL_TEXTURE_MIN_FILTER, GL_LINEAR);
                glTextureParameteri(row1d.id(), GL_TEXTURE_MAG_FILTER, GL_LINEAR);
                glTextureParameteri(row1d.id(), GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
            }
            auto atanProg = prog("atan.frag", "out vec4 o; void main() { vec2 d = gl_FragCoord.xy - vec2(640.5, 360.5);\n"
                                              "o = vec4(atan(d.x, d.y) * 0.159, gl_FragCoord.y * 1e-3, 1.0, 1.0); }");
#if __has_include(<welkin/embedded/sky_shaders.hpp>)
            // The Sky's skyAtan2() (skyelements/sky/shaders/sky_atan.shared.glsl), its own text.
            auto atanPolyProg = prog("atanpoly.frag", (std::string(embedded::sky_shaders("sky_atan.shared.glsl")) +
                                                       "\nout vec4 o; void main() { vec2 d = gl_FragCoord.xy - vec2(640.5, 360.5);\n"
                                                       "o = vec4(skyAtan2(d.x, d.y) * 0.159, gl_FragCoord.y * 1e-3, 1.0, 1.0); }")
                                                          .c_str());
#else
            auto atanPolyProg = prog("atanpoly.frag", "out vec4 o; void main() { o = vec4(0.0); }");  // no Sky in this build
#endif
            // The builtin log2 (the tone map's mesopic weight took it before 2026-11-27, docs/eye.md).
            auto log2Prog = prog("log2.frag", "out vec4 o; void main() { float y = gl_FragCoord.x * gl_FragCoord.y * 1e-5;\n"
                                              "o = vec4(log2(y), gl_FragCoord.y * 1e-3, 1.0, 1.0); }");
            auto row1dProg = prog("row1d.frag", "layout(binding = 0) uniform sampler1D u_row; out vec4 o;\n"
                                                "void main() { o = vec4(texture(u_row, gl_FragCoord.y * 7.7e-4).rgb, 1.0); }");
            auto multiplyProg = prog("multiply.frag", "out vec4 o; void main() { o = vec4(vec3(gl_FragCoord.y * 1e-3), 1.0); }");
            auto plainInto = [&](gl::Program& p, unsigned tex1d) {
                return [&, tex1d] {
                    trivialFbo.bind();
                    glViewport(0, 0, w, h);
                    vao.bind();
                    if (tex1d) glBindTextureUnit(0, tex1d);
                    p.use();
                    glDrawArrays(GL_TRIANGLES, 0, 3);
                };
            };
            auto multiplyPass = [&] {
                trivialFbo.bind();
                glViewport(0, 0, w, h);
                vao.bind();
                glEnable(GL_BLEND);
                multiplyProg.use();
                glBlendFuncSeparate(GL_ZERO, GL_SRC_COLOR, GL_ZERO, GL_ONE);
                glDrawArrays(GL_TRIANGLES, 0, 3);
                glDisable(GL_BLEND);
            };
            // The tone map's other shapes (docs/eye.md "Other shapes of the tone map"): a compute
            // pass (imageLoad of the HDR frame, imageStore into an RGBA8 image: it cannot write a
            // window), the frame tone-mapped in place through framebuffer fetch (RGBA32F, the
            // attachment read and written) and the blit that would then carry it to the display.
            gl::Program computeCopy = gl::ProgramBuilder("copy.comp")
                                          .compute("copy.comp", "layout(local_size_x = 8, local_size_y = 8) in;\n"
                                                                "layout(binding = 0, rgba32f) readonly uniform image2D u_in;\n"
                                                                "layout(binding = 1, rgba8) writeonly uniform image2D u_out;\n"
                                                                "void main() { ivec2 p = ivec2(gl_GlobalInvocationID.xy);\n"
                                                                "imageStore(u_out, p, vec4(imageLoad(u_in, p).rgb * 1e-3, 1.0)); }")
                                          .build();
            auto computePass = [&] {
                computeCopy.use();
                glBindImageTexture(0, trivialTarget.id(), 0, GL_FALSE, 0, GL_READ_ONLY, GL_RGBA32F);
                glBindImageTexture(1, ldr.texture.id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA8);
                glDispatchCompute(GLuint((w + 7) / 8), GLuint((h + 7) / 8), 1);
                glMemoryBarrier(GL_ALL_BARRIER_BITS);
            };
            auto blitPass = [&] {
                glBlitNamedFramebuffer(trivialFbo.id(), ldrFbo.id(), 0, 0, w, h, 0, 0, w, h, GL_COLOR_BUFFER_BIT, GL_NEAREST);
            };
            std::vector<std::pair<std::string, std::function<void()>>> floor = {
                {"floor: trivial pass RGBA32F (reference)", drawTrivial},
                {"floor: trivial pass RGBA8", trivial8},
                {"floor: constant colour RGBA8", pass(ldrFbo, constant8, 0, false)},
                {"floor: trivial pass SRGB8_ALPHA8", trivialInto(srgb8.fbo)},
                {"floor: trivial pass RGB10_A2", trivialInto(rgb10.fbo)},
                {"floor: copy texelFetch RGBA32F -> RGBA8", drawCopy},
                {"floor: copy imageLoad RGBA32F -> RGBA8", pass(ldrFbo, image8, trivialTarget.id(), true)},
                {"floor: copy textureLod (nearest) RGBA32F -> RGBA8", pass(ldrFbo, sampled, trivialTarget.id(), false)},
                {"floor: copy texelFetch RGBA16F -> RGBA8", pass(ldrFbo, copy, half.texture.id(), false)},
                {"floor: copy texelFetch RGBA32F -> RGBA32F", pass(floatOut.fbo, fetchNoScale, trivialTarget.id(), false)},
                {"floor: tone map (automatic exposure) into RGBA8", [&] { sky.toneMapInto(ldrFbo.id()); }},
                {"floor: tone map (automatic exposure) into SRGB8_ALPHA8 (encoded on write)", [&] { sky.toneMapInto(srgb8.fbo.id()); }},
                {"floor: tone map (automatic exposure) into RGBA32F", [&] { sky.toneMapInto(floatOut.fbo.id()); }},
                {"floor: additive blended pass RGBA32F (ONE, ONE)", blendedPass(false)},
                {"floor: dual-source blended pass RGBA32F (welkin_output)", blendedPass(true)},
                {"floor: bilinear RGBA16F panorama 2048x1024, level 0 constant", sampledPass(panoLevel0, panorama, 2048.0f)},
                {"floor: bilinear RGBA16F panorama 2048x1024, level per pixel", sampledPass(panoLevelPx, panorama, 2048.0f)},
                {"floor: bilinear R32F table 256x128", sampledPass(tableFetch, table, 256.0f)},
                {"floor: texelFetch of a 1x1 texture per pixel", sampledPass(oneTexel, one, 1.0f)},
            };
            if (fbFetch) floor.push_back({"floor: copy by framebuffer fetch RGBA32F -> RGBA8", fbFetchPass});
            floor.push_back({"floor: trivial pass + atan per pixel", plainInto(atanProg, 0)});
            floor.push_back({"floor: trivial pass + polynomial atan per pixel (the Sky's skyAtan2)", plainInto(atanPolyProg, 0)});
            floor.push_back({"floor: trivial pass + log2 per pixel (builtin)", plainInto(log2Prog, 0)});
            floor.push_back({"floor: bilinear RGBA16F 1-D row of 256", plainInto(row1dProg, row1d.id())});
            floor.push_back({"floor: multiply-only blended pass RGBA32F (ZERO, SRC_COLOR)", multiplyPass});
            floor.push_back({"floor: copy by compute imageLoad RGBA32F -> imageStore RGBA8", computePass});
            floor.push_back({"floor: blit RGBA32F -> RGBA8", blitPass});
            gl::Program fbInPlace;
            gl::Framebuffer fbInPlaceFbo = gl::Framebuffer::create();
            if (fbFetch) {
                fbInPlace = prog("fbinplace.frag", "#extension GL_EXT_shader_framebuffer_fetch : require\n"
                                                   "layout(location = 0) inout vec4 hdr;\n"
                                                   "void main() { hdr = vec4(hdr.rgb * 0.999, 1.0); }");
                fbInPlaceFbo.attach(GL_COLOR_ATTACHMENT0, trivialTarget);
                fbInPlaceFbo.checkComplete("bench frame in-place framebuffer fetch");
                floor.push_back({"floor: in place by framebuffer fetch RGBA32F (read and written)", [&] {
                                     fbInPlaceFbo.bind();
                                     glViewport(0, 0, w, h);
                                     vao.bind();
                                     fbInPlace.use();
                                     glDrawArrays(GL_TRIANGLES, 0, 3);
                                 }});
            }
            std::vector<std::function<void()>> fns;
            for (auto& f : floor) {
                f.second();  // warm-up: llvmpipe compiles a program (and its blend state) at first draw
                fns.push_back(f.second);
            }
            const std::vector<double> ms = alternatedOn(o.repeats, fns);
            for (size_t i = 0; i < floor.size(); ++i) {
                rows.push_back({floor[i].first, ms[i]});
                alternated.push_back({floor[i].first, ms[i] / ms[0]});
                copyRatio.push_back(ms[i] / ms[5]);
            }
        }
        // The Sky's pass as `welkin bench display` draws it (skyelements/sky/README.md "Cost"): at its
        // twilight (the eclipse table over absolute azimuth, Malta 2026-08-12 18:10 UTC) and
        // moonless (22:00 UTC, the Sun's term skipped) views, behind a trivial element (so the Sky
        // blends over something, as over the night sky), manual exposure (no tone map in
        // renderFrame()); the trivial element alone is the reference the Sky's share is over.
        if (elements::findDescriptor("sky")) {
            auto scene = [&](const char* time, bool withSky) {
                auto p = std::make_unique<SkyProcessor>(SkyVars::earth(), log);
                p->add(std::make_unique<TrivialElement>());
                SceneOptions so;
                so.time = time;
                so.latDeg = 35.9, so.lonDeg = 14.5, so.heightM = 50;
                so.azDeg = 180, so.altDeg = 30, so.fovDeg = 60;
                so.size = std::to_string(w) + "x" + std::to_string(h);
                so.exposure = "10";
                so.elements = withSky ? "sky" : "";
                so.elementsGiven = withSky;
                if (withSky) so.apply(*p);
                else {
                    p->setCamera(so.camera());
                    p->setExposure(so.exposureSetting());
                }
                p->renderFrame();
                p->renderFrame();
                return p;
            };
            auto twilight = scene("2026-08-12T18:10:00Z", true), moonless = scene("2026-08-12T22:00:00Z", true),
                 alone = scene("2026-08-12T22:00:00Z", false);
            const std::vector<double> ms = alternatedOn(o.repeats, {drawTrivial, [&] { alone->renderFrame(); }, [&] { twilight->renderFrame(); },
                                                                    [&] { moonless->renderFrame(); }, drawCopy});
            const char* names[] = {"Sky pass: trivial element alone (renderFrame)", "Sky pass: twilight, over the trivial element (renderFrame)",
                                   "Sky pass: moonless, over the trivial element (renderFrame)"};
            for (int i = 0; i < 3; ++i) {
                rows.push_back({names[i], ms[size_t(i) + 1]});
                alternated.push_back({names[i], ms[size_t(i) + 1] / ms[0]});
                copyRatio.push_back(ms[size_t(i) + 1] / ms[4]);
            }
        }
        rows.push_back({"read back HDR (RGBA32F -> RGB)", medianOn(std::min(o.repeats, 3), [&] { (void)sky.readHdr(); })});
    }
    std::printf("welkin bench frame, %dx%d, median of %d, %s clock, %s\n\n| pass | ms | x trivial RGBA32F |\n|---|---|---|\n", w, h,
                o.repeats, o.clock.c_str(), ctx->description().c_str());
    double reference = rows[0].ms;
    for (auto& r : rows)
        if (r.what == "trivial pass, RGBA32F") reference = r.ms;
    for (auto& r : rows) std::printf("| %s | %.2f | %.2f |\n", r.what.c_str(), r.ms, r.ms / reference);
    std::printf("\n| pass | x trivial RGBA32F, timed in alternation (target <= 2) | x copy pass (fetch + write) |\n|---|---|---|\n");
    for (size_t i = 0; i < alternated.size(); ++i)
        std::printf("| %s | %.2f | %.2f |\n", alternated[i].what.c_str(), alternated[i].ms, copyRatio[i]);
    if (!o.csv.empty()) {
        CsvWriter f(o.csv, {"pass", "ms"});
        for (auto& r : rows) f.row(r.what, r.ms);
        f.close();
    }
    return 0;
}

BenchRegistrar reg("frame", "cost of the HDR target formats, the tone map and the grid", [](CLI::App& sub) {
    auto o = std::make_shared<FrameBenchOptions>();  // the action below owns it
    sub.add_option("--size", o->size, "frame size WIDTHxHEIGHT")->capture_default_str();
    sub.add_option("--repeats", o->repeats, "timed repetitions (median reported)")->capture_default_str();
    sub.add_option("--csv", o->csv, "also write the rows as CSV");
    sub.add_option("--clock", o->clock, "wall (elapsed) or cpu (the process's CPU time, llvmpipe's threads included: steady on a loaded machine)")
        ->capture_default_str();
    return [o]() { return run(*o); };
});

}  // namespace
}  // namespace welkin::cli
