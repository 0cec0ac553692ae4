// Weather map generator (GPU: weather_map.vert/frag.glsl instanced, weather_resolve.glsl; CPU twin
// cpu::weatherTexel), its shapes, the artist's image and the animation by wind and flow.
#include <welkin/check.hpp>
#include <welkin/embedded/clouds_shaders.hpp>
#include <welkin/error.hpp>
#include <welkin/generators/cloud_keys.hpp>
#include <welkin/generators/cloud_noise.hpp>
#include <welkin/generators/weather_map.hpp>
#include <welkin/gl/bindings.hpp>
#include <welkin/gl/shader.hpp>
#include <welkin/glsl_cpp.hpp>
#include <welkin/keys.hpp>

#include <epoxy/gl.h>

#include <algorithm>
#include <cmath>

// The shapes' fade and the resolve: weather_shape.shared.glsl (the passes' text) in double, its
// cn_perlinFbm2() the noise's twin (cloud_noise.shared.glsl's, compiled in cloud_noise.cpp).
namespace welkin::glsl::dp::weather_shared {
real cn_perlinFbm2(vec2 p, int f, int octaves, uint seed) { return generators::cpu::perlinFbm2(p, f, octaves, seed); }
#include "weather_shape.shared.glsl"
}  // namespace welkin::glsl::dp::weather_shared

namespace welkin::generators {

namespace {
constexpr double kPi = 3.14159265358979323846;
double unit(uint32_t h) { return double(h & 0xffffffu) / 16777216.0; }
double wrapMod(double v, double p) {
    double m = std::fmod(v, p);
    return m < 0 ? m + p : m;
}
// The edge noise's offset of a shape, from its seed (in [0, 1)^2; GLSL gets it precomputed).
glm::dvec2 edgeOffset(uint32_t seed) { return {unit(cpu::noiseHash(seed ^ 0x5bd1e995u)), unit(cpu::noiseHash(seed ^ 0x1b873593u))}; }

void checkShape(const CloudShape& s) {
    checkOpenRange("WeatherMap", "semiAxes.x (m)", s.semiAxes.x, 0.0, kInfinity);
    checkOpenRange("WeatherMap", "semiAxes.y (m)", s.semiAxes.y, 0.0, kInfinity);
    checkRange("WeatherMap", "density", s.density, 0.0, 1.0);
    checkRange("WeatherMap", "baseFraction", s.baseFraction, 0.0, 1.0);
    checkRange("WeatherMap", "topFraction", s.topFraction, s.baseFraction, 1.0);
    checkRange("WeatherMap", "rain", s.rain, 0.0, 1.0);
    checkRange("WeatherMap", "centre.x (m)", s.centre.x, -1e12, 1e12);
    checkRange("WeatherMap", "centre.y (m)", s.centre.y, -1e12, 1e12);
    checkRange("WeatherMap", "rotation (rad)", s.rotation, -1e6, 1e6);
}

struct GpuShape {
    float geo[4], val[4], more[4];
    uint32_t ids[4];
};
}  // namespace

WeatherMap::WeatherMap(int size) : Generator("clouds.weather_map"), size_(size) {
    checkRange("WeatherMap", "size", size, 16, 4096);
    input(cloudkeys::seed, {.optional = true});
    input(cloudkeys::cloudCount);
    input(cloudkeys::cloudSizeMin);
    input(cloudkeys::cloudSizeMax);
    input(cloudkeys::weatherExtent, {.optional = true});
    input(cloudkeys::weatherFile, {.optional = true});
    input(cloudkeys::wind, {.optional = true});
    input(cloudkeys::cirrusWind, {.optional = true});
    input(cloudkeys::flowFile);
    input(cloudkeys::flowScale);
    input(keys::timeJdUtc, {.optional = true});
    output(cloudkeys::weatherMap);
    output(cloudkeys::weatherOffset);
    output(cloudkeys::cirrusOffset);
}

std::shared_ptr<WeatherMap> WeatherMap::obtain(SkyVars& vars) {
    static const Key<std::shared_ptr<WeatherMap>> kShared{"generators.weather_map"};
    return vars.obtain<WeatherMap>(kShared, [] { return std::make_shared<WeatherMap>(); });
}

void WeatherMap::doDeclare(SkyVars& vars) {
    vars.declare(cloudkeys::cloudCount, kDefaultCloudCount);
    vars.declare(cloudkeys::cloudSizeMin, kDefaultCloudSizeMinM);
    vars.declare(cloudkeys::cloudSizeMax, kDefaultCloudSizeMaxM);
    vars.declare(cloudkeys::flowFile, std::string());
    vars.declare(cloudkeys::flowScale, 10.0);
}

void WeatherMap::doRelease() {
    tex_ = {};
    fbo_ = {};
    prog_ = {};
    resolve_ = {};
    ssbo_ = {};
    vao_ = {};
    dirty_ = true;
    artistPath_.clear();
}

size_t WeatherMap::add(const CloudShape& shape) {
    checkShape(shape);
    shapes_.push_back(shape);
    dirty_ = true;
    invalidate();
    return shapes_.size() - 1;
}
void WeatherMap::move(size_t i, glm::dvec2 delta) {
    if (i >= shapes_.size()) throw Error("WeatherMap::move(): cloud " + std::to_string(i) + " not in [0, " + std::to_string(shapes_.size()) + ")");
    shapes_[i].centre += delta;
    dirty_ = true;
    invalidate();
}
void WeatherMap::grow(size_t i, double factor) {
    if (i >= shapes_.size()) throw Error("WeatherMap::grow(): cloud " + std::to_string(i) + " not in [0, " + std::to_string(shapes_.size()) + ")");
    checkOpenRange("WeatherMap::grow()", "factor", factor, 0.0, kInfinity);
    shapes_[i].semiAxes *= factor;
    dirty_ = true;
    invalidate();
}
void WeatherMap::dissolve(size_t i, double amount) {
    if (i >= shapes_.size())
        throw Error("WeatherMap::dissolve(): cloud " + std::to_string(i) + " not in [0, " + std::to_string(shapes_.size()) + ")");
    checkRange("WeatherMap::dissolve()", "amount", amount, 0.0, kInfinity);
    shapes_[i].density = std::max(shapes_[i].density - amount, 0.0);
    shapes_[i].rain = std::max(shapes_[i].rain - amount, 0.0);
    dirty_ = true;
    invalidate();
}
void WeatherMap::setClouds(std::vector<CloudShape> shapes) {
    for (const CloudShape& s : shapes) checkShape(s);
    shapes_ = std::move(shapes);
    generated_ = true;  // the caller's list replaces the generated one
    dirty_ = true;
    invalidate();
}
void WeatherMap::setFlow(Flow flow) {
    flow_ = std::move(flow);
    userFlow_ = bool(flow_);
    invalidate();
}

void WeatherMap::loadArtist(const std::string& path) {
    Image im;
    try {
        im = readImage(path);
    } catch (const std::exception& e) {
        throw Error(cloudkeys::weatherFile.name() + ": cannot read '" + path + "': " + e.what());
    }
    const std::vector<float> px = cpu::weatherMapTexels(im, path);
    tex_ = gl::Texture2D(im.width, im.height, GL_RGBA16F);
    tex_.setFilter(GL_LINEAR);
    tex_.setWrap(GL_REPEAT);
    tex_.upload(GL_RGBA, GL_FLOAT, px.data());
    fbo_ = {};
}

void WeatherMap::advect(double t0, double t1, double extent) {
    if (!flow_ || t1 == t0 || shapes_.empty()) return;
    // RK4 in sub-steps of at most 30 s (a 1e-3 rad/s rotation turns 0.03 rad a step: RK4's
    // local error ~ (0.03)^5 / 120 of the radius, far below a texel), at most 4000 per run.
    const int n = int(std::clamp(std::ceil(std::abs(t1 - t0) / 30.0), 1.0, 4000.0));
    const double h = (t1 - t0) / n;
    for (CloudShape& s : shapes_) {
        glm::dvec2 p = s.centre;
        for (int k = 0; k < n; ++k) {
            const double t = t0 + k * h;
            const glm::dvec2 k1 = flow_(p, t), k2 = flow_(p + 0.5 * h * k1, t + 0.5 * h), k3 = flow_(p + 0.5 * h * k2, t + 0.5 * h),
                             k4 = flow_(p + h * k3, t + h);
            p += h / 6.0 * (k1 + 2.0 * k2 + 2.0 * k3 + k4);
        }
        s.centre = p;
    }
    (void)extent;
    dirty_ = true;
}

void WeatherMap::render(double extent) {
    if (!tex_ || tex_.width() != size_ || !fbo_) {
        tex_ = gl::Texture2D(size_, size_, GL_RGBA16F);
        tex_.setFilter(GL_LINEAR);
        tex_.setWrap(GL_REPEAT);
        fbo_ = gl::Framebuffer::create();
        fbo_.attach(GL_COLOR_ATTACHMENT0, tex_);
        fbo_.checkComplete("WeatherMap");
    }
    if (!prog_) {
        const auto noise = embedded::clouds_shaders("cloud_noise.glsl");
        prog_ = gl::ProgramBuilder("WeatherMap")
                    .vertex("generators/weather_map.vert.glsl", embedded::clouds_shaders("weather_map.vert.glsl"))
                    .fragment("generators/cloud_noise.glsl", noise)
                    .fragment("generators/weather_map.frag.glsl", embedded::clouds_shaders("weather_map.frag.glsl"))
                    .build();
    }
    std::vector<GpuShape> gs;
    for (const CloudShape& s : shapes_) {
        if (s.density <= 0.0 && s.rain <= 0.0) continue;
        const glm::dvec2 off = edgeOffset(s.seed);
        gs.push_back({{float(wrapMod(s.centre.x, extent)), float(wrapMod(s.centre.y, extent)), float(s.semiAxes.x), float(s.semiAxes.y)},
                      {float(std::remainder(s.rotation, 2.0 * kPi)), float(s.density), float(1.0 - s.baseFraction), float(s.topFraction)},
                      {float(s.rain), float(off.x), float(off.y), 0.0f},
                      {s.seed, 0u, 0u, 0u}});
    }
    fbo_.bind();
    glViewport(0, 0, size_, size_);
    const float zero[4] = {0, 0, 0, 0};
    glClearBufferfv(GL_COLOR, 0, zero);
    if (!gs.empty()) {
        const size_t bytes = gs.size() * sizeof(GpuShape);
        if (!ssbo_ || ssbo_.size() < bytes) ssbo_ = gl::Buffer(bytes);
        ssbo_.update(gs.data(), bytes);
        ssbo_.bindBase(GL_SHADER_STORAGE_BUFFER, gl::binding::kWeatherShapesSsbo);
        GLboolean blend = glIsEnabled(GL_BLEND);
        GLint eqRgb = 0, eqA = 0;
        glGetIntegerv(GL_BLEND_EQUATION_RGB, &eqRgb);
        glGetIntegerv(GL_BLEND_EQUATION_ALPHA, &eqA);
        glEnable(GL_BLEND);
        glBlendEquation(GL_MAX);
        GLint vaoBefore = 0;
        glGetIntegerv(GL_VERTEX_ARRAY_BINDING, &vaoBefore);
        if (!vao_) vao_ = gl::VertexArray::create();
        vao_.bind();
        prog_.use();
        prog_.set("u_extent", float(extent));
        glDrawArraysInstanced(GL_TRIANGLES, 0, 6, GLsizei(gs.size() * 9));
        glBindVertexArray(GLuint(vaoBefore));
        glBlendEquationSeparate(GLenum(eqRgb), GLenum(eqA));
        if (!blend) glDisable(GL_BLEND);
    }
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    if (!resolve_)
        resolve_ = gl::ProgramBuilder("WeatherMapResolve")
                       .compute("generators/cloud_noise.glsl", embedded::clouds_shaders("cloud_noise.glsl"))
                       .compute("generators/weather_resolve.glsl", embedded::clouds_shaders("weather_resolve.glsl"))
                       .build();
    resolve_.use();
    resolve_.set("u_size", size_);
    glMemoryBarrier(GL_FRAMEBUFFER_BARRIER_BIT);
    glBindImageTexture(gl::binding::kLutImage, tex_.id(), 0, GL_FALSE, 0, GL_READ_WRITE, GL_RGBA16F);
    glDispatchCompute(GLuint((size_ + 7) / 8), GLuint((size_ + 7) / 8), 1);
    glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_SHADER_IMAGE_ACCESS_BARRIER_BIT | GL_TEXTURE_UPDATE_BARRIER_BIT);
    glBindImageTexture(gl::binding::kLutImage, 0, 0, GL_FALSE, 0, GL_READ_WRITE, GL_RGBA16F);
    glUseProgram(0);
    dirty_ = false;
}

void WeatherMap::doRun(SkyVars& vars, const Logger&) {
    const double extent = vars.getOr(cloudkeys::weatherExtent, kDefaultWeatherExtentM);
    const std::string artist = vars.getOr(cloudkeys::weatherFile, std::string());
    // Time: seconds since the first run.
    const glm::dvec2 jd = vars.getOr(keys::timeJdUtc, glm::dvec2(0.0));
    if (!started_) {
        started_ = true;
        jd0_ = jd;
        offset0_ = vars.getOr(cloudkeys::weatherOffset, glm::dvec2(0.0));
        cirrusOffset0_ = vars.getOr(cloudkeys::cirrusOffset, offset0_);
        lastT_ = 0.0;
    }
    const double t = ((jd.x - jd0_.x) + (jd.y - jd0_.y)) * 86400.0;
    elapsed_ = t;
    const glm::dvec2 wind = vars.getOr(cloudkeys::wind, glm::dvec2(0.0));
    // set(), not publish(): readers of the offset run again only when it moved.
    vars.set(cloudkeys::weatherOffset, offset0_ - wind * t);
    vars.set(cloudkeys::cirrusOffset, cirrusOffset0_ - vars.getOr(cloudkeys::cirrusWind, wind) * t);

    if (!artist.empty()) {
        if (artist != artistPath_ || !tex_) {
            loadArtist(artist);
            artistPath_ = artist;
            vars.publish(cloudkeys::weatherMap, tex_.ref());
        }
        lastT_ = t;
        return;
    }
    if (!artistPath_.empty()) {  // back from an artist's map to the generated one
        artistPath_.clear();
        tex_ = {};
        dirty_ = true;
    }
    // The shapes from the seed (again when the generation's keys change).
    const int seed = vars.getOr(cloudkeys::seed, 1), count = vars.get(cloudkeys::cloudCount);
    const double smin = vars.get(cloudkeys::cloudSizeMin), smax = vars.get(cloudkeys::cloudSizeMax);
    if (smax < smin)
        throw Error(cloudkeys::cloudSizeMax.name() + " " + std::to_string(smax) + " must be >= " + cloudkeys::cloudSizeMin.name() + " (" +
                    std::to_string(smin) + ")");
    if (!generated_ || seed != genSeed_ || count != genCount_ || smin != genMin_ || smax != genMax_ || extent != genExtent_) {
        // First run: the generated clouds follow any added before it (their indices stay);
        // a later change of the keys regenerates all; setClouds() before the first run wins.
        if (!generated_) {
            auto gen = cpu::generateClouds(uint32_t(seed), count, smin, smax, extent);
            shapes_.insert(shapes_.end(), gen.begin(), gen.end());
        } else if (genSeed_ >= 0) {
            shapes_ = cpu::generateClouds(uint32_t(seed), count, smin, smax, extent);
        }
        dirty_ = true;
        generated_ = true;
        genSeed_ = seed, genCount_ = count, genMin_ = smin, genMax_ = smax, genExtent_ = extent;
    }
    // The flow field from its image (unless one was set from C++).
    const std::string flowPath = vars.get(cloudkeys::flowFile);
    if (!userFlow_ && flowPath != flowPath_) {
        flowPath_ = flowPath;
        if (flowPath.empty()) {
            flow_ = {};
        } else {
            Image im;
            try {
                im = readImage(flowPath);
            } catch (const std::exception& e) {
                throw Error(cloudkeys::flowFile.name() + ": cannot read '" + flowPath + "': " + e.what());
            }
            cpu::checkFlowImage(im, flowPath);
            auto img = std::make_shared<Image>(std::move(im));
            const double scale = vars.get(cloudkeys::flowScale);
            flow_ = [img, scale, extent](glm::dvec2 p, double) { return cpu::flowAt(*img, scale, p, extent); };
        }
    }
    advect(lastT_, t, extent);
    lastT_ = t;
    // Republished only when drawn: the map's readers (shadow map...) do not re-run every frame
    // the clock advances.
    if (dirty_ || !tex_) {
        render(extent);
        vars.publish(cloudkeys::weatherMap, tex_.ref());
    }
}

namespace cpu {

std::vector<CloudShape> generateClouds(uint32_t seed, int count, double sizeMin, double sizeMax, double extent) {
    std::vector<CloudShape> out;
    out.reserve(size_t(std::max(count, 0)));
    for (int k = 0; k < count; ++k) {
        // Nine hashed uniforms per cloud (the integer hash, not <random>: identical everywhere).
        double u[9];
        const uint32_t base = noiseHash(seed * 0x9e3779b9u + uint32_t(k));
        for (int i = 0; i < 9; ++i) u[i] = unit(noiseHash(base + uint32_t(i) * 0x85ebca6bu));
        CloudShape s;
        s.centre = {u[0] * extent, u[1] * extent};
        // Sizes skewed to the small end (u^2): many small cumulus, few large ones.
        const double major = sizeMin + (sizeMax - sizeMin) * u[2] * u[2];
        s.semiAxes = {major, std::max(major * (0.5 + 0.5 * u[3]), sizeMin)};
        s.rotation = u[4] * kPi;
        s.density = 0.6 + 0.4 * u[5];
        s.baseFraction = 0.15 * u[6];
        s.topFraction = 0.4 + 0.6 * u[7];  // towers of 40-100 % of the layer
        s.rain = u[8] > 0.8 ? (u[8] - 0.8) / 0.2 : 0.0;  // one in five rains
        s.seed = noiseHash(base ^ 0xc2b2ae35u);
        out.push_back(s);
    }
    return out;
}

glm::dvec4 shapeTexel(const CloudShape& s, glm::dvec2 m, glm::dvec2 centre) {
    const double c = std::cos(s.rotation), sn = std::sin(s.rotation);
    const glm::dvec2 d = m - centre;
    const glm::dvec2 local = glm::dvec2(c * d.x + sn * d.y, -sn * d.x + c * d.y) / s.semiAxes;
    if (std::abs(local.x) > 1.6 || std::abs(local.y) > 1.6) return glm::dvec4(0.0);  // outside the quad
    const double fade = glsl::dp::weather_shared::cld_weatherFade(local, edgeOffset(s.seed), s.seed);  // the pass's text
    if (fade < 1e-3) return glm::dvec4(0.0);
    // Thinning towards the rim (weather_map.frag.glsl).
    return {s.density * fade, (1.0 - s.baseFraction) * fade, s.topFraction * fade, s.rain * fade};
}

glm::dvec4 weatherTexel(const std::vector<CloudShape>& shapes, int i, int j, int size, double extent) {
    const glm::dvec2 m = (glm::dvec2(i, j) + 0.5) / double(size) * extent;
    glm::dvec4 w(0.0);
    for (const CloudShape& s : shapes) {
        if (s.density <= 0.0 && s.rain <= 0.0) continue;
        const glm::dvec2 c(wrapMod(s.centre.x, extent), wrapMod(s.centre.y, extent));
        for (int o = 0; o < 9; ++o) w = glm::max(w, shapeTexel(s, m, c + glm::dvec2(o % 3 - 1, o / 3 - 1) * extent));
    }
    return glsl::dp::weather_shared::cld_weatherResolve(w);  // the resolve pass's text
}

// flowAt(), weatherMapTexels(), checkFlowImage(): weather_image.cpp (CPU only).

}  // namespace cpu
}  // namespace welkin::generators
