// Planet element: per-frame geometry, the Moon's calibration (a CPU integral of the shader's
// model), the maps; the model is described in include/welkin/elements/planet.hpp and skyelements/planet/README.md.
#include <welkin/astro/astro_keys.hpp>
#include <welkin/astro/eclipses.hpp>
#include <cctype>
#include <welkin/astro/frames.hpp>
#include <welkin/color.hpp>
#include <welkin/elements/planet.hpp>
#include <welkin/embedded/planet_shaders.hpp>
#include <welkin/error.hpp>
#include <welkin/generators/atmosphere.hpp>
#include <welkin/generators/lights.hpp>
#include <welkin/generators/sky_model.hpp>
#include <welkin/embedded/atmosphere_shaders.hpp>
#include <welkin/generators/point_sources.hpp>
#include <welkin/gl/shader.hpp>
#include <welkin/glsl_cpp.hpp>
#include <welkin/image.hpp>
#include <welkin/keys.hpp>
#include <welkin/point_source.hpp>

#include <epoxy/gl.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <numbers>
#include <sstream>

namespace welkin::glsl::dp::planet_corona_shared {
#include "../shaders/planet_corona.shared.glsl"
}  // namespace welkin::glsl::dp::planet_corona_shared

// The point sources' constants (WELKIN_GAUSSIAN_FWHM_PER_SIGMA): the engine's shared file, which the
// vertex shader gets through point_perceptual.glsl.
namespace welkin::glsl::dp::planet_point_shared {
#include "../../../engine/shaders/point_threshold.shared.glsl"
}  // namespace welkin::glsl::dp::planet_point_shared

namespace welkin::glsl::dp::planet_sphere_shared {
const real WELKIN_PI = std::numbers::pi;  // (the GPU's: camera_projection.shared.glsl)
#include "../shaders/planet_sphere.shared.glsl"
}  // namespace welkin::glsl::dp::planet_sphere_shared

namespace welkin::elements {

namespace {
constexpr double kPi = std::numbers::pi;
constexpr double kEarthRadiusM = 6371.0e3;      // mean radius (shadow geometry, earthshine)
constexpr double kEarthGeometricAlbedo = 0.20;  // Lambert sphere of Bond albedo 0.30 (2/3 x 0.30)
constexpr double kHapkeCompaction = 0.6;        // Hapke 1966 g, as in Jensen et al. 2001
constexpr double kPsfFwhmPx = 2.0;              // the Stars' minimum FWHM
// Shader kinds (planet.frag.glsl).
constexpr int kKindSun = 0, kKindMoon = 1, kKindDisk = 2, kKindPsf = 3;
// B-V of the planets, Mercury .. Neptune (Allen's Astrophysical Quantities, 4th ed., table 12.3).
constexpr double kPlanetBV[7] = {0.93, 0.82, 1.36, 0.83, 1.04, 0.56, 0.41};

// The planets' colours from their B-V, computed once: a black body's colour integrates the CIE
// functions over 471 wavelengths, and doing it per planet per frame was a tenth of the framework's
// own instructions per frame (docs/hardening.md). A constant table of constants, not state.
const glm::dvec3& planetColour(astro::Body b) {
    static const std::array<glm::dvec3, 7> colours = [] {
        std::array<glm::dvec3, 7> c{};
        for (int i = 0; i < 7; ++i) c[i] = color::starColourFromBV(kPlanetBV[i]);
        return c;
    }();
    return colours[std::size_t(int(b) - int(astro::Body::Mercury))];
}
// Earthshine colour (Mueller, Engel and Doellner 2012), normalised below to luminance 1.
const glm::dvec3 kEarthshineColour{0.88, 0.96, 1.00};
constexpr int kKindCorona = 4;

std::vector<astro::Body> parseBodies(const std::string& text) {
    std::vector<astro::Body> out;
    std::string s;
    for (char ch : text) s += char(std::tolower(static_cast<unsigned char>(ch)));
    if (s == "all") return {astro::kAllBodies.begin(), astro::kAllBodies.end()};
    if (s == "none" || s.empty()) return out;
    std::stringstream ss(s);
    std::string item;
    while (std::getline(ss, item, ',')) {
        item.erase(std::remove_if(item.begin(), item.end(), [](char ch) { return std::isspace(static_cast<unsigned char>(ch)); }), item.end());
        if (item.empty()) continue;
        const astro::Body b = astro::parseBody(item);
        if (std::find(out.begin(), out.end(), b) == out.end()) out.push_back(b);
    }
    return out;
}

// Unit vector towards the zenith in the tangent plane at `c` (north when c is vertical), and the
// left of an upright view there.
void verticalFrame(const glm::dvec3& c, glm::dvec3& up, glm::dvec3& left) {
    glm::dvec3 u = glm::dvec3(0, 0, 1) - c * c.z;
    if (glm::length(u) < 1e-9) u = glm::dvec3(0, 1, 0) - c * c.y;
    up = glm::normalize(u);
    left = glm::cross(up, c);
}

// The sphere's outward unit normal where the ray `d` meets a sphere of apparent radius asin(s)
// around `c` (d within it): the shader's planet_normal() (planet_sphere.shared.glsl).
glm::dvec3 sphereNormal(const glm::dvec3& d, const glm::dvec3& c, double s) {
    double rho = 0.0;
    return glsl::dp::planet_sphere_shared::planet_normal(d, c, s, rho);
}

// The magnitude written after a body's name: one decimal with an ASCII minus (the text atlas is
// Latin-1: U+2212 would draw as '?'), "?" when the astronomy has none.
std::string planetLabelMagnitude(const SkyVars& v, const std::string& bodyName) {
    namespace ak = astro::keys;
    constexpr double kAuM = 1.495978707e11;  // IAU 2012 astronomical unit, m
    const astro::Body b = astro::parseBody(bodyName);
    double m = 0;
    if (b == astro::Body::Sun) m = astro::magnitude::sun(v.getOr(ak::sunDistance, kAuM) / kAuM);
    else if (b == astro::Body::Moon && v.has(ak::moonMagnitude)) m = v.get(ak::moonMagnitude);
    else if (b != astro::Body::Moon && v.has(ak::planetMagnitude(b))) m = v.get(ak::planetMagnitude(b));
    else return "?";
    if (std::abs(m) < 0.05) m = 0.0;  // "0.0", not "-0.0"
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.1f", m);
    return buf;
}

float lumaOf(const Image& img, int x, int y) {
    if (img.channels < 3) return img.at(x, y, 0);
    return float(color::luminance({img.at(x, y, 0), img.at(x, y, 1), img.at(x, y, 2)}));
}
}  // namespace

double sunLimbExponent(double nm) {
    if (!(nm >= 300.0 && nm <= 2000.0)) throw Error("sunLimbExponent(): wavelength not in [300, 2000] nm");
    return -0.023 + 0.292 / (nm * 1e-3);
}

glm::dvec3 sunLimbExponents() { return {sunLimbExponent(612.0), sunLimbExponent(549.0), sunLimbExponent(465.0)}; }

double hapkePhase(double g) {
    if (!(g >= 0.0 && g <= kPi + 1e-9)) throw Error("hapkePhase(): phase angle not in [0, pi] rad");
    double B = 1.0;
    if (g < kPi / 2) {
        const double t = std::tan(g);
        const double e = t > 0.0 ? std::exp(-kHapkeCompaction / t) : 0.0;
        B = 2.0 - t / (2.0 * kHapkeCompaction) * (1.0 - e) * (3.0 - e);
    }
    const double c = std::cos(g);
    const double S = (std::sin(g) + (kPi - g) * c) / kPi + 0.1 * (1.0 - c) * (1.0 - c);
    return B * S;
}

double lambertPhase(double a) {
    a = std::clamp(a, 0.0, kPi);
    return (std::sin(a) + (kPi - a) * std::cos(a)) / kPi;
}

double coronaRelativeRadiance(double r, double flattening, double sinFromEquator) {
    if (!(r >= 1.0)) return 0.0;
    return glsl::dp::planet_corona_shared::planet_coronaRelativeRadiance(r, flattening, sinFromEquator);  // the shader's text
}

double earthshineRatio(double moonPhaseRad, double d) {
    if (!(d > kEarthRadiusM)) throw Error("earthshineRatio(): Earth-Moon distance not > the Earth's radius");
    const double r = kEarthRadiusM / d;
    return kEarthGeometricAlbedo * r * r * lambertPhase(kPi - std::clamp(moonPhaseRad, 0.0, kPi));
}

double visibleSunFraction(double rs, double re, double d) {
    if (!(rs > 0.0) || re <= 0.0) return 1.0;
    return astro::lensVisibleFraction(rs, re, d);  // the shader's text (disk_overlap.shared.glsl)
}

double verticalPositionAngle(const glm::dvec3& centre, const glm::dvec3& dir) {
    glm::dvec3 up, left;
    verticalFrame(centre, up, left);
    const glm::dvec3 t = dir - centre * glm::dot(centre, dir);
    return std::atan2(glm::dot(t, left), glm::dot(t, up));
}

MoonGeometry moonGeometry(const SkyVars& v, double sizeFactor) {
    namespace ak = astro::keys;
    MoonGeometry g;
    g.centre = glm::normalize(v.get(keys::moonDirection));
    const glm::dvec3 sunDir = glm::normalize(v.get(keys::sunDirection));
    const double Dm = v.getOr(ak::moonDistance, 3.844e8), Ds = v.getOr(ak::sunDistance, 1.496e11);
    const glm::dvec3 M = Dm * g.centre, S = Ds * sunDir;
    g.sunFromMoon = glm::normalize(S - M);
    g.phaseRad = std::acos(std::clamp(glm::dot(g.sunFromMoon, -g.centre), -1.0, 1.0));
    const double alpha = v.getOr(ak::moonAngularRadius, 1737.4e3 / Dm);
    g.angularRadius = std::min(alpha * sizeFactor, 1.4);
    const glm::dvec3 earthCentre(0.0, 0.0, -(kEarthRadiusM + v.getOr(keys::observerHeight, 0.0)));
    g.earthMoonDistanceM = glm::length(M - earthCentre);
    // Orientation: the pole from the axis' position angle P (turned into the vertical frame by
    // the parallactic angle q) and the sub-Earth latitude b; lon 0 from the sub-Earth longitude l.
    // The librations and P are geocentric: they are applied around the geocentric direction of
    // the Moon (the parallax moves the Moon along its vertical circle, so the vertical frame's
    // angles hold there); the view from the observer then shows the topocentric libration.
    const double P = v.getOr(ak::moonAxisAngle, 0.0), q = v.getOr(ak::moonParallacticAngle, 0.0);
    const double l = v.getOr(ak::moonLibrationLon, 0.0), b = v.getOr(ak::moonLibrationLat, 0.0);
    // The geometric (unrefracted) topocentric direction, then the geocentric one.
    glm::dvec3 unrefracted = g.centre;
    {
        const double h = std::asin(std::clamp(g.centre.z, -1.0, 1.0));
        const double hg = astro::geometricFromApparentAltitude(h, v.getOr(ak::refractionPressure, 1013.25), v.getOr(ak::refractionTemperature, 10.0));
        const double horiz = glm::length(glm::dvec2(g.centre));
        if (horiz > 1e-12) unrefracted = glm::dvec3(glm::dvec2(g.centre) / horiz * std::cos(hg), std::sin(hg));
    }
    const glm::dvec3 geo = glm::normalize(Dm * unrefracted - earthCentre);
    glm::dvec3 up, left;
    verticalFrame(geo, up, left);
    const glm::dvec3 towardPole = std::cos(P - q) * up + std::sin(P - q) * left;
    const glm::dvec3 o = -geo;  // Moon -> the Earth's centre
    const glm::dvec3 N = glm::normalize(std::sin(b) * o + std::cos(b) * towardPole);
    const glm::dvec3 w = glm::normalize(o - glm::dot(o, N) * N);
    const glm::dvec3 w2 = glm::cross(N, w);
    const glm::dvec3 X = std::cos(l) * w - std::sin(l) * w2;
    const glm::dvec3 Y = std::sin(l) * w + std::cos(l) * w2;
    g.axes = glm::dmat3(X, Y, N);
    return g;
}

double MoonMaps::albedoAt(double lon, double lat) const {
    if (albedo.empty()) return 1.0;
    // Texel centres at ((i + 0.5) / W, (j + 0.5) / H); u = 0.5 + lon / 2 pi, v = 0.5 - lat / pi.
    const double u = (0.5 + lon / (2 * kPi)) * width - 0.5, vv = (0.5 - lat / kPi) * height - 0.5;
    const double fu = std::floor(u), fv = std::floor(vv);
    const double tu = u - fu, tv = vv - fv;
    auto at = [&](long i, long j) {
        i = ((i % width) + width) % width;
        j = std::clamp(j, 0L, long(height) - 1);
        return double(albedo[size_t(j) * width + size_t(i)]);
    };
    const long i = long(fu), j = long(fv);
    return (1 - tv) * ((1 - tu) * at(i, j) + tu * at(i + 1, j)) + tv * ((1 - tu) * at(i, j + 1) + tu * at(i + 1, j + 1));
}

glm::dvec3 MoonMaps::normalAt(double lon, double lat) const {
    if (normal.empty()) return {0, 0, 1};
    const int i = std::clamp(int((0.5 + lon / (2 * kPi)) * width), 0, width - 1);
    const int j = std::clamp(int((0.5 - lat / kPi) * height), 0, height - 1);
    return glm::dvec3(normal[size_t(j) * width + size_t(i)]);
}

double moonDiskIntegral(const MoonGeometry& g, const MoonMaps& maps, int n) {
    if (n < 2) throw Error("moonDiskIntegral(): grid size not >= 2");
    const double s = std::sin(g.angularRadius);
    glm::dvec3 up, left;
    verticalFrame(g.centre, up, left);
    const glm::dmat3 toSel = glm::transpose(g.axes);
    const double B = hapkePhase(std::clamp(g.phaseRad, 0.0, kPi));
    double sum = 0.0;
    const double h = 2.0 / n;
    for (int iy = 0; iy < n; ++iy)
        for (int ix = 0; ix < n; ++ix) {
            const double x = -1.0 + (ix + 0.5) * h, y = -1.0 + (iy + 0.5) * h;
            const double rho = std::sqrt(x * x + y * y);
            if (rho >= 1.0) continue;
            const double sinT = rho * s, cosT = std::sqrt(1.0 - sinT * sinT);
            const glm::dvec3 e = rho > 0.0 ? (x * up + y * left) / rho : up;
            const glm::dvec3 d = cosT * g.centre + sinT * e;
            glm::dvec3 nrm = sphereNormal(d, g.centre, s);
            const glm::dvec3 sel = toSel * nrm;
            const double lon = std::atan2(sel.y, sel.x), lat = std::asin(std::clamp(sel.z, -1.0, 1.0));
            const double A = maps.albedoAt(lon, lat);
            if (!maps.normal.empty()) {
                const glm::dvec3 t = maps.normalAt(lon, lat);
                const glm::dvec3 tE = g.axes * glm::dvec3(-std::sin(lon), std::cos(lon), 0.0);
                const glm::dvec3 tN = g.axes * glm::dvec3(-std::sin(lat) * std::cos(lon), -std::sin(lat) * std::sin(lon), std::cos(lat));
                nrm = glsl::dp::planet_sphere_shared::planet_mapNormal(t, tE, tN, nrm);  // the shader's text (the map's G points south)
            }
            const double ci = glm::dot(nrm, g.sunFromMoon), ce = std::max(glm::dot(nrm, -d), 0.0);
            if (ci <= 0.0) continue;
            const double dOmega = s * s / cosT * h * h;
            sum += A * B * ci / (ci + ce + 1e-6) * dOmega;
        }
    return sum;
}

Planet::Planet() : Planet(std::string("planet")) {}

Planet::Planet(std::vector<astro::Body> bodies, std::string name) : Planet(std::move(name)) {
    if (this->name().empty()) throw Error("Planet(): empty element name");
    own_ = std::move(bodies);
}

Planet::Planet(std::string name) : SkyElement(std::move(name)) {
    setContributesToLighting(false);  // the Sun's and Moon's disks are SkyLighting's directional lights
    option(planetkeys::bodies, std::string("all"));
    option(planetkeys::sizeFactor, 1.0);
    option(planetkeys::earthshine, true);
    option(planetkeys::eclipse, true);
    option(planetkeys::corona, true);
    option(planetkeys::limbProfile, true);
    option(planetkeys::coronaFlattening, 0.1);
    option(planetkeys::labels, false);
    option(planetkeys::labelMagnitude, false);
    option(planetkeys::labelSize, 0.0);
    option(planetkeys::labelLuminance, 2e-3);
    option(planetkeys::moonTexture, std::string(kMoonTexturePath));
    option(planetkeys::moonNormals, std::string(kMoonNormalsPath));
    reads(keys::sunDirection);
    reads(keys::moonDirection);
    reads(keys::pointSources);
    reads(keys::pointContrast);
    reads(keys::exposureEv100);
    reads(astro::keys::sunDistance);
    reads(astro::keys::sunAngularRadius);
    reads(astro::keys::moonDistance);
    reads(astro::keys::moonAngularRadius);
    reads(astro::keys::moonAxisAngle);
    reads(astro::keys::moonParallacticAngle);
    reads(astro::keys::moonLibrationLon);
    reads(astro::keys::moonLibrationLat);
    reads(generators::lightkeys::sunDiskRadiance);
    reads(generators::lightkeys::sunTransmittance);
    reads(generators::lightkeys::moonIlluminance);
    reads(generators::lightkeys::moonIlluminanceUneclipsed);
    reads(keys::sunEclipseFraction);
    reads(astro::keys::starFrameRotation);
    reads(generators::lightkeys::moonTransmittance);
    for (astro::Body b : astro::kAllBodies) {
        if (b == astro::Body::Sun || b == astro::Body::Moon) continue;
        reads(astro::keys::planetDirection(b));
        reads(astro::keys::planetMagnitude(b));
        reads(astro::keys::planetAngularDiameter(b));
    }
}


void Planet::doValidateOptions(const SkyVars& v) const {
    try {
        (void)parseBodies(v.get(planetkeys::bodies));
    } catch (const Error& e) {
        throw Error(std::string("planet.bodies: ") + e.what());
    }
}

void Planet::loadMoonMaps(const std::string& albedoPath, const std::string& normalPath, const Logger& log) {
    loadedAlbedo_ = albedoPath;
    loadedNormals_ = normalPath;
    maps_ = MoonMaps{};
    integralValid_ = false;
    constexpr int kCpuW = 512, kCpuH = 256;  // the CPU integral's map
    // Albedo: the map's 8-bit values taken as linear relative albedo (the map is contrast-stretched
    // already: maria / highlands ~ 0.4-0.5 as measured; decoding sRGB would exaggerate it ~2x).
    std::vector<float> alb = {1.0f};
    int aw = 1, ah = 1;
    if (!albedoPath.empty()) {
        if (!std::filesystem::exists(albedoPath)) {
            log.warn("planet: the Moon's albedo map '" + albedoPath + "' is missing; a uniform Moon is drawn");
        } else {
            const Image img = readImage(albedoPath);
            aw = img.width;
            ah = img.height;
            alb.assign(size_t(aw) * ah, 0.f);
            for (int y = 0; y < ah; ++y)
                for (int x = 0; x < aw; ++x) alb[size_t(y) * aw + x] = lumaOf(img, x, y);
            maps_.width = kCpuW;
            maps_.height = kCpuH;
            maps_.albedo.assign(size_t(kCpuW) * kCpuH, 0.f);
            for (int y = 0; y < kCpuH; ++y)
                for (int x = 0; x < kCpuW; ++x) {
                    const int x0 = x * aw / kCpuW, x1 = std::max(x0 + 1, (x + 1) * aw / kCpuW);
                    const int y0 = y * ah / kCpuH, y1 = std::max(y0 + 1, (y + 1) * ah / kCpuH);
                    double s = 0;
                    for (int yy = y0; yy < y1; ++yy)
                        for (int xx = x0; xx < x1; ++xx) s += alb[size_t(yy) * aw + xx];
                    maps_.albedo[size_t(y) * kCpuW + x] = float(s / ((x1 - x0) * (y1 - y0)));
                }
        }
    }
    const int levelsA = 1 + int(std::floor(std::log2(double(std::max(aw, ah)))));
    albedoTex_ = gl::Texture2D(aw, ah, GL_R16F, levelsA);
    albedoTex_.upload(GL_RED, GL_FLOAT, alb.data());
    albedoTex_.generateMipmaps();
    albedoTex_.setFilter(GL_LINEAR_MIPMAP_LINEAR, GL_LINEAR);
    albedoTex_.setWrap(GL_REPEAT);
    glTextureParameteri(albedoTex_.id(), GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);

    std::vector<float> nrm = {0.f, 0.f, 1.f};
    int nw = 1, nh = 1;
    if (!normalPath.empty()) {
        if (!std::filesystem::exists(normalPath)) {
            log.warn("planet: the Moon's normal map '" + normalPath + "' is missing; a smooth Moon is drawn");
        } else {
            const Image img = readImage(normalPath);
            if (img.channels < 3) throw Error("planet: the normal map '" + normalPath + "' has fewer than 3 channels");
            nw = img.width;
            nh = img.height;
            nrm.assign(size_t(nw) * nh * 3, 0.f);
            for (int y = 0; y < nh; ++y)
                for (int x = 0; x < nw; ++x)
                    for (int c = 0; c < 3; ++c) nrm[(size_t(y) * nw + x) * 3 + c] = 2.f * img.at(x, y, c) - 1.f;
            {
                // The CPU integral's normals at its own grid (nearest texel of the full map).
                const int cw = maps_.width ? maps_.width : kCpuW, ch = maps_.height ? maps_.height : kCpuH;
                if (maps_.albedo.empty()) {
                    maps_.width = cw;
                    maps_.height = ch;
                    maps_.albedo.assign(size_t(cw) * ch, 1.f);
                }
                maps_.normal.resize(size_t(cw) * ch);
                for (int y = 0; y < ch; ++y)
                    for (int x = 0; x < cw; ++x) {
                        const int sx = std::min((2 * x + 1) * nw / (2 * cw), nw - 1), sy = std::min((2 * y + 1) * nh / (2 * ch), nh - 1);
                        const float* p = &nrm[(size_t(sy) * nw + sx) * 3];
                        maps_.normal[size_t(y) * cw + x] = glm::normalize(glm::vec3(p[0], p[1], p[2]));
                    }
            }
        }
    }
    const int levelsN = 1 + int(std::floor(std::log2(double(std::max(nw, nh)))));
    normalTex_ = gl::Texture2D(nw, nh, GL_RGB16F, levelsN);
    normalTex_.upload(GL_RGB, GL_FLOAT, nrm.data());
    normalTex_.generateMipmaps();
    normalTex_.setFilter(GL_LINEAR_MIPMAP_LINEAR, GL_LINEAR);
    normalTex_.setWrap(GL_REPEAT);
    glTextureParameteri(normalTex_.id(), GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    mapsLoaded_ = true;
}

void Planet::doInit(InitContext& ctx) {
    declareOptions(ctx.vars);
    addGenerator(generators::AtmosphereLights::obtain(ctx.vars));
    // The Moon's maps on units of the element's own (WELKIN_BINDING_MOON_*_TEXTURE in the shader).
    moonAlbedoUnit_ = textureUnit("MOON_ALBEDO_TEXTURE");
    moonNormalUnit_ = textureUnit("MOON_NORMAL_TEXTURE");
    programs_ = gl::ProjectionPrograms(gl::ProgramBuilder("Planet")
                                           .bindings(bindings())
                                           .vertex("engine/camera.glsl", gl::engineShader("camera.glsl"))
                                           .vertex("atmosphere/point_perceptual.glsl", embedded::atmosphere_shaders("point_perceptual.glsl"))
                                           .vertex("planet/planet.vert.glsl", embedded::planet_shaders("planet.vert.glsl"))
                                           .fragment("engine/camera.glsl", gl::engineShader("camera.glsl"))
                                           .fragment("engine/composite.glsl", gl::engineShader("composite.glsl"))
                                           .fragment("planet/planet.frag.glsl", embedded::planet_shaders("planet.frag.glsl")));
    programs_.get(Projection::Perspective);  // shader errors surface in init()
    mapsLoaded_ = false;
    // The Moon's maps (~0.3 s for the 4k JPEG) at init, not in the first frame.
    const std::vector<astro::Body> bodies = own_ ? *own_ : parseBodies(ctx.vars.get(planetkeys::bodies));
    if (std::find(bodies.begin(), bodies.end(), astro::Body::Moon) != bodies.end())
        loadMoonMaps(ctx.vars.get(planetkeys::moonTexture), ctx.vars.get(planetkeys::moonNormals), ctx.log);
}

glm::dvec3 Planet::transmittanceTowards(const SkyVars& v, double altitudeRad) const {
    const generators::SkyModel m = generators::SkyModel::fromVars(v);
    const double h = std::clamp(v.getOr(keys::observerHeight, 0.0), 0.0, m.topRadius - m.bottomRadius);
    if (h >= m.topRadius - m.bottomRadius) return glm::dvec3(1.0);
    const double mu = std::sin(altitudeRad);
    if (generators::cpu::rayIntersectsGround(m, h, mu)) return glm::dvec3(0.0);
    return glm::clamp(generators::cpu::transmittanceToTop(m, h, mu, 128), 0.0, 1.0);
}

void Planet::doRender(const FrameContext& ctx) {
    namespace lk = generators::lightkeys;
    namespace ak = astro::keys;
    const SkyVars& v = ctx.vars;
    drawn_ = 0;
    labelsDrawn_ = 0;
    moonDrawn_ = false;
    // Labels: collected while drawing (direction, name, disk radius in px), drawn last.
    struct Label {
        glm::dvec3 dir;
        std::string name;
        double radiusPx;
    };
    std::vector<Label> labels;
    const bool wantLabels = v.get(planetkeys::labels);
    moonIlluminanceLux_ = v.has(lk::moonIlluminance) ? color::luminance(v.get(lk::moonIlluminance) * v.get(lk::moonTransmittance)) : 0.0;
    const std::vector<astro::Body> bodies = own_ ? *own_ : parseBodies(v.get(planetkeys::bodies));
    if (bodies.empty()) {
        reportNothingDrawn();
        return;
    }
    const bool hasMoon = std::find(bodies.begin(), bodies.end(), astro::Body::Moon) != bodies.end();
    if (hasMoon && (!mapsLoaded_ || v.get(planetkeys::moonTexture) != loadedAlbedo_ || v.get(planetkeys::moonNormals) != loadedNormals_))
        loadMoonMaps(v.get(planetkeys::moonTexture), v.get(planetkeys::moonNormals), ctx.log);

    const bool later = ctx.attenuatedLater;
    const double f = v.get(planetkeys::sizeFactor);
    const Camera& cam = ctx.camera;
    const int copies = cam.projection == Projection::Equirect ? 2 : 1;
    const double psfSigmaPx = kPsfFwhmPx / WELKIN_GAUSSIAN_FWHM_PER_SIGMA;
    // The program is bound (and its per-frame uniforms set) at the first body on screen: a frame
    // with none makes no GL call at all.
    const gl::Program& p = programs_.get(cam.projection);
    bool bound = false;
    bool perceptual = pointSourceMode(v) == PointSourceMode::Perceptual;
    auto bind = [&] {
        if (bound) return;
        bound = true;
        p.use();
        p.set("u_copies", copies);
        p.set("u_psfSigma", float(psfSigmaPx));
        perceptual = generators::setPerceptualPointUniforms(p, v, later);
    };
    // Perceptual point sources (welkin/point_source.hpp): an unresolved planet's illuminance at
    // the eye (lux), its colour (luminance 1), the transmittance the Sky applies later, and its
    // disk's mean luminance at the eye (the drawn point's peak stays under it); set by the
    // planets' loop before draw(), 0 = no perceptual point.
    double ppEyeLux = 0.0, ppLaterT = 1.0, ppDiskCdM2 = 0.0;
    glm::dvec3 ppColour(1.0);

    // Pixels per radian (smallest, largest) at a body's centre; on a cube face also for a centre
    // on a neighbouring face in front of this one (at least the face centre's W / 2).
    auto scaleAt = [&](const glm::dvec3& dir) -> std::optional<glm::dvec2> {
        auto s = cam.pixelScale(dir);
        if (!s && cam.projection == Projection::CubeFace) {
            const auto forward = cam.directionAt({0.5 * cam.width, 0.5 * cam.height});
            if (forward && glm::dot(*forward, dir) > 0.0) s = glm::dvec2(0.5 * cam.width);
        }
        return s;
    };
    // Where a body would be drawn: its pixel scale, whether as a PSF, and whether its quad (as
    // planet.vert.glsl sizes it, 1 px wider) meets the image. A disk's quad: its apparent radius at
    // the largest local scale x 1.05 + 2 px; a PSF's: 4 sigma, sigma at most the perceptual
    // point's largest (FWHM 8 f0, point_perceptual.glsl) when `ppPossible`. In equirect either copy
    // (the seam twin) may meet it. A cube-face body centred on a neighbouring face (no pixel of
    // its own on this face) is kept: its quad is placed by the shader's pinhole maths.
    struct Placement {
        glm::dvec2 scale{0.0};
        bool psf = false, onScreen = false;
    };
    auto place = [&](int kind, const glm::dvec3& dir, double radius, double minPx, bool ppPossible) -> std::optional<Placement> {
        const auto s = scaleAt(dir);
        if (!s) return std::nullopt;
        Placement q;
        q.scale = *s;
        q.psf = kind == kKindPsf || 2.0 * radius * std::sqrt(s->x * s->y) < minPx;
        const double halfPx = (q.psf ? 4.0 * std::max(psfSigmaPx, ppPossible ? 8.0 * kPsfFwhmPx / WELKIN_GAUSSIAN_FWHM_PER_SIGMA : 0.0)
                                     : std::asin(std::min(std::sin(radius), 1.0)) * s->y * 1.05 + 2.0) +
                              1.0;
        for (int c = 0; c < copies && !q.onScreen; ++c) {
            const auto clip = cam.clipFromDirection(dir, c);
            if (!clip) {
                q.onScreen = c == 0;  // the cube face's neighbour (scaleAt() gave it a scale)
                continue;
            }
            if (clip->w <= 0.0) continue;
            const glm::dvec2 px = cam.pixelFromClip(*clip);
            q.onScreen = px.x + halfPx > 0.0 && px.x - halfPx < cam.width && px.y + halfPx > 0.0 && px.y - halfPx < cam.height;
        }
        return q;
    };
    // Draws one placed body: a disk of apparent radius `radius` (rad) around `dir`, or the PSF of
    // illuminance `E` (lux per channel). The caller has bound the program (bind()).
    auto draw = [&](int kind, const Placement& q, const glm::dvec3& dir, double radius, const glm::dvec3& flux, const glm::dvec3& E) {
        p.set("u_kind", q.psf ? kKindPsf : kind);
        p.set("u_centre", glm::vec3(dir));
        p.set("u_sinRadius", float(std::sin(radius)));
        p.set("u_flux", glm::vec3(q.psf ? E : flux));
        const bool ppPoint = perceptual && q.psf && ppEyeLux > 0.0;
        p.set("u_ppPoint", ppPoint ? 1 : 0);
        if (ppPoint) {
            p.set("u_ppEyeLux", float(ppEyeLux));
            p.set("u_ppLaterT", float(ppLaterT));
            p.set("u_ppDiskCdM2", float(ppDiskCdM2));
            p.set("u_ppColour", glm::vec3(ppColour));
            p.set("u_ppFwhmPx", float(kPsfFwhmPx));
        }
        glDrawArraysInstanced(GL_TRIANGLES, 0, 6, copies);
        ++drawn_;
    };
    // A label for a body the projection shows (drawn or just off the image: its text may reach in).
    auto label = [&](const Placement& q, const glm::dvec3& dir, double radius, const char* name) {
        if (wantLabels) labels.push_back({dir, name, q.psf ? 0.5 * kPsfFwhmPx : radius * std::sqrt(q.scale.x * q.scale.y)});
    };

    // The Sun.
    coronaDrawn_ = false;
    diamondRing_ = false;
    if (std::find(bodies.begin(), bodies.end(), astro::Body::Sun) != bodies.end() && v.has(lk::sunDiskRadiance)) {
        const glm::dvec3 T = later ? glm::dvec3(1.0) : v.get(lk::sunTransmittance);
        const glm::dvec3 mean = v.get(lk::sunDiskRadiance) * T;
        const double alpha = v.getOr(ak::sunAngularRadius, 4.65e-3);
        const glm::dvec3 a = sunLimbExponents();
        const glm::dvec3 dir = glm::normalize(v.get(keys::sunDirection));
        // A solar eclipse: the corona (additive, before the disk: the Sun and the dark Moon are
        // drawn over it) while the Moon overlaps the Sun.
        const double visible = v.getOr(keys::sunEclipseFraction, 1.0);
        if (v.get(planetkeys::corona) && visible < 1.0 && (mean != glm::dvec3(0.0) || later)) {
            const double extent = kCoronaExtentSolarRadii * alpha;
            if (const auto q = place(kKindCorona, dir, extent, 2.0, false); q && q->onScreen && !q->psf) {
                bind();
                // The Sun's rotation axis, taken as the ecliptic's north pole (within 7.25 deg).
                glm::dvec3 axis(0.0, 0.0, 1.0);
                if (v.has(ak::starFrameRotation)) {
                    constexpr double eps = 23.4392911 * kPi / 180.0;  // obliquity J2000 (IAU 1980)
                    axis = v.get(ak::starFrameRotation) * glm::dvec3(0.0, -std::sin(eps), std::cos(eps));
                }
                p.set("u_coronaAxis", glm::vec3(axis));
                p.set("u_coronaSunRadius", float(alpha));
                p.set("u_coronaFlattening", float(v.get(planetkeys::coronaFlattening)));
                draw(kKindCorona, *q, dir, extent, mean, glm::dvec3(0.0));
                coronaDrawn_ = true;
            }
        }
        if (mean != glm::dvec3(0.0) || later)
            if (const auto q = place(kKindSun, dir, alpha, 2.0, false)) {
                if (q->onScreen) {
                    bind();
                    p.set("u_limb", glm::vec3(a));
                    draw(kKindSun, *q, dir, alpha, mean * (a + 2.0) / 2.0, mean * kPi * alpha * alpha);
                }
                label(*q, dir, alpha, "Sun");
            }
        // The diamond ring: the last sliver's glare at the limb point farthest from the Moon.
        if (v.get(planetkeys::corona) && visible > 0.0 && visible < kDiamondRingFraction && v.has(keys::moonDirection)) {
            const glm::dvec3 moonDir = glm::normalize(v.get(keys::moonDirection));
            glm::dvec3 away = dir - moonDir - dir * glm::dot(dir - moonDir, dir);
            if (glm::length(away) > 1e-12) {
                away = glm::normalize(away);
                const glm::dvec3 bead = glm::normalize(dir + std::tan(alpha) * away);
                if (const auto s = scaleAt(bead)) {
                    bind();
                    Placement q;
                    q.scale = *s;
                    q.psf = true;
                    q.onScreen = true;
                    const double sigmaPx = std::max(alpha * std::sqrt(s->x * s->y), psfSigmaPx);
                    p.set("u_psfSigma", float(sigmaPx));
                    const double saved = ppEyeLux;
                    ppEyeLux = 0.0;
                    const glm::dvec3 E = kDiamondGlare * visible * mean * kPi * alpha * alpha;
                    draw(kKindPsf, q, bead, 0.0, E, E);
                    ppEyeLux = saved;
                    p.set("u_psfSigma", float(psfSigmaPx));
                    diamondRing_ = true;
                }
            }
        }
    }

    // The planets.
    const glm::dvec3 sunPos = v.getOr(ak::sunDistance, 1.496e11) * glm::normalize(v.get(keys::sunDirection));
    for (astro::Body b : bodies) {
        if (b == astro::Body::Sun || b == astro::Body::Moon) continue;
        if (!v.has(ak::planetDirection(b))) continue;
        const glm::dvec3 dir = glm::normalize(v.get(ak::planetDirection(b)));
        const double radius = std::min(0.5 * v.getOr(ak::planetAngularDiameter(b), 0.0) * f, 1.4);
        // Off the image (and not labelled): nothing to compute.
        const auto q = place(kKindDisk, dir, radius, 3.0, perceptual);
        if (!q || (!q->onScreen && !wantLabels)) continue;
        const double m = v.get(ak::planetMagnitude(b));
        const glm::dvec3 T = later ? glm::dvec3(1.0) : transmittanceTowards(v, std::asin(std::clamp(dir.z, -1.0, 1.0)));
        if (T == glm::dvec3(0.0)) continue;
        label(*q, dir, radius, astro::bodyName(b));
        if (!q->onScreen) continue;
        bind();
        const glm::dvec3 E = astro::magnitude::illuminanceLux(m) * planetColour(b) * T;
        // Lambert sphere lit from the Sun: L = L0 max(n.s, 0), L0 = E / (Omega (2/3) Phi(a)).
        const double dist = astro::bodyRadiusMeters(b) / std::max(std::tan(0.5 * v.getOr(ak::planetAngularDiameter(b), 1e-9)), 1e-12);
        const glm::dvec3 P = dist * dir;
        const glm::dvec3 light = glm::normalize(sunPos - P);
        const double phase = std::acos(std::clamp(glm::dot(light, -dir), -1.0, 1.0));
        const double omega = 2 * kPi * (1 - std::cos(radius));
        const glm::dvec3 L0 = E / (omega * (2.0 / 3.0) * std::max(lambertPhase(phase), 1e-6));
        p.set("u_light", glm::vec3(light));
        if (perceptual) {
            // With the Sky later, E is above the air: the eye gets E x T (T towards the planet).
            const glm::dvec3 Te = later ? transmittanceTowards(v, std::asin(std::clamp(dir.z, -1.0, 1.0))) : glm::dvec3(1.0);
            ppEyeLux = color::luminance(E * Te);
            ppLaterT = later ? color::luminance(Te) : 1.0;
            ppColour = E / std::max(color::luminance(E), 1e-300);
            ppDiskCdM2 = ppEyeLux / std::max(kPi * radius * radius, 1e-30);
        }
        draw(kKindDisk, *q, dir, radius, L0, E);
        ppEyeLux = 0.0;
    }

    // The Moon: calibrated so that its disk integral is lights.moon_illuminance without the
    // lunar eclipse (lights.moon_illuminance_uneclipsed): the disk draws the eclipse per pixel below
    // (planet.eclipse).
    if (hasMoon && v.has(lk::moonIlluminance)) {
        const glm::dvec3 T = later ? glm::dvec3(1.0) : v.get(lk::moonTransmittance);
        const glm::dvec3 E = v.getOr(lk::moonIlluminanceUneclipsed, v.get(lk::moonIlluminance)) * T;
        const MoonGeometry g = moonGeometry(v, f);
        // Off the image (or dark with no Sky after it) and not labelled: nothing to compute.
        const auto q = (E != glm::dvec3(0.0) || later) ? place(kKindMoon, g.centre, g.angularRadius, 2.0, false) : std::nullopt;
        if (q) label(*q, g.centre, g.angularRadius, "Moon");
        if (q && q->onScreen) {
            bind();
            // The integral depends only on the Sun's and the observer's directions in the Moon's
            // frame and the apparent radius: recomputed when one moves by more than 1e-4 rad (its
            // relative change is then < 1e-4).
            const glm::dmat3 toSel = glm::transpose(g.axes);
            const double key[7] = {(toSel * g.sunFromMoon).x, (toSel * g.sunFromMoon).y, (toSel * g.sunFromMoon).z,
                                   (toSel * -g.centre).x, (toSel * -g.centre).y, (toSel * -g.centre).z, g.angularRadius};
            bool same = integralValid_;
            for (int i = 0; i < 6; ++i) same = same && std::abs(key[i] - integralKey_[i]) < 1e-4;
            same = same && std::abs(key[6] / integralKey_[6] - 1.0) < 1e-4;
            if (!same) {
                integral_ = moonDiskIntegral(g, maps_, 96);
                std::copy(key, key + 7, integralKey_);
                integralValid_ = true;
            }
            const double integral = integral_;
            const glm::dvec3 K = integral > 0.0 ? E / integral : glm::dvec3(0.0);  // cd/m^2 per unit A B LS
            moonScale_ = color::luminance(K);
            // Earthshine: K x (E_earth / E_sun) x B(0) S(0) (the Earth is behind the observer).
            glm::dvec3 es(0.0);
            if (v.get(planetkeys::earthshine)) {
                // Unlike sunlight the earthshine is not in the calibration: its own Hapke factor and
                // ratio, over the sunlit model's B(g) (K divides it out).
                es = K * earthshineRatio(g.phaseRad, g.earthMoonDistanceM) * hapkePhase(0.0) * (kEarthshineColour / color::luminance(kEarthshineColour));
            }
            p.set("u_moonAxes", glm::mat3(g.axes));
            p.set("u_worldToSel", glm::mat3(glm::transpose(g.axes)));
            p.set("u_light", glm::vec3(g.sunFromMoon));
            p.set("u_hapke", float(hapkePhase(std::clamp(g.phaseRad, 0.0, kPi))));
            p.set("u_earthshine", glm::vec3(es));
            // Eclipse geometry, in units of 1e6 m (float-friendly): Earth's centre and the Sun
            // relative to the observer, the Moon's distance and true radius.
            const double unit = 1e6;
            const glm::dvec3 earthCentre(0.0, 0.0, -(kEarthRadiusM + v.getOr(keys::observerHeight, 0.0)));
            const double Dm = v.getOr(ak::moonDistance, 3.844e8);
            // The shadow is evaluated per pixel only when the Moon's disk reaches into the penumbra
            // (the Moon's centre within penumbra radius + Moon radius + 1 % of the shadow's axis).
            bool nearShadow = false;
            if (v.get(planetkeys::eclipse)) {
                const glm::dvec3 Mg = Dm * g.centre - earthCentre, Sg = sunPos - earthCentre;
                const glm::dvec3 axis = -glm::normalize(Sg);
                const double along = glm::dot(Mg, axis);
                const double off = glm::length(Mg - along * axis);
                const double Rs = astro::bodyRadiusMeters(astro::Body::Sun), Re = astro::kEarthShadowRadiusMeters;
                const double penumbra = Re + along * (Rs + Re) / glm::length(Sg);
                nearShadow = along > 0.0 && off < 1.01 * (penumbra + astro::bodyRadiusMeters(astro::Body::Moon) * f);
            }
            p.set("u_eclipse", nearShadow ? 1 : 0);
            p.set("u_earthCentre", glm::vec3(earthCentre / unit));
            p.set("u_sunPos", glm::vec3(sunPos / unit));
            p.set("u_moonDist", float(Dm / unit));
            p.set("u_moonRadius", float(astro::bodyRadiusMeters(astro::Body::Moon) / unit));
            // One shadow model with the astronomy's moon.eclipse_factor (welkin/astro/eclipses.hpp).
            p.set("u_earthRadius", float(astro::kEarthShadowRadiusMeters / unit));
            p.set("u_umbraRefracted", glm::vec2(astro::kUmbraRefractedCentre, astro::kUmbraRefractedEdge));
            p.set("u_sunRadius", float(astro::bodyRadiusMeters(astro::Body::Sun) / unit));
            p.set("u_umbraColour", glm::vec3(astro::umbraColour()));
            const auto s = scaleAt(g.centre);
            const double rPx = s ? g.angularRadius * std::sqrt(s->x * s->y) : 1.0;
            p.set("u_albedoLod", float(std::max(std::log2(albedoTex_.width() / (2 * kPi * std::max(rPx, 1e-3))), 0.0)));
            p.set("u_normalLod", float(std::max(std::log2(normalTex_.width() / (2 * kPi * std::max(rPx, 1e-3))), 0.0)));
            albedoTex_.bind(moonAlbedoUnit_);
            normalTex_.bind(moonNormalUnit_);
            // Baily's beads: the limb profile while the Moon overlaps the Sun (heights over the
            // Moon's radius; the 4 x 4 limb samples then resolve 1/4 of a pixel).
            const bool beads = v.get(planetkeys::limbProfile) && v.getOr(keys::sunEclipseFraction, 1.0) < 1.0;
            p.set("u_limbOn", beads ? 1 : 0);
            if (beads) {
                std::array<float, kLimbProfileSamples> rel{};
                const auto& prof = lunarLimbProfileMeters();
                for (std::size_t i = 0; i < rel.size(); ++i) rel[i] = float(prof[i] / astro::bodyRadiusMeters(astro::Body::Moon));
                glUniform1fv(p.location("u_limbProfile"), kLimbProfileSamples, rel.data());  // p is in use (bind())
                p.set("u_limbMax", float(4.0 * kLimbProfileRmsMeters / astro::bodyRadiusMeters(astro::Body::Moon)));
            }
            draw(kKindMoon, *q, g.centre, g.angularRadius, K, E);
            p.set("u_limbOn", 0);
            moonDrawn_ = true;
        }
    }

    // Labels: right of each body drawn, past its disk (or its point image), vertically centred.
    if (wantLabels && !labels.empty()) {
        if (!font_) font_ = gl::Font::load();
        double L = v.get(planetkeys::labelLuminance);
        if (L <= 0) L = 0.8 * 1.2 * std::exp2(v.get(keys::exposureEv100));  // 0.8 of the manual exposure's white
        gl::TextStyle style;
        style.pixelSize = float(v.get(planetkeys::labelSize));
        if (style.pixelSize <= 0) style.pixelSize = std::max(11.0f, float(std::min(cam.width, cam.height)) / 64.0f);
        style.colour = glm::vec3(1.0f, 0.93f, 0.75f);
        style.luminanceCdM2 = float(L);
        style.align = {0.0f, 0.5f};
        for (const Label& l : labels) {
            style.offsetPx = {float(l.radiusPx) + 0.4f * style.pixelSize, 0.0f};
            std::string name = l.name;
            if (!name.empty()) name[0] = char(std::toupper(static_cast<unsigned char>(name[0])));
            if (v.get(planetkeys::labelMagnitude)) name += " " + planetLabelMagnitude(v, l.name);
            labelBatch_.addAt(font_, glm::vec3(l.dir), name, style);
            ++labelsDrawn_;
        }
        labelBatch_.draw(font_);
    }
    if (drawn_ == 0 && labelsDrawn_ == 0) reportNothingDrawn();  // every quad counts in drawn_
}

void Planet::doRelease() {
    programs_.releasePrograms();
    albedoTex_ = gl::Texture2D();
    normalTex_ = gl::Texture2D();
    mapsLoaded_ = false;
    labelBatch_ = gl::TextBatch();
    font_ = gl::Font();
}

void Planet::doStats(nlohmann::json& root) const {
    // moon.illuminated_fraction is the astronomy's (already in the stats).
    root["moon"]["illuminance_lux"] = moonIlluminanceLux_;
    root[name()]["drawn"] = drawn_;
    root[name()]["corona_drawn"] = coronaDrawn_;
    root[name()]["diamond_ring"] = diamondRing_;
    root[name()]["labels"] = labelsDrawn_;
}

}  // namespace welkin::elements

WELKIN_ELEMENT_DESCRIPTOR(planet) {
    static const welkin::ElementDescriptor d{
        "planet", "the Sun's limb-darkened disk, the Moon (phase, libration, earthshine, eclipses) and the planets at their apparent places",
        welkin::Layer::Bodies, true, [] { return std::make_unique<welkin::elements::Planet>(); }};
    return d;
}
