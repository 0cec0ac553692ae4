#include <welkin/check.hpp>
#include <welkin/elements/grid.hpp>
#include <welkin/embedded/grid_shaders.hpp>
#include <welkin/gl/shader.hpp>
#include <welkin/keys.hpp>

#include <epoxy/gl.h>

#include <cmath>

namespace welkin::elements {

void GridOptions::validate() const {
    auto check = [](const char* name, double v, double lo, double hi) { checkRange("Grid", name, v, lo, hi); };
    check("altitudeStepDeg", altitudeStepDeg, 1, 90);
    check("azimuthStepDeg", azimuthStepDeg, 1, 180);
    check("lineWidthPx", lineWidthPx, 0.5, 20);
    check("horizonWidthPx", horizonWidthPx, 0.5, 40);
    check("luminanceCdM2", luminanceCdM2, 0, 1e10);
}

Grid::Grid(const GridOptions& options) : SkyElement("grid"), options_(options) {
    options_.validate();
    reads(keys::exposureEv100);
}

void Grid::setOptions(const GridOptions& options) {
    options.validate();
    options_ = options;
}

void Grid::doInit(InitContext& ctx) {
    ctx.vars.declare(keys::exposureEv100, 15.0);
    programs_ = gl::ProjectionPrograms(gl::ProgramBuilder("Grid")
                                           .fullscreenVertex()
                                           .fragment("engine/camera.glsl", gl::engineShader("camera.glsl"))
                                           .fragment("engine/composite.glsl", gl::engineShader("composite.glsl"))
                                           .fragment("grid/grid.frag.glsl", embedded::grid_shaders("grid.frag.glsl")));
    programs_.get(Projection::Perspective);  // shader errors surface in init()
}

void Grid::doRender(const FrameContext& ctx) {
    double L = options_.luminanceCdM2;
    if (L <= 0) L = 0.8 * 1.2 * std::exp2(ctx.vars.get(keys::exposureEv100));  // ~80 % of white
    const gl::Program& program_ = programs_.get(ctx.camera.projection);
    program_.use();
    program_.set("u_altStep", float(options_.altitudeStepDeg * M_PI / 180));
    program_.set("u_azStep", float(options_.azimuthStepDeg * M_PI / 180));
    program_.set("u_lineWidthPx", float(options_.lineWidthPx));
    program_.set("u_horizonWidthPx", float(options_.horizonWidthPx));
    program_.set("u_luminance", float(L));
    // Cardinal markers: placed in pixel space so the letters read upright in every projection.
    static constexpr double kAz[4] = {0, M_PI / 2, M_PI, 3 * M_PI / 2};  // N, E, S, W
    glm::vec4 pos[4];
    for (int i = 0; i < 4; ++i) {
        auto p = ctx.camera.pixelOf(directionFromAzAlt(kAz[i], kMarkerAltitudeRad));
        pos[i] = (p && options_.markers) ? glm::vec4(float(p->x), float(p->y), 1, 0) : glm::vec4(0);
    }
    glProgramUniform4fv(program_.id(), program_.location("u_markers"), 4, &pos[0].x);
    float scale = std::max(1.0f, std::round(float(std::min(ctx.camera.width, ctx.camera.height)) / 128.0f));
    program_.set("u_glyphScale", scale);
    ctx.drawFullscreen();
}

void Grid::doRelease() { programs_.releasePrograms(); }

}  // namespace welkin::elements
