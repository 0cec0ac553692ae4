// Star labels: which stars are named and where (include/welkin/elements/star_labels.hpp).
#include <welkin/astro/astro_keys.hpp>
#include <welkin/astro/frames.hpp>
#include <welkin/elements/star_labels.hpp>
#include <welkin/keys.hpp>

#include <algorithm>
#include <cctype>
#include <cmath>

namespace welkin::elements {

bool isProperStarName(const std::string& name) {
    // kstars' stars.dat gives a long name ("Vega") where it has one, else the genitive Bayer or
    // Flamsteed designation ("alp2Cen", "61 Cyg"): those start with a lower-case letter or a digit.
    if (name.empty() || !std::isupper(static_cast<unsigned char>(name[0]))) return false;
    // BSC5 and HYG designations are capitalised ("Alp Lyr", "Bet1Sco"): a Greek letter's
    // three-letter abbreviation (with an optional digit) before a constellation's is not a name.
    static const char* kGreek[] = {"alp", "bet", "gam", "del", "eps", "zet", "eta", "the", "iot", "kap", "lam", "mu",
                                   "nu",  "xi",  "omi", "pi",  "rho", "sig", "tau", "ups", "phi", "chi", "psi", "ome"};
    // The constellation: the last three letters, after a space or the Greek letter's digit.
    const size_t n = name.size();
    if (n < 5 || !std::isalpha(static_cast<unsigned char>(name[n - 3])) || !std::isalpha(static_cast<unsigned char>(name[n - 2])) ||
        !std::isalpha(static_cast<unsigned char>(name[n - 1])) || !(name[n - 4] == ' ' || std::isdigit(static_cast<unsigned char>(name[n - 4]))))
        return true;
    const size_t sp = n - 3;
    std::string first;
    for (size_t i = 0; i < sp; ++i)
        if (std::isalpha(static_cast<unsigned char>(name[i]))) first += char(std::tolower(static_cast<unsigned char>(name[i])));
        else if (!std::isdigit(static_cast<unsigned char>(name[i])) && name[i] != ' ') return true;
    for (const char* g : kGreek)
        if (first == g) return false;
    return true;
}

std::vector<NamedStar> namedStars(const std::vector<astro::Star>& stars) {
    std::vector<NamedStar> out;
    for (const astro::Star& s : stars)
        if (isProperStarName(s.name)) out.push_back({s.name, astro::starDirectionJ2000(s), astro::starProperMotion(s), s.magnitudeV});
    std::stable_sort(out.begin(), out.end(), [](const NamedStar& a, const NamedStar& b) { return a.magnitudeV < b.magnitudeV; });
    return out;
}

glm::dvec3 starApparentEnu(const SkyVars& v, const glm::dvec3& p0, const glm::dvec3& pm) {
    // As stars.vert.glsl: proper motion, aberration, rotation, then refraction of the altitude.
    glm::dvec3 p = glm::normalize(p0 + v.getOr(astro::keys::starFrameEpochYears, 0.0) * pm);
    p = glm::normalize(p + v.getOr(astro::keys::starFrameAberration, glm::dvec3(0.0)));
    const glm::dvec3 d = v.getOr(astro::keys::starFrameRotation, glm::dmat3(1.0)) * p;
    if (!v.has(astro::keys::starFrameRotation)) return d;  // no astronomy: no refraction either
    const double P = v.getOr(astro::keys::refractionPressure, 1013.25), Tc = v.getOr(astro::keys::refractionTemperature, 10.0);
    const double h = std::asin(std::clamp(d.z, -1.0, 1.0));
    const double hApp = astro::apparentFromGeometricAltitude(h, P, Tc);
    const double horiz = std::hypot(d.x, d.y);
    const glm::dvec2 sc = horiz > 0.0 ? glm::dvec2(d.x, d.y) / horiz : glm::dvec2(0.0, 1.0);
    return {sc.x * std::cos(hApp), sc.y * std::cos(hApp), std::sin(hApp)};
}

double starLabelEmPx(const SkyVars& v, int w, int h) {
    const double s = v.get(starkeys::labelSize);
    return s > 0 ? s : std::max(11.0, double(std::min(w, h)) / 64.0);
}

void StarLabels::render(const FrameContext& ctx, double limitingMagnitude) {
    drawn_ = 0;
    const SkyVars& v = ctx.vars;
    if (!v.get(starkeys::labels) || named_.empty()) return;
    const double limit = std::min(v.get(starkeys::labelMagnitude), limitingMagnitude);
    if (!font_) font_ = gl::Font::load();
    double L = v.get(starkeys::labelLuminance);
    if (L <= 0) L = 0.8 * 1.2 * std::exp2(v.get(keys::exposureEv100));  // 0.8 of the manual exposure's white
    gl::TextStyle style;
    style.pixelSize = float(starLabelEmPx(v, ctx.camera.width, ctx.camera.height));
    style.colour = glm::vec3(0.78f, 0.86f, 1.0f);  // a cool white, apart from the planets' warm labels
    style.luminanceCdM2 = float(L);
    style.align = {0.0f, 0.5f};
    style.offsetPx = {float(starLabelGapPx(style.pixelSize)), 0.0f};
    for (const NamedStar& s : named_) {
        if (s.magnitudeV > limit) break;  // brightest first
        const glm::dvec3 d = starApparentEnu(v, s.p0, s.pm);
        if (d.z < 0.0) continue;  // below the horizon: behind the ground
        const auto px = ctx.camera.pixelOf(d);
        if (!px) continue;
        batch_.addAt(font_, glm::vec3(d), s.name, style);
        if (px->x >= 0 && px->y >= 0 && px->x < ctx.camera.width && px->y < ctx.camera.height) ++drawn_;
    }
    batch_.draw(font_);
}

void StarLabels::release() {
    batch_ = gl::TextBatch();
    font_ = gl::Font();
}

}  // namespace welkin::elements
