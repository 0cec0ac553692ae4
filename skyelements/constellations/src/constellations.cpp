// Constellations element: clines.dat/cnames.dat parsing, HD resolution, arcs, per-frame draw;
// the model is described in include/welkin/elements/constellations.hpp and skyelements/constellations/README.md.
#include <welkin/astro/astro_keys.hpp>
#include <welkin/astro/frames.hpp>
#include <welkin/elements/constellations.hpp>
#include <welkin/embedded/constellations_shaders.hpp>
#include <welkin/error.hpp>
#include <welkin/gl/shader.hpp>
#include <welkin/keys.hpp>

#include <epoxy/gl.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <fstream>
#include <numbers>
#include <sstream>
#include <filesystem>
#include <unordered_map>
#include <unordered_set>

namespace welkin::elements {

namespace {
constexpr int kTableN = 64;  // CONSTELLATIONS_TABLE_N: refraction samples (as the Stars element's)
constexpr double kTableLo = -5.0 * std::numbers::pi / 180.0;
constexpr double kTableSpan = 95.0 * std::numbers::pi / 180.0;
double tableAltitude(int i) {
    const double u = double(i) / (kTableN - 1);
    return kTableLo + kTableSpan * u * u;
}
}  // namespace

// The files' parsers and resolveConstellationSegments(): constellation_files.cpp.

std::vector<astro::Star> loadConstellationStars(const std::string& catalogue) {
    // The figures' stars are naked-eye stars: the catalogue to V 7 (any fainter one of another
    // culture is found among the binary records below).
    std::vector<astro::Star> stars = astro::loadKStarsCatalogue(catalogue, 7.0);
    // namedstars.dat (read by the loader) gives the HD numbers of the ~1600 named stars; the
    // figures also use unnamed ones, whose HD numbers are in unnamedstars.dat (same format).
    const std::filesystem::path dir = std::filesystem::path(catalogue).parent_path();
    const std::filesystem::path unnamed = dir / "unnamedstars.dat";
    if (std::filesystem::exists(unnamed)) astro::attachKStarsHdNumbers(stars, unnamed.string());
    // A few close doubles do not match (stars.dat and the binary files reduce them differently):
    // their binary records, at the records' own J2000 places, stand in for them.
    std::unordered_set<int> have;
    for (const astro::Star& s : stars)
        if (s.hd > 0) have.insert(s.hd);
    for (const char* f : {"namedstars.dat", "unnamedstars.dat"}) {
        if (!std::filesystem::exists(dir / f)) continue;
        for (astro::Star& r : astro::loadKStarsBinaryStars((dir / f).string()))
            if (r.hd > 0 && have.insert(r.hd).second) stars.push_back(std::move(r));
    }
    return stars;
}

Constellations::Constellations() : SkyElement("constellations") {
    setContributesToLighting(false);  // overlay: not light from the sky
    option(constellationkeys::linesFile, std::string(kConstellationLinesFile));
    option(constellationkeys::namesFile, std::string(kConstellationNamesFile));
    option(constellationkeys::culture, std::string("Western"));
    option(constellationkeys::lines, true);
    option(constellationkeys::belowHorizon, false);
    option(constellationkeys::labels, std::string("name"));
    option(constellationkeys::lineWidth, 1.5);
    // 1e-3 cd/m^2: ~6x a dark site's night sky (1.7e-4 cd/m^2): visible at the exposures that
    // show the stars (EV100 -9: ~40 % of white), fainter than the labels, hidden by twilight.
    option(constellationkeys::lineLuminance, 1e-3);
    option(constellationkeys::lineColour, glm::dvec3(0.35, 0.55, 1.0));
    option(constellationkeys::labelSize, 0.0);
    option(constellationkeys::labelLuminance, 2e-3);  // gl::TextStyle's default (welkin/gl/text.hpp)
    option(constellationkeys::labelColour, glm::dvec3(0.75, 0.85, 1.0));
    reads(astro::keys::starFrameRotation);
    reads(astro::keys::refractionPressure);
    reads(astro::keys::refractionTemperature);
    reads(keys::exposureEv100);
}

void Constellations::doValidateOptions(const SkyVars& v) const {
    const std::string l = v.get(constellationkeys::labels);
    if (l != "name" && l != "abbreviation" && l != "none")
        throw Error("constellations.labels: '" + l + "' is not one of name, abbreviation, none");
}

void Constellations::load(const SkyVars& v) {
    const std::string lf = v.get(constellationkeys::linesFile), nf = v.get(constellationkeys::namesFile);
    const std::string culture = v.get(constellationkeys::culture);
    const std::string key = lf + "\n" + nf + "\n" + culture;
    if (key == loadedKey_) return;
    const std::vector<astro::Star> stars = loadConstellationStars();
    segments_ = resolveConstellationSegments(loadConstellationLines(lf, culture), stars, &unresolved_);
    labels_ = loadConstellationNames(nf, culture);
    // Great-circle arcs cut into pieces of at most kArcStepRad (slerp between the ends).
    std::vector<float> data;
    for (const ConstellationSegment& s : segments_) {
        const double angle = std::acos(std::clamp(glm::dot(s.a, s.b), -1.0, 1.0));
        const int n = std::max(1, int(std::ceil(angle / kArcStepRad)));
        auto at = [&](int i) {
            const double t = double(i) / n;
            if (angle < 1e-9) return s.a;
            return (std::sin((1 - t) * angle) * s.a + std::sin(t * angle) * s.b) / std::sin(angle);
        };
        for (int i = 0; i < n; ++i) {
            const glm::dvec3 a = at(i), b = at(i + 1);
            const float rec[8] = {float(a.x), float(a.y), float(a.z), 0.f, float(b.x), float(b.y), float(b.z), 0.f};
            data.insert(data.end(), rec, rec + 8);
        }
    }
    pieces_ = int(data.size() / 8);
    if (data.empty()) data.assign(8, 0.f);  // a buffer of size 0 is not allowed
    buffer_ = gl::Buffer(data.size() * sizeof(float), data.data());
    if (!vao_) {
        vao_ = gl::VertexArray::create();
        for (unsigned a = 0; a < 2; ++a) {
            glEnableVertexArrayAttrib(vao_.id(), a);
            glVertexArrayAttribFormat(vao_.id(), a, 4, GL_FLOAT, GL_FALSE, a * 4 * sizeof(float));
            glVertexArrayAttribBinding(vao_.id(), a, 0);
        }
    }
    glVertexArrayVertexBuffer(vao_.id(), 0, buffer_.id(), 0, 8 * sizeof(float));
    loadedKey_ = key;
}

void Constellations::doInit(InitContext& ctx) {
    declareOptions(ctx.vars);
    ctx.vars.declare(keys::exposureEv100, 15.0);
    validateOptions(ctx.vars);
    load(ctx.vars);
    programs_ = gl::ProjectionPrograms(gl::ProgramBuilder("Constellations")
                                           .define("CONSTELLATIONS_TABLE_N", kTableN)
                                           .vertex("engine/camera.glsl", gl::engineShader("camera.glsl"))
                                           .vertex("constellations/constellations.vert.glsl", embedded::constellations_shaders("constellations.vert.glsl"))
                                           .fragment("engine/camera.glsl", gl::engineShader("camera.glsl"))
                                           .fragment("engine/composite.glsl", gl::engineShader("composite.glsl"))
                                           .fragment("constellations/constellations.frag.glsl", embedded::constellations_shaders("constellations.frag.glsl")));
    programs_.get(Projection::Perspective);  // shader errors surface in init()
    font_ = gl::Font::load();
}

void Constellations::doRender(const FrameContext& ctx) {
    const SkyVars& v = ctx.vars;
    validateOptions(v);
    load(v);
    const glm::dmat3 R = v.getOr(astro::keys::starFrameRotation, glm::dmat3(1.0));
    const double P = v.getOr(astro::keys::refractionPressure, 1013.25), Tc = v.getOr(astro::keys::refractionTemperature, 10.0);
    const double white = 1.2 * std::exp2(v.get(keys::exposureEv100));  // luminance at the top of the manual exposure
    auto scaled = [](glm::dvec3 c, double L) {
        const double Y = 0.2126 * c.r + 0.7152 * c.g + 0.0722 * c.b;
        return Y > 0 ? glm::vec3(c / Y * L) : glm::vec3(0.0f);
    };
    if (v.get(constellationkeys::lines) && pieces_ > 0) {
        double L = v.get(constellationkeys::lineLuminance);
        if (L <= 0) L = 0.6 * white;
        const gl::Program& p = programs_.get(ctx.camera.projection);
        p.use();
        p.set("u_icrsToEnu", glm::mat3(R));
        const int copies = ctx.camera.projection == Projection::Equirect ? 2 : 1;
        p.set("u_copies", copies);
        p.set("u_widthPx", float(v.get(constellationkeys::lineWidth)));
        p.set("u_clipHorizon", v.get(constellationkeys::belowHorizon) ? 0 : 1);
        p.set("u_radiance", scaled(v.get(constellationkeys::lineColour), L));
        float refr[kTableN];
        for (int i = 0; i < kTableN; ++i) refr[i] = float(astro::refraction(tableAltitude(i), P, Tc));
        glProgramUniform1fv(p.id(), p.location("u_refr"), kTableN, refr);
        vao_.bind();
        glVertexArrayBindingDivisor(vao_.id(), 0, GLuint(copies));
        glDrawArraysInstanced(GL_TRIANGLES, 0, 6, pieces_ * copies);
    }
    labelsDrawn_ = 0;
    const std::string mode = v.get(constellationkeys::labels);
    if (mode != "none") {
        double L = v.get(constellationkeys::labelLuminance);
        if (L <= 0) L = 0.8 * white;
        gl::TextStyle style;
        style.pixelSize = float(v.get(constellationkeys::labelSize));
        if (style.pixelSize <= 0) style.pixelSize = std::max(11.0f, float(std::min(ctx.camera.width, ctx.camera.height)) / 64.0f);
        const glm::dvec3 c = v.get(constellationkeys::labelColour);
        style.colour = glm::vec3(c);
        style.luminanceCdM2 = float(L);
        for (const ConstellationLabel& l : labels_) {
            const std::string& s = mode == "abbreviation" && !l.abbreviation.empty() ? l.abbreviation : l.name;
            const glm::dvec3 p0(std::cos(l.decJ2000Rad) * std::cos(l.raJ2000Rad), std::cos(l.decJ2000Rad) * std::sin(l.raJ2000Rad), std::sin(l.decJ2000Rad));
            const glm::dvec3 d = R * p0;
            const double h = std::asin(std::clamp(d.z, -1.0, 1.0));
            const double hApp = astro::apparentFromGeometricAltitude(h, P, Tc);
            const double horiz = std::hypot(d.x, d.y);
            const glm::dvec2 sc = horiz > 0 ? glm::dvec2(d.x, d.y) / horiz : glm::dvec2(0, 1);
            const auto clip = ctx.camera.clipFromDirection(glm::dvec3(sc * std::cos(hApp), std::sin(hApp)));
            if (!clip || (hApp < 0.0 && !v.get(constellationkeys::belowHorizon))) continue;
            // Perspective: skip anchors off the frame (a label there would be half drawn at best).
            if (std::abs(clip->x) > clip->w * 1.2 || std::abs(clip->y) > clip->w * 1.2) continue;
            text_.add(font_, glm::vec4(*clip), s, style);
            ++labelsDrawn_;
        }
        text_.draw(font_);
    }
    if (ctx.emptyVao) ctx.emptyVao->bind();  // later elements draw attribute-less
}

void Constellations::doRelease() {
    programs_.releasePrograms();
    buffer_ = gl::Buffer();
    vao_ = gl::VertexArray();
    font_ = gl::Font();
    text_ = gl::TextBatch();
    loadedKey_.clear();
}

void Constellations::doStats(nlohmann::json& root) const {
    root["constellations"]["segments"] = int(segments_.size());
    root["constellations"]["pieces"] = pieces_;
    root["constellations"]["unresolved_stars"] = unresolved_;
    root["constellations"]["labels_drawn"] = labelsDrawn_;
}

}  // namespace welkin::elements

WELKIN_ELEMENT_DESCRIPTOR(constellations) {
    static const welkin::ElementDescriptor d{
        "constellations", "constellation figures (kstars clines.dat) as great-circle lines through the stars, and their names (cnames.dat)",
        welkin::Layer::Overlay, false, [] { return std::make_unique<welkin::elements::Constellations>(); }};
    return d;
}
