#include <welkin/astro/astro_keys.hpp>
#include <welkin/elements/sky.hpp>
#include <welkin/embedded/atmosphere_shaders.hpp>
#include <welkin/embedded/sky_shaders.hpp>
#include <welkin/error.hpp>
#include <welkin/generators/atmosphere.hpp>
#include <welkin/gl/shader.hpp>
#include <welkin/keys.hpp>

#include <epoxy/gl.h>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <optional>

namespace welkin::elements {

using namespace welkin::generators;

namespace {
constexpr double kPi = std::numbers::pi;
constexpr double kMoonAngularRadius = 0.0045;  // rad, mean (the Moon's share of the sky view)
// Above this solar altitude the Moon's sky term is left out (README "The Moon's sky by day").
constexpr double kMoonSkySunAltitudeRad = 6.0 * kPi / 180.0;
}  // namespace

void SkyOptions::validate() const {
    if (quality < -1 || quality > 3) {
        char buf[96];
        std::snprintf(buf, sizeof buf, "Sky: quality %d not in [-1, 3] (-1 follows render.quality)", quality);
        throw Error(buf);
    }
    validateWavelengthCount(wavelengths, "Sky: wavelengths");
}

Sky::Sky() : Sky(SkyOptions{}, false) {}

Sky::Sky(const SkyOptions& options) : Sky(options, true) {}

Sky::Sky(const SkyOptions& options, bool force) : SkyElement("sky"), options_(options) {
    options_.validate();
    option(skykeys::quality, options_.quality, force);
    option(skykeys::moonLight, options_.moon, force);
    option(skykeys::wavelengths, options_.wavelengths, force);
    option(skykeys::aerialVolume, options_.aerialPerspective, force);
    // Time running (skyelements/sky/README.md): the keyframe tables' budget and disk cache, options here so that
    // `--var` sets them before the first frame (the generators declare them too, alike).
    option(skykeys::keyframeBudget, kKeyframeBudgetDefault);
    option(skykeys::keyframeCache, true);
    option(skyNightMultiply, true);
    option(skyPrebuildPrograms, true);
    option(skyMoonByDay, false);
    setAttenuatesBehind(true);  // its transmittance output: stars and planets drawn before it
    reads(keys::sunDirection);
    reads(keys::moonDirection);
    reads(keys::observerHeight);
    reads(keys::quality);
    reads(atmosphere::kAtmosphere);
    reads(lightkeys::sunIlluminance);
    reads(lightkeys::moonIlluminance);
    reads(skykeys::shadowLossLut);  // optional: a direct-light shadow (the clouds')
    reads(skykeys::shadowLossMieLut);
    reads(skykeys::shadowLossMoon);
    reads(skykeys::eclipseViewLut);  // optional: a solar eclipse's sky (EclipseSkyLut)
    reads(skykeys::eclipseViewMieLut);
    reads(skykeys::eclipseViewTotalLut);
}

namespace {
// The element's options as they stand in `v` (checked: a host may have set any value in range).
SkyOptions optionsFrom(const SkyVars& v) {
    SkyOptions o;
    o.quality = skykeys::quality.value(v);
    o.moon = v.get(skykeys::moonLight);
    o.wavelengths = v.get(skykeys::wavelengths);
    o.aerialPerspective = v.get(skykeys::aerialVolume);
    validateWavelengthCount(o.wavelengths, "sky.wavelengths");
    return o;
}
}  // namespace

void Sky::doValidateOptions(const SkyVars& vars) const { optionsFrom(vars); }

void Sky::doInit(InitContext& ctx) {
    SkyVars& v = ctx.vars;
    declareOptions(v);
    options_ = optionsFrom(v);
    auto lights = generators::AtmosphereLights::obtain(v);
    luts_ = SkyLuts::obtain(v);
    addGenerator(lights);
    addGenerator(luts_.lightZenith);
    addGenerator(luts_.transmittance);
    addGenerator(luts_.multiScattering);
    addGenerator(luts_.sh);
    addGenerator(luts_.sunView);
    addGenerator(luts_.moonView);
    addGenerator(luts_.irradiance);
    addGenerator(luts_.aerial);
    addGenerator(luts_.eclipse);
    // Every variant compiles on first use (which ones a frame needs depends on the projection,
    // the composition, the Moon and the quality, none known yet); shader errors surface from the
    // first render(), naming the file and line.
    for (int moon = 0; moon < 2; ++moon)
        for (int t = 0; t < 2; ++t)
            for (int baked = 0; baked < 2; ++baked)
                for (int sh = 0; sh < 2; ++sh)
                    lutPrograms_[moon][t][baked][sh] = gl::ProjectionPrograms(recipe(false, moon == 1, t == 1, baked == 1, false, 0, sh == 1));
    for (int moon = 0; moon < 2; ++moon)
        for (int t = 0; t < 2; ++t)
            for (int baked = 0; baked < 2; ++baked)
                eclipsePrograms_[moon][t][baked] = gl::ProjectionPrograms(recipe(false, moon == 1, t == 1, baked == 1, false, 0, false, true));
    for (int moon = 0; moon < 2; ++moon)
        for (int t = 0; t < 2; ++t)
            for (int baked = 0; baked < 2; ++baked)
                nightPrograms_[moon][t][baked] = gl::ProjectionPrograms(recipe(false, moon == 1, t == 1, baked == 1, false, 0, false, false, true));
    for (int baked = 0; baked < 2; ++baked)
        nightMultiplyPrograms_[baked] = gl::ProjectionPrograms(recipe(false, false, true, baked == 1, false, 0, false, false, true, true));
    marchBands_ = 0;
    ubo_ = gl::Buffer(sizeof(AtmosphereBlock));
}

gl::ProgramBuilder Sky::recipe(bool perPixel, bool moon, bool transmittance, bool baked, bool spectral, int shBands, bool shadow,
                               bool eclipse, bool noSun, bool multiply) {
    gl::ProgramBuilder b(std::string(perPixel ? "Sky (per pixel)" : "Sky") + (moon ? " + Moon" : "") +
                         (transmittance ? "" : " (nothing behind)") + (baked ? " (baked phase)" : "") + (spectral ? " spectral" : "") +
                         (shadow ? " (shadowed)" : "") + (eclipse ? " (eclipse)" : "") + (noSun ? " (night)" : "") + (multiply ? " (multiply)" : ""));
    if (noSun) b.define("SKY_NO_SUN");
    if (multiply) b.define("SKY_MULTIPLY");
    if (eclipse) b.define(perPixel ? "ATM_ECLIPSE" : "SKY_ECLIPSE");
    b.define("ATM_USE_TRANSMITTANCE");
    if (moon) b.define("SKY_MOON");
    if (transmittance) b.define("SKY_TRANSMITTANCE");
    if (baked) b.define("SKY_BAKED_PHASE");
    if (perPixel)
        b.define("ATM_USE_MULTISCATTERING").define("ATM_MS_DIRECTIONAL").define("ATM_SH_BANDS", shBands).define("SKY_PER_PIXEL");
    if (spectral) b.define("SKY_SPECTRAL");
    if (shadow) b.define("SKY_SHADOW_LOSS");
    b.fullscreenVertex()
        .fragment("engine/camera.glsl", gl::engineShader("camera.glsl"))
        .fragment("engine/composite.glsl", gl::engineShader("composite.glsl"))
        .fragment("generators/atmosphere.glsl", embedded::atmosphere_shaders("atmosphere.glsl"))
        .fragment("sky/sky.frag.glsl", embedded::sky_shaders("sky.frag.glsl"));
    return b;
}

const gl::Program& Sky::program(gl::ProjectionPrograms& pp, Projection proj) {
    if (!pp.built(proj)) ++programBuilds_;
    return pp.get(proj);
}

void Sky::doUpdate(const FrameContext& ctx) {
    SkyVars& v = ctx.vars;
    options_ = optionsFrom(v);
    glm::dvec3 hv = v.getOr(skykeys::horizontalIlluminance, glm::dvec3(0.0));
    global_ = hv.x;
    direct_ = hv.y;
    diffuse_ = hv.z;
    zenith_ = v.getOr(skykeys::zenithLuminance, 0.0);
}

void Sky::doRender(const FrameContext& ctx) {
    SkyVars& v = ctx.vars;
    // The eclipse table's bands are sized to the frame (thinner on small frames: a band costs
    // at most about half a frame; EclipseSkyLut::setFramePixels); from the next rebuild on.
    if (luts_.eclipse) luts_.eclipse->setFramePixels(long(ctx.camera.width) * long(ctx.camera.height));
    const SkyModel& m = luts_.sunView->model();
    const SkyQuality& q = luts_.sunView->quality();
    const double h = std::max(v.getOr(keys::observerHeight, 0.0), 0.0);
    // Above the top of the atmosphere (less 1 m) the sky-view parameterisation does not apply.
    perPixel_ = q.perPixel || h > m.topRadius - m.bottomRadius - 1.0;
    if (perPixel_ && marchBands_ != q.shBands) {
        marchBands_ = q.shBands;
        for (int moon = 0; moon < 2; ++moon) {
            for (int sh = 0; sh < 2; ++sh)
                marchPrograms_[moon][sh] = gl::ProjectionPrograms(recipe(true, moon == 1, true, false, false, marchBands_, sh == 1));
            spectralPrograms_[moon] = gl::ProjectionPrograms(recipe(true, moon == 1, true, false, true, marchBands_, false));
            marchEclipsePrograms_[moon] = gl::ProjectionPrograms(recipe(true, moon == 1, true, false, false, marchBands_, false, true));
        }
    }
    AtmosphereBlock block = AtmosphereBlock::from(m, q.shBands);
    ubo_.update(&block, sizeof block);
    ubo_.bindBase(GL_UNIFORM_BUFFER, gl::binding::kAtmosphereUbo);
    // With the phase baked in, units 0 and 2 get the total LUTs and 1, 3 are not read.
    glBindTextureUnit(gl::binding::kSunViewLut, v.get(q.bakedMiePhase ? skykeys::sunViewTotalLut : skykeys::sunViewLut).id);
    glBindTextureUnit(gl::binding::kSunViewMieLut, v.get(skykeys::sunViewMieLut).id);
    glBindTextureUnit(gl::binding::kMoonViewLut, v.get(q.bakedMiePhase ? skykeys::moonViewTotalLut : skykeys::moonViewLut).id);
    glBindTextureUnit(gl::binding::kMoonViewMieLut, v.get(skykeys::moonViewMieLut).id);
    glBindTextureUnit(gl::binding::kViewTransmittanceLut, v.get(skykeys::viewTransmittanceLut).id);
    glBindTextureUnit(gl::binding::kTransmittanceLut, v.get(skykeys::transmittanceLut).id);
    glBindTextureUnit(gl::binding::kMultiScatteringLut, v.get(skykeys::multiScatteringLut).id);
    glBindTextureUnit(gl::binding::kShLut, v.get(skykeys::shLut).id);
    auto unit = [](glm::dvec3 d) { return glm::length(d) > 0 ? glm::normalize(d) : glm::dvec3(0, 0, -1); };
    const glm::dvec3 moonE = options_.moon ? v.getOr(lightkeys::moonIlluminance, glm::dvec3(0.0)) : glm::dvec3(0.0);
    // The Moon's term only while it gives light and is above -20 deg (its LUT is black below), and
    // not while the Sun is up (above kMoonSkySunAltitudeRad): its sky is then below 1e-4 of the
    // Sun's in every direction (measured, README "The Moon's sky by day"; test "Sky: by day the
    // Moon's term is skipped").
    moonDaySkipped_ = glm::length(moonE) > 0.0 && !v.getOr(skyMoonByDay, false) && unit(v.get(keys::sunDirection)).z > std::sin(kMoonSkySunAltitudeRad);
    const bool moon = glm::length(moonE) > 0.0 && unit(v.get(keys::moonDirection)).z > -0.342 && !moonDaySkipped_;
    const glm::dvec3 sunE = v.getOr(lightkeys::sunIlluminance, m.solarIlluminance);
    const Projection proj = ctx.camera.projection;
    auto setUniforms = [&](const gl::Program& p, const glm::dvec3& eSun, const glm::dvec3& eMoon) {
        p.use();
        p.set("u_h", float(h));
        p.set("u_sunDir", glm::vec3(unit(v.get(keys::sunDirection))));
        p.set("u_moonDir", glm::vec3(unit(v.get(keys::moonDirection))));
        p.set("u_sunE", glm::vec3(eSun));
        p.set("u_moonE", glm::vec3(eMoon));
        p.set("u_invScale", float(1.0 / kLutScale));
        p.set("u_steps", q.raymarchSteps);
        p.set("u_moonAngular", float(kMoonAngularRadius));
        p.set("u_sH", float(skyViewHorizonS(m, std::min(h, m.topRadius - m.bottomRadius))));
        p.set("u_lutSize", glm::vec2(float(q.skyViewW), float(q.skyViewH)));
    };
    const auto& sp = luts_.sunView->spectral();
    // The direct light's shadow (sky.shadow_loss_lut, published by e.g. the clouds'
    // CloudSkyShadow): only while the table exists, the observer is inside the atmosphere (the
    // table is for the observer's position), except in the spectral per-pixel march (one draw per
    // wavelength triple; the table is RGB: not shadowed, skyelements/clouds/README.md).
    const bool shadow = (!perPixel_ || !sp) && h <= m.topRadius - m.bottomRadius - 1.0 && v.has(skykeys::shadowLossLut) &&
                        v.get(skykeys::shadowLossLut).id != 0 && v.has(skykeys::shadowLossMieLut) &&
                        v.get(skykeys::shadowLossLut).height == q.skyViewH;  // it reuses the sky view's v (a quality change: next run)
    shadowed_ = shadow;
    // A solar eclipse (sky.eclipse_view_lut, EclipseSkyLut): the Sun's sky from the eclipse's
    // table over absolute azimuth, or the per-pixel march seeing the Moon's shadow. The clouds'
    // shadow table is not applied then (it is the uneclipsed sky's loss).
    const bool eclipse = !sp && h <= m.topRadius - m.bottomRadius - 1.0 && v.has(skykeys::eclipseViewLut) &&
                         v.get(skykeys::eclipseViewLut).id != 0 && v.get(skykeys::eclipseViewLut).height == q.skyViewH;
    const bool eclipseMarch = perPixel_ && !sp && luts_.eclipse && luts_.eclipse->active() && v.has(astro::keys::moonPosition);
    eclipse_ = eclipse;
    // Night: below kSkySunNightAltitudeRad (-21 deg) the Sun's sky-view LUT is 0 everywhere
    // (measured, skyelements/sky/README.md): the LUT path skips its term (the Moon's stays).
    sunTerm_ = perPixel_ || eclipse || shadow || unit(v.get(keys::sunDirection)).z > std::sin(kSkySunNightAltitudeRad);
    // Night without the Moon over something: no radiance, the pass only multiplies by T.
    nightMultiply_ = !perPixel_ && !sunTerm_ && !moon && !ctx.nothingBehind && v.getOr(skyNightMultiply, true);
    if (!perPixel_ && v.getOr(skyPrebuildPrograms, true)) {
        // The variants this composition can switch to while only the lights move (the Moon on
        // and off, night, night multiply, an eclipse), built and drawn once now, in its first
        // frame: llvmpipe links a program at glLinkProgram and JITs its fragment code at the
        // first draw with the frame's state (blend, target), which would otherwise fall into
        // the frame after a time jump (README "No program builds after the first frame"). The
        // draws are scissored to no pixel: they write nothing.
        const int t = ctx.nothingBehind ? 0 : 1, bk = q.bakedMiePhase ? 1 : 0, sh = shadow ? 1 : 0;
        if (warmed_.insert(((int(proj) * 2 + t) * 2 + bk) * 2 + sh).second) {
            const GLboolean blend = glIsEnabled(GL_BLEND), scissor = glIsEnabled(GL_SCISSOR_TEST);
            GLint f[4] = {}, box[4] = {};
            glGetIntegerv(GL_BLEND_SRC_RGB, &f[0]);
            glGetIntegerv(GL_BLEND_DST_RGB, &f[1]);
            glGetIntegerv(GL_BLEND_SRC_ALPHA, &f[2]);
            glGetIntegerv(GL_BLEND_DST_ALPHA, &f[3]);
            glGetIntegerv(GL_SCISSOR_BOX, box);
            glEnable(GL_SCISSOR_TEST);
            glScissor(0, 0, 0, 0);
            auto warm = [&](gl::ProjectionPrograms& pp, bool multiply) {
                setUniforms(program(pp, proj), sunE, moonE);
                if (t == 0) glDisable(GL_BLEND);
                if (multiply) glBlendFuncSeparate(GL_ZERO, GL_SRC_COLOR, GL_ZERO, GL_ONE);
                ctx.drawFullscreen();
                if (blend) glEnable(GL_BLEND);
                glBlendFuncSeparate(GLenum(f[0]), GLenum(f[1]), GLenum(f[2]), GLenum(f[3]));
            };
            for (int mo = 0; mo < 2; ++mo) {
                warm(lutPrograms_[mo][t][bk][sh], false);
                warm(nightPrograms_[mo][t][bk], false);
                if (luts_.eclipse) warm(eclipsePrograms_[mo][t][bk], false);
            }
            if (t == 1 && v.getOr(skyNightMultiply, true)) warm(nightMultiplyPrograms_[bk], true);
            if (!scissor) glDisable(GL_SCISSOR_TEST);
            glScissor(box[0], box[1], box[2], box[3]);
        }
    }
    if (!perPixel_ || !sp) {
        const gl::Program& p = perPixel_ ? (eclipseMarch ? program(marchEclipsePrograms_[moon], proj) : program(marchPrograms_[moon][shadow], proj))
                               : eclipse ? program(eclipsePrograms_[moon][ctx.nothingBehind ? 0 : 1][q.bakedMiePhase], proj)
                               : nightMultiply_ ? program(nightMultiplyPrograms_[q.bakedMiePhase], proj)
                               : !sunTerm_ ? program(nightPrograms_[moon][ctx.nothingBehind ? 0 : 1][q.bakedMiePhase], proj)
                                         : program(lutPrograms_[moon][ctx.nothingBehind ? 0 : 1][q.bakedMiePhase][shadow], proj);
        setUniforms(p, sunE, moonE);
        // One draw over the processor's black target (nothing drawn before it: by day, or a scene
        // of the Sky alone): the blend dst = L + dst T gives L exactly (and the alpha 1 of the
        // clear), so the pass writes without reading the target (~0.8 of a trivial pass on
        // llvmpipe; README "Cost"). The processor restores its blend state for the next element.
        if (ctx.nothingBehind) glDisable(GL_BLEND);
        // dst = 0 src + T dst (the general blend's dst = L + T dst with L = 0: the same values,
        // without the second source; README "The Sky's pass at twilight and at night").
        if (nightMultiply_) glBlendFuncSeparate(GL_ZERO, GL_SRC_COLOR, GL_ZERO, GL_ONE);
        if (eclipse && !perPixel_) {
            // With the phase baked in, one fetch of the total table (as the ordinary sky view).
            glBindTextureUnit(gl::binding::kSunViewLut, v.get(q.bakedMiePhase ? skykeys::eclipseViewTotalLut : skykeys::eclipseViewLut).id);
            glBindTextureUnit(gl::binding::kSunViewMieLut, v.get(skykeys::eclipseViewMieLut).id);
            ctx.drawFullscreen();
            return;
        }
        if (eclipseMarch) {
            const glm::dvec3 sd = unit(v.get(keys::sunDirection));
            p.set("u_eclMoonPos", glm::vec3(v.get(astro::keys::moonPosition)));
            p.set("u_eclMoonRadius", float(astro::keys::kMoonRadiusMeters));
            p.set("u_eclSunPos", glm::vec3(sd * v.getOr(astro::keys::sunDistance, 1.496e11)));
            p.set("u_eclSunRadius", float(kSunRadiusMeters));
            luts_.eclipse->bindMsField(p);
            ctx.drawFullscreen();
            return;
        }
        if (shadow) {
            const TextureRef loss = v.get(skykeys::shadowLossLut);
            const bool lossMoon = v.getOr(skykeys::shadowLossMoon, false);
            glBindTextureUnit(gl::binding::kShadowLossLut, loss.id);
            glBindTextureUnit(gl::binding::kShadowLossMieLut, v.get(skykeys::shadowLossMieLut).id);
            p.set("u_lossLight", glm::vec3(unit(v.get(lossMoon ? keys::moonDirection : keys::sunDirection))));
            p.set("u_lossE", glm::vec3((lossMoon ? moonE : sunE) / kLutScale));
        }
        ctx.drawFullscreen();
        return;
    }
    // Spectral mode, per pixel (reference quality, space): the compositor blends
    // dst = L + T dst, so a first draw outputs only the transmittance (L = 0) and then one draw
    // per wavelength triple adds that triple's radiance (converted by its matrix) with T = 1.
    // Inside the atmosphere the transmittance is the combined (solar-weighted) LUT's, as on the
    // LUT path; above it, a ray march with the RGB coefficients (Atmosphere::rgb()). With nothing
    // behind the sky (black), the first draw would multiply black: skipped.
    if (!ctx.nothingBehind) {
        if (h <= m.topRadius - m.bottomRadius - 1.0) {
            setUniforms(program(lutPrograms_[0][1][q.bakedMiePhase][0], proj), glm::dvec3(0.0), glm::dvec3(0.0));
        } else {
            setUniforms(program(marchPrograms_[0][0], proj), glm::dvec3(0.0), glm::dvec3(0.0));
        }
        ctx.drawFullscreen();
    }
    const gl::Program& ps = program(spectralPrograms_[moon], proj);
    const skykeys::TextureList T = v.get(skykeys::transmittanceLuts), MS = v.get(skykeys::multiScatteringLuts),
                               SH = v.get(skykeys::shLuts);
    for (int k = 0; k < sp->triples(); ++k) {
        AtmosphereBlock bk = AtmosphereBlock::from(sp->models[size_t(k)], q.shBands);
        ubo_.update(&bk, sizeof bk);
        ubo_.bindBase(GL_UNIFORM_BUFFER, gl::binding::kAtmosphereUbo);
        glBindTextureUnit(gl::binding::kTransmittanceLut, T->at(size_t(k)).id);
        glBindTextureUnit(gl::binding::kMultiScatteringLut, MS->at(size_t(k)).id);
        glBindTextureUnit(gl::binding::kShLut, SH->at(size_t(k)).id);
        setUniforms(ps, sunE, moonE);
        ps.set("u_toRgb", glm::mat3(sp->toRgb[size_t(k)]));
        ctx.drawFullscreen();
    }
}

void Sky::doApplyToScene(const FrameContext& ctx, ScenePass pass) {
    if (pass != ScenePass::Air) return;
    if (ctx.camera.projection != Projection::Perspective) return;  // a host's depth belongs to a pinhole view
    GLint fb = 0;
    glGetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &fb);  // the host's, bound by the processor
    aerial_.apply(ctx.vars, ctx.camera, *ctx.depth, GLuint(fb));
}

void Sky::doRelease() {
    aerial_.release();
    for (auto& row : lutPrograms_)
        for (auto& col : row)
            for (auto& baked : col)
                for (auto& p : baked) p.releasePrograms();
    for (auto& row : marchPrograms_)
        for (auto& p : row) p.releasePrograms();
    for (auto& p : spectralPrograms_) p.releasePrograms();
    for (auto& row : eclipsePrograms_)
        for (auto& col : row)
            for (auto& p : col) p.releasePrograms();
    for (auto& p : marchEclipsePrograms_) p.releasePrograms();
    for (auto& row : nightPrograms_)
        for (auto& col : row)
            for (auto& p : col) p.releasePrograms();
    for (auto& p : nightMultiplyPrograms_) p.releasePrograms();
    warmed_.clear();
    ubo_ = {};
    luts_.releaseGl();
}

void Sky::doStats(nlohmann::json& root) const {
    root["sky"]["zenith_luminance_cd_m2"] = zenith_;
    root["sky"]["horizontal_illuminance_lux"] = global_;
    root["sky"]["sun_illuminance_lux"] = direct_;
    root["sky"]["diffuse_illuminance_lux"] = diffuse_;
    root["sky"]["per_pixel"] = perPixel_;
    root["sky"]["shadowed"] = shadowed_;
    root["sky"]["eclipse"] = eclipse_;
    root["sky"]["sun_term"] = sunTerm_;  // false: the Sun below kSkySunNightAltitudeRad, its term skipped
    root["sky"]["moon_term_skipped_by_day"] = moonDaySkipped_;
    root["sky"]["program_builds"] = programBuilds_;  // programs compiled and linked so far (programBuilds())
    root["sky"]["night_multiply"] = nightMultiply_;  // the pass only multiplied by T (sky.night_multiply)
}

}  // namespace welkin::elements

WELKIN_ELEMENT_DESCRIPTOR(sky) {
    static const welkin::ElementDescriptor d{
        "sky", "the atmosphere: Rayleigh, Mie and ozone scattering of the Sun's and Moon's light, every projection",
        welkin::Layer::Atmosphere, true, [] { return std::make_unique<welkin::elements::Sky>(); }};
    return d;
}
