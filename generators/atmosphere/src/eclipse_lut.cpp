// The Moon's shadow on the air: EclipseSkyLut (GPU pass eclipse_lut.glsl; CPU twin
// cpu::eclipseRadiance in sky_model.cpp).
#include <welkin/astro/astro_keys.hpp>
#include <welkin/embedded/atmosphere_shaders.hpp>
#include <welkin/error.hpp>
#include <welkin/generators/sky_luts.hpp>
#include <welkin/gl/shader.hpp>
#include <welkin/keys.hpp>

#include <epoxy/gl.h>

#include <algorithm>
#include <cmath>

namespace welkin::generators {

EclipseSkyLut::EclipseSkyLut() : SkyGenerator("sky.eclipse_view") {
    input(skykeys::transmittanceLuts);
    input(skykeys::multiScatteringLuts);
    input(skykeys::shLuts);
    input(keys::observerHeight);
    input(keys::sunDirection);
    input(astro::keys::moonPosition, {.optional = true});
    input(astro::keys::sunDistance, {.optional = true});
    input(astro::keys::eclipses, {.optional = true});
    output(skykeys::eclipseViewLut);
    output(skykeys::eclipseViewMieLut);
    output(skykeys::eclipseViewTotalLut);
}

void EclipseSkyLut::releaseGl() {
    smooth_ = {};
    mie_ = {};
    total_ = {};
    backSmooth_ = {};
    backMie_ = {};
    backTotal_ = {};
    msTex_ = {};
    backMsTex_ = {};
    fbo_ = {};
    backFbo_ = {};
    prog_ = {};
    active_ = published_ = false;
    nextBand_ = -1;
    msBuilder_.reset();
    haveLast_ = false;
    releaseCommon();
}

namespace {
// Where the shadow's axis (the Moon's centre towards the Sun's) crosses the plane through the
// observer perpendicular to it, ENU m.
glm::dvec3 axisCrossing(const glm::dvec3& moonPos, const glm::dvec3& sunPos) {
    const glm::dvec3 a = glm::normalize(sunPos - moonPos);
    return moonPos - a * glm::dot(moonPos, a);
}
}  // namespace

void EclipseSkyLut::bindMsField(const gl::Program& p) const {
    glBindTextureUnit(kEclipseMsFieldUnit, msTex_.id());
    p.set("u_eclMsField", kEclipseMsFieldUnit);
    p.set("u_eclMsE1", glm::vec3(shownMs_.e1));
    p.set("u_eclMsE2", glm::vec3(shownMs_.e2));
    p.set("u_eclMsCentre", glm::vec2(shownMs_.centre));
    p.set("u_eclMsHalf", msTex_ ? float(shownMs_.halfExtentMeters) : 0.0f);
}

int EclipseSkyLut::fieldPiecesFor(long pixels) {
    if (pixels <= 0) return 1;
    return int(std::clamp(std::ceil(kEclipseFieldPixels / double(pixels)), 1.0, double(kEclipseMaxFieldPieces)));
}

int EclipseSkyLut::bandsFor(long pixels, int W, int H) {
    if (pixels <= 0) return kEclipseTimeSlices;
    const double maxTexels = std::max(double(pixels) / kEclipseBandPixelsPerTexel, 1.0);
    const double n = std::ceil(double(W) * double(H) / maxTexels);
    return int(std::clamp(n, double(kEclipseTimeSlices), double(kEclipseMaxTimeSlices)));
}

// Band k of buildBands_: up to the table's height, bands of rows; beyond it, each row band cut
// into `cols` tiles of columns.
void EclipseSkyLut::renderTile(int k) {
    const int W = backSmooth_.width(), H = backSmooth_.height(), n = buildBands_;
    const int cols = std::max(1, (n + H - 1) / H), rows = (n + cols - 1) / cols;
    const int r = k / cols, c = k % cols;
    renderBand(c * W / cols, (c + 1) * W / cols, r * H / rows, (r + 1) * H / rows);
}

void EclipseSkyLut::renderBand(int x0, int x1, int y0, int y1) {
    const int W = backSmooth_.width(), H = backSmooth_.height();
    const long texels = long(x1 - x0) * long(y1 - y0);
    largestBand_ = std::max(largestBand_, texels);
    buildTexels_ += texels;
    backFbo_.bind();
    glViewport(0, 0, W, H);
    glEnable(GL_SCISSOR_TEST);
    glScissor(x0, y0, x1 - x0, y1 - y0);
    const GLenum bufs[3] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1, GL_COLOR_ATTACHMENT2};
    glNamedFramebufferDrawBuffers(backFbo_.id(), 3, bufs);
    const Build& b = building_;
    prog_.use();
    prog_.set("u_h", float(b.h));
    prog_.set("u_sunDir", glm::vec3(b.sunDir));
    prog_.set("u_steps", q_.skyViewSteps);
    prog_.set("u_size", glm::ivec2(W, H));
    prog_.set("u_scale", float(kLutScale));
    prog_.set("u_angular", float(model_.sunAngularRadius));
    prog_.set("u_eclMoonPos", glm::vec3(b.moonPos));
    prog_.set("u_eclMoonRadius", float(astro::keys::kMoonRadiusMeters));
    prog_.set("u_eclSunPos", glm::vec3(b.sunDir * b.sunDist));
    prog_.set("u_eclSunRadius", float(kSunRadiusMeters));
    glBindTextureUnit(kEclipseMsFieldUnit, backMsTex_.id());
    prog_.set("u_eclMsField", kEclipseMsFieldUnit);
    prog_.set("u_eclMsE1", glm::vec3(buildingMs_.e1));
    prog_.set("u_eclMsE2", glm::vec3(buildingMs_.e2));
    prog_.set("u_eclMsCentre", glm::vec2(buildingMs_.centre));
    prog_.set("u_eclMsHalf", float(buildingMs_.halfExtentMeters));
    fullscreen();
    glDisable(GL_SCISSOR_TEST);
    glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_FRAMEBUFFER_BARRIER_BIT);
}

bool EclipseSkyLut::shadowNear(const glm::dvec3& sunDir, double sunAngularRadius, const glm::dvec3& moonPos, double reachMeters) {
    const double dm = glm::length(moonPos);
    if (!(dm > astro::keys::kMoonRadiusMeters)) return false;
    const glm::dvec3 m = moonPos / dm, s = glm::normalize(sunDir);
    const double sep = 2.0 * std::asin(std::min(0.5 * glm::length(m - s), 1.0));
    const double ro = std::asin(astro::keys::kMoonRadiusMeters / dm);
    // From a point `reach` metres away the Moon moves by at most reach / dm (the Sun by ~1e-6 of
    // that): 1e-4 rad of margin.
    return sep < sunAngularRadius + ro + reachMeters / dm + 1e-4;
}

void EclipseSkyLut::doRun(SkyVars& vars, const Logger&) {
    prepare(vars);
    const double Ht = model_.topRadius - model_.bottomRadius;
    const double h = std::clamp(vars.getOr(keys::observerHeight, 0.0), 0.0, Ht);
    const glm::dvec3 sunDir = glm::normalize(vars.get(keys::sunDirection));
    const bool haveMoon = vars.has(astro::keys::moonPosition) && vars.getOr(astro::keys::eclipses, true);
    const glm::dvec3 moonPos = haveMoon ? vars.get(astro::keys::moonPosition) : glm::dvec3(0.0);
    // The farthest air a sky-view ray reaches: the horizontal ray to the top of the atmosphere
    // (rays below the horizon end on the ground, nearer). The multiple-scattering field differs
    // from the fraction only near the umbra, which is inside the penumbra this tests.
    const double R = model_.bottomRadius, r = R + h, reach = std::sqrt(std::max(model_.topRadius * model_.topRadius - r * r, 0.0));
    const bool want = haveMoon && !spectral_ && sunDir.z > kDarkBelowCosZenith &&
                      shadowNear(sunDir, model_.sunAngularRadius, moonPos, reach);
    if (!want) {
        if (active_ || !published_) {
            vars.publish(skykeys::eclipseViewLut, TextureRef{});
            vars.publish(skykeys::eclipseViewMieLut, TextureRef{});
            vars.publish(skykeys::eclipseViewTotalLut, TextureRef{});
        }
        active_ = false;
        published_ = true;
        nextBand_ = -1;
        msBuilder_.reset();
        haveLast_ = false;
        return;
    }
    const int W = 2 * q_.skyViewW, H = q_.skyViewH;
    const GLenum fmt = q_.halfFloat ? GL_RGBA16F : GL_RGBA32F;
    if (!smooth_ || smooth_.width() != W || smooth_.height() != H || smooth_.internalFormat() != fmt) {
        for (gl::Texture2D* t : {&smooth_, &mie_, &total_, &backSmooth_, &backMie_, &backTotal_}) {
            *t = gl::Texture2D(W, H, fmt);
            t->setFilter(GL_LINEAR);
            t->setWrap(GL_CLAMP_TO_EDGE);
            glTextureParameteri(t->id(), GL_TEXTURE_WRAP_S, GL_REPEAT);  // the circle of azimuth
        }
        fbo_ = gl::Framebuffer::create();
        fbo_.attach(GL_COLOR_ATTACHMENT0, smooth_);
        fbo_.attach(GL_COLOR_ATTACHMENT1, mie_);
        fbo_.attach(GL_COLOR_ATTACHMENT2, total_);
        fbo_.checkComplete("EclipseSkyLut");
        backFbo_ = gl::Framebuffer::create();
        backFbo_.attach(GL_COLOR_ATTACHMENT0, backSmooth_);
        backFbo_.attach(GL_COLOR_ATTACHMENT1, backMie_);
        backFbo_.attach(GL_COLOR_ATTACHMENT2, backTotal_);
        backFbo_.checkComplete("EclipseSkyLut (back)");
        active_ = false;  // nothing shown yet: build whole
        nextBand_ = -1;
        msBuilder_.reset();
    }
    if (!prog_ || progBands_ != q_.shBands) {
        progBands_ = q_.shBands;
        prog_ = gl::ProgramBuilder(name())
                    .define("ATM_USE_TRANSMITTANCE")
                    .define("ATM_USE_MULTISCATTERING")
                    .define("ATM_MS_DIRECTIONAL")
                    .define("ATM_ECLIPSE")
                    .define("ATM_SH_BANDS", q_.shBands)
                    .fullscreenVertex()
                    .fragment("generators/atmosphere.glsl", embedded::atmosphere_shaders("atmosphere.glsl"))
                    .fragment("generators/eclipse_lut.glsl", embedded::atmosphere_shaders("eclipse_lut.glsl"))
                    .build();
    }
    const skykeys::TextureList T = vars.get(skykeys::transmittanceLuts), MS = vars.get(skykeys::multiScatteringLuts),
                               SH = vars.get(skykeys::shLuts);
    if (T->empty() || MS->empty() || SH->empty()) throw Error("EclipseSkyLut: no input LUTs");
    glBindTextureUnit(gl::binding::kTransmittanceLut, (*T)[0].id);
    glBindTextureUnit(gl::binding::kMultiScatteringLut, (*MS)[0].id);
    glBindTextureUnit(gl::binding::kShLut, (*SH)[0].id);
    const Build now{.sunDir = sunDir, .moonPos = moonPos, .h = h, .sunDist = vars.getOr(astro::keys::sunDistance, 1.496e11)};
    // How far the shadow has moved across the observer's air between two builds' geometries: the
    // axis' crossing, the Sun's turn seen at the farthest air (reach) and the observer's height.
    auto movedBetween = [&](const Build& a, const Build& b) {
        const double axis = glm::length(axisCrossing(a.moonPos, a.sunDir * a.sunDist) - axisCrossing(b.moonPos, b.sunDir * b.sunDist));
        const double turn = 2.0 * std::asin(std::min(0.5 * glm::length(a.sunDir - b.sunDir), 1.0)) * reach;
        return axis + turn + std::abs(a.h - b.h);
    };
    auto moved = [&](const Build& b) { return movedBetween(now, b); };
    // Since the previous run: a jump of the clock (set, not running) beyond kEclipseJumpMeters, or
    // the clock running (then the shadow's motion per run predicts where it will be).
    const bool haveLast = haveLast_;
    const double step = haveLast ? moved(last_) : 1e30;
    const bool jumped = step > kEclipseJumpMeters;
    const Build last = last_;
    last_ = now;
    haveLast_ = true;
    // The geometry `runs` runs ahead, extrapolated linearly from the last run's motion (the clock
    // running: the Moon's topocentric motion is smooth, its curvature over a minute ~0.1 km).
    auto ahead = [&](double runs) {
        if (jumped || !haveLast || !predict_) return now;
        Build b = now;
        b.moonPos = now.moonPos + (now.moonPos - last.moonPos) * runs;
        b.sunDir = glm::normalize(now.sunDir + (now.sunDir - last.sunDir) * runs);
        b.sunDist = now.sunDist + (now.sunDist - last.sunDist) * runs;
        b.h = std::clamp(now.h + (now.h - last.h) * runs, 0.0, Ht);
        return b;
    };
    auto uploadMs = [&] {
        const int n = buildingMs_.n;
        if (!backMsTex_ || backMsTex_.width() != n) {
            backMsTex_ = gl::Texture2D(n, n, GL_R32F);
            backMsTex_.setFilter(GL_LINEAR);
            backMsTex_.setWrap(GL_CLAMP_TO_EDGE);
        }
        backMsTex_.upload(GL_RED, GL_FLOAT, buildingMs_.d.data());
    };
    // A rebuild: the multiple-scattering field's CPU table (in fieldPieces_ runs of its own when
    // time runs, before the first band: docs/eclipse.md "Frame cost"), then the bands. `whole`:
    // all of it now (nothing shown, or a jump).
    const int bandsPlanned = explicitSlices_ ? std::clamp(slices_, 1, H) : bandsFor(framePixels_, W, H);
    const int piecesPlanned = explicitFieldPieces_ > 0 ? explicitFieldPieces_ : fieldPiecesFor(framePixels_);
    // The runs from a rebuild's start to the run that shows it: the field's runs (the last of them
    // renders the first band when there is one piece), the bands (whole tiles), the swap's run.
    const int tileCols = std::max(1, (bandsPlanned + H - 1) / H);
    const double leadRuns = double((piecesPlanned > 1 ? piecesPlanned : 0) + tileCols * ((bandsPlanned + tileCols - 1) / tileCols));
    auto startBuild = [&](bool whole) {
        buildBands_ = bandsPlanned;
        fieldPieces_ = whole ? 1 : piecesPlanned;
        // Built for where the shadow will be when the table is shown; when the shadow moves more
        // than kEclipseRebuildMeters in a rebuild's runs (the clock fast: rebuilds back to back,
        // each table shown for one rebuild's runs), for the middle of the runs it will be shown
        // in, so that it is half as far from the shadow at worst (ahead, then behind).
        const double cycle = leadRuns + 1.0;
        const bool backToBack = haveLast && !jumped && step * cycle > kEclipseRebuildMeters;
        building_ = whole ? now : ahead(backToBack ? leadRuns + 0.5 * cycle : leadRuns);
        const cpu::EclipseGeometry g{.moonPos = building_.moonPos, .moonRadius = astro::keys::kMoonRadiusMeters,
                                     .sunPos = building_.sunDir * building_.sunDist, .sunRadius = kSunRadiusMeters};
        msBuilder_.emplace(g, cpu::eclipseMsLength(g));
        nextBand_ = 0;
        largestBand_ = buildTexels_ = 0;
    };
    // One run's share of the field's table; true once it is finished (and uploaded).
    auto advanceField = [&](bool all) {
        if (!msBuilder_) return true;
        if (all || fieldPieces_ <= 1) {
            while (!msBuilder_->finished()) msBuilder_->step();
        } else {
            msBuilder_->advance(msBuilder_->totalWork() / fieldPieces_);
            ++fieldRuns_;
        }
        if (!msBuilder_->finished()) return false;
        buildingMs_ = msBuilder_->take();
        msBuilder_.reset();
        uploadMs();
        return true;
    };
    bool swapped = false;
    auto finish = [&] {
        std::swap(smooth_, backSmooth_);
        std::swap(mie_, backMie_);
        std::swap(total_, backTotal_);
        std::swap(fbo_, backFbo_);
        std::swap(msTex_, backMsTex_);
        shown_ = building_;
        shownMs_ = buildingMs_;
        nextBand_ = -1;
        swapped = true;
        lastBuildTexels_ = buildTexels_;
    };
    const double motion = active_ ? moved(shown_) : 1e30;
    if (!active_ || jumped || (slices_ <= 1 && motion > kEclipseRebuildMeters)) {
        // Nothing shown, or the shadow jumped (time set): the whole table now.
        startBuild(true);
        advanceField(true);
        renderBand(0, W, 0, H);
        ++rebuilds_;
        finish();
    } else {
        // A rebuild starts when the shadow has moved kEclipseRebuildMeters from the table shown, or
        // will have by the time a rebuild started now could be shown (time running: the table
        // shown then stays within ~kEclipseRebuildMeters of the shadow, however long a rebuild).
        if (nextBand_ < 0 && std::max(motion, movedBetween(ahead(leadRuns), shown_)) > kEclipseRebuildMeters) startBuild(false);
        if (nextBand_ >= 0) {
            const int cols = std::max(1, (buildBands_ + H - 1) / H), n = cols * ((buildBands_ + cols - 1) / cols);
            if (msBuilder_) {
                // The field's table: one piece a run, no band with it (one piece: the whole table
                // and the first band in the same run, as before).
                const bool done = advanceField(false);
                if (done && fieldPieces_ <= 1) {
                    renderTile(nextBand_);
                    ++rebuilds_;
                    ++nextBand_;
                }
                runAgain();
            } else if (nextBand_ >= n) {
                // The last band was rendered in the previous run: show the new table now, in a
                // run that renders no band (sampling a table in the frame that rendered it makes
                // llvmpipe finish that band before the Sky pass can start: the swap frame cost
                // 1.6-1.7x a normal frame with the band in it; docs/eclipse.md "Frame cost").
                finish();
            } else {
                renderTile(nextBand_);
                ++rebuilds_;
                ++nextBand_;
                runAgain();  // the next band (or the swap) in the next frame, whether or not an input changed
            }
        }
    }
    active_ = true;
    shownOffset_ = moved(shown_);
    if (swapped || !published_) {
        vars.publish(skykeys::eclipseViewLut, smooth_.ref());
        vars.publish(skykeys::eclipseViewMieLut, mie_.ref());
        vars.publish(skykeys::eclipseViewTotalLut, total_.ref());
    }
    published_ = true;
}

}  // namespace welkin::generators
