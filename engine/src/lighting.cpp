// SkyLighting (welkin/lighting.hpp) and its machinery (lighting_engine.hpp), with the
// SkyProcessor members that drive it (setLighting(), lighting(), the environment's compositing).
#include "lighting_engine.hpp"

#include <welkin/check.hpp>
#include <welkin/color.hpp>
#include <welkin/error.hpp>
#include <welkin/gl/bindings.hpp>
#include <welkin/gl/shader.hpp>
#include <welkin/keys.hpp>
#include <welkin/lighting.hpp>
#include <welkin/processor.hpp>

#include <epoxy/gl.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>

namespace welkin {

namespace {
double msSince(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}
bool isPowerOfTwo(int n) { return n > 0 && (n & (n - 1)) == 0; }
int log2i(int n) {
    int k = 0;
    while ((1 << (k + 1)) <= n) ++k;
    return k;
}
// Where the storage buffer holds what: 6 faces x 27 SH partial sums, then 6 axis lights x RGB.
constexpr int kShFloats = 6 * 27, kAxisOffset = kShFloats, kSsboFloats = kShFloats + 18;
constexpr int kLightMapSize = 16;
}  // namespace

// --- SH ---------------------------------------------------------------------------------------
namespace sh {
std::array<double, 9> basis(const glm::dvec3& n) {
    return {0.282094791773878, 0.488602511902920 * n.y, 0.488602511902920 * n.z, 0.488602511902920 * n.x,
            1.092548430592079 * n.x * n.y, 1.092548430592079 * n.y * n.z, 0.315391565252520 * (3 * n.z * n.z - 1),
            1.092548430592079 * n.x * n.z, 0.546274215296040 * (n.x * n.x - n.y * n.y)};
}
double convolution(int i) { return i == 0 ? kA0 : i < 4 ? kA1 : kA2; }
}  // namespace sh

std::array<glm::dvec3, 9> SkyLighting::sh9Irradiance() const {
    std::array<glm::dvec3, 9> e{};
    for (int i = 0; i < 9; ++i) e[size_t(i)] = sh::convolution(i) * sh9Radiance[size_t(i)];
    return e;
}

glm::dvec3 SkyLighting::irradiance(const glm::dvec3& n) const {
    const std::array<double, 9> y = sh::basis(n);
    glm::dvec3 e(0.0);
    for (int i = 0; i < 9; ++i) e += sh::convolution(i) * sh9Radiance[size_t(i)] * y[size_t(i)];
    return glm::max(e, glm::dvec3(0.0));  // nine coefficients can ring below zero; irradiance cannot
}

void LightingOptions::validate(const char* where) const {
    checkRange(where, "cubeSize", cubeSize, 8, 1024);
    if (!isPowerOfTwo(cubeSize)) throw Error(std::string(where) + ": cubeSize " + std::to_string(cubeSize) + " is not a power of two");
    checkRange(where, "specularMips", specularMips, 1, log2i(cubeSize) + 1);
    checkRange(where, "slicesPerFrame", slicesPerFrame, 1, 64);
}

// --- GLSL for hosts ---------------------------------------------------------------------------
std::vector<std::pair<std::string, std::string>> lightingGlslChunks() {
    return {{"welkin/lighting.glsl", std::string(gl::engineShader("lighting_host.glsl"))}};
}

void bindLighting(unsigned program, const SkyLighting& l, int textureUnit, const glm::dmat3& enuFromWorld) {
    checkRange("welkin::bindLighting()", "textureUnit", textureUnit, 0, 79);
    if (!glIsProgram(program)) throw Error("welkin::bindLighting(): " + std::to_string(program) + " is not a program");
    const std::array<glm::dvec3, 9> e = l.sh9Irradiance();
    float v[27];
    for (int i = 0; i < 9; ++i)
        for (int c = 0; c < 3; ++c) v[3 * i + c] = float(e[size_t(i)][c]);
    glProgramUniform3fv(program, glGetUniformLocation(program, "welkin_sh9"), 9, v);
    glProgramUniform1i(program, glGetUniformLocation(program, "welkin_specularCube"), textureUnit);
    glProgramUniform1f(program, glGetUniformLocation(program, "welkin_specularMips"), float(std::max(l.specularMips, 1)));
    const glm::mat3 m(enuFromWorld);
    glProgramUniformMatrix3fv(program, glGetUniformLocation(program, "welkin_enuFromWorld"), 1, GL_FALSE, &m[0][0]);
    glBindTextureUnit(GLuint(textureUnit), l.specularCube.id);
}

// --- The engine -------------------------------------------------------------------------------
LightingEngine::~LightingEngine() {
    if (fence_) glDeleteSync(static_cast<GLsync>(fence_));
}

void LightingEngine::declareKeys(SkyVars& vars) {
    const LightingOptions d;
    vars.declare(keys::lightingEnabled, false);
    vars.declare(keys::lightingCubeSize, d.cubeSize);
    vars.declare(keys::lightingSpecularMips, d.specularMips);
    vars.declare(keys::lightingSlicesPerFrame, d.slicesPerFrame);
    // The outputs: no value until the first frame with lighting on.
    vars.declareUnset(keys::lightingSunIlluminance);
    vars.declareUnset(keys::lightingMoonIlluminance);
    vars.declareUnset(keys::lightingIrradianceUp);
    vars.declareUnset(keys::lightingSpecularCube);
    vars.declareUnset(keys::lightingSkyLightMap);
}

void LightingEngine::release() {
    if (fence_) glDeleteSync(static_cast<GLsync>(fence_));
    fence_ = nullptr;
    work_ = {};
    specular_ = {};
    face_ = {};
    lightMap_ = {};
    faceFbo_ = {};
    cubeFbo_ = {};
    ssbo_ = {};
    faceUbo_ = {};
    texels_ = {};
    shProgram_ = {};
    mapProgram_ = {};
    prefilterProgram_ = {};
    size_ = mips_ = 0;
    nextSlice_ = -1;
    captured_ = false;
    out_.specularCube = {};
    out_.skyLightMap = {};
}

void LightingEngine::ensureResources(const LightingOptions& o) {
    if (size_ == o.cubeSize && mips_ == o.specularMips && work_) return;
    release();
    size_ = o.cubeSize;
    mips_ = o.specularMips;
    work_ = gl::TextureCube(size_, GL_RGBA32F, log2i(size_) + 1);
    work_.setFilter(GL_LINEAR_MIPMAP_LINEAR, GL_LINEAR);
    work_.setWrap(GL_CLAMP_TO_EDGE);
    specular_ = gl::TextureCube(size_, GL_RGBA32F, mips_);
    specular_.setFilter(GL_LINEAR_MIPMAP_LINEAR, GL_LINEAR);
    specular_.setWrap(GL_CLAMP_TO_EDGE);
    face_ = gl::Texture2D(size_, size_, GL_RGBA32F);
    face_.setFilter(GL_NEAREST);
    lightMap_ = gl::Texture2D(kLightMapSize, kLightMapSize, GL_RGBA32F);
    lightMap_.setFilter(GL_LINEAR);
    lightMap_.setWrap(GL_CLAMP_TO_EDGE);
    // Black until the first capture writes them.
    const float black[4] = {0, 0, 0, 0};
    for (int m = 0; m < mips_; ++m) glClearTexImage(specular_.id(), m, GL_RGBA, GL_FLOAT, black);
    glClearTexImage(lightMap_.id(), 0, GL_RGBA, GL_FLOAT, black);
    faceFbo_ = gl::Framebuffer::create();
    faceFbo_.attach(GL_COLOR_ATTACHMENT0, face_);
    faceFbo_.checkComplete("SkyLighting capture");
    cubeFbo_ = gl::Framebuffer::create();
    ssbo_ = gl::Buffer(sizeof(float) * kSsboFloats);
    // The prefilter's source texels, for every level it reads: direction (ENU) and exact solid
    // angle, in double precision, stored as float.
    {
        std::vector<float> table;
        texelOffsets_.assign(size_t(log2i(size_) + 1), -1);
        for (int mip = 1; mip < mips_; ++mip) {
            const int level = sourceLevel(mip);
            if (texelOffsets_[size_t(level)] >= 0) continue;
            texelOffsets_[size_t(level)] = int(table.size() / 4);
            const int n = size_ >> level;
            auto corner = [](double x, double y) { return std::atan2(x * y, std::sqrt(x * x + y * y + 1)); };
            for (int face = 0; face < 6; ++face)
                for (int j = 0; j < n; ++j)
                    for (int i = 0; i < n; ++i) {
                        Camera c;
                        c.projection = Projection::CubeFace;
                        c.cubeFace = face;
                        c.width = c.height = n;
                        const glm::dvec3 d = *c.directionAt({i + 0.5, j + 0.5});
                        const double x0 = 2.0 * i / n - 1, x1 = 2.0 * (i + 1) / n - 1, y0 = 2.0 * j / n - 1, y1 = 2.0 * (j + 1) / n - 1;
                        const double omega = corner(x0, y0) - corner(x0, y1) - corner(x1, y0) + corner(x1, y1);
                        table.insert(table.end(), {float(d.x), float(d.y), float(d.z), float(omega)});
                    }
        }
        if (table.empty()) table.assign(4, 0.0f);
        texels_ = gl::Buffer(table.size() * sizeof(float), table.data());
    }
    faceUbo_ = gl::Buffer(sizeof(CameraBlock));
    auto build = [](const char* label, const char* file) {
        return gl::ProgramBuilder(label)
            .compute("engine/lighting_common.glsl", gl::engineShader("lighting_common.glsl"))
            .compute(std::string("engine/") + file, gl::engineShader(file))
            .build();
    };
    shProgram_ = build("SkyLighting (SH)", "lighting_sh9.comp.glsl");
    mapProgram_ = build("SkyLighting (light map)", "lighting_map.comp.glsl");
    prefilterProgram_ = build("SkyLighting (prefilter)", "lighting_prefilter.comp.glsl");
    out_.specularCube = specular_.ref();
    out_.specularMips = mips_;
    out_.skyLightMap = lightMap_.ref();
    bump();
}

std::vector<uint64_t> LightingEngine::snapshot(const SkyVars& vars, std::vector<std::string>& names) const {
    // Every key but SkyLighting's own outputs and options: anything an element or generator reads
    // changes one of them (a texture rewritten in place is republished with a new version).
    names.clear();
    std::vector<uint64_t> v;
    for (std::string& n : vars.names()) {
        if (n.rfind("lighting.", 0) == 0) continue;
        v.push_back(vars.version(n));
        names.push_back(std::move(n));
    }
    return v;
}

void LightingEngine::setEv100(double ev100) const {
    if (ev100 != out_.ev100) {
        out_.ev100 = ev100;
        bump();
    }
}

void LightingEngine::updateDirectionalLights(const SkyVars& vars) {
    auto light = [](glm::dvec3 dir, glm::dvec3 e) {
        DirectionalLight l;
        const double len = glm::length(dir);
        l.directionEnu = len > 0 ? dir / len : glm::dvec3(0, 0, 1);
        l.illuminanceRgb = glm::max(e, glm::dvec3(0.0));
        l.illuminanceLux = std::max(color::luminance(l.illuminanceRgb), 0.0);
        l.colorRgb = l.illuminanceLux > 0 ? l.illuminanceRgb / l.illuminanceLux : glm::dvec3(1.0);
        return l;
    };
    // The Sun: above the air x the atmosphere's transmittance x the clouds' x the part of its
    // disk the Moon leaves visible. The Moon: its illuminance already carries a lunar eclipse
    // (atmosphere.lights applies moon.eclipse_factor).
    const glm::dvec3 sunE = vars.getOr(keys::sunIlluminance, glm::dvec3(0.0)) * vars.getOr(keys::sunTransmittance, glm::dvec3(1.0)) *
                            vars.getOr(keys::sunCloudTransmittance, 1.0) * vars.getOr(keys::sunEclipseFraction, 1.0);
    const glm::dvec3 moonE = vars.getOr(keys::moonIlluminance, glm::dvec3(0.0)) * vars.getOr(keys::moonTransmittance, glm::dvec3(1.0)) *
                             vars.getOr(keys::moonCloudTransmittance, 1.0);
    const DirectionalLight sun = light(vars.getOr(keys::sunDirection, glm::dvec3(0, 0, 1)), sunE);
    const DirectionalLight moon = light(vars.getOr(keys::moonDirection, glm::dvec3(0, 0, -1)), moonE);
    auto same = [](const DirectionalLight& a, const DirectionalLight& b) {
        return a.directionEnu == b.directionEnu && a.illuminanceRgb == b.illuminanceRgb;
    };
    if (!same(sun, out_.sun) || !same(moon, out_.moon)) {
        out_.sun = sun;
        out_.moon = moon;
        bump();
    }
}

void LightingEngine::step(SkyProcessor& processor, SkyVars& vars, bool timing) {
    capture_.frameMs = sh_.frameMs = map_.frameMs = prefilterStage_.frameMs = 0;
    enabled_ = vars.getOr(keys::lightingEnabled, false);
    if (!enabled_) return;
    LightingOptions o;
    o.cubeSize = vars.get(keys::lightingCubeSize);
    o.specularMips = vars.get(keys::lightingSpecularMips);
    o.slicesPerFrame = vars.get(keys::lightingSlicesPerFrame);
    o.validate("SkyLighting (lighting.* keys)");
    ensureResources(o);
    const bool interactive = vars.getOr(keys::interactive, false);

    pollReadback(false);
    if (nextSlice_ < 0) {
        std::vector<std::string> names;
        std::vector<uint64_t> versions = snapshot(vars, names);
        if (!captured_ || versions != capturedVersions_ || names != capturedNames_) {
            nextSlice_ = 0;
            cycleVersions_ = std::move(versions);
            cycleNames_ = std::move(names);
            cycleTotalMs_ = 0;
            cycleFrameCount_ = 0;
        }
    }
    if (nextSlice_ >= 0) {
        const int budget = interactive ? o.slicesPerFrame : totalSlices();
        const auto t0 = std::chrono::steady_clock::now();
        for (int k = 0; k < budget && nextSlice_ < totalSlices(); ++k) runSlice(processor, nextSlice_++, timing);
        cycleTotalMs_ += msSince(t0);
        ++cycleFrameCount_;
        if (nextSlice_ >= totalSlices()) {
            nextSlice_ = -1;
            captured_ = true;
            capturedVersions_ = std::move(cycleVersions_);
            capturedNames_ = std::move(cycleNames_);
            ++refreshes_;
            lastRefreshTotalMs_ = cycleTotalMs_;
            lastRefreshFrames_ = cycleFrameCount_;
            vars.publish(keys::lightingSpecularCube, out_.specularCube);
            vars.publish(keys::lightingSkyLightMap, out_.skyLightMap);
            bump();
        }
        // An offline frame is complete on its own: wait for the reductions now.
        if (!interactive) pollReadback(true);
    }
    // The directional lights are read from the keys every frame (the clouds' transmittance is
    // written while they are drawn, also by the capture above).
    updateDirectionalLights(vars);
    vars.set(keys::lightingSunIlluminance, glm::min(out_.sun.illuminanceRgb, glm::dvec3(1e7)));
    vars.set(keys::lightingMoonIlluminance, glm::min(out_.moon.illuminanceRgb, glm::dvec3(1e6)));
    vars.set(keys::lightingIrradianceUp, glm::min(out_.irradiance({0, 0, 1}), glm::dvec3(1e7)));
}

void LightingEngine::runSlice(SkyProcessor& processor, int slice, bool timing) {
    if (slice == 0)
        for (Stage* st : {&capture_, &sh_, &map_, &prefilterStage_}) st->refreshMs = 0;
    if (slice == 6) {
        reduce(timing);
        return;
    }
    if (timing) glFinish();
    const auto t0 = std::chrono::steady_clock::now();
    Stage& stage = slice < 6 ? capture_ : prefilterStage_;
    if (slice < 6) captureFace(processor, slice);
    else prefilter(slice - 6);
    if (timing) glFinish();
    const double ms = msSince(t0);
    stage.frameMs += ms;
    stage.refreshMs += ms;
    ++stage.runs;
}
void LightingEngine::captureFace(SkyProcessor& processor, int face) {
    Camera cam;
    cam.projection = Projection::CubeFace;
    cam.cubeFace = face;
    cam.width = cam.height = size_;
    const CameraBlock block = makeCameraBlock(cam, processor.seconds());
    faceUbo_.update(&block, sizeof block);
    faceFbo_.bind();
    const float black[4] = {0, 0, 0, 1};
    glClearBufferfv(GL_COLOR, 0, black);
    processor.compositeEnvironment(cam, faceUbo_, faceFbo_.id());
    // The camera's CubeFace pixels run top row first (pixel row 0 at t = -1) while a framebuffer's
    // row 0 is its bottom: a flipped blit puts the face into the cube as GL samples it.
    cubeFbo_.attach(GL_COLOR_ATTACHMENT0, work_, 0, face);
    glDisable(GL_SCISSOR_TEST);
    glBlitNamedFramebuffer(faceFbo_.id(), cubeFbo_.id(), 0, 0, size_, size_, 0, size_, size_, 0, GL_COLOR_BUFFER_BIT, GL_NEAREST);
    ++facesCaptured_;
}

void LightingEngine::reduce(bool timing) {
    if (fence_) glDeleteSync(static_cast<GLsync>(fence_));
    fence_ = nullptr;
    if (timing) glFinish();
    const auto t0 = std::chrono::steady_clock::now();
    work_.generateMipmaps();
    glCopyImageSubData(work_.id(), GL_TEXTURE_CUBE_MAP, 0, 0, 0, 0, specular_.id(), GL_TEXTURE_CUBE_MAP, 0, 0, 0, 0, size_, size_, 6);
    ssbo_.bindBase(GL_SHADER_STORAGE_BUFFER, gl::binding::kLightingSsbo);
    // SH: one work group per face.
    shProgram_.use();
    shProgram_.set("u_size", size_);
    glBindImageTexture(gl::binding::kLightingSourceImage, work_.id(), 0, GL_TRUE, 0, GL_READ_ONLY, GL_RGBA32F);
    glDispatchCompute(6, 1, 1);
    if (timing) glFinish();
    const double shMs = msSince(t0);
    const auto t1 = std::chrono::steady_clock::now();
    // The light map: its texels are 22.5 x 11.25 deg, sampled 8 x 8: the cube's level whose
    // texels are ~2.8 deg (a face of 32).
    mapProgram_.use();
    mapProgram_.set("u_lod", float(std::max(0, log2i(size_) - 5)));
    mapProgram_.set("u_offset", kAxisOffset);
    glBindTextureUnit(gl::binding::kLightingCube, work_.id());
    glBindImageTexture(gl::binding::kLightingOutputImage, lightMap_.id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA32F);
    glDispatchCompute(1, 1, 1);
    glMemoryBarrier(GL_ALL_BARRIER_BITS);
    fence_ = glFenceSync(GL_SYNC_GPU_COMMANDS_COMPLETE, 0);
    if (timing) glFinish();
    const double mapMs = msSince(t1);
    ++sh_.runs;
    ++map_.runs;
    sh_.frameMs += shMs;
    sh_.refreshMs += shMs;
    map_.frameMs += mapMs;
    map_.refreshMs += mapMs;
}

int LightingEngine::sourceLevel(int mip) const {
    // Level 0 (the radiance itself) for every mip but the first, level 1 (box-filtered) for mip 1:
    // the brute-force sum costs outputs x sources, 36 (n/2)^4 for mip 1 from level 1 and the same
    // or less for mip k >= 2 from level 0, so no slice costs more than mip 1's (and mip 1's lobe,
    // alpha 1/16 at 5 mips, is about a level-1 texel). Sources are capped at 32 texels a face
    // (cubes above 32: the cost stays 6 (n/2^k)^2 x 6144 weights, the lobes of the finest mips
    // then blur to the source's texel, 2.8 deg).
    const int cap = std::max(0, log2i(size_) - 5);
    return std::max(mip == 1 ? 1 : 0, cap);
}

void LightingEngine::prefilter(int mip) {
    const int outSize = std::max(size_ >> mip, 1);
    const int level = sourceLevel(mip);
    const int sourceSize = std::max(size_ >> level, 1);
    const double roughness = mips_ > 1 ? double(mip) / (mips_ - 1) : 0.0;
    prefilterProgram_.use();
    prefilterProgram_.set("u_outSize", outSize);
    prefilterProgram_.set("u_sourceSize", sourceSize);
    prefilterProgram_.set("u_sourceOffset", texelOffsets_.at(size_t(level)));
    prefilterProgram_.set("u_alpha", float(std::max(roughness * roughness, 1e-4)));
    texels_.bindBase(GL_SHADER_STORAGE_BUFFER, gl::binding::kLightingSsbo);
    glBindImageTexture(gl::binding::kLightingSourceImage, work_.id(), level, GL_TRUE, 0, GL_READ_ONLY, GL_RGBA32F);
    glBindImageTexture(gl::binding::kLightingOutputImage, specular_.id(), mip, GL_TRUE, 0, GL_WRITE_ONLY, GL_RGBA32F);
    glDispatchCompute(GLuint((outSize + 7) / 8), GLuint((outSize + 7) / 8), 6);
    glMemoryBarrier(GL_ALL_BARRIER_BITS);
}

void LightingEngine::pollReadback(bool wait) {
    if (!fence_) return;
    const GLenum r = glClientWaitSync(static_cast<GLsync>(fence_), GL_SYNC_FLUSH_COMMANDS_BIT, wait ? GLuint64(60'000'000'000) : 0);
    if (r != GL_ALREADY_SIGNALED && r != GL_CONDITION_SATISFIED) {
        if (wait) throw Error("SkyLighting: the reductions did not finish within 60 s");
        return;
    }
    glDeleteSync(static_cast<GLsync>(fence_));
    fence_ = nullptr;
    float v[kSsboFloats];
    glGetNamedBufferSubData(ssbo_.id(), 0, sizeof v, v);
    for (int i = 0; i < 9; ++i) {
        glm::dvec3 s(0.0);
        for (int f = 0; f < 6; ++f)
            for (int c = 0; c < 3; ++c) s[c] += double(v[f * 27 + 3 * i + c]);
        out_.sh9Radiance[size_t(i)] = s;
    }
    for (int a = 0; a < 6; ++a)
        out_.axisLights[size_t(a)] = {v[kAxisOffset + 3 * a], v[kAxisOffset + 3 * a + 1], v[kAxisOffset + 3 * a + 2]};
    ++readbacks_;
    bump();
}

void LightingEngine::stats(nlohmann::json& root) const {
    using nlohmann::json;
    json j;
    j["enabled"] = enabled_;
    if (!enabled_) {
        root["lighting"] = j;
        return;
    }
    j["cube_size"] = size_;
    j["specular_mips"] = mips_;
    // This frame's cost per stage (ms; with glFinish when timing is on), and the last complete
    // refresh's (all its slices, possibly over several frames).
    j["frame_ms"] = {{"capture", capture_.frameMs},
                     {"sh", sh_.frameMs},
                     {"light_map", map_.frameMs},
                     {"prefilter", prefilterStage_.frameMs},
                     {"total", capture_.frameMs + sh_.frameMs + map_.frameMs + prefilterStage_.frameMs}};
    j["refresh_ms"] = {{"capture", capture_.refreshMs},
                       {"sh", sh_.refreshMs},
                       {"light_map", map_.refreshMs},
                       {"prefilter", prefilterStage_.refreshMs},
                       {"total", lastRefreshTotalMs_},
                       {"frames", lastRefreshFrames_}};
    j["faces_captured"] = facesCaptured_;
    j["prefilter_runs"] = prefilterStage_.runs;
    j["sh_runs"] = sh_.runs;
    j["readbacks"] = readbacks_;
    j["refreshes"] = refreshes_;
    j["refreshing"] = nextSlice_ >= 0;
    j["revision"] = out_.revision;
    j["sun_illuminance_lux"] = out_.sun.illuminanceLux;
    j["moon_illuminance_lux"] = out_.moon.illuminanceLux;
    j["irradiance_up_lux"] = color::luminance(out_.irradiance({0, 0, 1}));
    j["ev100"] = out_.ev100;
    root["lighting"] = j;
}

// --- SkyProcessor's side ----------------------------------------------------------------------
void SkyProcessor::setLighting(std::optional<LightingOptions> o) {
    if (!o) {
        vars_->set(keys::lightingEnabled, false);
        return;
    }
    o->validate("SkyProcessor::setLighting()");
    vars_->set(keys::lightingEnabled, true);
    vars_->set(keys::lightingCubeSize, o->cubeSize);
    vars_->set(keys::lightingSpecularMips, o->specularMips);
    vars_->set(keys::lightingSlicesPerFrame, o->slicesPerFrame);
}

const SkyLighting& SkyProcessor::lighting() const {
    lighting_->setEv100(lastEv100());
    return lighting_->result();
}

void SkyProcessor::declareLightingKeys() {
    lighting_ = std::make_unique<LightingEngine>();
    SkyVars::DeclarerScope scope(*vars_, "lighting");
    LightingEngine::declareKeys(*vars_);
}

void SkyProcessor::updateLighting() {
    lighting_->setEv100(lastEv100());
    lighting_->step(*this, *vars_, options_.timing);
    cameraUbo_.bindBase(GL_UNIFORM_BUFFER, gl::binding::kCameraUbo);
}

void SkyProcessor::releaseLighting() { lighting_->release(); }

void SkyProcessor::lightingStats(nlohmann::json& root) const {
    lighting_->setEv100(lastEv100());
    lighting_->stats(root);
}

void SkyProcessor::compositeEnvironment(const Camera& cam, const gl::Buffer& ubo, unsigned framebuffer) {
    // As composite(), for the elements that contribute to the lighting, into a cleared target.
    std::vector<SkyElement*> list;
    for (auto& e : elements_)
        if (e->contributesToLighting() && e->initialized()) list.push_back(e.get());
    FrameContext ctx{*vars_, log_, cam, seconds(), &emptyVao_};
    ctx.nothingBehind = true;
    for (size_t i = 0; i < list.size(); ++i) {
        ctx.attenuatedLater = false;
        for (size_t j = i + 1; j < list.size(); ++j) ctx.attenuatedLater = ctx.attenuatedLater || list[j]->attenuatesBehind();
        applyCompositeState(framebuffer, false, cam, ubo);
        list[i]->render(ctx);
        if (!list[i]->drewNothing()) ctx.nothingBehind = false;  // as composite()
    }
    glDisable(GL_BLEND);
    glDepthMask(GL_TRUE);
}

}  // namespace welkin
