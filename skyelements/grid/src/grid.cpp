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
#include <functional>
#include <numbers>
#include <vector>

namespace welkin::elements {

namespace {
constexpr int kTableN = 64;  // GRID_TABLE_N: refraction samples over apparent altitude
constexpr double kTableLo = -5.0 * std::numbers::pi / 180.0;
constexpr double kTableSpan = 95.0 * std::numbers::pi / 180.0;
constexpr int kTilePx = 4;  // side of the tiles the lines mark (pixels)

// The tiles of the image that the grid's lines can reach: grid.frag.glsl runs only there (one quad
// per run of marked tiles in a row), so the grid costs in proportion to its lines' pixels. The
// marking is conservative: a tile is marked if any part of it lies within a line's angular
// half-width plus its antialiasing (mapped to pixels by the largest local pixel scale) plus a
// margin; the fragment shader still decides every pixel's coverage exactly as a fullscreen pass
// would, so the image is the same.
struct TileMask {
    int tilesX = 0, tilesY = 0;
    std::vector<unsigned char> marked;
    TileMask(int w, int h) : tilesX((w + kTilePx - 1) / kTilePx), tilesY((h + kTilePx - 1) / kTilePx), marked(size_t(tilesX) * tilesY, 0) {}
    // Marks the tiles meeting the square of half-side r (pixels) around p (pixels, y down).
    void mark(glm::dvec2 p, double rx, double ry) {
        const double x0 = std::floor((p.x - rx) / kTilePx), x1 = std::floor((p.x + rx) / kTilePx);
        const double y0 = std::floor((p.y - ry) / kTilePx), y1 = std::floor((p.y + ry) / kTilePx);
        if (!(x1 >= 0 && y1 >= 0 && x0 < tilesX && y0 < tilesY)) return;  // off the image (or NaN)
        const int i0 = int(std::max(x0, 0.0)), i1 = int(std::min(x1, double(tilesX - 1)));
        const int j0 = int(std::max(y0, 0.0)), j1 = int(std::min(y1, double(tilesY - 1)));
        for (int j = j0; j <= j1; ++j) std::fill_n(&marked[size_t(j) * tilesX + i0], i1 - i0 + 1, 1);
    }
};

// Marks the tiles along the curve t -> curve(t) (unit ENU directions as drawn, t in [t0, t1]
// radians of a parameter proportional to arc length), each point with an angular half-width
// `halfRad`. Steps so that consecutive points in view are at most kTilePx / 2 pixels apart, and
// bisects to within 1e-6 rad of where the curve enters or leaves the view (a fisheye's rim, the
// side of a perspective camera, the equirect seam).
void traceCurve(TileMask& mask, const Camera& cam, const std::function<glm::dvec3(double)>& curve, double t0, double t1,
                double halfRad, double pxRad) {
    constexpr double kMaxStepPx = 0.5 * kTilePx;
    // The step where the curve is not in view: 8 centre pixels (a curve in view for less than
    // that lies in the margin, not the image), at most 1 deg.
    const double kHiddenStep = std::clamp(8.0 * pxRad, 1e-5, std::numbers::pi / 180.0);
    constexpr double kMinStep = 1e-6;
    constexpr double margin = 64.0;  // "in view": within this many pixels of the image
    const double maxScale = 4.0 * (cam.width + cam.height);  // pixels per radian, cap (equirect poles)
    auto onImage = [&](const glm::dvec3& d) -> std::optional<glm::dvec2> {
        auto p = cam.pixelOf(d);
        if (p && (p->x < -margin || p->y < -margin || p->x > cam.width + margin || p->y > cam.height + margin)) p.reset();
        return p;
    };
    // The curve's point at t if it is in view; else the edge of its band (the point `halfRad`
    // across the curve, either side) if that is: a line just off a cube face or below a
    // fisheye's horizon still reaches into the image by its width.
    struct Seen {
        glm::dvec3 d;
        glm::dvec2 p;
    };
    auto inView = [&](double t) -> std::optional<Seen> {
        const glm::dvec3 d = curve(t);
        if (auto p = onImage(d)) return Seen{d, *p};
        const glm::dvec3 n = glm::cross(d, curve(t + 1e-4) - d);
        if (glm::length(n) < 1e-12) return std::nullopt;
        for (double side : {-1.0, 1.0}) {
            const glm::dvec3 e = glm::normalize(d + side * std::tan(halfRad) * glm::normalize(n));
            if (auto p = onImage(e)) return Seen{e, *p};
        }
        return std::nullopt;
    };
    auto markAt = [&](const Seen& s) {
        const auto sc = cam.pixelScale(s.d);
        // A point of the curve is within half a step of a sample; 0.5 px more for the rounding of
        // the scale along the step.
        const double r = halfRad * std::min(sc ? sc->y : maxScale, maxScale) + 0.5 * kMaxStepPx + 0.5;
        mask.mark(s.p, r, r);
    };
    double t = t0, dt = kHiddenStep;
    std::optional<Seen> p = inView(t);
    if (p) markAt(*p);
    while (t < t1) {
        dt = std::min(dt, t1 - t);
        const std::optional<Seen> pn = inView(t + dt);
        const bool edge = bool(p) != bool(pn);
        const bool far = p && pn && glm::length(pn->p - p->p) > kMaxStepPx;
        if ((edge || far) && dt > kMinStep) {
            dt *= 0.5;
            continue;
        }
        t += dt;
        if (pn) markAt(*pn);
        if (p && pn && glm::length(pn->p - p->p) < 0.25 * kMaxStepPx) dt *= 2.0;
        else if (!p && !pn) dt = std::min(2.0 * dt, kHiddenStep);
        p = pn;
    }
}

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
    option(gridkeys::tiled, true);
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
                                           .vertex("grid/grid.vert.glsl", embedded::grid_shaders("grid.vert.glsl"))
                                           .fragment("engine/camera.glsl", gl::engineShader("camera.glsl"))
                                           .fragment("engine/composite.glsl", gl::engineShader("composite.glsl"))
                                           .fragment("grid/grid.frag.glsl", embedded::grid_shaders("grid.frag.glsl")));
    programs_.get(Projection::Perspective);  // shader errors surface in init()
    vao_ = gl::VertexArray::create();
    glEnableVertexArrayAttrib(vao_.id(), 0);
    glVertexArrayAttribFormat(vao_.id(), 0, 4, GL_FLOAT, GL_FALSE, 0);
    glVertexArrayAttribBinding(vao_.id(), 0, 0);
    glVertexArrayBindingDivisor(vao_.id(), 0, 1);
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
    const glm::dmat3 icrsToEnu = v.getOr(astro::keys::starFrameRotation, glm::dmat3(1.0));
    float refr[kTableN];
    if (frameBits & 6) {
        // ENU -> ICRS (the transpose of the star frame's rotation), and the refraction to take off
        // an apparent altitude (a table over apparent altitude, like the Stars element's).
        program_.set("u_enuToIcrs", glm::mat3(glm::transpose(icrsToEnu)));
        program_.set("u_raStep", float(v.get(gridkeys::raStep)));
        program_.set("u_decStep", float(v.get(gridkeys::decStep)));
        // The J2000 mean ecliptic's north pole in ICRS axes (obliquity IAU 2006, 84381.406").
        const double eps = 84381.406 / 3600.0 * gridkeys::kDeg;
        program_.set("u_eclipticPole", glm::vec3(0.0f, float(-std::sin(eps)), float(std::cos(eps))));
        const double P = v.getOr(astro::keys::refractionPressure, 1013.25), Tc = v.getOr(astro::keys::refractionTemperature, 10.0);
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
    program_.set("u_sizePx", glm::vec2(float(ctx.camera.width), float(ctx.camera.height)));

    vao_.bind();
    if (!(tiled_ && ctx.vars.get(gridkeys::tiled))) {  // the whole image: one run per row of tiles
        std::vector<float> rows;
        for (int y = 0; y < ctx.camera.height; y += kTilePx)
            for (float f : {0.0f, float(y), float(ctx.camera.width), float(std::min(y + kTilePx, ctx.camera.height))}) rows.push_back(f);
        drawRuns(rows);
        shadedPixels_ = (long long)ctx.camera.width * ctx.camera.height;
        return;
    }
    // The tiles the lines reach (TileMask): the angular half-width of each line plus its
    // antialiasing (grid.frag.glsl: half a centre pixel's angle), 25 % more for safety.
    const Camera& cam = ctx.camera;
    double pxRad = 0;  // welkin_pixelAngle(): the angle of a pixel at the image centre
    switch (cam.projection) {
        case Projection::Perspective: pxRad = 2.0 * std::tan(0.5 * cam.verticalFovRad) / cam.height; break;
        case Projection::Fisheye: pxRad = std::numbers::pi / std::min(cam.width, cam.height); break;
        case Projection::Equirect: pxRad = std::numbers::pi / cam.height; break;
        case Projection::CubeFace: pxRad = 2.0 / cam.height; break;
    }
    if (cam.host) {  // the host's own projection: the centre pixel's angle from its scale
        if (auto d = cam.directionAt({0.5 * cam.width, 0.5 * cam.height}))
            if (auto sc = cam.pixelScale(*d)) pxRad = std::max(pxRad, 1.0 / sc->x);
    }
    auto half = [&](double widthPx) { return 1.25 * (0.5 * widthPx + 0.5) * pxRad; };
    const double lineHalf = half(v.get(gridkeys::lineWidth));
    TileMask mask(cam.width, cam.height);
    constexpr double kPi = std::numbers::pi;
    auto trace = [&](const std::function<glm::dvec3(double)>& f, double t0, double t1, double h) { traceCurve(mask, cam, f, t0, t1, h, pxRad); };
    if (frameBits & 1) {
        const double altStep = v.get(gridkeys::altitudeStep), azStep = v.get(gridkeys::azimuthStep);
        for (int k = -int(std::floor(0.5 * kPi / altStep)); k <= int(std::floor(0.5 * kPi / altStep)); ++k) {
            const double alt = k * altStep;
            trace([&](double t) { return directionFromAzAlt(t, alt); }, 0.0, 2.0 * kPi, k == 0 ? std::max(lineHalf, half(v.get(gridkeys::horizonWidth))) : lineHalf);
        }
        const int n = int(std::ceil(kPi / azStep));
        for (int k = -n; k <= n; ++k) {
            const double az = k * azStep;
            trace([&](double t) { return directionFromAzAlt(az, t); }, -0.5 * kPi, 0.5 * kPi, lineHalf);
        }
    }
    if (frameBits & 6) {
        // ICRS (geometric) -> the apparent ENU direction the shader draws it at: the inverse of its
        // table (apparent a -> geometric a - T(a)), by fixed-point iteration (T changes slowly).
        auto table = [&](double a) {
            const double x = std::sqrt(std::clamp((a - kTableLo) / kTableSpan, 0.0, 1.0)) * (kTableN - 1);
            const int i = std::min(int(x), kTableN - 2);
            return refr[i] + (refr[i + 1] - refr[i]) * (x - i);
        };
        auto apparent = [&](const glm::dvec3& icrs) {
            const glm::dvec3 e = icrsToEnu * icrs;
            const double g = std::asin(std::clamp(e.z, -1.0, 1.0)), h = std::hypot(e.x, e.y);
            double a = g;
            for (int it = 0; it < 6; ++it) a = g + table(a);
            const glm::dvec2 sc = h > 0 ? glm::dvec2(e.x, e.y) / h : glm::dvec2(0.0, 1.0);
            return glm::dvec3(sc * std::cos(a), std::sin(a));
        };
        if (frameBits & 2) {
            const double decStep = v.get(gridkeys::decStep), raStep = v.get(gridkeys::raStep);
            for (int k = -int(std::floor(0.5 * kPi / decStep)); k <= int(std::floor(0.5 * kPi / decStep)); ++k) {
                const double dec = k * decStep;
                trace([&](double t) { return apparent({std::cos(dec) * std::cos(t), std::cos(dec) * std::sin(t), std::sin(dec)}); }, 0.0,
                      2.0 * kPi, lineHalf);
            }
            const int n = int(std::ceil(kPi / raStep));
            for (int k = -n; k <= n; ++k) {
                const double ra = k * raStep;
                trace([&](double t) { return apparent({std::cos(t) * std::cos(ra), std::cos(t) * std::sin(ra), std::sin(t)}); }, -0.5 * kPi,
                      0.5 * kPi, lineHalf);
            }
        }
        if (frameBits & 4) {  // the ecliptic: the great circle of pole (0, -sin e, cos e)
            const double eps = 84381.406 / 3600.0 * gridkeys::kDeg;
            const glm::dvec3 u(1, 0, 0), w(0, std::cos(eps), std::sin(eps));
            trace([&](double t) { return apparent(std::cos(t) * u + std::sin(t) * w); }, 0.0, 2.0 * kPi, half(1.5 * v.get(gridkeys::lineWidth)));
        }
    }
    for (const glm::vec4& m : pos)
        if (m.z > 0.5f) mask.mark({m.x, m.y}, 2.5 * scale + 2.0, 3.5 * scale + 2.0);  // the 5x7 glyph cells
    // One instance per run of marked tiles in a row.
    std::vector<float> rects;
    for (int j = 0; j < mask.tilesY; ++j)
        for (int i = 0; i < mask.tilesX;) {
            if (!mask.marked[size_t(j) * mask.tilesX + i]) {
                ++i;
                continue;
            }
            int e = i;
            while (e < mask.tilesX && mask.marked[size_t(j) * mask.tilesX + e]) ++e;
            const float r[4] = {float(i * kTilePx), float(j * kTilePx), float(std::min(e * kTilePx, cam.width)),
                                float(std::min((j + 1) * kTilePx, cam.height))};
            rects.insert(rects.end(), r, r + 4);
            i = e;
        }
    shadedPixels_ = 0;
    for (size_t i = 0; i < rects.size(); i += 4) shadedPixels_ += (long long)(rects[i + 2] - rects[i]) * (long long)(rects[i + 3] - rects[i + 1]);
    drawRuns(rects);
}

void Grid::drawRuns(const std::vector<float>& rects) {
    const int runs = int(rects.size() / 4);
    if (runs == 0) return;
    const size_t bytes = rects.size() * sizeof(float);
    if (buffer_.size() < bytes) buffer_ = gl::Buffer(std::max(bytes, buffer_.size() * 2));
    buffer_.update(rects.data(), bytes);
    glVertexArrayVertexBuffer(vao_.id(), 0, buffer_.id(), 0, 4 * sizeof(float));
    glDrawArraysInstanced(GL_TRIANGLES, 0, 6, runs);
}

void Grid::doRelease() {
    programs_.releasePrograms();
    vao_ = {};
    buffer_ = {};
}

}  // namespace welkin::elements

WELKIN_ELEMENT_DESCRIPTOR(grid) {
    static const welkin::ElementDescriptor d{"grid", "altitude/azimuth coordinate grid with the horizon and N/E/S/W markers",
                                             welkin::Layer::Overlay, false, [] { return std::make_unique<welkin::elements::Grid>(); }};
    return d;
}
