#include <welkin/elements/rainbow.hpp>
#include <welkin/embedded/optics_shaders.hpp>
#include <welkin/embedded/rainbow_shaders.hpp>
#include <welkin/error.hpp>
#include <welkin/generators/cloud_keys.hpp>
#include <welkin/generators/cloud_shadow.hpp>
#include <welkin/generators/lights.hpp>
#include <welkin/generators/sky_luts.hpp>
#include <welkin/generators/weather_map.hpp>
#include <welkin/gl/bindings.hpp>
#include <welkin/gl/shader.hpp>
#include <welkin/keys.hpp>

#include <epoxy/gl.h>

#include <cmath>

namespace welkin::elements {

using generators::cloudkeys::weatherMap;
namespace rk = generators::rainkeys;
namespace lk = generators::lightkeys;
namespace ck = generators::cloudkeys;

Rainbow::Rainbow() : SkyElement("rainbow") {
    option(rk::rate, 0.0);
    option(rk::dropRadius, 0.5e-3);
    option(rk::dropVariance, 0.02);
    option(rk::distribution, std::string("gamma"));
    option(rk::tableQuality, std::string("default"));
    option(rainbowkeys::distance, 2000.0);
    option(rainbowkeys::depth, 1000.0);
    option(rainbowkeys::height, 1500.0);
    option(rainbowkeys::halfWidth, 90.0 * rainbowkeys::kDeg);
    optionUnset(rainbowkeys::directionCache);  // unset: follows render.interactive
    option(rainbowkeys::cacheSlices, rainbowkeys::kCacheSlicesDefault);
    reads(keys::interactive);
    reads(keys::sunDirection);
    reads(keys::moonDirection);
    reads(keys::observerHeight);
    reads(lk::sunIlluminance);
    reads(lk::sunTransmittance);
    reads(lk::moonIlluminance);
    reads(lk::moonTransmittance);
    reads(rk::phaseLut);
    reads(rk::scattering);
    reads(rk::extinction);
    reads(generators::skykeys::diffuseIrradiance);
    reads(ck::cloudType);
    reads(ck::coverage);        // CloudShadowMap::nothingToShadow(): no lookup without clouds
    reads(ck::cirrusCoverage);
}

bool Rainbow::bowPossible(double lightElevation, double observerHeightM, double curtainDistanceM) {
    const double lowest = -std::atan2(std::max(observerHeightM, 0.0), std::max(curtainDistanceM, 0.0));
    return 54.0 * rainbowkeys::kDeg - lightElevation >= lowest;
}

void Rainbow::doValidateOptions(const SkyVars& vars) const {
    // Before any GL work: the string keys' values (one-line errors naming the key).
    (void)generators::dropDistributionFromVars(vars);
    const std::string q = vars.get(rk::tableQuality);
    if (q != "low" && q != "default" && q != "high")
        throw Error("rain.table_quality: '" + q + "' is not one of low, default, high");
}

void Rainbow::doInit(InitContext& ctx) {
    declareOptions(ctx.vars);
    addGenerator(generators::AtmosphereLights::obtain(ctx.vars));
    mie_ = std::make_shared<generators::MiePhaseGenerator>();
    addGenerator(mie_);
    // The clouds' shadow on the light reaching the rain (clouds.shadow_map): shared with the host
    // and any element; every cloud input of it is optional, and without a weather map it is a
    // map of 1 built once per 0.03 deg of the light's motion (a trivial pass).
    addGenerator(generators::CloudShadowMap::obtain(ctx.vars));
    auto recipe = [](bool clouds) {
        gl::ProgramBuilder b("Rainbow");
        b.fullscreenVertex();
        if (clouds) b.define("WELKIN_RAINBOW_CLOUDS");
        b.fragment("engine/camera.glsl", gl::engineShader("camera.glsl"))
            .fragment("engine/composite.glsl", gl::engineShader("composite.glsl"))
            .fragment("generators/clouds/cloud_shadow.glsl", std::string(generators::CloudShadowMap::hostGlsl()))
            .fragment("optics/mie_angle.glsl", embedded::optics_shaders("mie_angle.glsl"))
            .fragment("rainbow/rainbow_curtain.glsl", embedded::rainbow_shaders("rainbow_curtain.glsl"))
            .fragment("rainbow/rainbow.frag.glsl", embedded::rainbow_shaders("rainbow.frag.glsl"));
        return b;
    };
    programs_ = gl::ProjectionPrograms(recipe(false));
    cloudPrograms_ = gl::ProjectionPrograms(recipe(true));
    // The real-time path: the cache's fill (compute) and the clipped polar mesh that shows it.
    cacheFill_ = gl::ProgramBuilder("Rainbow cache")
                     .compute("generators/clouds/cloud_shadow.glsl", std::string(generators::CloudShadowMap::hostGlsl()))
                     .compute("optics/mie_angle.glsl", embedded::optics_shaders("mie_angle.glsl"))
                     .compute("rainbow/rainbow_curtain.glsl", embedded::rainbow_shaders("rainbow_curtain.glsl"))
                     .compute("rainbow/rainbow_polar.glsl", embedded::rainbow_shaders("rainbow_polar.glsl"))
                     .compute("rainbow/rainbow_cache.comp.glsl", embedded::rainbow_shaders("rainbow_cache.comp.glsl"))
                     .build();
    cacheUnit_ = textureUnit("RAINBOW_CACHE");  // the cache as the mesh samples it: a unit of its own
    meshPrograms_ = gl::ProjectionPrograms(gl::ProgramBuilder("Rainbow grid")
                                               .bindings(bindings())
                                               .vertex("engine/camera.glsl", gl::engineShader("camera.glsl"))
                                               .vertex("rainbow/rainbow_polar.glsl", embedded::rainbow_shaders("rainbow_polar.glsl"))
                                               .vertex("rainbow/rainbow_grid.vert.glsl", embedded::rainbow_shaders("rainbow_grid.vert.glsl"))
                                               .fragment("engine/composite.glsl", gl::engineShader("composite.glsl"))
                                               .fragment("rainbow/rainbow_polar.glsl", embedded::rainbow_shaders("rainbow_polar.glsl"))
                                               .fragment("rainbow/rainbow_grid.frag.glsl", embedded::rainbow_shaders("rainbow_grid.frag.glsl")));
    meshPrograms_.get(Projection::Perspective);
    cache_ = {};  // 8 MB: made on the real-time path's first frame, not for an offline render
    cacheInputs_.clear();
    programs_.get(Projection::Perspective);  // shader errors surface in init()
}

namespace {

double luminance(const glm::dvec3& c) { return 0.2126 * c.r + 0.7152 * c.g + 0.0722 * c.b; }

// The elevations (sines and cosines) between which a view ray meets the curtain: some horizontal
// distance rho in [d, d + depth] has a height h0 + rho tan(e) in [0, H], i.e. tan(e) in
// [-h0 / rho, (H - h0) / rho] for some rho; the union over rho is one interval (continuous in rho).
struct ElevationRange {
    double lo, hi;  // rad
};
ElevationRange curtainElevations(double h0, double dist, double depth, double H) {
    const double r0 = std::max(dist, 1e-3), r1 = dist + depth;
    const double a = -h0, b = H - h0;
    return {std::atan(std::min(a / r0, a / r1)), std::atan(std::max(b / r0, b / r1))};
}

}  // namespace

void Rainbow::doRender(const FrameContext& ctx) {
    drew_ = false;
    cached_ = false;
    rowsLast_ = 0;
    const SkyVars& v = ctx.vars;
    // The light: the Sun, or the Moon when the Sun gives no light at the observer (moonbows).
    glm::dvec3 E = v.get(lk::sunIlluminance) * v.get(lk::sunTransmittance);
    glm::dvec3 L = v.get(keys::sunDirection);
    if (E == glm::dvec3(0.0) || L.z < 0.0) {
        E = v.has(lk::moonIlluminance) ? v.get(lk::moonIlluminance) * v.get(lk::moonTransmittance) : glm::dvec3(0.0);
        L = v.get(keys::moonDirection);
    }
    if (E == glm::dvec3(0.0) || L.z < 0.0) return;  // no light
    L = glm::normalize(L);
    const double h0 = v.has(keys::observerHeight) ? v.get(keys::observerHeight) : 0.0;
    const double dist = v.get(rainbowkeys::distance);
    if (!bowPossible(std::asin(std::clamp(L.z, -1.0, 1.0)), h0, dist)) return;
    const double rate = v.get(rk::rate);
    const bool clouds = v.has(weatherMap) && v.has(ck::rainDensity) && v.get(ck::rainDensity) > 0.0 &&
                        v.get(weatherMap).id != 0;
    if (rate <= 0.0 && !clouds) return;  // no rain: nothing drawn, nothing bound

    // The curtain's uniforms (rainbow_curtain.glsl), on the per-pixel program or the cache's fill.
    const glm::dvec3 skyE = v.has(generators::skykeys::diffuseIrradiance) ? v.get(generators::skykeys::diffuseIrradiance) : glm::dvec3(0.0);
    // Nothing to shadow (no cloud coverage): the map is 1 everywhere, exactly, so the lookup (a fetch
    // per texel of the cache's fill, per pixel of the per-pixel pass) and its rebuilds (a refill
    // whenever the light moved 0.03 deg) are skipped; the pixels are the same.
    const bool shadow = v.has(generators::cloudkeys::shadowMap) && v.get(generators::cloudkeys::shadowMap).id != 0 &&
                        !generators::CloudShadowMap::nothingToShadow(v);
    glm::dvec2 axis(-L.x, -L.y);
    axis = glm::length(axis) > 1e-9 ? glm::normalize(axis) : glm::dvec2(0.0, 1.0);
    const glm::dvec3 ext = v.get(rk::extinction);
    // Grey extinction (rainbow_curtain.glsl): the luminance-weighted mean of the channels.
    const double extGrey = luminance(ext);
    auto setCurtainWith = [&](const gl::Program& p, const glm::dvec3& Lc, const glm::dvec3& Ec, const glm::dvec3& skyEc) {
        glm::dvec2 ax(-Lc.x, -Lc.y);
        ax = glm::length(ax) > 1e-9 ? glm::normalize(ax) : glm::dvec2(0.0, 1.0);
        glBindTextureUnit(gl::binding::kMiePhaseLut, v.get(rk::phaseLut).id);
        p.set("u_light", glm::vec3(Lc));
        p.set("u_E", glm::vec3(Ec));
        p.set("u_sca", glm::vec3(v.get(rk::scattering)));
        p.set("u_ext", float(extGrey));
        p.set("u_dist", float(dist));
        p.set("u_depth", float(v.get(rainbowkeys::depth)));
        p.set("u_height", float(v.get(rainbowkeys::height)));
        p.set("u_axis", glm::vec2(ax));
        p.set("u_cosHalfWidth", float(std::cos(v.get(rainbowkeys::halfWidth))));
        p.set("u_obsHeight", float(h0));
        // The Sky's diffuse illuminance when a Sky runs (optional: 0 otherwise).
        p.set("u_skyE", glm::vec3(skyEc));
        // The clouds' shadow, once its map exists (before, and without clouds: no shadow).
        p.set("u_shadow", shadow ? 1 : 0);
        if (shadow) generators::CloudShadowMap::bindForHost(v, p.id());
    };
    auto setCurtain = [&](const gl::Program& p) { setCurtainWith(p, L, E, skyE); };

    // The real-time path: the curtain alone (the clouds' rain is marched per pixel), perspective
    // projection (the grid's interpolation and clip distances rely on rays affine in the pixel).
    const bool realtime = v.has(rainbowkeys::directionCache) ? v.get(rainbowkeys::directionCache) : v.getOr(keys::interactive, false);
    if (realtime && ctx.camera.projection == Projection::Perspective && !clouds) {
        // Refill when an input changed: the rain and curtain exactly, the light by
        // kLightTolerance, its illuminance or the sky's by 2 % (within that, u_scale follows the
        // light's luminance), the clouds' shadow map when it was rebuilt.
        const ElevationRange el = curtainElevations(h0, dist, v.get(rainbowkeys::depth), v.get(rainbowkeys::height));
        std::vector<double> in = {double(v.get(rk::phaseLut).id), double(v.version(rk::phaseLut)),
                                  v.get(rk::scattering).r, v.get(rk::scattering).g, v.get(rk::scattering).b, extGrey, dist,
                                  v.get(rainbowkeys::depth), v.get(rainbowkeys::height), v.get(rainbowkeys::halfWidth), h0,
                                  shadow ? 1.0 : 0.0};
        const double eY = luminance(E), skyY = luminance(skyE);
        const uint64_t shadowVersion = shadow ? v.version(generators::cloudkeys::shadowMap) : 0;
        rowsLast_ = 0;
        auto polar = [](const glm::dvec3& Lx, glm::dvec3& A, glm::dvec3& e1, glm::dvec3& e2) {
            A = -Lx;
            e1 = glm::normalize(std::abs(A.z) < 0.999 ? glm::cross(glm::dvec3(0, 0, 1), A) : glm::dvec3(1, 0, 0));
            e2 = glm::cross(A, e1);
        };
        // The polar frame around the anti-light point (the display's: always the current light).
        glm::dvec3 A, e1, e2;
        polar(L, A, e1, e2);
        auto makeCache = [](gl::Texture2D& t) {
            t = gl::Texture2D(kCacheU, kCachePsi, GL_RGBA32F);
            t.setFilter(GL_LINEAR);
            t.setWrap(GL_REPEAT);  // psi goes round; x is clamped below
            glTextureParameteri(t.id(), GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
        };
        // Both textures at the first real-time frame (8 MB each): the first refill spread over
        // frames, when time starts, then allocates nothing.
        if (!cache_) makeCache(cache_);
        if (!back_) makeCache(back_);
        // Rows [y0, y1) of `target` for the light Lx (its illuminance Ex, the sky's skyEx).
        auto fillRows = [&](const gl::Texture2D& target, int y0, int y1, const glm::dvec3& Lx, const glm::dvec3& Ex, const glm::dvec3& skyEx) {
            glm::dvec3 fA, f1, f2;
            polar(Lx, fA, f1, f2);
            cacheFill_.use();
            setCurtainWith(cacheFill_, Lx, Ex, skyEx);
            cacheFill_.set("u_polarA", glm::vec3(fA));
            cacheFill_.set("u_polarE1", glm::vec3(f1));
            cacheFill_.set("u_polarE2", glm::vec3(f2));
            cacheFill_.set("u_cacheSize", glm::ivec2(kCacheU, kCachePsi));
            cacheFill_.set("u_rowOffset", y0);
            // Inset by 1e-4 rad so that the clamped directions lie strictly inside the curtain.
            cacheFill_.set("u_sinElLo", float(std::sin(std::min(el.lo + 1e-4, 0.5 * (el.lo + el.hi)))));
            cacheFill_.set("u_sinElHi", float(std::sin(std::max(el.hi - 1e-4, 0.5 * (el.lo + el.hi)))));
            cacheFill_.set("u_halfWidth", float(std::max(v.get(rainbowkeys::halfWidth) - 1e-4, 0.0)));
            glBindImageTexture(gl::binding::kLutImage, target.id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA32F);
            glDispatchCompute(GLuint((kCacheU + 63) / 64), GLuint(y1 - y0), 1);  // workgroups of 64 x 1 texels
            glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT);
            rowsLast_ += y1 - y0;
        };
        // What is stale: anything but the light (and the illuminances) exactly, or a first frame:
        // the whole cache now. The light moving past kLightTolerance, its or the sky's illuminance
        // by 2 %, the clouds' shadow map rebuilt (time running): a refill over rain.cache_slices
        // frames into back_, the cache drawn meanwhile. A jump of the light (a new time) restarts
        // a refill under way with the new light, spread the same way (the whole fill in the
        // jump's frame made it ~19x a still frame): the bows stay placed around the current
        // anti-light point, and the cache from before the jump is drawn until the new one is complete.
        const int slices = std::clamp(v.getOr(rainbowkeys::cacheSlices, rainbowkeys::kCacheSlicesDefault), 1, rainbowkeys::kCacheSlicesMax);
        const bool jump = glm::dot(L, lastLight_) < std::cos(kLightJump);  // since the last frame (the cache may lag more)
        lastLight_ = L;
        const bool whole = in != cacheInputs_;
        if (jump && !whole && slices > 1) backRow_ = -1;  // superseded: restarted below with this light
        const bool moved = jump || glm::dot(L, cacheLight_) < std::cos(kLightTolerance) || std::abs(eY - cacheE_) > 0.02 * cacheE_ ||
                           std::abs(skyY - cacheSkyE_) > 0.02 * std::max(cacheSkyE_, 1e-9) || shadowVersion != cacheShadowVersion_;
        if (whole || (moved && slices == 1 && backRow_ < 0)) {  // always on the first frame: cacheInputs_ starts empty
            backRow_ = -1;  // a refill in progress is superseded
            fillRows(cache_, 0, kCachePsi, L, E, skyE);
            cacheInputs_ = in;
            cacheLight_ = L;
            cacheE_ = eY;
            cacheSkyE_ = skyY;
            cacheShadowVersion_ = shadowVersion;
            ++cacheFills_;
        } else {
            if (moved && backRow_ < 0) {  // a refill starts, with this frame's light
                backRow_ = 0;
                backLight_ = L;
                backE_ = eY;
                backSkyE_ = skyY;
                backShadowVersion_ = shadowVersion;
                ++cacheFills_;
                // The light's colour and the sky's of the refill's start (one light for every band).
                backEColour_ = E;
                backSkyColour_ = skyE;
            }
            if (backRow_ >= 0) {
                const int rows = rowsPerSlice(slices);
                const int y1 = std::min(backRow_ + rows, kCachePsi);
                fillRows(back_, backRow_, y1, backLight_, backEColour_, backSkyColour_);
                backRow_ = y1;
                if (backRow_ >= kCachePsi) {  // complete: drawn from this frame on
                    std::swap(cache_, back_);
                    backRow_ = -1;
                    cacheLight_ = backLight_;
                    cacheE_ = backE_;
                    cacheSkyE_ = backSkyE_;
                    cacheShadowVersion_ = backShadowVersion_;
                }
            }
        }
        const gl::Program& m = meshPrograms_.get(ctx.camera.projection);
        m.use();
        m.set("u_polarA", glm::vec3(A));
        m.set("u_polarE1", glm::vec3(e1));
        m.set("u_polarE2", glm::vec3(e2));
        const int gx = (ctx.camera.width + kGridCellPx - 1) / kGridCellPx, gy = (ctx.camera.height + kGridCellPx - 1) / kGridCellPx;
        m.set("u_grid", glm::ivec2(gx, gy));
        m.set("u_cellPx", float(kGridCellPx));
        m.set("u_axis", glm::vec2(axis));
        m.set("u_cosHalfWidth", float(std::cos(v.get(rainbowkeys::halfWidth))));
        // The cones clip widened by 0.5 deg (rainbow_grid.vert.glsl), the fragments exactly.
        const double wlo = std::max(el.lo - 0.5 * rainbowkeys::kDeg, -0.5 * M_PI), whi = std::min(el.hi + 0.5 * rainbowkeys::kDeg, 0.5 * M_PI);
        m.set("u_elLoClip", glm::vec2(std::cos(wlo), std::sin(wlo)));
        m.set("u_elHiClip", glm::vec2(std::cos(whi), std::sin(whi)));
        m.set("u_sinEl", glm::vec2(std::sin(el.lo), std::sin(el.hi)));
        m.set("u_scale", float(cacheE_ > 0.0 ? eY / cacheE_ : 1.0));
        glBindTextureUnit(GLuint(cacheUnit_), cache_.id());
        for (int c = 0; c < 3; ++c) glEnable(GL_CLIP_DISTANCE0 + c);
        if (ctx.emptyVao) ctx.emptyVao->bind();
        glDrawArrays(GL_TRIANGLES, 0, GLsizei(6 * gx * gy));
        for (int c = 0; c < 3; ++c) glDisable(GL_CLIP_DISTANCE0 + c);
        drew_ = true;
        cached_ = true;
        return;
    }

    const gl::Program& p = (clouds ? cloudPrograms_ : programs_).get(ctx.camera.projection);
    p.use();
    setCurtain(p);
    if (clouds) {
        const TextureRef w = v.get(weatherMap);
        glBindTextureUnit(gl::binding::kCloudWeatherMap, w.id);
        // The weather map's extent and offset are optional keys (a host or the wind sets them):
        // unset, they take the clouds generators' defaults. v.get() threw "key
        // 'clouds.weather_extent_m' is not set" from every frame that drew rain under the clouds
        // with the defaults (found by the extreme grid, tests/apps/test_extreme_grid.cpp).
        p.set("u_weatherExtent", float(v.getOr(ck::weatherExtent, generators::kDefaultWeatherExtentM)));
        p.set("u_weatherOffset", glm::vec2(v.getOr(ck::weatherOffset, glm::dvec2(0.0))));
        p.set("u_cloudBottom", float(v.get(ck::bottom)));
        p.set("u_cloudTop", float(v.get(ck::top)));
        p.set("u_cloudType", float(v.getOr(ck::cloudType, 0.0)));
        p.set("u_rainRateScale", float(v.get(ck::rainDensity) * generators::kRainRateAtFullDensityMmH));
        p.set("u_scaPerWater", glm::vec3(mie_->scatteringPerWater()));
        p.set("u_extPerWater", glm::vec3(mie_->extinctionPerWater()));
        p.set("u_marchMax", 20000.0f);
    }
    ctx.drawFullscreen();
    drew_ = true;
}

void Rainbow::doRelease() {
    programs_.releasePrograms();
    cloudPrograms_.releasePrograms();
    meshPrograms_.releasePrograms();
    cacheFill_ = {};
    cache_ = {};
    cacheInputs_.clear();
    mie_.reset();
}

}  // namespace welkin::elements

WELKIN_ELEMENT_DESCRIPTOR(rainbow) {
    static const welkin::ElementDescriptor d{"rainbow", "rainbows, fogbows and the glory from exact Mie tables where rain is (skyelements/rainbow/README.md)",
                                             welkin::Layer::Foreground, false,
                                             [] { return std::make_unique<welkin::elements::Rainbow>(); }};
    return d;
}
