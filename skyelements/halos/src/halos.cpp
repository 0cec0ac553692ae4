// The Halos element (contract in welkin/elements/halos.hpp; the trace in halos_trace.cpp).
#include <welkin/elements/halos.hpp>
#include <welkin/embedded/clouds_shaders.hpp>
#include <welkin/embedded/halos_shaders.hpp>
#include <welkin/error.hpp>
#include <welkin/generators/cloud_density.hpp>
#include <welkin/generators/cloud_keys.hpp>
#include <welkin/generators/cloud_shadow.hpp>
#include <welkin/generators/lights.hpp>
#include <welkin/gl/bindings.hpp>
#include <welkin/gl/shader.hpp>
#include <welkin/keys.hpp>

#include <epoxy/gl.h>
#include <nlohmann/json.hpp>

#include <cmath>

namespace welkin::elements {

namespace hk = haloskeys;
namespace lk = generators::lightkeys;
namespace ck = generators::cloudkeys;

namespace {
// The cirrus height when no clouds.cirrus_height_m is declared (the Clouds element's default).
constexpr double kDefaultLayerHeightM = 9000.0;
}  // namespace

Halos::Halos() : SkyElement("halos") {
    option(hk::preset, std::string("common"));
    option(hk::opticalDepth, 0.0);
    optionUnset(hk::cirrusFraction);
    optionUnset(hk::plates);
    optionUnset(hk::columns);
    optionUnset(hk::random);
    optionUnset(hk::parry);
    option(hk::plateAspect, 0.2);
    option(hk::columnAspect, 2.0);
    option(hk::tilt, 1.0 * hk::kDeg);
    option(hk::tableQuality, std::string("default"));
    reads(keys::sunDirection);
    reads(keys::moonDirection);
    reads(keys::observerHeight);
    reads(lk::sunIlluminance);
    reads(lk::sunTransmittance);
    reads(lk::moonIlluminance);
    reads(lk::moonTransmittance);
    reads(lk::planetRadius);
    reads(ck::cirrusCoverage);
    reads(ck::cirrusHeight);
    reads(ck::curlNoise);
}

void Halos::doValidateOptions(const SkyVars& v) const {
    (void)halos::haloPreset(v.getOr(hk::preset, std::string("common")));
    (void)halos::HaloTables::quality(v.getOr(hk::tableQuality, std::string("default")));
}

void Halos::doInit(InitContext& ctx) {
    declareOptions(ctx.vars);
    validateOptions(ctx.vars);
    addGenerator(generators::AtmosphereLights::obtain(ctx.vars));
    tableUnit_ = textureUnit("HALOS_TABLE");  // the table's own unit: WELKIN_BINDING_HALOS_TABLE
    programs_ = gl::ProjectionPrograms(gl::ProgramBuilder("Halos")
                                           .bindings(bindings())
                                           .fullscreenVertex()
                                           .fragment("engine/camera.glsl", gl::engineShader("camera.glsl"))
                                           .fragment("engine/composite.glsl", gl::engineShader("composite.glsl"))
                                           .fragment("generators/cloud_density.glsl", embedded::clouds_shaders("cloud_density.glsl"))
                                           .fragment("halos/halos.frag.glsl", embedded::halos_shaders("halos.frag.glsl")));
    gridPrograms_ = gl::ProjectionPrograms(gl::ProgramBuilder("Halos grid")
                                               .bindings(bindings())
                                               .vertex("engine/camera.glsl", gl::engineShader("camera.glsl"))
                                               .vertex("halos/halos_grid.vert.glsl", embedded::halos_shaders("halos_grid.vert.glsl"))
                                               .fragment("engine/composite.glsl", gl::engineShader("composite.glsl"))
                                               .fragment("halos/halos_grid.frag.glsl", embedded::halos_shaders("halos_grid.frag.glsl")));
    programs_.get(Projection::Perspective);  // shader errors surface in init()
    gridPrograms_.get(Projection::Perspective);
    table_ = {};
    tables_ = nullptr;
    mixed_ = {-1, -1, -1, -1};
    mix_.clear();
    tableElevation_ = -1.0;
}

void Halos::doRender(const FrameContext& ctx) {
    drew_ = false;
    grid_ = false;
    const SkyVars& v = ctx.vars;
    // The light: the Sun, or the Moon when the Sun gives no light at the observer.
    glm::dvec3 E = v.get(lk::sunIlluminance) * v.get(lk::sunTransmittance);
    glm::dvec3 L = v.get(keys::sunDirection);
    if (E == glm::dvec3(0.0) || L.z < 0.0) {
        E = v.has(lk::moonIlluminance) ? v.get(lk::moonIlluminance) * v.get(lk::moonTransmittance) : glm::dvec3(0.0);
        L = v.get(keys::moonDirection);
    }
    if (E == glm::dvec3(0.0) || L.z < 0.0 || glm::length(L) == 0.0) return;  // no light
    L = glm::normalize(L);

    // The crystals: the user's layer and the cirrus' share.
    const halos::HaloPreset& preset = halos::haloPreset(v.get(hk::preset));
    const double tauUser = v.get(hk::opticalDepth);
    const double fraction = v.has(hk::cirrusFraction) ? v.get(hk::cirrusFraction) : preset.cirrusFraction;
    const bool cirrus = v.has(ck::curlNoise) && v.get(ck::curlNoise).id != 0 && v.getOr(ck::cirrusCoverage, 0.0) > 0.0 && fraction > 0.0;
    std::array<double, 4> w = preset.weights;
    const Key<double>* wk[4] = {&hk::plates, &hk::columns, &hk::random, &hk::parry};
    double wsum = 0;
    for (int i = 0; i < 4; ++i) {
        if (v.has(*wk[i])) w[std::size_t(i)] = v.get(*wk[i]);
        wsum += w[std::size_t(i)];
    }
    if ((tauUser <= 0.0 && !cirrus) || wsum <= 0.0) return;  // no crystals

    // The tables (traced once per crystal shape and quality, from disk afterwards) and their mix.
    const halos::HaloTables& t = halos::HaloTables::cached(halos::HaloTables::quality(v.get(hk::tableQuality)),
                                                           v.get(hk::plateAspect), v.get(hk::columnAspect), v.get(hk::tilt));
    const double el = std::asin(std::clamp(L.z, -1.0, 1.0));
    if (&t != tables_ || w != mixed_) {
        mix_ = t.mix(w);
        tables_ = &t;
        mixed_ = w;
        tableElevation_ = -1.0;
    }
    if (!table_ || table_.width() != t.q.na || table_.height() != t.q.ne) {
        table_ = gl::Texture2D(t.q.na, t.q.ne, GL_RGBA16F);
        table_.setFilter(GL_LINEAR);
        table_.setWrap(GL_CLAMP_TO_EDGE);
        tableElevation_ = -1.0;
    }
    if (std::abs(el - tableElevation_) > kElevationTolerance) {
        // The light's elevation between two slices (evenly over [0, 90] deg): linear in elevation,
        // on the CPU once per 0.02 deg of the light's motion, so that the pass makes one 2-D fetch.
        const double f = std::clamp(el / (0.5 * M_PI), 0.0, 1.0) * (t.q.slices - 1);
        const int s0 = std::min(int(f), t.q.slices - 1), s1 = std::min(s0 + 1, t.q.slices - 1);
        const float a = float(f - s0);
        const std::size_t cells = std::size_t(t.q.ne) * std::size_t(t.q.na);
        std::vector<glm::vec4> slice(cells);
        for (std::size_t i = 0; i < cells; ++i)
            slice[i] = mix_[std::size_t(s0) * cells + i] * (1.0f - a) + mix_[std::size_t(s1) * cells + i] * a;
        table_.upload(GL_RGBA, GL_FLOAT, slice.data());
        tableElevation_ = el;
    }

    const double layerH = v.getOr(ck::cirrusHeight, kDefaultLayerHeightM);
    const double h0 = v.getOr(keys::observerHeight, 0.0);
    const double R = v.getOr(lk::planetRadius, 6360000.0);
    glm::dvec3 lx(L.x, L.y, 0.0);
    lx = glm::length(lx) > 1e-9 ? glm::normalize(lx) : glm::dvec3(1, 0, 0);
    const glm::dvec3 ly = glm::cross(glm::dvec3(0, 0, 1), lx);
    if (ctx.camera.projection == Projection::Perspective && !cirrus) {
        // The real-time path: per-vertex coordinates on a grid, one fetch per pixel.
        const gl::Program& g = gridPrograms_.get(ctx.camera.projection);
        g.use();
        glBindTextureUnit(GLuint(tableUnit_), table_.id());
        const int gx = (ctx.camera.width + kGridCellPx - 1) / kGridCellPx, gy = (ctx.camera.height + kGridCellPx - 1) / kGridCellPx;
        g.set("u_grid", glm::ivec2(gx, gy));
        g.set("u_cellPx", float(kGridCellPx));
        g.set("u_lightX", glm::vec3(lx));
        g.set("u_lightY", glm::vec3(ly));
        g.set("u_tauUser", float(tauUser));
        g.set("u_h", float(h0));
        g.set("u_R", float(R));
        g.set("u_layerH", float(layerH));
        g.set("u_E", glm::vec3(E));
        g.set("u_below", h0 < layerH ? 1.0f : 0.0f);
        if (ctx.emptyVao) ctx.emptyVao->bind();
        glDrawArrays(GL_TRIANGLES, 0, GLsizei(6 * gx * gy));
        drew_ = true;
        grid_ = true;
        return;
    }
    const gl::Program& p = programs_.get(ctx.camera.projection);
    p.use();
    glBindTextureUnit(GLuint(tableUnit_), table_.id());
    if (cirrus) {
        const generators::CloudLayerBlock block = generators::CloudLayerBlock::from(v);
        if (!cloudUbo_) cloudUbo_ = gl::Buffer(sizeof block);
        cloudUbo_.update(&block, sizeof block);
        cloudUbo_.bindBase(GL_UNIFORM_BUFFER, gl::binding::kCloudUbo);
        glBindTextureUnit(gl::binding::kCloudCurlNoise, v.get(ck::curlNoise).id);
    }
    p.set("u_light", glm::vec3(L));
    p.set("u_E", glm::vec3(E));
    p.set("u_lightX", glm::vec3(lx));
    p.set("u_lightY", glm::vec3(ly));
    p.set("u_tauUser", float(tauUser));
    p.set("u_tauCirrus", float(cirrus ? fraction * generators::kCirrusOpticalDepth : 0.0));
    p.set("u_h", float(h0));
    p.set("u_R", float(R));
    p.set("u_layerH", float(layerH));
    ctx.drawFullscreen();
    drew_ = true;
}

void Halos::doStats(nlohmann::json& root) const {
    if (!tables_) return;
    root["halos"]["table_quality"] = tables_->q.name;
    root["halos"]["table_seconds"] = tables_->buildSeconds;
    root["halos"]["table_from_cache"] = tables_->fromCache;
}

void Halos::doRelease() {
    programs_.releasePrograms();
    gridPrograms_.releasePrograms();
    table_ = {};
    cloudUbo_ = {};
    tables_ = nullptr;
    mix_.clear();
    tableElevation_ = -1.0;
}

}  // namespace welkin::elements

WELKIN_ELEMENT_DESCRIPTOR(halos) {
    static const welkin::ElementDescriptor d{"halos",
                                             "ice-crystal halos (22/46 deg halos, sundogs, arcs) from ray-traced crystal tables, where the light shines "
                                             "through cirrus or a crystal layer (skyelements/halos/README.md)",
                                             welkin::Layer::Foreground, false, [] { return std::make_unique<welkin::elements::Halos>(); }};
    return d;
}
