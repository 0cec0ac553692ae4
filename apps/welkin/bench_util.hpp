// Timing helpers shared by the `welkin bench` subcommands. GL timer queries mean nothing on
// llvmpipe: passes are timed on the CPU clock, bracketed by glFinish so GPU work is included.
//
//   double ms = welkin::cli::medianMs(10, [&] { processor.renderFrame(); });
//   processor.add(std::make_unique<welkin::cli::TrivialElement>());  // the cost floor of an element
#pragma once
#include <welkin/element.hpp>
#include <welkin/error.hpp>
#include <welkin/gl/objects.hpp>
#include <welkin/gl/shader.hpp>

#include <epoxy/gl.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <sstream>
#include <string>
#include <vector>

namespace welkin::cli {

/// What a shell command prints on its standard output, the trailing newlines removed; "" when it
/// cannot be run. For the few facts a benchmark's report states (the commit, a peer's version).
inline std::string shellOut(const std::string& cmd) {
    std::string out;
    if (FILE* p = popen(cmd.c_str(), "r")) {
        char buf[512];
        while (std::fgets(buf, sizeof buf, p)) out += buf;
        pclose(p);
    }
    while (!out.empty() && (out.back() == '\n' || out.back() == '\r')) out.pop_back();
    return out;
}

/// The commit a report was measured on: the short hash of `sourceDir`'s HEAD, with
/// " (with uncommitted changes)" when tracked files differ from it; "unknown" outside a checkout.
inline std::string sourceCommit(const std::string& sourceDir) {
    std::string commit = shellOut("git -C '" + sourceDir + "' rev-parse --short HEAD 2>/dev/null");
    if (commit.empty()) return "unknown";
    if (!shellOut("git -C '" + sourceDir + "' status --porcelain --untracked-files=no 2>/dev/null").empty()) commit += " (with uncommitted changes)";
    return commit;
}

/// The median of `v` (the upper one of an even count); NaN when empty.
inline double median(std::vector<double> v) {
    if (v.empty()) return NAN;
    std::sort(v.begin(), v.end());
    return v[v.size() / 2];
}

/// The items of a comma list, empty ones dropped ("low,,high" -> {"low", "high"}).
inline std::vector<std::string> splitList(const std::string& s) {
    std::vector<std::string> out;
    std::stringstream ss(s);
    for (std::string item; std::getline(ss, item, ',');)
        if (!item.empty()) out.push_back(item);
    return out;
}

/// A benchmark's output file (`option` names it: "--csv", "--plot") must go to an existing
/// directory: checked before minutes of measurement, not after. Empty: no output, no check.
inline void checkOutputDirectory(const char* option, const std::string& path) {
    const std::filesystem::path dir = std::filesystem::path(path).parent_path();
    if (!path.empty() && !dir.empty() && !std::filesystem::is_directory(dir))
        throw Error(std::string(option) + " '" + path + "': no directory '" + dir.string() + "'");
}

/// Median wall time of `repeats` (>= 1) calls of `fn`, milliseconds, each bracketed by glFinish.
inline double medianMs(int repeats, const std::function<void()>& fn) {
    std::vector<double> t;
    for (int i = 0; i < std::max(repeats, 1); ++i) {
        glFinish();
        auto t0 = std::chrono::steady_clock::now();
        fn();
        glFinish();
        t.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
    }
    std::sort(t.begin(), t.end());
    return t[t.size() / 2];
}

/// Medians of several passes timed in alternation (pass 0, 1, ..., 0, 1, ...), milliseconds, each
/// call bracketed by glFinish: every pass sees the same machine load, so their ratios hold on a
/// busy machine where separate runs would not.
inline std::vector<double> alternatedMedianMs(int repeats, const std::vector<std::function<void()>>& fns) {
    std::vector<std::vector<double>> t(fns.size());
    for (int i = 0; i < std::max(repeats, 1); ++i)
        for (size_t k = 0; k < fns.size(); ++k) {
            glFinish();
            auto t0 = std::chrono::steady_clock::now();
            fns[k]();
            glFinish();
            t[k].push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
        }
    std::vector<double> medians;
    for (auto& v : t) {
        std::sort(v.begin(), v.end());
        medians.push_back(v[v.size() / 2]);
    }
    return medians;
}

/// The trivial fullscreen pass: one constant-cost fragment per pixel into its own RGBA32F target,
/// no camera, no blending (the floor of any fullscreen draw; the clouds and night benches).
class TrivialPass {
public:
    TrivialPass(int w, int h) : w_(w), h_(h), target_(w, h, GL_RGBA32F) {
        vao_ = gl::VertexArray::create();
        prog_ = gl::ProgramBuilder("trivial")
                    .fullscreenVertex()
                    .fragment("trivial.frag", "out vec4 o; void main() { o = vec4(gl_FragCoord.xy * 1e-3, 1.0, 1.0); }")
                    .build();
        fbo_ = gl::Framebuffer::create();
        fbo_.attach(GL_COLOR_ATTACHMENT0, target_);
        fbo_.checkComplete("bench trivial pass");
    }
    void draw() {
        fbo_.bind();
        glViewport(0, 0, w_, h_);
        vao_.bind();
        prog_.use();
        glDrawArrays(GL_TRIANGLES, 0, 3);
    }
    /// Its framebuffer (RGBA32F, the frame's size): a display target for a frame's tone map
    /// (SkyProcessor::toneMapInto; the write format costs the same as RGBA8 on llvmpipe).
    unsigned framebuffer() const { return fbo_.id(); }

private:
    int w_, h_;
    gl::Texture2D target_;
    gl::VertexArray vao_;
    gl::Program prog_;
    gl::Framebuffer fbo_;
};

/// A trivial element: constant radiance through the composite contract (camera block, dual-source
/// blend into the HDR target), the cost floor of any fullscreen element. Benchmarks report an
/// element's cost as a ratio to this one's, timed in the same frames.
class TrivialElement final : public SkyElement {
public:
    TrivialElement() : SkyElement("trivial") {}

private:
    void doInit(InitContext&) override {
        prog_ = gl::ProgramBuilder("trivial")
                    .fullscreenVertex()
                    .fragment("engine/composite.glsl", gl::engineShader("composite.glsl"))
                    .fragment("trivial.frag", "void main() { welkin_output(vec3(gl_FragCoord.xy * 1e-3, 1.0), vec3(0.0)); }")
                    .build();
    }
    void doRender(const FrameContext& ctx) override {
        prog_.use();
        ctx.drawFullscreen();
    }
    void doRelease() override { prog_ = {}; }
    gl::Program prog_;
};

}  // namespace welkin::cli
