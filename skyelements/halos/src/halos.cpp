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
#include <welkin/glsl_cpp.hpp>
#include <welkin/keys.hpp>

#include <epoxy/gl.h>
#include <nlohmann/json.hpp>

#include <chrono>
#include <cmath>

namespace welkin::glsl::dp::halos_shared {
#include "../shaders/halos_layer.shared.glsl"
}  // namespace welkin::glsl::dp::halos_shared

namespace welkin::elements {

namespace hk = haloskeys;
namespace lk = generators::lightkeys;
namespace ck = generators::cloudkeys;

namespace {
// The cirrus height when no clouds.cirrus_height_m is declared (the Clouds element's default).
constexpr double kDefaultLayerHeightM = 9000.0;

// The table at a light elevation between two slices: the two slices blended linearly in the
// light's elevation, each shifted in elevation by the light's offset from its slice (rows of the
// (azimuth, elevation) table), so that what moves with the light (the 22 and 46 deg halos, the
// sundogs, the parhelic circle, the tangent arcs) is blended in place rather than as two copies
// a slice apart. Below the horizon the pattern of crystals with horizontal faces (plates, Parry)
// is the reflection of the one above (the subsun at -h, the subparhelia), which moves against the
// light: for their mix the shift is mirrored there, going over linearly between 5 deg below and
// above the horizon (rowShift); columns and random crystals are shifted everywhere. skyelements/halos/README.md.
struct SliceBlend {
    int s0 = 0, s1 = 0;
    float a = 0.0f;                     // weight of slice s1
    double shift0 = 0.0, shift1 = 0.0;  // rows to add to a row's index to read slice s0, s1
};
SliceBlend sliceBlend(const halos::HaloTables& t, double el) {
    SliceBlend b;
    const double f = std::clamp(el / (0.5 * M_PI), 0.0, 1.0) * (t.q.slices - 1);
    b.s0 = std::min(int(f), t.q.slices - 1);
    b.s1 = std::min(b.s0 + 1, t.q.slices - 1);
    b.a = float(f - b.s0);
    const double rowsPerRad = t.q.ne / M_PI;
    b.shift0 = (t.sliceElevationRad(b.s0) - el) * rowsPerRad;
    b.shift1 = (t.sliceElevationRad(b.s1) - el) * rowsPerRad;
    return b;
}
struct RowLerp {
    int e0, e1;
    float w;
};
// The shift of a row at `row` (fractional, bin centres at integers): the light's offset above
// 5 deg, mirrored below -5 deg, linear between.
double rowShift(const halos::HaloTables& t, double row, double shift) {
    const double e = ((row + 0.5) / t.q.ne - 0.5) * M_PI;
    return shift * std::clamp(e / (5.0 * M_PI / 180.0), -1.0, 1.0);
}
RowLerp rowLerp(const halos::HaloTables& t, double row) {
    const double f = std::clamp(row, 0.0, double(t.q.ne - 1));
    const int e0 = int(f);
    return {e0, std::min(e0 + 1, t.q.ne - 1), float(f - e0)};
}
glm::vec4 sampleRow(const std::vector<glm::vec4>& mix, int slice, const RowLerp& r, int ia, const halos::HaloTables& t) {
    const std::size_t base = std::size_t(slice) * std::size_t(t.q.ne) * std::size_t(t.q.na) + std::size_t(ia);
    return mix[base + std::size_t(r.e0) * std::size_t(t.q.na)] * (1.0f - r.w) + mix[base + std::size_t(r.e1) * std::size_t(t.q.na)] * r.w;
}
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
    option(hk::tableSlices, hk::kTableSlicesDefault);
    reads(keys::interactive);
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
    meanUnit_ = textureUnit("HALOS_MEAN");    // the adaptive cells' maps (halos_cells.comp.glsl)
    detailUnit_ = textureUnit("HALOS_DETAIL");
    cellsSsbo_ = storageBuffer("HALOS_CELLS");  // their lists of leaves and draw commands
    fineImage_ = imageUnit("HALOS_FINE");       // the fetching pieces' fine table, written (halos_fine.comp.glsl)
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
    finePrograms_ = gl::ProjectionPrograms(gl::ProgramBuilder("Halos grid, fine table")
                                               .bindings(bindings())
                                               .define("HALOS_FINE")
                                               .vertex("engine/camera.glsl", gl::engineShader("camera.glsl"))
                                               .vertex("halos/halos_grid.vert.glsl", embedded::halos_shaders("halos_grid.vert.glsl"))
                                               .fragment("engine/composite.glsl", gl::engineShader("composite.glsl"))
                                               .fragment("halos/halos_grid.frag.glsl", embedded::halos_shaders("halos_grid.frag.glsl")));
    smoothPrograms_ = gl::ProjectionPrograms(gl::ProgramBuilder("Halos grid, smooth leaves")
                                                 .bindings(bindings())
                                                 .define("HALOS_SMOOTH")
                                                 .vertex("engine/camera.glsl", gl::engineShader("camera.glsl"))
                                                 .vertex("halos/halos_grid.vert.glsl", embedded::halos_shaders("halos_grid.vert.glsl"))
                                                 .fragment("engine/composite.glsl", gl::engineShader("composite.glsl"))
                                                 .fragment("halos/halos_smooth.frag.glsl", embedded::halos_shaders("halos_smooth.frag.glsl")));
    cellPrograms_ = gl::ProjectionPrograms(gl::ProgramBuilder("Halos cells")
                                               .bindings(bindings())
                                               .compute("engine/camera.glsl", gl::engineShader("camera.glsl"))
                                               .compute("halos/halos_cells.comp.glsl", embedded::halos_shaders("halos_cells.comp.glsl")));
    fineProgram_ = gl::ProgramBuilder("Halos fine table")
                       .bindings(bindings())
                       .compute("halos/halos_fine.comp.glsl", embedded::halos_shaders("halos_fine.comp.glsl"))
                       .build();
    octFine_ = {};
    fineVersion_ = ~uint64_t(0);
    programs_.get(Projection::Perspective);  // shader errors surface in init()
    gridPrograms_.get(Projection::Perspective);
    finePrograms_.get(Projection::Perspective);
    smoothPrograms_.get(Projection::Perspective);
    cellPrograms_.get(Projection::Perspective);
    cellsKey_.clear();
    table_ = {};
    tables_ = nullptr;
    mixed_ = {-1, -1, -1, -1};
    mix_.clear();
    mixShift_.clear();
    pix_.held = NAN;
    tableBack_ = {};
    pix_.backRow = -1;
    octTable_ = {};
    octBack_ = {};
    octRemap_.clear();
    octN_ = 0;
    oct_.held = NAN;
    oct_.backRow = -1;
}

void Halos::doRender(const FrameContext& ctx) {
    drew_ = false;
    grid_ = false;
    oct_.rowsLast = 0;
    pix_.rowsLast = 0;
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
        // Two mixes: the populations with horizontal faces (plates, Parry), whose pattern below
        // the horizon is their reflection and moves against the light, and the others (columns,
        // random), whose pattern moves with it everywhere (sliceBlend).
        const double sum = w[0] + w[1] + w[2] + w[3];
        auto part = [&](std::array<double, 4> ws) {
            const double ps = ws[0] + ws[1] + ws[2] + ws[3];
            std::vector<glm::vec4> m = t.mix(ws);
            for (glm::vec4& c : m) c *= float(ps / sum);
            return m;
        };
        mix_ = part({w[0], 0.0, 0.0, w[3]});
        mixShift_ = part({0.0, w[1], w[2], 0.0});
        tables_ = &t;
        mixed_ = w;
        pix_.held = NAN;
        oct_.held = NAN;
    }
    if (!table_ || table_.width() != t.q.na || table_.height() != t.q.ne) {
        for (gl::Texture2D* tex : {&table_, &tableBack_}) {
            *tex = gl::Texture2D(t.q.na, t.q.ne, GL_RGBA16F);
            tex->setFilter(GL_LINEAR);
            tex->setWrap(GL_CLAMP_TO_EDGE);
        }
        pix_.held = NAN;
    }
    const double layerH = v.getOr(ck::cirrusHeight, kDefaultLayerHeightM);
    const double h0 = v.getOr(keys::observerHeight, 0.0);
    const double R = v.getOr(lk::planetRadius, 6360000.0);
    glm::dvec3 lx(L.x, L.y, 0.0);
    lx = glm::length(lx) > 1e-9 ? glm::normalize(lx) : glm::dvec3(1, 0, 0);
    const glm::dvec3 ly = glm::cross(glm::dvec3(0, 0, 1), lx);
    if (ctx.camera.projection == Projection::Perspective && !cirrus && !forcePerPixel_) {
        // The real-time path: a grid of big cells whose vertices pass the unnormalised view ray
        // (affine in the pixel: exact at every pixel); per pixel a few additions, one division
        // and one fetch of the octahedral table, which holds the layer's scattered fraction and
        // transmittance too; the horizon is a clip distance.
        const int slices = v.getOr(keys::interactive, false) ? std::clamp(v.getOr(hk::tableSlices, hk::kTableSlicesDefault), 1, 64) : 1;
        if (adaptive_ && !frontMaps_) oct_.held = NAN;  // the adaptive cells turned on: the table and its maps whole now
        updateOctTable(el, tauUser, h0, layerH, R, slices);
        // The pieces' side: kGridCellPx, or a probe's (setDisplayProbe: benchmarks, never with the adaptive cells).
        const int cellPx = adaptive_ ? kGridCellPx : probeCellPx_;
        const int gx = (ctx.camera.width + cellPx - 1) / cellPx, gy = (ctx.camera.height + cellPx - 1) / cellPx;
        // The table's frame turned about the light's horizontal normal by its lag in elevation
        // (0 once a refill completed at the current light): the table's light lands on the current
        // light, and what moves with it (the halos, the sundogs) stays around it while a refill is
        // under way; the exact elevation shift it stands in for differs by the lag times 1 - cos
        // of the angle from the light's vertical plane (skyelements/halos/README.md, "Time running").
        const double lag = oct_.held - el;
        const glm::dvec3 up(0.0, 0.0, 1.0);
        const glm::vec3 fx(std::cos(lag) * lx - std::sin(lag) * up), fy(ly), fz(std::sin(lag) * lx + std::cos(lag) * up);
        // Under the layer the ground hides it below the horizon (mu < muH); above it, nothing does.
        const double r = R + h0;
        const double muH = h0 < layerH ? -std::sqrt(std::max(1.0 - R * R / (r * r), 0.0)) : -2.0;
        auto setCommon = [&](const gl::Program& g) {
            g.set("u_grid", glm::ivec2(gx, gy));
            g.set("u_cellPx", float(cellPx));
            g.set("u_lightX", fx);
            g.set("u_lightY", fy);
            g.set("u_lightZ", fz);
            g.set("u_muHorizon", float(muH));
        };
        glBindTextureUnit(GLuint(tableUnit_), octTable_.id());
        if (ctx.emptyVao) ctx.emptyVao->bind();
        glEnable(GL_CLIP_DISTANCE0);
        // The adaptive cells need the drawn table's maps: a table swapped in this frame without
        // them (the cells turned on while its refill was under way) is drawn by every cell
        // fetching this once; the next frame fills table and maps whole (above).
        // The cells' lists are made only for a view that rests: in a frame whose view, table,
        // turn or horizon differ from the frame before's (a moving camera, time running) every
        // cell fetches, as if the cells were off, so the lists' test is never paid per frame; the
        // second frame of a resting view makes them (skyelements/halos/README.md, "The default
        // display").
        std::vector<double> key;
        if (adaptive_ && frontMaps_) {
            const int gxc = (ctx.camera.width + kGridCellPx - 1) / kGridCellPx, gyc = (ctx.camera.height + kGridCellPx - 1) / kGridCellPx;
            key = {double(gxc), double(gyc), muH, cellTolerance_, double(octVersion_), fx.x, fx.y, fx.z, fy.x, fy.y, fz.x, fz.y, fz.z,
                   double(ctx.camera.width), double(ctx.camera.height)};
            for (const glm::dvec2 px : {glm::dvec2(0.0), glm::dvec2(ctx.camera.width, 0.0), glm::dvec2(0.0, ctx.camera.height)}) {
                const glm::dvec3 d = ctx.camera.directionAt(px).value_or(glm::dvec3(0.0));
                key.insert(key.end(), {d.x, d.y, d.z});
            }
        }
        const bool rests = key == lastKey_ || !restOnly_;
        lastKey_ = key;
        listsDrawn_ = adaptive_ && frontMaps_ && (rests || key == cellsKey_);
        if (listsDrawn_) {
            // The adaptive cells (on by default for a resting view: skyelements/halos/README.md, "The default display"): the lists of pieces
            // (halos_cells.comp.glsl), made again only when what they depend on changed, then two
            // draws, the pieces drawn from their corners and those that fetch.
            const uint32_t listSize = uint32_t(4 * gx * gy);  // a cell lists at most its 4 quarters
            if (!cellBuf_ || listSize_ != listSize) {
                cellBuf_ = gl::Buffer(32 + 2 * std::size_t(listSize) * 4);
                listSize_ = listSize;
                cellsKey_.clear();
            }
            cellBuf_.bindBase(GL_SHADER_STORAGE_BUFFER, GLuint(cellsSsbo_));
            if (fineScale_ > 0) updateFineTable();
            if (key != cellsKey_) {
                const auto t0 = std::chrono::steady_clock::now();
                const uint32_t header[8] = {0, 1, 0, 0, 0, 1, 0, 0};  // DrawArraysIndirectCommand x 2, counts 0
                cellBuf_.update(header, sizeof header);
                const gl::Program& c = cellPrograms_.get(ctx.camera.projection);
                c.use();
                setCommon(c);
                c.set("u_mapSize", octN_ / kMapBlock);
                glUniform1ui(glGetUniformLocation(c.id(), "u_listSize"), listSize);
                c.set("u_rel", float(cellTolerance_));
                c.set("u_floor", glm::vec3(kSkyFloor[0], kSkyFloor[1], kSkyFloor[2]));
                glBindTextureUnit(GLuint(meanUnit_), octMean_.id());
                glBindTextureUnit(GLuint(detailUnit_), octDetail_.id());
                glDispatchCompute(GLuint((gx * gy + 15) / 16), 1, 1);
                glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
                // The two lists' vertex counts read back once, here (a wait for the pass, once per
                // resting view), so that each frame draws them with plain draws: an indirect draw
                // makes llvmpipe finish the frame's queued work before it reads its command, a
                // stall in every frame (measured: the wall time of the pass no better than every
                // cell fetching at 1280 x 720, twice it at 512 x 256).
                uint32_t counts[8] = {};
                glGetNamedBufferSubData(cellBuf_.id(), 0, sizeof counts, counts);
                listVertices_ = {counts[0], counts[4]};
                cellsKey_ = key;
                cellsMs_ = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
            } else {
                cellsMs_ = 0.0;
            }
            for (int list = 0; list < 2; ++list) {
                if (listVertices_[std::size_t(list)] == 0) continue;
                const bool fine = list == 1 && fineScale_ > 0;
                const gl::Program& g = (list == 0 ? smoothPrograms_ : fine ? finePrograms_ : gridPrograms_).get(ctx.camera.projection);
                // The smooth pieces' vertices read the table bilinearly (what the cells' test
                // compared); the fetching pieces' pixels the fine table nearest-texel.
                glBindTextureUnit(GLuint(tableUnit_), fine ? octFine_.id() : octTable_.id());
                g.use();
                if (fine) g.set("u_fineSize", octFine_.width());
                setCommon(g);
                g.set("u_E", glm::vec3(E));
                g.set("u_list", 1);
                glUniform1ui(glGetUniformLocation(g.id(), "u_listOffset"), list == 0 ? 0u : listSize);
                glDrawArrays(GL_TRIANGLES, 0, GLsizei(listVertices_[std::size_t(list)]));
            }
        } else {
            cellsMs_ = 0.0;
            // Every cell whole, fetching per pixel (the cells off, or a view that moves); a probe (setDisplayProbe) may read
            // the table nearest-texel or draw every piece from its corners instead.
            const bool corners = probe_ == DisplayProbe::Corners, nearest = probe_ == DisplayProbe::Nearest, fine = probe_ == DisplayProbe::Fine;
            if (fine) {
                if (fineScale_ == 0) throw Error("Halos: DisplayProbe::Fine needs a fine scale > 0");
                updateFineTable();
                glBindTextureUnit(GLuint(tableUnit_), octFine_.id());
            }
            const gl::Program& g = (corners ? smoothPrograms_ : fine ? finePrograms_ : gridPrograms_).get(ctx.camera.projection);
            g.use();
            if (fine) g.set("u_fineSize", octFine_.width());
            setCommon(g);
            g.set("u_E", glm::vec3(E));
            g.set("u_list", 0);
            if (nearest) octTable_.setFilter(GL_NEAREST);
            glDrawArrays(GL_TRIANGLES, 0, GLsizei(6 * gx * gy));
            if (nearest) octTable_.setFilter(GL_LINEAR);
        }
        glDisable(GL_CLIP_DISTANCE0);
        drew_ = true;
        grid_ = true;
        return;
    }
    updatePixelTable(el, v.getOr(keys::interactive, false) ? std::clamp(v.getOr(hk::tableSlices, hk::kTableSlicesDefault), 1, 64) : 1);

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
    // The table's frame turned onto the current light by its lag in elevation, as the grid's
    // (0 once a refill completed at the current light: then exactly lx and up).
    const double plag = pix_.held - el;
    const glm::dvec3 pup(0.0, 0.0, 1.0);
    p.set("u_lightX", glm::vec3(std::cos(plag) * lx - std::sin(plag) * pup));
    p.set("u_lightY", glm::vec3(ly));
    p.set("u_lightZ", glm::vec3(std::sin(plag) * lx + std::cos(plag) * pup));
    p.set("u_tauUser", float(tauUser));
    p.set("u_tauCirrus", float(cirrus ? fraction * generators::kCirrusOpticalDepth : 0.0));
    p.set("u_h", float(h0));
    p.set("u_R", float(R));
    p.set("u_layerH", float(layerH));
    ctx.drawFullscreen();
    drew_ = true;
}

// The layer's scattered fraction 1 - exp(-tau slant) and transmittance exp(-tau slant) along a
// direction of sine of elevation mu from the observer (halos.frag.glsl's rule); a direction the
// ground hides (observer under the layer) takes the horizon's (the clip distance cuts it exactly,
// so the table's bilinear filter never blends the horizon with the ground's zero); a direction
// that misses the layer scatters nothing.
static glm::vec2 layerFactor(double mu, double tau, double h0, double layerH, double R) {
    const double r = R + h0, rc = R + layerH;
    if (h0 < layerH) mu = std::max(mu, -std::sqrt(std::max(1.0 - R * R / (r * r), 0.0)));
    const double d = glsl::dp::halos_shared::halos_layerDistance(r, rc, mu);  // the pass's text
    if (d <= 0.0) return {0.0f, 1.0f};
    const double horiz = std::sqrt(std::max(1.0 - mu * mu, 0.0));  // the horizontal component
    const glm::dvec3 p(d * horiz, 0.0, h0 + d * mu);
    const glm::dvec3 up = glm::normalize(p + glm::dvec3(0.0, 0.0, R));
    const double slant = 1.0 / std::max(std::abs(up.x * horiz + up.z * mu), 0.1);
    const double t = std::exp(-tau * slant);
    return {float(1.0 - t), float(t)};
}

// One frame of a table refilled over frames (the rules: updateOctTable's comment).
template <class Fill>
bool Halos::refillFrame(Refill& s, double el, bool whole, int slices, int n, Fill&& fill) {
    s.rowsLast = 0;
    const double step = el - s.lastElevation;
    const bool jump = !(std::abs(step) <= kElevationJump);
    s.lastElevation = el;
    const auto t0 = std::chrono::steady_clock::now();
    bool complete = false;
    if (whole || std::isnan(s.held) || (slices <= 1 && std::abs(el - s.held) > kElevationTolerance)) {
        s.backRow = -1;
        fill(false, el, 0, n);
        s.rowsLast = n;
        s.held = el;
        ++s.refills;
    } else {
        if (s.backRow >= 0 && jump) s.backRow = -1;  // superseded: restarted below at the new elevation
        if (s.backRow < 0 && std::abs(el - s.held) > kElevationTolerance) {
            s.backRow = 0;
            s.backElevation = std::clamp(el + (jump ? 0.0 : 1.5 * slices * step), -0.5 * M_PI, 0.5 * M_PI);
            ++s.refills;
        }
        if (s.backRow < 0) return false;
        const int r1 = std::min(n, s.backRow + (n + slices - 1) / slices);
        fill(true, s.backElevation, s.backRow, r1);
        s.rowsLast = r1 - s.backRow;
        s.backRow = r1;
        if (s.backRow >= n) {  // complete: drawn from this frame on
            s.held = s.backElevation;
            s.backRow = -1;
            complete = true;
        }
    }
    s.updateMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    return complete;
}

void Halos::updateOctTable(double el, double tauUser, double h0, double layerH, double R, int slices) {
    const halos::HaloTables& t = *tables_;
    const int N = int(std::lround(kOctScale * t.q.na));
    if (N != octN_ || octRemap_.empty()) {
        // The octahedral half sky: texel (i, j) at (s, t) = 2 (i + 0.5, j + 0.5) / N - 1; the
        // direction (x, |y|, z) / (|x| + |y| + |z|) in the light's frame (x to the light's azimuth,
        // z up) has x + z = s and x - z = t, so x = (s + t) / 2, z = (s - t) / 2, |y| = 1 -
        // max(|s|, |t|): the whole square is the half sky, its edge the light's vertical plane.
        octN_ = N;
        octRemap_.assign(std::size_t(N) * std::size_t(N), {});
        for (int j = 0; j < N; ++j)
            for (int i = 0; i < N; ++i) {
                const double s = 2.0 * (i + 0.5) / N - 1.0, tt = 2.0 * (j + 0.5) / N - 1.0;
                const glm::dvec3 d = glm::normalize(glm::dvec3(0.5 * (s + tt), 1.0 - std::max(std::abs(s), std::abs(tt)), 0.5 * (s - tt)));
                const double e = std::asin(std::clamp(d.z, -1.0, 1.0)), a = std::atan2(d.y, d.x);
                // Bilinear between the (azimuth, elevation) table's bin centres, clamped at its edges
                // (the row, fractional, is shifted per slice at each update).
                const double fa = std::clamp(a / M_PI * t.q.na - 0.5, 0.0, double(t.q.na - 1));
                OctTexel& o = octRemap_[std::size_t(j) * std::size_t(N) + std::size_t(i)];
                o.a0 = uint16_t(fa);
                o.a1 = uint16_t(std::min(int(fa) + 1, t.q.na - 1));
                o.wa = float(fa - int(fa));
                o.row = float((e / M_PI + 0.5) * t.q.ne - 0.5);
                o.mu = float(d.z);
            }
        for (gl::Texture2D* tex : {&octTable_, &octBack_}) {
            *tex = gl::Texture2D(N, N, GL_RGBA16F);
            tex->setFilter(GL_LINEAR);
            tex->setWrap(GL_CLAMP_TO_EDGE);
        }
        const int M = N / kMapBlock;  // N = kOctScale x 180, 256 or 512: a multiple of kMapBlock
        for (gl::Texture2D* tex : {&octMean_, &octMeanBack_, &octDetail_, &octDetailBack_}) {
            *tex = gl::Texture2D(M, M, GL_RGBA16F);
            tex->setFilter(GL_LINEAR);  // the detail is read with texelFetch
            tex->setWrap(GL_CLAMP_TO_EDGE);
        }
        octCpu_.assign(std::size_t(N) * std::size_t(N), glm::vec4(0.0f));
        blkMean_.assign(std::size_t(M) * std::size_t(M), glm::vec4(0.0f));
        blkDev_ = blkMean_;
        blkDetail_ = blkMean_;
        oct_.held = NAN;
        octLayerKey_ = glm::dvec4(-1.0);
    }
    const glm::dvec4 layerKey(tauUser, h0, layerH, R);
    const bool layerChanged = layerKey != octLayerKey_;
    if (layerChanged) {
        octLayer_.resize(octRemap_.size());
        for (std::size_t k = 0; k < octRemap_.size(); ++k) octLayer_[k] = layerFactor(octRemap_[k].mu, tauUser, h0, layerH, R);
        octLayerKey_ = layerKey;
    }
    // What is stale: the layer, the mix or the table's size (no elevation held), or slices 1: the
    // whole table now, a refill in progress superseded. The light's elevation moved past the
    // tolerance: a refill into octBack_ over `slices` frames while octTable_ is drawn (turned onto
    // the current light: doRender). The refill is made for the elevation the light will have
    // midway through the table's turn on screen (it is drawn from `slices` to 2 `slices` frames
    // after the refill starts: the light's motion in the last frame times 1.5 `slices` ahead), so
    // that with time running steadily the drawn table lags or leads the light by at most half a
    // refill's motion; with the light at rest the prediction is the light itself. A jump of the
    // light (kElevationJump in a frame: a new time) restarts a refill in progress at the new
    // elevation, predicting nothing.
    if (refillFrame(oct_, el, layerChanged, slices, N, [&](bool back, double e, int r0, int r1) { fillOctRows(back, e, r0, r1); })) {
        std::swap(octTable_, octBack_);
        std::swap(octMean_, octMeanBack_);
        std::swap(octDetail_, octDetailBack_);
        std::swap(frontMaps_, backMaps_);
        ++octVersion_;
    }
}

void Halos::setDisplayProbe(DisplayProbe probe, int cellPx) {
    if (cellPx < 8 || cellPx > 1024) throw Error("Halos::setDisplayProbe(): cellPx " + std::to_string(cellPx) + " not in [8, 1024]");
    probe_ = probe;
    probeCellPx_ = cellPx;
}

void Halos::setFineScale(int scale) {
    if (scale < 0 || scale > 4) throw Error("Halos::setFineScale(): " + std::to_string(scale) + " not in [0, 4]");
    fineScale_ = scale;
}

// The fine table (halos_fine.comp.glsl), made again whenever the drawn grid table changed (a
// whole fill, a refill swapped in) or its scale did: one GPU pass over (fineScale_ N)^2 texels.
void Halos::updateFineTable() {
    const int F = fineScale_ * octN_;
    if (!octFine_ || octFine_.width() != F) {
        octFine_ = gl::Texture2D(F, F, GL_RGBA16F);
        octFine_.setFilter(GL_NEAREST);
        octFine_.setWrap(GL_CLAMP_TO_EDGE);
        fineVersion_ = ~uint64_t(0);
    }
    if (fineVersion_ == octVersion_) return;
    const auto t0 = std::chrono::steady_clock::now();
    fineProgram_.use();
    fineProgram_.set("u_size", F);
    glBindTextureUnit(GLuint(tableUnit_), octTable_.id());
    glBindImageTexture(GLuint(fineImage_), octFine_.id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA16F);
    glDispatchCompute(GLuint((F + 7) / 8), GLuint((F + 7) / 8), 1);
    glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT);
    fineVersion_ = octVersion_;
    ++fineMade_;
    fineMs_ = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

void Halos::setCellTolerance(double t) {
    if (!(t > 0.0 && t <= 1.0)) throw Error("Halos::setCellTolerance(): " + std::to_string(t) + " not in (0, 1]");
    cellTolerance_ = t;
}

void Halos::fillOctRows(bool back, double el, int r0, int r1) {
    gl::Texture2D& target = back ? octBack_ : octTable_;
    const halos::HaloTables& t = *tables_;
    const int N = octN_;
    // The light's elevation between two slices (as the per-pixel path's table), resampled.
    const SliceBlend b = sliceBlend(t, el);
    const std::size_t k0 = std::size_t(r0) * std::size_t(N), k1 = std::size_t(r1) * std::size_t(N);
    octRows_.resize(k1 - k0);
    for (std::size_t k = k0; k < k1; ++k) {
        const OctTexel& o = octRemap_[k];
        const RowLerp r0l = rowLerp(t, o.row + rowShift(t, o.row, b.shift0)), r1l = rowLerp(t, o.row + rowShift(t, o.row, b.shift1));
        const RowLerp q0 = rowLerp(t, o.row + b.shift0), q1 = rowLerp(t, o.row + b.shift1);
        const glm::vec4 p0 = (sampleRow(mix_, b.s0, r0l, o.a0, t) + sampleRow(mixShift_, b.s0, q0, o.a0, t)) * (1.0f - o.wa) +
                             (sampleRow(mix_, b.s0, r0l, o.a1, t) + sampleRow(mixShift_, b.s0, q0, o.a1, t)) * o.wa;
        const glm::vec4 p1 = (sampleRow(mix_, b.s1, r1l, o.a0, t) + sampleRow(mixShift_, b.s1, q1, o.a0, t)) * (1.0f - o.wa) +
                             (sampleRow(mix_, b.s1, r1l, o.a1, t) + sampleRow(mixShift_, b.s1, q1, o.a1, t)) * o.wa;
        const glm::vec4 p = p0 * (1.0f - b.a) + p1 * b.a;
        octRows_[k - k0] = glm::vec4(glm::vec3(p) * octLayer_[k].x, octLayer_[k].y);
    }
    // Inside a frame the pixel-store parameters are GL's defaults and no unpack buffer is bound
    // (docs/writing-an-element.md): tightly packed rows.
    glTextureSubImage2D(target.id(), 0, 0, r0, N, r1 - r0, GL_RGBA, GL_FLOAT, octRows_.data());
    // The adaptive cells' maps, only while they are on (a table filled without them, or from a row
    // other than the first after they were turned on, has none: doRender fills it whole again).
    bool& maps = back ? backMaps_ : frontMaps_;
    if (adaptive_ && (r0 == 0 || maps)) {
        std::copy(octRows_.begin(), octRows_.end(), octCpu_.begin() + std::ptrdiff_t(k0));
        updateOctMaps(back, r0, r1);
        maps = true;
    } else {
        maps = false;
    }
    if (!back) ++octVersion_;
}

// The adaptive cells' maps of the table being filled, as far as its rows [0, r1) allow (rows
// [r0, r1) new; r0 = 0 starts a table): the means of the blocks whose rows are all there; the
// deviation |table - mean| of a block's texels from the means interpolated bilinearly between
// block centres (GL_LINEAR's rule, as halos_cells.comp.glsl reads them), largest per channel,
// once the block rows around it have their means; the detail, the largest deviation over the
// block and its eight neighbours, once those have theirs. The rows done are uploaded at once.
void Halos::updateOctMaps(bool back, int r0, int r1) {
    const int N = octN_, B = kMapBlock, M = N / B;
    if (r0 == 0) mapMeanRows_ = mapDevRows_ = mapDetailRows_ = 0;
    const bool complete = r1 >= N;
    const auto at = [M](std::vector<glm::vec4>& m, int i, int j) -> glm::vec4& { return m[std::size_t(j) * std::size_t(M) + std::size_t(i)]; };
    const int meanTo = complete ? M : r1 / B;
    for (int J = mapMeanRows_; J < meanTo; ++J)
        for (int I = 0; I < M; ++I) {
            glm::vec4 sum(0.0f);
            for (int y = J * B; y < (J + 1) * B; ++y)
                for (int x = I * B; x < (I + 1) * B; ++x) sum += octCpu_[std::size_t(y) * std::size_t(N) + std::size_t(x)];
            at(blkMean_, I, J) = sum / float(B * B);
        }
    const int devTo = complete ? M : std::max(meanTo - 1, mapDevRows_);
    for (int J = mapDevRows_; J < devTo; ++J)
        for (int I = 0; I < M; ++I) {
            glm::vec4 dev(0.0f);
            for (int y = J * B; y < (J + 1) * B; ++y) {
                const float fy = std::clamp((y + 0.5f) / B - 0.5f, 0.0f, float(M - 1));
                const int j0 = std::min(int(fy), M - 1), j1 = std::min(j0 + 1, M - 1);
                const float wy = fy - float(j0);
                for (int x = I * B; x < (I + 1) * B; ++x) {
                    const float fx = std::clamp((x + 0.5f) / B - 0.5f, 0.0f, float(M - 1));
                    const int i0 = std::min(int(fx), M - 1), i1 = std::min(i0 + 1, M - 1);
                    const float wx = fx - float(i0);
                    const glm::vec4 mean = (at(blkMean_, i0, j0) * (1.0f - wx) + at(blkMean_, i1, j0) * wx) * (1.0f - wy) +
                                           (at(blkMean_, i0, j1) * (1.0f - wx) + at(blkMean_, i1, j1) * wx) * wy;
                    dev = glm::max(dev, glm::abs(octCpu_[std::size_t(y) * std::size_t(N) + std::size_t(x)] - mean));
                }
            }
            at(blkDev_, I, J) = dev;
        }
    const int detailTo = complete ? M : std::max(devTo - 1, mapDetailRows_);
    for (int J = mapDetailRows_; J < detailTo; ++J)
        for (int I = 0; I < M; ++I) {
            glm::vec4 d(0.0f);
            for (int b = std::max(J - 1, 0); b <= std::min(J + 1, M - 1); ++b)
                for (int a = std::max(I - 1, 0); a <= std::min(I + 1, M - 1); ++a) d = glm::max(d, at(blkDev_, a, b));
            at(blkDetail_, I, J) = d;
        }
    gl::Texture2D& mean = back ? octMeanBack_ : octMean_;
    gl::Texture2D& detail = back ? octDetailBack_ : octDetail_;
    if (meanTo > mapMeanRows_)
        glTextureSubImage2D(mean.id(), 0, 0, mapMeanRows_, M, meanTo - mapMeanRows_, GL_RGBA, GL_FLOAT,
                            blkMean_.data() + std::size_t(mapMeanRows_) * std::size_t(M));
    if (detailTo > mapDetailRows_)
        glTextureSubImage2D(detail.id(), 0, 0, mapDetailRows_, M, detailTo - mapDetailRows_, GL_RGBA, GL_FLOAT,
                            blkDetail_.data() + std::size_t(mapDetailRows_) * std::size_t(M));
    mapMeanRows_ = std::max(mapMeanRows_, meanTo);
    mapDevRows_ = std::max(mapDevRows_, devTo);
    mapDetailRows_ = std::max(mapDetailRows_, detailTo);
}

Halos::CellCounts Halos::readCellCounts(const Camera& cam) const {
    CellCounts c;
    if (!grid_) return c;
    if (!listsDrawn_) {  // every cell fetched (the cells off, or a view that moved)
        const int gx = (cam.width + kGridCellPx - 1) / kGridCellPx, gy = (cam.height + kGridCellPx - 1) / kGridCellPx;
        c.fetchLeaves = gx * gy;
        c.fetchPixels = long(cam.width) * long(cam.height);
        return c;
    }
    if (!cellBuf_) return c;
    std::vector<uint32_t> buf(cellBuf_.size() / 4);
    glGetNamedBufferSubData(cellBuf_.id(), 0, GLsizeiptr(cellBuf_.size()), buf.data());
    const int gx = (cam.width + kGridCellPx - 1) / kGridCellPx;
    c.smoothLeaves = int(buf[0] / 6);
    c.fetchLeaves = int(buf[4] / 6);
    for (int list = 0; list < 2; ++list)
        for (int i = 0; i < (list == 0 ? c.smoothLeaves : c.fetchLeaves); ++i) {
            const uint32_t entry = buf[8 + std::size_t(list) * listSize_ + std::size_t(i)], cell = entry / 5, slot = entry % 5;
            int side = kGridCellPx, ox = 0, oy = 0;
            if (slot >= 1) {
                side = kGridCellPx / 2;
                ox = int((slot - 1) & 1) * side;
                oy = int((slot - 1) >> 1) * side;
            }
            const int x0 = int(cell) % gx * kGridCellPx + ox, y0 = int(cell) / gx * kGridCellPx + oy;
            const long area = long(std::max(std::min(x0 + side, cam.width) - x0, 0)) * long(std::max(std::min(y0 + side, cam.height) - y0, 0));
            (list == 0 ? c.smoothPixels : c.fetchPixels) += area;
        }
    return c;
}

// The per-pixel path's (azimuth, elevation) table, refilled over frames as the grid's
// (updateOctTable: the same rules, in rows of the table): the mix or the table's size changed (no
// elevation held) or slices 1: the whole table now; the light moved past the tolerance: a refill
// into tableBack_, ne / slices rows a frame, made for where the light will be midway through its
// turn on screen, restarted at a jump; the table drawn meanwhile is turned onto the light (doRender).
void Halos::updatePixelTable(double el, int slices) {
    const halos::HaloTables& t = *tables_;
    const int ne = t.q.ne;
    if (refillFrame(pix_, el, false, slices, ne, [&](bool back, double e, int r0, int r1) { fillPixelRows(back ? tableBack_ : table_, e, r0, r1); }))
        std::swap(table_, tableBack_);
}

void Halos::fillPixelRows(gl::Texture2D& target, double el, int r0, int r1) {
    // The light's elevation between two slices (evenly over [0, 90] deg): sliceBlend.
    const halos::HaloTables& t = *tables_;
    const SliceBlend b = sliceBlend(t, el);
    const std::size_t na = std::size_t(t.q.na);
    tableRows_.resize(std::size_t(r1 - r0) * na);
    for (int ie = r0; ie < r1; ++ie) {
        const RowLerp e0 = rowLerp(t, ie + rowShift(t, ie, b.shift0)), e1 = rowLerp(t, ie + rowShift(t, ie, b.shift1));
        const RowLerp q0 = rowLerp(t, ie + b.shift0), q1 = rowLerp(t, ie + b.shift1);
        for (int ia = 0; ia < t.q.na; ++ia)
            tableRows_[std::size_t(ie - r0) * na + std::size_t(ia)] =
                (sampleRow(mix_, b.s0, e0, ia, t) + sampleRow(mixShift_, b.s0, q0, ia, t)) * (1.0f - b.a) +
                (sampleRow(mix_, b.s1, e1, ia, t) + sampleRow(mixShift_, b.s1, q1, ia, t)) * b.a;
    }
    // Inside a frame the pixel-store parameters are GL's defaults and no unpack buffer is bound
    // (docs/writing-an-element.md): tightly packed rows.
    glTextureSubImage2D(target.id(), 0, 0, r0, t.q.na, r1 - r0, GL_RGBA, GL_FLOAT, tableRows_.data());
}

std::vector<float> Halos::readPixelTable() const { return table_ ? table_.readRgbaFloat() : std::vector<float>{}; }

std::vector<float> Halos::readGridTable() const { return octTable_ ? octTable_.readRgbaFloat() : std::vector<float>{}; }

void Halos::doStats(nlohmann::json& root) const {
    if (!tables_) return;
    root["halos"]["table_quality"] = tables_->q.name;
    root["halos"]["table_seconds"] = tables_->buildSeconds;
    root["halos"]["table_from_cache"] = tables_->fromCache;
    if (octN_ > 0) {
        root["halos"]["grid_table_texels"] = octN_;
        root["halos"]["grid_table_update_ms"] = oct_.updateMs;
        root["halos"]["grid_table_rows_last_frame"] = oct_.rowsLast;
        root["halos"]["grid_adaptive_cells"] = adaptive_;
        root["halos"]["grid_cells_drawn"] = listsDrawn_;
        root["halos"]["grid_cells_ms"] = cellsMs_;
        root["halos"]["grid_fine_scale"] = adaptive_ ? fineScale_ : 0;
        root["halos"]["grid_fine_table_ms"] = fineMs_;
    }
    if (!std::isnan(pix_.held)) {
        root["halos"]["pixel_table_update_ms"] = pix_.updateMs;
        root["halos"]["pixel_table_rows_last_frame"] = pix_.rowsLast;
    }
}

void Halos::doRelease() {
    programs_.releasePrograms();
    gridPrograms_.releasePrograms();
    finePrograms_.releasePrograms();
    smoothPrograms_.releasePrograms();
    cellPrograms_.releasePrograms();
    fineProgram_ = {};
    octFine_ = {};
    fineVersion_ = ~uint64_t(0);
    octMean_ = {};
    octMeanBack_ = {};
    octDetail_ = {};
    octDetailBack_ = {};
    octCpu_.clear();
    cellBuf_ = {};
    listSize_ = 0;
    cellsKey_.clear();
    lastKey_.clear();
    listsDrawn_ = false;
    table_ = {};
    tableBack_ = {};
    pix_.backRow = -1;
    octTable_ = {};
    octBack_ = {};
    oct_.backRow = -1;
    octRemap_.clear();
    octLayer_.clear();
    octN_ = 0;
    oct_.held = NAN;
    cloudUbo_ = {};
    tables_ = nullptr;
    mix_.clear();
    mixShift_.clear();
    pix_.held = NAN;
}

}  // namespace welkin::elements

WELKIN_ELEMENT_DESCRIPTOR(halos) {
    static const welkin::ElementDescriptor d{"halos",
                                             "ice-crystal halos (22/46 deg halos, sundogs, arcs) from ray-traced crystal tables, where the light shines "
                                             "through cirrus or a crystal layer (skyelements/halos/README.md)",
                                             welkin::Layer::Foreground, false, [] { return std::make_unique<welkin::elements::Halos>(); }};
    return d;
}
