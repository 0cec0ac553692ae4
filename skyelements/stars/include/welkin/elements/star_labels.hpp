// Star labels: the proper names of the bright stars beside them (an education overlay of the
// Stars element, drawn with the engine's text, welkin/gl/text.hpp).
//
//   processor.add(welkin::elements::makeElement("stars"));
//   processor.vars().set(welkin::elements::starkeys::labels, true);          // "Vega", "Antares", ...
//   processor.vars().set(welkin::elements::starkeys::labelMagnitude, 1.5);   // only stars this bright
//   // command line: welkin render --var stars.labels=true --var stars.label_magnitude=2
//
// Which stars: those of the catalogue with a proper name (kstars' stars.dat "long name", e.g.
// "Vega"; a Bayer designation such as "alp Lyr" or a name starting with a digit is not a proper
// name), at least as bright as stars.label_magnitude and as the limiting magnitude the Stars element
// used for the frame (a star not drawn is not named), above the horizon the projection shows.
// Where: at the star's apparent place exactly as the Stars shader computes it (proper motion,
// aberration, the stars.frame_icrs_to_enu rotation, refraction: starApparentEnu()); the text's
// box (advance x ascender..descender) starts starLabelGapPx() right of the star, vertically centred
// on it (TextStyle align (0, 0.5)), as the Planet element places its labels.
#pragma once
#include <welkin/astro/stars.hpp>
#include <welkin/element.hpp>
#include <welkin/gl/text.hpp>

#include <glm/glm.hpp>

#include <string>
#include <vector>

namespace welkin::elements {

namespace starkeys {
inline const Key<bool> labels{"stars.labels", "proper names beside the bright stars (kstars' names: Vega, Antares, ...)"};
inline const Key<double> labelMagnitude{"stars.label_magnitude", Range{-30, 30}, "with stars.labels, only stars at least this bright are named", "mag"};
/// Label size, px (0: the image's shorter side / 64, at least 11 px: the Planet's rule).
inline const Key<double> labelSize{"stars.label_size_px", Range{0, 256}, "star label em height, px (0: shorter image side / 64, >= 11)", "px"};
/// Label luminance, cd/m^2 (default 2e-3, as the Planet's; 0: 0.8 of the manual exposure's white).
inline const Key<double> labelLuminance{"stars.label_luminance_cd_m2", Range{0, 1e9}, "star label luminance (0: 0.8 of the manual exposure's white)", "cd/m^2"};
}  // namespace starkeys

/// A catalogue star with a proper name, as the labels need it.
struct NamedStar {
    std::string name;      ///< "Vega"
    glm::dvec3 p0{0, 0, 1};  ///< ICRS unit direction at J2000.0 (astro::starDirectionJ2000)
    glm::dvec3 pm{0.0};    ///< proper motion, rad per Julian year (astro::starProperMotion)
    float magnitudeV = 0;  ///< visual magnitude
};

/// True for a proper name ("Vega", "Al Na'ir"), false for a designation ("alp Lyr", "61 Cyg",
/// BSC5's "Alp Lyr") or "".
bool isProperStarName(const std::string& name);
/// The stars of `stars` with a proper name, brightest first.
std::vector<NamedStar> namedStars(const std::vector<astro::Star>& stars);
/// Apparent ENU unit direction of a star (J2000 direction `p0`, proper motion `pm`) for the frame
/// in `vars` (the astronomy's stars.frame_* keys and refraction keys; identity and no refraction
/// without them): the CPU twin of the Stars vertex shader's placement.
glm::dvec3 starApparentEnu(const SkyVars& vars, const glm::dvec3& p0, const glm::dvec3& pm);
/// Gap between a star and the left edge of its label's box, px, for an em height `emPx`:
/// 1 px (the PSF's half width at its 2 px minimum) + 0.4 em.
inline double starLabelGapPx(double emPx) { return 1.0 + 0.4 * emPx; }
/// The label em height, px, for `vars` (stars.label_size_px, or its default for the image).
double starLabelEmPx(const SkyVars& vars, int imageWidth, int imageHeight);

/// The Stars element's labels (held by Stars; usable by a host element the same way).
class StarLabels {
public:
    /// The names to draw from (kept: the catalogue's named stars only).
    void setCatalogue(const std::vector<astro::Star>& stars) { named_ = namedStars(stars); }
    /// Draws the labels of the named stars brighter than min(stars.label_magnitude,
    /// `limitingMagnitude`) when stars.labels is on (inside SkyElement::render()).
    void render(const FrameContext& ctx, double limitingMagnitude);
    void release();
    /// Labels of the last render() whose star is inside the image.
    int drawn() const { return drawn_; }
    const std::vector<NamedStar>& named() const { return named_; }

private:
    std::vector<NamedStar> named_;
    gl::Font font_;  // loaded on the first frame with labels
    gl::TextBatch batch_;
    int drawn_ = 0;
};

}  // namespace welkin::elements
