// Constellations: the figures' lines (kstars-data clines.dat) and names (cnames.dat) as an
// overlay, at the stars' apparent places.
//
//   processor.add(welkin::elements::makeElement("stars"));
//   processor.add(welkin::elements::makeElement("sky"));
//   processor.add(welkin::elements::makeElement("constellations"));   // overlay: after the Sky
//   processor.vars().set(welkin::elements::constellationkeys::labels, std::string("abbreviation"));
//   // command line: welkin render --elements stars,sky,constellations --var constellations.line_width_px=2
//
// Model (skyelements/constellations/README.md has the sources, the cost and the tests):
//  - Lines: clines.dat lists, per sky culture ("C Western"), polylines of stars by HD number
//    ("M hd" moves, "D hd" draws). Each HD number is resolved against the star catalogue
//    (loadConstellationStars(): astro::loadKStarsCatalogue + attachKStarsHdNumbers, kstars'
//    namedstars.dat and unnamedstars.dat hold the HD numbers); an unresolved star ends its
//    polyline there. Each segment is a great-circle arc
//    between the two J2000 (ICRS) star directions, cut on the CPU once into pieces of at most
//    kArcStepRad so it curves as it should in a fisheye or equirect image.
//  - Place: per frame the astronomy's stars.frame_icrs_to_enu rotation and the refraction
//    (astro::refraction at the astronomy's pressure and temperature, the Stars element's table),
//    so the lines meet the stars the Stars element draws. Proper motion (< 0.3 deg over 1000
//    years for the figures' stars; < 1" for most of them since J2000) and annual aberration
//    (< 20.5") are left out: both are far below a line's width.
//  - Drawing: each piece is a screen-space quad of constellations.line_width_px (antialiased),
//    split at the equirect seam (drawn twice, once per side), clipped at the apparent horizon
//    (always in a fisheye; elsewhere unless constellations.below_horizon) and a perspective
//    camera's near plane; radiance constellations.line_colour x
//    constellations.line_luminance_cd_m2, transmittance 1 - coverage.
//  - Names: cnames.dat gives each figure's label position (J2000 RA/Dec), abbreviation and name
//    (Latin, upper case in the file; drawn title-cased: "Ursa Major"); drawn centred on that
//    direction with welkin::gl::TextBatch (engine/include/welkin/gl/text.hpp).
#pragma once
#include <welkin/astro/stars.hpp>
#include <welkin/element.hpp>
#include <welkin/gl/objects.hpp>
#include <welkin/gl/projection_programs.hpp>
#include <welkin/gl/text.hpp>

#include <glm/glm.hpp>

#include <string>
#include <vector>

namespace welkin::elements {

namespace constellationkeys {
inline const Key<std::string> linesFile{"constellations.lines_file", "kstars clines.dat: figures' polylines by HD number"};
inline const Key<std::string> namesFile{"constellations.names_file", "kstars cnames.dat: figures' label positions and names"};
inline const Key<std::string> culture{"constellations.culture", "sky culture of clines.dat/cnames.dat (Western, Chinese, Norse, ...)"};
inline const Key<bool> lines{"constellations.lines", "draw the figures' lines"};
inline const Key<bool> belowHorizon{"constellations.below_horizon", "draw lines and names below the (apparent) horizon too"};
inline const Key<std::string> labels{"constellations.labels", Choices{{"name", "abbreviation", "none"}}, "figure labels: name (Latin), abbreviation, or none"};
inline const Key<double> lineWidth{"constellations.line_width_px", Range{0.5, 20}, "line width", "px"};
inline const Key<double> lineLuminance{"constellations.line_luminance_cd_m2", Range{0, 1e10}, "line luminance; 0 = 60 % of white at the manual exposure"};
inline const Key<glm::dvec3> lineColour{"constellations.line_colour", Range{0, 1}, "line colour, linear sRGB (scaled to luminance 1)", "1"};
inline const Key<double> labelSize{"constellations.label_size_px", Range{0, 256}, "label em height; 0 = min(width, height) / 64, at least 11", "px"};
inline const Key<double> labelLuminance{"constellations.label_luminance_cd_m2", Range{0, 1e10}, "label luminance; 0 = 80 % of white at the manual exposure"};
inline const Key<glm::dvec3> labelColour{"constellations.label_colour", Range{0, 1}, "label colour, linear sRGB (scaled to luminance 1)", "1"};
}  // namespace constellationkeys

/// Default kstars-data files.
inline constexpr const char* kConstellationLinesFile = "/usr/share/kstars/clines.dat";
inline constexpr const char* kConstellationNamesFile = "/usr/share/kstars/cnames.dat";
/// Longest piece of a great-circle arc drawn as one straight quad, rad (1 deg: the chord of a
/// 1-deg piece departs from the arc by < 0.02 px on a 1024-px fisheye).
inline constexpr double kArcStepRad = 0.017453292519943295;

/// One figure of clines.dat: its name (the comment line before it, may be empty) and its
/// polylines as HD numbers.
struct ConstellationFigure {
    std::string name;
    std::vector<std::vector<int>> polylines;
};
/// One entry of cnames.dat.
struct ConstellationLabel {
    double raJ2000Rad = 0, decJ2000Rad = 0;  ///< label position (ICRS), rad
    std::string abbreviation;               ///< "Ori" (may be empty in other cultures)
    std::string name;                       ///< "Orion" (title case of the file's "ORION")
};

/// Parses clines.dat text for one culture (case-insensitive; "Western" is the IAU figures).
/// Throws welkin::Error "source:line: message" for a malformed line, or naming the culture and
/// listing the file's cultures when it has none of that name.
std::vector<ConstellationFigure> parseConstellationLines(const std::string& text, const std::string& source, const std::string& culture);
/// Parses cnames.dat text ("HHMMSS+DDMMSSAbb NAME" per line, per culture). Same errors.
std::vector<ConstellationLabel> parseConstellationNames(const std::string& text, const std::string& source, const std::string& culture);
/// The two files read from disk (throws naming the file if it cannot be read).
std::vector<ConstellationFigure> loadConstellationLines(const std::string& path, const std::string& culture);
std::vector<ConstellationLabel> loadConstellationNames(const std::string& path, const std::string& culture);
/// The stars the figures are resolved against: the kstars catalogue to V 7 with HD numbers from
/// namedstars.dat and unnamedstars.dat (beside it), plus the binary files' records whose HD number
/// no catalogue star received (close doubles the two reductions place > 6" apart).
std::vector<astro::Star> loadConstellationStars(const std::string& catalogue = astro::kKStarsCatalogue);
/// Segments (pairs of ICRS unit directions) of the figures with each HD number resolved against
/// `stars` (their `hd`); `unresolved` counts the HD numbers not found.
struct ConstellationSegment {
    glm::dvec3 a{0.0}, b{0.0};
    int hdA = 0, hdB = 0;
};
std::vector<ConstellationSegment> resolveConstellationSegments(const std::vector<ConstellationFigure>& figures,
                                                               const std::vector<astro::Star>& stars, int* unresolved = nullptr);

class Constellations final : public SkyElement {
public:
    Constellations();

    /// After init: segments drawn (resolved) and HD numbers left unresolved, labels loaded.
    int segments() const { return int(segments_.size()); }
    int unresolvedStars() const { return unresolved_; }
    int labelCount() const { return int(labels_.size()); }

private:
    void doInit(InitContext& ctx) override;
    void doRender(const FrameContext& ctx) override;
    void doRelease() override;
    void doStats(nlohmann::json& root) const override;
    void doValidateOptions(const SkyVars& vars) const override;
    void load(const SkyVars& v);

    std::string loadedKey_;  // files + culture last loaded
    std::vector<ConstellationSegment> segments_;
    std::vector<ConstellationLabel> labels_;
    int unresolved_ = 0;
    int pieces_ = 0;
    gl::Buffer buffer_;
    gl::VertexArray vao_;
    gl::ProjectionPrograms programs_;
    gl::Font font_;
    gl::TextBatch text_;
    int labelsDrawn_ = 0;
};

}  // namespace welkin::elements
