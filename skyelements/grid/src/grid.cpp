#include <welkin/astro/astro_keys.hpp>
#include <welkin/astro/frames.hpp>
#include <welkin/check.hpp>
#include <welkin/elements/grid.hpp>
#include <welkin/error.hpp>
#include <welkin/embedded/grid_shaders.hpp>
#include <welkin/gl/shader.hpp>
#include <welkin/keys.hpp>

#include <epoxy/gl.h>

#include <algorithm>
#include <cmath>
#include <numbers>

namespace welkin::elements {

namespace {
constexpr int kTableN = 64;  // GRID_TABLE_N: refraction samples over apparent altitude
constexpr double kTableLo = -5.0 * std::numbers::pi / 180.0;
constexpr double kTableSpan = 95.0 * std::numbers::pi / 180.0;
void checkFrame(const std::string& f, const char* where) {
    if (f != "horizontal" && f != "equatorial" && f != "both")
        throw Error(std::string(where) + ": '" + f + "' is not one of horizontal, equatorial, both");
}
}  // namespace

void GridOptions::validate() const {
    auto check = [](const char* name, double v, double lo, double hi) { checkRange("Grid", name, v, lo, hi); };
    check("altitudeStepDeg", altitudeStepDeg, 1, 90);
    check("azimuthStepDeg", azimuthStepDeg, 1, 180);
    check("lineWidthPx", lineWidthPx, 0.5, 20);
    check("horizonWidthPx", horizonWidthPx, 0.5, 40);
    check("luminanceCdM2", luminanceCdM2, 0, 1e10);
    check("raStepDeg", raStepDeg, 1, 180);
    check("decStepDeg", decStepDeg, 1, 90);
    checkFrame(frame, "Grid: frame");
}

void Grid::doValidateOptions(const SkyVars& v) const { checkFrame(v.get(gridkeys::frame), "grid.frame"); }

Grid::Grid() : Grid(GridOptions{}, false) {}

Grid::Grid(const GridOptions& options) : Grid(options, true) {}

Grid::Grid(const GridOptions& o, bool force) : SkyElement("grid") {
    setContributesToLighting(false);  // overlay: not light from the sky
    o.validate();
    option(gridkeys::altitudeStep, o.altitudeStepDeg * gridkeys::kDeg, force);
    option(gridkeys::azimuthStep, o.azimuthStepDeg * gridkeys::kDeg, force);
    option(gridkeys::lineWidth, o.lineWidthPx, force);
    option(gridkeys::horizonWidth, o.horizonWidthPx, force);
    option(gridkeys::luminance, o.luminanceCdM2, force);
    option(gridkeys::markers, o.markers, force);
    option(gridkeys::frame, o.frame, force);
    option(gridkeys::raStep, o.raStepDeg * gridkeys::kDeg, force);
    option(gridkeys::decStep, o.decStepDeg * gridkeys::kDeg, force);
    option(gridkeys::ecliptic, o.ecliptic, force);
    reads(keys::exposureEv100);
    reads(astro::keys::starFrameRotation);
    reads(astro::keys::refractionPressure);
    reads(astro::keys::refractionTemperature);
}

void Grid::doInit(InitContext& ctx) {
    declareOptions(ctx.vars);
    ctx.vars.declare(keys::exposureEv100, 15.0);
    programs_ = gl::ProjectionPrograms(gl::ProgramBuilder("Grid")
                                           .define("GRID_TABLE_N", kTableN)
                                           .fullscreenVertex()
                                           .fragment("engine/camera.glsl", gl::engineShader("camera.glsl"))
                                           .fragment("engine/composite.glsl", gl::engineShader("composite.glsl"))
                                           .fragment("grid/grid.frag.glsl", embedded::grid_shaders("grid.frag.glsl")));
    programs_.get(Projection::Perspective);  // shader errors surface in init()
}

void Grid::doRender(const FrameContext& ctx) {
    const SkyVars& v = ctx.vars;
    double L = v.get(gridkeys::luminance);
    if (L <= 0) L = 0.8 * 1.2 * std::exp2(v.get(keys::exposureEv100));  // ~80 % of white
    validateOptions(v);
    const std::string frame = v.get(gridkeys::frame);
    const int frameBits = (frame != "equatorial" ? 1 : 0) | (frame != "horizontal" ? 2 : 0) | (v.get(gridkeys::ecliptic) ? 4 : 0);
    const bool markers = v.get(gridkeys::markers) && (frameBits & 1);
    const gl::Program& program_ = programs_.get(ctx.camera.projection);
    program_.use();
    program_.set("u_altStep", float(v.get(gridkeys::altitudeStep)));
    program_.set("u_azStep", float(v.get(gridkeys::azimuthStep)));
    program_.set("u_lineWidthPx", float(v.get(gridkeys::lineWidth)));
    program_.set("u_horizonWidthPx", float(v.get(gridkeys::horizonWidth)));
    program_.set("u_luminance", float(L));
    program_.set("u_frame", frameBits);
    if (frameBits & 6) {
        // ENU -> ICRS (the transpose of the star frame's rotation), and the refraction to take off
        // an apparent altitude (a table over apparent altitude, like the Stars element's).
        program_.set("u_enuToIcrs", glm::mat3(glm::transpose(v.getOr(astro::keys::starFrameRotation, glm::dmat3(1.0)))));
        program_.set("u_raStep", float(v.get(gridkeys::raStep)));
        program_.set("u_decStep", float(v.get(gridkeys::decStep)));
        // The J2000 mean ecliptic's north pole in ICRS axes (obliquity IAU 2006, 84381.406").
        const double eps = 84381.406 / 3600.0 * gridkeys::kDeg;
        program_.set("u_eclipticPole", glm::vec3(0.0f, float(-std::sin(eps)), float(std::cos(eps))));
        const double P = v.getOr(astro::keys::refractionPressure, 1013.25), Tc = v.getOr(astro::keys::refractionTemperature, 10.0);
        float refr[kTableN];
        for (int i = 0; i < kTableN; ++i) {
            const double u = double(i) / (kTableN - 1), h = kTableLo + kTableSpan * u * u;
            refr[i] = float(h - astro::geometricFromApparentAltitude(h, P, Tc));
        }
        glProgramUniform1fv(program_.id(), program_.location("u_refrApparent"), kTableN, refr);
    }
    // Cardinal markers: placed in pixel space so the letters read upright in every projection.
    static constexpr double kAz[4] = {0, M_PI / 2, M_PI, 3 * M_PI / 2};  // N, E, S, W
    glm::vec4 pos[4];
    for (int i = 0; i < 4; ++i) {
        auto p = ctx.camera.pixelOf(directionFromAzAlt(kAz[i], kMarkerAltitudeRad));
        pos[i] = (p && markers) ? glm::vec4(float(p->x), float(p->y), 1, 0) : glm::vec4(0);
    }
    glProgramUniform4fv(program_.id(), program_.location("u_markers"), 4, &pos[0].x);
    float scale = std::max(1.0f, std::round(float(std::min(ctx.camera.width, ctx.camera.height)) / 128.0f));
    program_.set("u_glyphScale", scale);
    ctx.drawFullscreen();
}

void Grid::doRelease() { programs_.releasePrograms(); }

}  // namespace welkin::elements

WELKIN_ELEMENT_DESCRIPTOR(grid) {
    static const welkin::ElementDescriptor d{"grid", "altitude/azimuth coordinate grid with the horizon and N/E/S/W markers",
                                             welkin::Layer::Overlay, false, [] { return std::make_unique<welkin::elements::Grid>(); }};
    return d;
}
