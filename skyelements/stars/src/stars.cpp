// Stars element: catalogue upload, per-frame uniforms, limiting magnitude; the model is described
// in include/welkin/elements/stars.hpp and skyelements/stars/README.md.
#include <welkin/astro/astro_keys.hpp>
#include <welkin/astro/bodies.hpp>
#include <welkin/astro/frames.hpp>
#include <welkin/color.hpp>
#include <welkin/elements/stars.hpp>
#include <welkin/embedded/atmosphere_shaders.hpp>
#include <welkin/embedded/stars_shaders.hpp>
#include <welkin/error.hpp>
#include <welkin/generators/atmosphere.hpp>
#include <welkin/generators/point_sources.hpp>
#include <welkin/generators/sky_luts.hpp>
#include <welkin/generators/sky_model.hpp>
#include <welkin/gl/shader.hpp>
#include <welkin/glsl_cpp.hpp>
#include <welkin/keys.hpp>
#include <welkin/point_source.hpp>

#include <epoxy/gl.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <numbers>

namespace welkin::glsl::dp::stars_scintillation_shared {
#include "../shaders/stars_scintillation.shared.glsl"
}  // namespace welkin::glsl::dp::stars_scintillation_shared

namespace welkin::elements {

namespace {
constexpr int kTableN = 64;                      // STARS_TABLE_N: refraction and extinction samples
constexpr double kTableLo = -5.0 * std::numbers::pi / 180.0;
constexpr double kTableSpan = 95.0 * std::numbers::pi / 180.0;
double tableAltitude(int i) {
    const double u = double(i) / (kTableN - 1);
    return kTableLo + kTableSpan * u * u;
}
constexpr double kBvLo = -0.4, kBvHi = 2.0, kBvStep = 0.01;  // colour table

std::string lower(std::string s) {
    for (char& c : s) c = char(std::tolower(static_cast<unsigned char>(c)));
    return s;
}

std::vector<astro::Star> loadCatalogue(const std::string& path) {
    const std::string name = lower(path.substr(path.find_last_of('/') == std::string::npos ? 0 : path.find_last_of('/') + 1));
    if (name.size() > 4 && name.substr(name.size() - 4) == ".csv") return astro::loadHygCsv(path);
    if (name == "catalog" || name.find("bsc") != std::string::npos) return astro::loadYaleBrightStarCatalogue(path);
    return astro::loadKStarsCatalogue(path);
}
}  // namespace

double limitingMagnitude(double backgroundCdM2) {
    if (!(backgroundCdM2 >= 0.0)) throw Error("limitingMagnitude(): background luminance not >= 0 cd/m^2");
    // Schaefer 1990 (Hecht 1947), welkin/point_source.hpp: the magnitude of the threshold.
    return -16.57 - 2.5 * std::log10(pointThresholdFootCandles(backgroundCdM2));
}

double scintillationAmplitude(double altitudeRad, double strength) {
    return glsl::dp::stars_scintillation_shared::stars_scintillationAmplitude(altitudeRad, strength);  // the vertex shader's text
}

Stars::Stars() : SkyElement("stars") {
    option(starkeys::catalogue, std::string(astro::kKStarsCatalogue));
    option(starkeys::magnitudeLimit, 30.0);
    option(starkeys::adaptiveLimit, true);
    option(starkeys::backgroundFloor, astro::magnitude::surfaceBrightnessCdM2(astro::magnitude::kDarkSkyZenithMag));  // 1.7e-4: 22.0 mag/arcsec^2
    option(starkeys::psfFwhm, 1.0 * starkeys::kArcmin);
    option(starkeys::psfMinPx, 2.0);
    option(starkeys::glare, 0.05);
    option(starkeys::glareMagnitude, 1.5);
    option(starkeys::scintillation, 1.0);
    option(starkeys::seed, 1);
    option(starkeys::labels, false);
    option(starkeys::labelMagnitude, 1.5);
    option(starkeys::labelSize, 0.0);
    option(starkeys::labelLuminance, 2e-3);
    reads(astro::keys::starFrameRotation);
    reads(astro::keys::starFrameAberration);
    reads(astro::keys::starFrameEpochYears);
    reads(astro::keys::refractionPressure);
    reads(astro::keys::refractionTemperature);
    reads(keys::timeJdUtc);
    reads(generators::skykeys::zenithLuminance);
    reads(keys::nightBackground);
    reads(keys::pointSources);
    reads(keys::pointContrast);
}

Stars::Stars(std::vector<astro::Star> stars) : Stars() {
    own_ = true;
    given_ = std::move(stars);
}

void Stars::upload(std::vector<astro::Star> stars) {
    labels_.setCatalogue(stars);
    std::stable_sort(stars.begin(), stars.end(), [](const astro::Star& a, const astro::Star& b) { return a.magnitudeV < b.magnitudeV; });
    std::vector<glm::dvec3> colours;
    for (double bv = kBvLo; bv <= kBvHi + 1e-9; bv += kBvStep) colours.push_back(starColourFromBV(bv));
    std::vector<float> data;
    data.reserve(stars.size() * 12 + 12);
    mags_.clear();
    for (const astro::Star& s : stars) {
        const glm::dvec3 p = astro::starDirectionJ2000(s), pm = astro::starProperMotion(s);
        const double x = (std::clamp(double(s.colorBV), kBvLo, kBvHi) - kBvLo) / kBvStep;
        const size_t i = std::min(size_t(x), colours.size() - 2);
        const glm::dvec3 c = glm::mix(colours[i], colours[i + 1], x - double(i));
        const float rec[12] = {float(p.x), float(p.y), float(p.z), s.magnitudeV, float(pm.x), float(pm.y), float(pm.z), 0.f,
                               float(c.r), float(c.g), float(c.b), 0.f};
        data.insert(data.end(), rec, rec + 12);
        mags_.push_back(s.magnitudeV);
    }
    if (data.empty()) data.assign(12, 0.f);  // a buffer of size 0 is not allowed
    buffer_ = gl::Buffer(data.size() * sizeof(float), data.data());
}

void Stars::doInit(InitContext& ctx) {
    declareOptions(ctx.vars);
    if (own_) {
        upload(std::move(given_));
        given_.clear();
    } else {
        loadedPath_ = ctx.vars.get(starkeys::catalogue);
        upload(loadCatalogue(loadedPath_));
    }
    starsSsbo_ = storageBuffer("STARS_SSBO");  // the catalogue's binding point, of its own
    gl::ProgramBuilder builder("Stars");
    if (instanced_) builder.define("STARS_INSTANCED");
    programs_ = gl::ProjectionPrograms(builder
                                           .bindings(bindings())
                                           .define("STARS_TABLE_N", kTableN)
                                           .vertex("engine/camera.glsl", gl::engineShader("camera.glsl"))
                                           .vertex("atmosphere/point_perceptual.glsl", embedded::atmosphere_shaders("point_perceptual.glsl"))
                                           .vertex("stars/stars.vert.glsl", embedded::stars_shaders("stars.vert.glsl"))
                                           .fragment("engine/camera.glsl", gl::engineShader("camera.glsl"))
                                           .fragment("engine/composite.glsl", gl::engineShader("composite.glsl"))
                                           .fragment("stars/stars.frag.glsl", embedded::stars_shaders("stars.frag.glsl")));
    programs_.get(Projection::Perspective);  // shader errors surface in init()
}

void Stars::updateExtinction(const SkyVars& v) {
    // The atmosphere's transmittance towards each table altitude (RGB, CPU), recomputed when the
    // observer's height or the atmosphere changes.
    const void* atm = v.has(atmosphere::kAtmosphere) ? v.get(atmosphere::kAtmosphere).get() : nullptr;
    const double h = v.getOr(keys::observerHeight, 0.0);
    if (!extinction_.empty() && atm == extinctionAtm_ && h == extinctionKey_[0]) return;
    const generators::SkyModel m = generators::SkyModel::fromVars(v);
    const double hc = std::clamp(h, 0.0, m.topRadius - m.bottomRadius);
    extinction_.assign(3 * kTableN, 1.0f);
    for (int i = 0; i < kTableN; ++i) {
        const double mu = std::sin(tableAltitude(i));
        glm::dvec3 T(1.0);
        if (hc < m.topRadius - m.bottomRadius) {
            T = generators::cpu::rayIntersectsGround(m, hc, mu) ? glm::dvec3(0.0) : generators::cpu::transmittanceToTop(m, hc, mu, 128);
        }
        for (int k = 0; k < 3; ++k) extinction_[3 * i + k] = float(std::clamp(T[k], 0.0, 1.0));
    }
    extinctionAtm_ = atm;
    extinctionKey_[0] = h;
}

void Stars::doRender(const FrameContext& ctx) {
    const SkyVars& v = ctx.vars;
    if (!own_ && v.get(starkeys::catalogue) != loadedPath_) {
        loadedPath_ = v.get(starkeys::catalogue);
        upload(loadCatalogue(loadedPath_));
    }
    // Limiting magnitude from the sky background (the Sky's zenith luminance when a Sky runs);
    // only the brighter prefix is drawn.
    const bool sky = v.has(generators::skykeys::zenithLuminance);
    // Extinction: left to an element composited after the stars that attenuates them (the Sky),
    // else applied here (FrameContext::attenuatedLater, set by the processor from the order).
    const bool attenuatedLater = ctx.attenuatedLater;
    limit_ = v.get(starkeys::magnitudeLimit);
    if (v.get(starkeys::adaptiveLimit)) {
        // The night sky's own background: the NightSky element's (natural and artificial) when it
        // runs, else the dark-sky floor.
        const double night = v.has(keys::nightBackground) ? v.get(keys::nightBackground) : v.get(starkeys::backgroundFloor);
        const double B = (sky ? v.get(generators::skykeys::zenithLuminance) : 0.0) + night;
        limit_ = std::min(limit_, limitingMagnitude(B));
    }
    drawn_ = int(std::upper_bound(mags_.begin(), mags_.end(), float(limit_)) - mags_.begin());
    perceptual_ = pointSourceMode(v) == PointSourceMode::Perceptual;
    if (drawn_ == 0) {
        reportNothingDrawn();
        return;
    }

    const gl::Program& p = programs_.get(ctx.camera.projection);
    p.use();
    p.set("u_icrsToEnu", glm::mat3(v.getOr(astro::keys::starFrameRotation, glm::dmat3(1.0))));
    p.set("u_aberration", glm::vec3(v.getOr(astro::keys::starFrameAberration, glm::dvec3(0.0))));
    p.set("u_years", float(v.getOr(astro::keys::starFrameEpochYears, 0.0)));
    const int copies = ctx.camera.projection == Projection::Equirect ? 2 : 1;
    p.set("u_copies", copies);
    p.set("u_e0", float(astro::magnitude::illuminanceLux(0.0)));
    p.set("u_fwhmRad", float(v.get(starkeys::psfFwhm)));
    p.set("u_minFwhmPx", float(v.get(starkeys::psfMinPx)));
    p.set("u_glare", float(v.get(starkeys::glare)));
    p.set("u_glareMag", float(v.get(starkeys::glareMagnitude)));
    p.set("u_scint", float(v.get(starkeys::scintillation)));
    const glm::dvec2 jd = v.getOr(keys::timeJdUtc, glm::dvec2(2451545.0, 0.0));
    const double dayFraction = std::fmod((jd.x - std::floor(jd.x)) + (jd.y - std::floor(jd.y)), 1.0);
    p.set("u_time", float(std::fmod(dayFraction * 86400.0, 3600.0)));
    glProgramUniform1ui(p.id(), p.location("u_seed"), unsigned(v.get(starkeys::seed)));
    // Refraction table at the astronomy's pressure and temperature.
    const double P = v.getOr(astro::keys::refractionPressure, 1013.25), Tc = v.getOr(astro::keys::refractionTemperature, 10.0);
    float refr[kTableN];
    for (int i = 0; i < kTableN; ++i) refr[i] = float(astro::refraction(tableAltitude(i), P, Tc));
    glProgramUniform1fv(p.id(), p.location("u_refr"), kTableN, refr);
    // Without a Sky composited over the stars, the atmosphere's extinction is applied here; the
    // perceptual mode needs it either way (the eye's threshold is for the light that reaches it).
    p.set("u_extinction", attenuatedLater ? 0 : 1);
    perceptual_ = generators::setPerceptualPointUniforms(p, v, attenuatedLater);
    if (perceptual_ || !attenuatedLater) {
        updateExtinction(v);
        glProgramUniform3fv(p.id(), p.location("u_ext"), kTableN, extinction_.data());
    }
    buffer_.bindBase(GL_SHADER_STORAGE_BUFFER, unsigned(starsSsbo_));
    if (instanced_) {
        glDrawArraysInstanced(GL_TRIANGLES, 0, 6, copies * drawn_);
    } else {
        // One indexed draw: vertex 4 i + k is corner k of star copy i, the indices (0 1 2, 0 2 3)
        // + 4 i its two triangles (the instanced draw's six corners); llvmpipe shades each of the
        // 4 vertices once (its vertex cache) instead of 6 times, in one pass instead of one per
        // instance (README "Cost").
        const int n = copies * drawn_;
        if (n > indexedStars_) {
            std::vector<unsigned> idx(size_t(n) * 6);
            for (int i = 0; i < n; ++i) {
                const unsigned b = 4u * unsigned(i), q[6] = {b, b + 1, b + 2, b, b + 2, b + 3};
                std::copy(q, q + 6, idx.begin() + 6 * size_t(i));
            }
            indices_ = gl::Buffer(idx.size() * sizeof(unsigned), idx.data());
            if (vao_.id() == 0) vao_ = gl::VertexArray::create();
            glVertexArrayElementBuffer(vao_.id(), indices_.id());
            indexedStars_ = n;
        }
        GLint prevVao = 0;
        glGetIntegerv(GL_VERTEX_ARRAY_BINDING, &prevVao);
        glBindVertexArray(vao_.id());
        glDrawElements(GL_TRIANGLES, 6 * n, GL_UNSIGNED_INT, nullptr);
        glBindVertexArray(GLuint(prevVao));
    }
    labels_.render(ctx, limit_);
}

void Stars::doRelease() {
    programs_.releasePrograms();
    buffer_ = gl::Buffer();
    indices_ = gl::Buffer();
    vao_ = gl::VertexArray();
    indexedStars_ = 0;
    mags_.clear();
    extinction_.clear();
    labels_.release();
}

void Stars::doStats(nlohmann::json& root) const {
    root["stars"]["drawn"] = drawn_;
    root["stars"]["limiting_magnitude"] = limit_;
    root["stars"]["catalogue_size"] = int(mags_.size());
    root["stars"]["point_sources"] = perceptual_ ? "perceptual" : "physical";
    root["stars"]["labels"] = labels_.drawn();
}

}  // namespace welkin::elements

WELKIN_ELEMENT_DESCRIPTOR(stars) {
    static const welkin::ElementDescriptor d{
        "stars", "the star catalogue (kstars stars.dat, BSC5 or HYG) at its apparent places, coloured by B-V, twinkling, to the sky's limiting magnitude",
        welkin::Layer::Background, true, [] { return std::make_unique<welkin::elements::Stars>(); }};
    return d;
}
