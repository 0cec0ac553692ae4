// NightSky element: the Milky Way's calibration, the CPU twins of the four terms, the published
// background and the per-frame uniforms; the model is described in
// include/welkin/elements/nightsky.hpp and skyelements/nightsky/README.md.
#include <welkin/astro/astro_keys.hpp>
#include <welkin/astro/bodies.hpp>
#include <welkin/color.hpp>
#include <welkin/elements/nightsky.hpp>
#include <welkin/embedded/nightsky_shaders.hpp>
#include <welkin/error.hpp>
#include <welkin/eye.hpp>
#include <welkin/generators/atmosphere.hpp>
#include <welkin/generators/sky_luts.hpp>
#include <welkin/generators/sky_model.hpp>
#include <welkin/gl/shader.hpp>
#include <welkin/glsl_cpp.hpp>
#include <welkin/image.hpp>
#include <welkin/keys.hpp>

#include <epoxy/gl.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <limits>
#include <numbers>

namespace welkin::glsl::dp::nightsky_vanrhijn_shared {
#include "../shaders/nightsky_vanrhijn.shared.glsl"
}  // namespace welkin::glsl::dp::nightsky_vanrhijn_shared

namespace welkin::elements {

namespace {
constexpr double kPi = std::numbers::pi;
constexpr double kDeg = kPi / 180.0;
constexpr double kEarthRadiusM = 6371e3;
constexpr double kObliquityJ2000Rad = 23.4392911 * kDeg;  // IAU 1980 value at J2000 (84381.448")
constexpr double kLightPollutionLayerM = 8000.0;           // the air's scale height
constexpr double kLightPollutionKelvin = 3000.0;           // sodium and warm-white LED light
constexpr double kAirglowLineShare = 0.5;                  // OI 557.7 nm share of the V luminance
// Milky Way calibration (skyelements/nightsky/README.md): the Large Sagittarius Star Cloud (galactic l = 2 deg,
// b = -4 deg, a 3-deg disc) at 20.5 V mag/arcsec^2, the galactic poles at 23.0 (a uniform floor,
// where the panorama is black), L = gain Y^gamma + floor.
constexpr double kMwCloudL = 2.0 * kDeg, kMwCloudB = -4.0 * kDeg, kMwCloudRadius = 3.0 * kDeg;
constexpr double kMwCloudMag = 20.5, kMwFloorMag = 23.0, kMwGamma = 0.5;
constexpr double kMwStorageScale = 1e4;
// Not drawn when the Sky's zenith is this many times brighter than the night sky's (daylight,
// bright twilight): the pass would change pixels by less than 1e-5 relative (6e-5 at the horizon,
// van Rhijn's 6 at most for the airglow), below the float target's visible precision.
constexpr double kSkipRatio = 1e5;  // cd/m^2 -> texture value (fp16 keeps 1e-4 cd/m^2 normal)

constexpr int kZodiTexW = 256, kZodiTexH = 128;  // baked zodiacal light: 1.4 deg texels (the table's grid is 5-15 deg)
constexpr double kZodiRebakeRad = 0.1 * kDeg;       // re-baked when the Sun's longitude moved more (2.4 h)
constexpr int kTableN = 64;  // NIGHT_TABLE_N: extinction samples over altitude (as the Stars')
constexpr double kTableLo = -5.0 * kDeg, kTableSpan = 95.0 * kDeg;
double tableAltitude(int i) {
    const double u = double(i) / (kTableN - 1);
    return kTableLo + kTableSpan * u * u;
}

// Leinert et al. 1998 (A&AS 127, 1), Table 17: zodiacal light at 500 nm in 1e-8 W m^-2 sr^-1
// um^-1, rows |lambda - lambda_sun| = 0, 5, ..., 45, 60, 75, ..., 180 deg, columns |beta| = 0, 5,
// ..., 30, 45, 60, 75, 90 deg. 0 marks the cells the paper leaves empty (near the Sun).
constexpr int kZodiRows = 19, kZodiCols = 11;
constexpr float kZodi[kZodiRows][kZodiCols] = {
    {0, 0, 0, 3140, 1610, 985, 640, 275, 150, 100, 77},
    {0, 0, 0, 2940, 1540, 945, 625, 271, 150, 100, 77},
    {0, 0, 4740, 2470, 1370, 865, 590, 264, 148, 100, 77},
    {11500, 6780, 3440, 1860, 1110, 755, 525, 251, 146, 100, 77},
    {6400, 4480, 2410, 1410, 910, 635, 454, 237, 141, 99, 77},
    {3840, 2830, 1730, 1100, 749, 545, 410, 223, 136, 97, 77},
    {2480, 1870, 1220, 845, 615, 467, 365, 207, 131, 95, 77},
    {1650, 1270, 910, 680, 510, 397, 320, 193, 125, 93, 77},
    {1180, 940, 700, 530, 416, 338, 282, 179, 120, 92, 77},
    {910, 730, 555, 442, 356, 292, 250, 166, 116, 90, 77},
    {505, 442, 352, 292, 243, 209, 183, 134, 104, 86, 77},
    {338, 317, 269, 227, 196, 172, 151, 116, 93, 82, 77},
    {259, 251, 225, 193, 166, 147, 132, 104, 86, 79, 77},
    {212, 210, 197, 170, 150, 133, 119, 96, 82, 77, 77},
    {188, 186, 177, 154, 138, 125, 113, 90, 77, 74, 77},
    {179, 178, 166, 147, 134, 122, 110, 90, 77, 73, 77},
    {179, 178, 165, 148, 137, 127, 116, 96, 79, 72, 77},
    {196, 192, 179, 165, 151, 141, 131, 104, 82, 72, 77},
    {230, 212, 195, 178, 163, 148, 134, 105, 83, 72, 77},
};

// The table with its empty cells filled by the nearest tabulated latitude of the same row.
const std::vector<float>& zodiacalFilled() {
    static const std::vector<float> t = [] {
        std::vector<float> out(kZodiRows * kZodiCols);
        for (int i = 0; i < kZodiRows; ++i) {
            int first = 0;
            while (kZodi[i][first] == 0) ++first;
            for (int j = 0; j < kZodiCols; ++j) out[i * kZodiCols + j] = kZodi[i][std::max(j, first)];
        }
        return out;
    }();
    return t;
}

double rowCoord(double dlDeg) { return dlDeg < 45.0 ? dlDeg / 5.0 : 9.0 + (dlDeg - 45.0) / 15.0; }
double colCoord(double bDeg) { return bDeg < 30.0 ? bDeg / 5.0 : 6.0 + (bDeg - 30.0) / 15.0; }

double srgbToLinear(double c) { return c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4); }

glm::dvec3 normalisedLuminance(glm::dvec3 rgb) {
    rgb = glm::max(rgb, glm::dvec3(0.0));
    return rgb / color::luminance(rgb);
}

// The airglow's colour: the OI 557.7 nm line carrying kAirglowLineShare of the luminance, an
// equal-energy continuum the rest (clipped to the sRGB gamut), luminance 1.
glm::dvec3 airglowColour() {
    const glm::dvec3 line = color::xyzToLinearSrgb(color::cie1931(557.7) / color::cie1931(557.7).y);
    const glm::dvec3 white = color::xyzToLinearSrgb(glm::dvec3(1.0));
    return normalisedLuminance(kAirglowLineShare * line + (1.0 - kAirglowLineShare) * white);
}

// Sun's colour (ASTM G-173 through CIE 1931), luminance 1.
glm::dvec3 solarColour() { return normalisedLuminance(color::solarIlluminanceSrgb()); }

glm::dvec3 lightPollutionColour() { return color::blackBodyLinearSrgb(kLightPollutionKelvin); }

double sunEclipticLongitude(const glm::dmat3& icrsToEnu, const glm::dvec3& sunEnu) {
    const glm::dvec3 e = icrsToEcliptic() * (glm::transpose(icrsToEnu) * sunEnu);
    return std::atan2(e.y, e.x);
}

double zodiacalAt(const glm::dvec3& icrs, double sunLon) {
    const glm::dvec3 e = icrsToEcliptic() * icrs;
    return zodiacalTable(std::atan2(e.y, e.x) - sunLon, std::asin(std::clamp(e.z, -1.0, 1.0)));
}
}  // namespace

double vanRhijn(double z, double h) {
    if (!(z >= 0.0 && z <= kPi / 2 + 1e-12)) throw Error("vanRhijn(): zenith angle not in [0, pi/2] rad");
    if (!(h > 0.0)) throw Error("vanRhijn(): layer height not > 0 m");
    const double r = kEarthRadiusM / (kEarthRadiusM + h);
    return glsl::dp::nightsky_vanrhijn_shared::night_vanRhijn(std::cos(z), r * r);  // the shader's text
}

double bortleZenithMag(int c) {
    // Total zenith V brightness per class: class midpoints of the sky-quality ranges usually given
    // with Bortle's scale (Bortle 2001, Sky & Telescope 101 (2), 126); class 1 is the dark-sky
    // reference, class 9 "brighter than 18".
    static constexpr double kMag[9] = {nightkeys::kDarkSkyZenithMag, 21.9, 21.7, 21.1, 20.0, 19.2, 18.7, 18.2, 17.5};
    if (c < 1 || c > 9) throw Error("bortleZenithMag(): class " + std::to_string(c) + " not in [1, 9]");
    return kMag[c - 1];
}

double zodiacalTable(double dLambda, double beta) {
    if (!(std::abs(beta) <= kPi / 2 + 1e-9)) throw Error("zodiacalTable(): ecliptic latitude not in [-pi/2, pi/2] rad");
    const double dl = std::abs(std::remainder(dLambda, 2.0 * kPi)) / kDeg;  // [0, 180]
    const double r = std::clamp(rowCoord(dl), 0.0, double(kZodiRows - 1));
    const double c = std::clamp(colCoord(std::abs(beta) / kDeg), 0.0, double(kZodiCols - 1));
    const int i = std::min(int(r), kZodiRows - 2), j = std::min(int(c), kZodiCols - 2);
    const auto& t = zodiacalFilled();
    auto at = [&](int a, int b) { return double(t[a * kZodiCols + b]); };
    const double fr = r - i, fc = c - j;
    const double a = at(i, j) + (at(i, j + 1) - at(i, j)) * fc;
    const double b = at(i + 1, j) + (at(i + 1, j + 1) - at(i + 1, j)) * fc;
    return a + (b - a) * fr;
}

double zodiacalMaxBeyond(double minElongationRad) {
    static const double kRowDeg[kZodiRows] = {0, 5, 10, 15, 20, 25, 30, 35, 40, 45, 60, 75, 90, 105, 120, 135, 150, 165, 180};
    static const double kColDeg[kZodiCols] = {0, 5, 10, 15, 20, 25, 30, 45, 60, 75, 90};
    const auto& t = zodiacalFilled();
    double best = 0.0;
    for (int i = 0; i + 1 < kZodiRows; ++i)
        for (int j = 0; j + 1 < kZodiCols; ++j) {
            // The cell's largest elongation is at its far corner (cos e = cos dl cos b, both in [0, 180] and [0, 90]).
            const double far = std::acos(std::cos(kRowDeg[i + 1] * kDeg) * std::cos(kColDeg[j + 1] * kDeg));
            if (far < minElongationRad) continue;
            best = std::max({best, double(t[i * kZodiCols + j]), double(t[i * kZodiCols + j + 1]), double(t[(i + 1) * kZodiCols + j]),
                             double(t[(i + 1) * kZodiCols + j + 1])});
        }
    return best;
}

double zodiacalUnitCdM2() {
    // Radiance R(l) = S(l) x 1e-11 / S(500 nm) W m^-2 sr^-1 nm^-1 (1e-8 per um at 500 nm), so
    // L = 683 integral R y dl = (the Sun's illuminance, lux) x 1e-11 / S(500 nm).
    static const double unit = color::luminance(color::solarIlluminanceSrgb()) * 1e-11 / color::solarIrradianceAstmG173(500.0);
    return unit;
}

glm::dmat3 icrsToGalactic() {
    // Hipparcos Catalogue (ESA 1997) vol. 1 eq. 1.5.11: the IAU 1958 galactic system in ICRS axes
    // (NGP at RA 192.85948 deg, Dec 27.12825 deg; l of the north celestial pole 122.93192 deg).
    // glm is column-major: the rows below are written as the columns of the transpose.
    const glm::dmat3 rows(-0.0548755604, -0.8734370902, -0.4838350155,   //
                          0.4941094279, -0.4448296300, 0.7469822445,     //
                          -0.8676661490, -0.1980763734, 0.4559837762);
    return glm::transpose(rows);
}

glm::dmat3 icrsToEcliptic() {
    const double c = std::cos(kObliquityJ2000Rad), s = std::sin(kObliquityJ2000Rad);
    // x' = x, y' = c y + s z, z' = -s y + c z (columns of glm's column-major constructor).
    return glm::dmat3(1, 0, 0, 0, c, -s, 0, s, c);
}

NightCubeStale nightCubeStale(const NightCubeInputs& built, const NightCubeInputs& now) {
    NightCubeStale out;
    out.milkyWay = std::isnan(built.milkyWayScale) || built.milkyWayScale != now.milkyWayScale || built.milkyWayPath != now.milkyWayPath ||
                   built.milkyWayLoaded != now.milkyWayLoaded;
    out.zodiacal = std::isnan(built.sunEclipticLongitudeRad) || built.zodiacalScale != now.zodiacalScale ||
                   !(std::abs(std::remainder(now.sunEclipticLongitudeRad - built.sunEclipticLongitudeRad, 2.0 * kPi)) <= kNightCubeSunToleranceRad);
    return out;
}

glm::dvec2 milkyWayTexCoord(const glm::dvec3& p) {
    const double u = (0.5 * kPi - std::atan2(p.y, p.x)) / (2.0 * kPi);
    return {u - std::floor(u), std::acos(std::clamp(p.z, -1.0, 1.0)) / kPi};
}

NightSky::NightSky() : SkyElement("nightsky") {
    option(nightkeys::milkyWayTexture, std::string("/usr/share/stellarium/textures/milkyway.png"));
    option(nightkeys::milkyWayScale, 1.0);
    option(nightkeys::airglowZenithMag, 22.38);  // 145 S10 (Leinert et al. 1998)
    option(nightkeys::airglowHeight, 90e3);
    option(nightkeys::zodiacalScale, 1.0);
    option(nightkeys::bortle, 1);
    reads(astro::keys::starFrameRotation);
    reads(keys::sunDirection);
    reads(keys::observerHeight);
    reads(generators::skykeys::zenithLuminance);
    reads(keys::interactive);  // the folded texture's rebuild spread over frames (foldUpdate)
    option(nightkeys::skipInvisible, true);
    // The pass's image kept and reused while nothing it reads changed (doRender).
    option(nightkeys::reuse, true);
    option(nightkeys::reuseTolerancePx, 0.05);
    // The skip where the previous frame's exposure cannot show the pass (doRender).
    reads(keys::exposurePrevious);
    reads(keys::exposureAuto);
    reads(eye::keys::curve);
    reads(eye::keys::mesopic);
    reads(eye::keys::scotopicBelow);
    reads(eye::keys::photopicAbove);
    reads(eye::keys::rodChromaticity);
    writes(nightkeys::background);
}

double NightSky::milkyWayFloorCdM2() const { return surfaceBrightnessCdM2(kMwFloorMag); }

void NightSky::loadMilkyWay(const std::string& path, const Logger& log) {
    mwPath_ = path;
    mwLoaded_ = false;
    mwCpu_.clear();
    mwMax_ = glm::dvec3(0.0);
    mwTexture_ = gl::Texture2D();
    if (path.empty() || !std::filesystem::exists(path)) {
        log.warn("nightsky: Milky Way panorama '" + path + "' not found (stellarium-data); only its uniform floor is drawn");
        return;
    }
    Image img = readImage(path);
    if (img.channels < 3 || img.width < 2 || img.height < 2) throw Error("nightsky: '" + path + "' is not an RGB image");
    const int W = img.width, H = img.height;
    // sRGB -> linear, luminance; the calibration region and the mean colour (solid-angle weighted).
    std::vector<float> Y(size_t(W) * H);
    std::vector<float> rgb(size_t(W) * H * 3);
    const glm::dmat3 toGal = icrsToGalactic();
    const glm::dvec3 cloud(std::cos(kMwCloudB) * std::cos(kMwCloudL), std::cos(kMwCloudB) * std::sin(kMwCloudL), std::sin(kMwCloudB));
    const double cosR = std::cos(kMwCloudRadius);
    // 8-bit sources decode exactly through a table (OpenImageIO gives k / 255); others per value.
    double decode[256];
    for (int k = 0; k < 256; ++k) decode[k] = srgbToLinear(k / 255.0);
    auto linear = [&](float v) {
        const double c = std::clamp(double(v), 0.0, 1.0), k = std::round(c * 255.0);
        return std::abs(c * 255.0 - k) < 1e-4 ? decode[int(k)] : srgbToLinear(c);
    };
    double cloudSum = 0, cloudW = 0;
    glm::dvec3 colourSum(0.0);
    for (int y = 0; y < H; ++y) {
        const double dec = kPi / 2 - (y + 0.5) / H * kPi, w = std::cos(dec);
        for (int x = 0; x < W; ++x) {
            const size_t i = size_t(y) * W + x;
            glm::dvec3 c;
            for (int k = 0; k < 3; ++k) c[k] = linear(img.pixels[i * img.channels + k]);
            const double Yi = color::luminance(c);
            Y[i] = float(Yi);
            for (int k = 0; k < 3; ++k) rgb[3 * i + k] = float(c[k]);
            colourSum += w * c;
            const double ra = 0.5 * kPi - (x + 0.5) / W * 2.0 * kPi;
            const glm::dvec3 p(std::cos(dec) * std::cos(ra), std::cos(dec) * std::sin(ra), std::sin(dec));
            if (glm::dot(toGal * p, cloud) > cosR) {
                cloudSum += w * std::pow(Yi, kMwGamma);
                cloudW += w;
            }
        }
    }
    if (!(cloudSum > 0.0)) throw Error("nightsky: '" + path + "' is black over the Sagittarius star cloud (not the J2000 Milky Way panorama?)");
    mwGain_ = (surfaceBrightnessCdM2(kMwCloudMag) - surfaceBrightnessCdM2(kMwFloorMag)) / (cloudSum / cloudW);
    mwColour_ = normalisedLuminance(colourSum);
    // Calibrated radiance (before the floor): rgb x gain Y^(gamma - 1), stored x kMwStorageScale.
    std::vector<float> tex(size_t(W) * H * 4);
    mwCpu_.assign(size_t(W) * H, 0.f);
    for (size_t i = 0; i < Y.size(); ++i) {
        const double f = Y[i] > 0.f ? mwGain_ * std::pow(double(Y[i]), kMwGamma - 1.0) : 0.0;
        for (int k = 0; k < 3; ++k) tex[4 * i + k] = float(rgb[3 * i + k] * f * kMwStorageScale);
        tex[4 * i + 3] = 1.f;
        mwCpu_[i] = float(Y[i] * f);
        for (int k = 0; k < 3; ++k) mwMax_[k] = std::max(mwMax_[k], double(rgb[3 * i + k]) * f);
    }
    int levels = 1;
    while ((std::max(W, H) >> levels) > 0) ++levels;
    mwTexture_ = gl::Texture2D(W, H, GL_RGBA16F, levels);
    mwTexture_.upload(GL_RGBA, GL_FLOAT, tex.data());
    mwTexture_.generateMipmaps();
    mwTexture_.setFilter(GL_LINEAR_MIPMAP_LINEAR, GL_LINEAR);
    glTextureParameteri(mwTexture_.id(), GL_TEXTURE_WRAP_S, GL_REPEAT);
    glTextureParameteri(mwTexture_.id(), GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    mwW_ = W;
    mwH_ = H;
    mwLoaded_ = true;
}

namespace {
// The table over the panorama's mapping for this solar longitude (texel centres), row 0 the top.
std::vector<float> bakeZodiacalTable(double sunLon) {
    std::vector<float> t(size_t(kZodiTexW) * kZodiTexH);
    for (int y = 0; y < kZodiTexH; ++y) {
        const double dec = kPi / 2 - (y + 0.5) / kZodiTexH * kPi;
        for (int x = 0; x < kZodiTexW; ++x) {
            const double ra = 0.5 * kPi - (x + 0.5) / kZodiTexW * 2.0 * kPi;
            t[size_t(y) * kZodiTexW + x] = float(zodiacalAt({std::cos(dec) * std::cos(ra), std::cos(dec) * std::sin(ra), std::sin(dec)}, sunLon));
        }
    }
    return t;
}
}  // namespace

void NightSky::uploadZodiacal(const std::vector<float>& t) {
    if (zodiTexture_.id() == 0) {
        zodiTexture_ = gl::Texture2D(kZodiTexW, kZodiTexH, GL_R32F);
        zodiTexture_.setFilter(GL_LINEAR);
        glTextureParameteri(zodiTexture_.id(), GL_TEXTURE_WRAP_S, GL_REPEAT);
        glTextureParameteri(zodiTexture_.id(), GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    }
    zodiTexture_.upload(GL_RED, GL_FLOAT, t.data());
}

void NightSky::bakeZodiacal(double sunLon) {
    uploadZodiacal(bakeZodiacalTable(sunLon));
    zodiLon_ = sunLon;
}

void NightSky::foldAllocate(int slot) {
    const int W = mwLoaded_ ? mwW_ : kZodiTexW, H = mwLoaded_ ? mwH_ : kZodiTexH;
    const int levels = mwLoaded_ ? mwTexture_.levels() : 1;
    gl::Texture2D& t = fold_[slot];
    if (t.id() != 0 && t.width() == W && t.height() == H && t.levels() == levels) return;
    t = gl::Texture2D(W, H, GL_RGBA32F, levels);
    t.setFilter(GL_LINEAR_MIPMAP_LINEAR, GL_LINEAR);
    glTextureParameteri(t.id(), GL_TEXTURE_WRAP_S, GL_REPEAT);
    glTextureParameteri(t.id(), GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
}

bool NightSky::foldStep(const FrameContext& ctx, long budget) {
    const int back = 1 - foldFront_;
    if (foldStage_ == 0) {
        // The zodiacal table for the target longitude (32,768 lookups on the CPU): a frame of its
        // own when the rebuild is spread.
        zodiBaked_[back] = bakeZodiacalTable(foldTargetLon_);
        uploadZodiacal(zodiBaked_[back]);
        foldStage_ = 1;
        foldLevel_ = foldRow_ = 0;
        if (budget != kFoldWhole) return false;
    }
    gl::Texture2D& t = fold_[back];
    GLint prevFbo = 0, prevViewport[4], prevScissor[4];
    glGetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &prevFbo);
    glGetIntegerv(GL_VIEWPORT, prevViewport);
    glGetIntegerv(GL_SCISSOR_BOX, prevScissor);
    const GLboolean blend = glIsEnabled(GL_BLEND), scissor = glIsEnabled(GL_SCISSOR_TEST), depth = glIsEnabled(GL_DEPTH_TEST);
    glDisable(GL_BLEND);
    glDisable(GL_DEPTH_TEST);
    glEnable(GL_SCISSOR_TEST);
    if (foldFbo_.id() == 0) foldFbo_ = gl::Framebuffer::create();
    const gl::Program& p = foldProgram_;
    p.use();
    p.set("u_zodi", foldZodi_);
    p.set("u_mwFloor", foldFloor_);
    p.set("u_mwScale", foldMwScale_);
    zodiTexture_.bind(zodiacalUnit_);
    if (mwLoaded_) mwTexture_.bind(milkyWayUnit_);
    // Whole rows of one level at a time, top level first, until the budget is spent (at least
    // one row a frame); each band is the same draw whether a frame draws one or all of them.
    long left = budget;
    while (foldLevel_ < t.levels() && left > 0) {
        const int w = std::max(t.width() >> foldLevel_, 1), h = std::max(t.height() >> foldLevel_, 1);
        const int rows = int(std::min<long>(h - foldRow_, std::max<long>(1, left / w)));
        foldFbo_.attach(GL_COLOR_ATTACHMENT0, t, foldLevel_);
        foldFbo_.bind();
        glViewport(0, 0, w, h);
        glScissor(0, foldRow_, w, rows);
        p.set("u_level", foldLevel_);
        p.set("u_size", glm::vec2(float(w), float(h)));
        ctx.drawFullscreen();
        left -= long(rows) * w;
        foldRow_ += rows;
        if (foldRow_ == h) {
            ++foldLevel_;
            foldRow_ = 0;
        }
    }
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, GLuint(prevFbo));
    glViewport(prevViewport[0], prevViewport[1], prevViewport[2], prevViewport[3]);
    glScissor(prevScissor[0], prevScissor[1], prevScissor[2], prevScissor[3]);
    if (blend) glEnable(GL_BLEND);
    if (!scissor) glDisable(GL_SCISSOR_TEST);
    if (depth) glEnable(GL_DEPTH_TEST);
    if (foldLevel_ < t.levels()) return false;
    foldFront_ = back;
    foldLon_[back] = foldTargetLon_;
    foldStage_ = -1;
    ++foldBuilds_;
    return true;
}

void NightSky::foldUpdate(const FrameContext& ctx) {
    const SkyVars& v = ctx.vars;
    const NightCubeInputs now{sunLon_, v.get(nightkeys::milkyWayScale), v.get(nightkeys::zodiacalScale), mwPath_, mwLoaded_};
    const bool keysChanged = fold_[foldFront_].id() == 0 || std::isnan(foldLon_[foldFront_]) || foldInputs_.milkyWayScale != now.milkyWayScale ||
                             foldInputs_.zodiacalScale != now.zodiacalScale || foldInputs_.milkyWayPath != now.milkyWayPath ||
                             foldInputs_.milkyWayLoaded != now.milkyWayLoaded;
    if (keysChanged) {
        // The first build, or another Milky Way or zodiacal scale or panorama: whole, now (a key
        // change is an edit, not time running), into both textures' sizes.
        foldInputs_ = now;
        foldZodi_ = glm::vec3(now.zodiacalScale * zodiacalUnitCdM2() * solarColour() * kMwStorageScale);
        foldFloor_ = glm::vec3(now.milkyWayScale * milkyWayFloorCdM2() * mwColour_ * kMwStorageScale);
        foldMwScale_ = float(mwLoaded_ ? now.milkyWayScale : 0.0);
        foldAllocate(0);
        foldAllocate(1);
        foldTargetLon_ = sunLon_;
        foldStage_ = 0;
        foldStep(ctx, kFoldWhole);
        return;
    }
    if (foldStage_ < 0 && !(std::abs(std::remainder(sunLon_ - foldLon_[foldFront_], 2.0 * kPi)) < kZodiRebakeRad)) {
        foldTargetLon_ = sunLon_;  // the Sun moved 0.1 deg: rebuild the back texture for it
        foldStage_ = 0;
    }
    // Spread over frames only where frames are shown one after another (render.interactive:
    // welkin view, a game loop); otherwise every frame is complete (welkin render, a timelapse).
    const bool spread = foldBudget_ > 0 && v.getOr(keys::interactive, false);
    if (foldStage_ >= 0) foldStep(ctx, spread ? foldBudget_ : kFoldWhole);
}

void NightSky::doInit(InitContext& ctx) {
    declareOptions(ctx.vars);
    ctx.vars.declare(nightkeys::background, surfaceBrightnessCdM2(nightkeys::kDarkSkyZenithMag));
    loadMilkyWay(ctx.vars.get(nightkeys::milkyWayTexture), ctx.log);
    // The Milky Way and the zodiacal light (panoramas, or their cubes) on units of its own.
    milkyWayUnit_ = textureUnit("MILKY_WAY_TEXTURE");
    zodiacalUnit_ = textureUnit("ZODIACAL_TEXTURE");
    // Two recipes: with and without the element's own extinction (compiled in, not a uniform
    // branch: llvmpipe runs both sides of a branch, so the table's lookup cost every pixel under a
    // Sky too).
    for (int extinction = 0; extinction < 2; ++extinction)
        for (int lod0 = 0; lod0 < 2; ++lod0) {
            gl::ProgramBuilder b(direct_ ? "NightSky (direct)" : "NightSky");
            b.bindings(bindings());
            if (direct_) b.define("NIGHT_DIRECT");
            if (extinction) b.define("NIGHT_EXTINCTION");
            if (lod0) b.define("NIGHT_LOD0");
            programs_[extinction][lod0] = gl::ProjectionPrograms(
                b.define("NIGHT_TABLE_N", kTableN)
                    .fullscreenVertex()
                    .fragment("engine/camera.glsl", gl::engineShader("camera.glsl"))
                    .fragment("engine/composite.glsl", gl::engineShader("composite.glsl"))
                    .fragment("nightsky/nightsky.frag.glsl", embedded::nightsky_shaders("nightsky.frag.glsl")));
        }
    // Shader errors surface in init(): the default scene's programs (the others: first use).
    programs_[0][0].get(Projection::Perspective);
    programs_[0][1].get(Projection::Perspective);
    if (direct_)
        foldProgram_ = gl::ProgramBuilder("NightSky fold")
                           .bindings(bindings())
                           .fullscreenVertex()
                           .fragment("nightsky/nightsky_fold.frag.glsl", embedded::nightsky_shaders("nightsky_fold.frag.glsl"))
                           .build();
    else
        cubeProgram_ = gl::ProgramBuilder("NightSky cube")
                           .bindings(bindings())
                           .fullscreenVertex()
                           .fragment("nightsky/nightsky_cube.frag.glsl", embedded::nightsky_shaders("nightsky_cube.frag.glsl"))
                           .build();
}

NightCubeInputs NightSky::cubeInputs(const SkyVars& v) const {
    // The zodiacal texture is re-baked (doUpdate) at the same tolerance: the cube follows it.
    return {zodiLon_, v.get(nightkeys::milkyWayScale), v.get(nightkeys::zodiacalScale), mwPath_, mwLoaded_};
}

void NightSky::buildCube(const FrameContext& ctx, const NightCubeInputs& in, bool zodiacal) {
    const auto t0 = std::chrono::steady_clock::now();
    const int N = zodiacal ? kNightZodiCubeSize : kNightCubeSize;
    gl::TextureCube& cube = zodiacal ? zodiCube_ : cube_;
    if (cube.id() == 0) {
        int levels = 1;
        while (!zodiacal && (N >> levels) > 0) ++levels;
        cube = gl::TextureCube(N, GL_RGBA16F, levels);
        cube.setFilter(zodiacal ? GL_LINEAR : GL_LINEAR_MIPMAP_LINEAR, GL_LINEAR);
        cube.setWrap(GL_CLAMP_TO_EDGE);
    }
    if (cubeFbo_.id() == 0) cubeFbo_ = gl::Framebuffer::create();
    GLint prevFbo = 0, prevViewport[4];
    glGetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &prevFbo);
    glGetIntegerv(GL_VIEWPORT, prevViewport);
    const GLboolean blend = glIsEnabled(GL_BLEND), scissor = glIsEnabled(GL_SCISSOR_TEST), depth = glIsEnabled(GL_DEPTH_TEST);
    glDisable(GL_BLEND);
    glDisable(GL_SCISSOR_TEST);
    glDisable(GL_DEPTH_TEST);
    glViewport(0, 0, N, N);
    const gl::Program& p = cubeProgram_;
    p.use();
    p.set("u_part", zodiacal ? 1 : 0);
    p.set("u_size", float(N));
    p.set("u_zodi", glm::vec3(in.zodiacalScale * zodiacalUnitCdM2() * solarColour() * kMwStorageScale));
    p.set("u_mwFloor", glm::vec3(in.milkyWayScale * milkyWayFloorCdM2() * mwColour_ * kMwStorageScale));
    p.set("u_mwScale", float(mwLoaded_ ? in.milkyWayScale : 0.0));
    p.set("u_texelsPerRad", float(mwW_ / (2.0 * kPi)));
    zodiTexture_.bind(zodiacalUnit_);
    if (mwLoaded_) mwTexture_.bind(milkyWayUnit_);
    for (int face = 0; face < 6; ++face) {
        cubeFbo_.attach(GL_COLOR_ATTACHMENT0, cube, 0, face);
        if (face == 0) cubeFbo_.checkComplete("nightsky cube");
        cubeFbo_.bind();
        p.set("u_face", face);
        ctx.drawFullscreen();
    }
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, GLuint(prevFbo));
    glViewport(prevViewport[0], prevViewport[1], prevViewport[2], prevViewport[3]);
    if (blend) glEnable(GL_BLEND);
    if (scissor) glEnable(GL_SCISSOR_TEST);
    if (depth) glEnable(GL_DEPTH_TEST);
    const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    if (zodiacal) {
        cubeBuiltFor_.sunEclipticLongitudeRad = in.sunEclipticLongitudeRad;
        cubeBuiltFor_.zodiacalScale = in.zodiacalScale;
        ++zodiCubeBuilds_;
        zodiCubeBuildMs_ = ms;
    } else {
        cube.generateMipmaps();
        cubeBuiltFor_.milkyWayScale = in.milkyWayScale;
        cubeBuiltFor_.milkyWayPath = in.milkyWayPath;
        cubeBuiltFor_.milkyWayLoaded = in.milkyWayLoaded;
        ++cubeBuilds_;
        cubeBuildMs_ = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    }
}

void NightSky::doUpdate(const FrameContext& ctx) {
    SkyVars& v = ctx.vars;
    // The skip's slope bound (doRender) is computed once per mesopic setting and memoised (a few
    // ms: a sampled Jacobian); asked in every frame, so that computation falls in the first frame
    // rather than in the first frame where an exposure is known (time starting: it made that
    // frame 5-10 still frames at 512x256, docs/BENCHMARKS.md).
    if (v.get(nightkeys::skipInvisible) && v.get(eye::keys::mesopic))
        (void)eye::displaySlopeBound(eye::keys::curve.value(v), true, v.get(eye::keys::scotopicBelow), v.get(eye::keys::photopicAbove),
                                     v.get(eye::keys::rodChromaticity));
    if (v.get(nightkeys::milkyWayTexture) != mwPath_) loadMilkyWay(v.get(nightkeys::milkyWayTexture), ctx.log);
    // The four terms at the zenith (CPU twins of the shader), published for the stars.
    const glm::dmat3 R = v.getOr(astro::keys::starFrameRotation, glm::dmat3(1.0));
    const glm::dvec3 zenithIcrs = glm::transpose(R) * glm::dvec3(0, 0, 1);
    const double sunLon = sunEclipticLongitude(R, v.getOr(keys::sunDirection, glm::dvec3(0, 0, -1)));
    sunLon_ = sunLon;
    // The cube path's table (the per-pixel path bakes its own for the folded texture: foldStep).
    if (!direct_ && !(std::abs(std::remainder(sunLon - zodiLon_, 2.0 * kPi)) < kZodiRebakeRad)) bakeZodiacal(sunLon);
    zenith_.airglow = surfaceBrightnessCdM2(v.get(nightkeys::airglowZenithMag));
    zenith_.zodiacal = v.get(nightkeys::zodiacalScale) * zodiacalUnitCdM2() * zodiacalAt(zenithIcrs, sunLon);
    const double mwScale = v.get(nightkeys::milkyWayScale);
    zenith_.milkyWay = mwScale * milkyWayFloorCdM2();
    if (mwLoaded_) {
        const glm::dvec2 uv = milkyWayTexCoord(zenithIcrs);
        const int x = std::min(int(uv.x * mwW_), mwW_ - 1), y = std::min(int(uv.y * mwH_), mwH_ - 1);
        zenith_.milkyWay += mwScale * mwCpu_[size_t(y) * mwW_ + x];
    }
    zenith_.lightPollution = std::max(surfaceBrightnessCdM2(bortleZenithMag(v.get(nightkeys::bortle))) - surfaceBrightnessCdM2(nightkeys::kDarkSkyZenithMag), 0.0);
    v.set(nightkeys::background, zenith_.airglow + zenith_.zodiacal + zenith_.milkyWay + zenith_.lightPollution);
}

void NightSky::updateExtinction(const SkyVars& v) {
    // The atmosphere's transmittance towards each table altitude (as the Stars' table), when the
    // observer's height or the atmosphere changed.
    const void* atm = v.has(atmosphere::kAtmosphere) ? v.get(atmosphere::kAtmosphere).get() : nullptr;
    const double h = v.getOr(keys::observerHeight, 0.0);
    if (!extinction_.empty() && atm == extinctionAtm_ && h == extinctionHeight_) return;
    const generators::SkyModel m = generators::SkyModel::fromVars(v);
    const double hc = std::clamp(h, 0.0, m.topRadius - m.bottomRadius);
    extinction_.assign(3 * kTableN, 1.0f);
    for (int i = 0; i < kTableN; ++i) {
        const double mu = std::sin(tableAltitude(i));
        glm::dvec3 T(1.0);
        if (hc < m.topRadius - m.bottomRadius)
            T = generators::cpu::rayIntersectsGround(m, hc, mu) ? glm::dvec3(0.0) : generators::cpu::transmittanceToTop(m, hc, mu, 128);
        for (int k = 0; k < 3; ++k) extinction_[3 * i + k] = float(std::clamp(T[k], 0.0, 1.0));
    }
    extinctionAtm_ = atm;
    extinctionHeight_ = h;
}

double NightSky::radianceBound(const glm::dvec3& axisEnu, double coneHalfAngleRad, const SkyVars& v) const {
    auto r2 = [](double h) {
        const double r = kEarthRadiusM / (kEarthRadiusM + h);
        return r * r;
    };
    // Van Rhijn's factor is largest at the horizon (cos z = 0; the shader's floor 1e-6 included).
    auto horizon = [](double rr) { return 1.0 / std::sqrt(std::max(1.0 - rr, 1e-6)); };
    glm::dvec3 L = zenith_.airglow * airglowColour() * horizon(r2(v.get(nightkeys::airglowHeight))) +
                   zenith_.lightPollution * lightPollutionColour() * horizon(r2(kLightPollutionLayerM));
    const double mwScale = v.get(nightkeys::milkyWayScale);
    L += mwScale * (mwLoaded_ ? mwMax_ : glm::dvec3(0.0)) + mwScale * milkyWayFloorCdM2() * mwColour_;
    double minElongation = 0.0;
    if (coneHalfAngleRad < kPi && v.has(keys::sunDirection)) {
        const glm::dvec3 sun = glm::normalize(v.get(keys::sunDirection)), axis = glm::normalize(axisEnu);
        const double sunFromAxis = std::acos(std::clamp(glm::dot(sun, axis), -1.0, 1.0));
        // 3 deg: the baked zodiacal table's bilinear footprint in the folded texture (1.4 deg texels),
        // the Sun's refraction and parallax, the folded texture's lag (< 0.1 deg of longitude).
        minElongation = sunFromAxis - coneHalfAngleRad - 3.0 * kDeg;
    }
    L += v.get(nightkeys::zodiacalScale) * zodiacalUnitCdM2() * zodiacalMaxBeyond(minElongation) * solarColour();
    return std::max({L.r, L.g, L.b});
}

void NightSky::doRender(const FrameContext& ctx) {
    const SkyVars& v = ctx.vars;
    const double background = zenith_.airglow + zenith_.zodiacal + zenith_.milkyWay + zenith_.lightPollution;
    drawn_ = !(v.has(generators::skykeys::zenithLuminance) && v.get(generators::skykeys::zenithLuminance) > kSkipRatio * background);
    skippedInvisible_ = false;
    invisibleBoundCodes_ = 0.0;
    lastReused_ = false;
    if (!drawn_) {
        kept_.valid = last_.valid = false;  // a skipped frame: the next drawn one starts afresh
        reportNothingDrawn();
        return;
    }
    // Twilight: nothing of the pass can show. The displayed value moves by at most
    // eye::displaySlopeBound() x exposure x the added radiance (any channel; the air's
    // transmittance only lowers it), with the previous frame's exposure x 2 for the eye's step to
    // this frame's (automatic exposure; a manual one is this frame's own, x 1). Under half an 8-bit
    // code at every pixel, the pass is skipped (README "Twilight: the pass skipped where it cannot show").
    const double exposure = v.getOr(keys::exposurePrevious, 0.0);
    if (exposure > 0.0) {
        const Camera& cam = ctx.camera;
        // The camera's cone: a pinhole's half diagonal; any other projection the whole sky.
        double cone = kPi;
        glm::dvec3 axis(0.0, 0.0, 1.0);
        if (cam.projection == Projection::Perspective && !cam.host) {
            const double t = std::tan(0.5 * cam.verticalFovRad);
            // Widened by 4 pixels at the centre (the widest there): the mip level's footprint.
            cone = std::atan(t * std::hypot(1.0, double(cam.width) / double(cam.height))) + 4.0 * 2.0 * t / double(cam.height);
            axis = cam.basis()[2];
        }
        const double growth = v.getOr(keys::exposureAuto, false) ? 2.0 : 1.0;
        const bool mesopic = v.get(eye::keys::mesopic);
        const double slope = eye::displaySlopeBound(eye::keys::curve.value(v), mesopic, v.get(eye::keys::scotopicBelow),
                                                    v.get(eye::keys::photopicAbove), v.get(eye::keys::rodChromaticity));
        invisibleBoundCodes_ = 255.0 * slope * exposure * growth * radianceBound(axis, cone, v);
        if (v.get(nightkeys::skipInvisible) && invisibleBoundCodes_ < 0.5) {
            skippedInvisible_ = true;
            drawn_ = false;
            kept_.valid = last_.valid = false;
            reportNothingDrawn();
            return;
        }
    }
    if (direct_) foldUpdate(ctx);
    if (!direct_) {
        const NightCubeInputs in = cubeInputs(v);
        const NightCubeStale stale = nightCubeStale(cubeBuiltFor_, in);
        if (stale.milkyWay) buildCube(ctx, in, false);
        if (stale.zodiacal) buildCube(ctx, in, true);
    }
    // The level of detail is fixed at 0 where the shader's max(log2(texels per radian x radians
    // per pixel), 0) is 0 at every pixel: a pinhole's pixel spans at most 1 / f radians (f its
    // focal length in pixels, at the image centre; less off axis), and the derivative the shader
    // takes (the chord between neighbouring pixels' directions) is shorter still. A margin of
    // 10 % keeps log2 below -0.15 whatever the float rounding. llvmpipe then samples one level
    // for a whole group of pixels instead of a level per pixel (~0.8 trivial pass, README).
    const double texelsPerRad = mwW_ > 0 ? mwW_ / (2.0 * kPi) : kNightCubeSize / 2.0;
    const Camera& cam = ctx.camera;
    const bool lod0 = fast_ && cam.projection == Projection::Perspective && !cam.host &&
                      texelsPerRad * 2.0 * std::tan(0.5 * cam.verticalFovRad) / double(cam.height) <= 0.9;
    lastLevelFixed_ = lod0;
    const gl::Program& p = programs_[ctx.attenuatedLater ? 0 : 1][lod0 ? 1 : 0].get(ctx.camera.projection);
    p.use();
    const glm::dmat3 R = v.getOr(astro::keys::starFrameRotation, glm::dmat3(1.0));
    p.set("u_enuToIcrs", glm::mat3(glm::transpose(R)));
    auto r2 = [](double h) {
        const double r = kEarthRadiusM / (kEarthRadiusM + h);
        return float(r * r);
    };
    const glm::vec3 airglow(zenith_.airglow * airglowColour()), lp(zenith_.lightPollution * lightPollutionColour());
    const float airglowR2 = r2(v.get(nightkeys::airglowHeight)), lpR2 = r2(kLightPollutionLayerM);
    const float texelsPerRadU = float(direct_ ? mwW_ / (2.0 * kPi) : (mwW_ > 0 ? mwW_ / (2.0 * kPi) : kNightCubeSize / 2.0));
    p.set("u_airglow", airglow);
    p.set("u_airglowR2", airglowR2);
    p.set("u_lp", lp);
    p.set("u_lpR2", lpR2);
    // Direct: the folded texture (the Milky Way, its floor and the zodiacal light), one fetch.
    // Cubes: the panorama's density, not the cube's (N / 2 = 512 texels/rad at a face's centre):
    // the cube's level 0 is used wherever the panorama's level 0 was (its finer texels add no
    // detail, its level 1 would blur it), mipmapping starts where the panorama's did.
    p.set("u_texelsPerRad", texelsPerRadU);
    if (direct_) {
        fold_[foldFront_].bind(milkyWayUnit_);
    } else {
        cube_.bind(milkyWayUnit_);
        zodiCube_.bind(zodiacalUnit_);
    }
    if (!ctx.attenuatedLater) {
        updateExtinction(v);
        glProgramUniform3fv(p.id(), p.location("u_ext"), kTableN, extinction_.data());
    }

    // Image reuse (README "Reusing the image"): in displayed frames, as the first pass over the
    // processor's black target, the image is the pass's alone; while every input is the same and
    // the sky's rotation moved no screen direction by nightsky.reuse_tolerance_px, the kept image
    // is copied in place of the draw. Not in welkin render (every frame complete, no memory paid),
    // not over a host's target (renderInto: something may be behind), not on the cube path.
    const bool reuseWanted = direct_ && v.get(nightkeys::reuse) && v.getOr(keys::interactive, false);
    if (!reuseWanted) reuseForget();  // frees the kept texture
    GLint target = 0, targetW = 0, targetH = 0, targetFormat = 0;
    bool eligible = reuseWanted && ctx.nothingBehind && cam.projection != Projection::CubeFace;
    if (eligible) {
        // The draw target: level 0 of a 2D texture of the camera's size (the processor's HDR
        // target; a lighting cube face or a renderbuffer is not kept).
        GLint fbo = 0, type = 0, level = -1, kind = 0;
        glGetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &fbo);
        if (fbo != 0) glGetNamedFramebufferAttachmentParameteriv(GLuint(fbo), GL_COLOR_ATTACHMENT0, GL_FRAMEBUFFER_ATTACHMENT_OBJECT_TYPE, &type);
        if (type == GL_TEXTURE) {
            glGetNamedFramebufferAttachmentParameteriv(GLuint(fbo), GL_COLOR_ATTACHMENT0, GL_FRAMEBUFFER_ATTACHMENT_OBJECT_NAME, &target);
            glGetNamedFramebufferAttachmentParameteriv(GLuint(fbo), GL_COLOR_ATTACHMENT0, GL_FRAMEBUFFER_ATTACHMENT_TEXTURE_LEVEL, &level);
            glGetTextureParameteriv(GLuint(target), GL_TEXTURE_TARGET, &kind);
        }
        eligible = type == GL_TEXTURE && level == 0 && kind == GL_TEXTURE_2D;
        if (eligible) {
            glGetTextureLevelParameteriv(GLuint(target), 0, GL_TEXTURE_WIDTH, &targetW);
            glGetTextureLevelParameteriv(GLuint(target), 0, GL_TEXTURE_HEIGHT, &targetH);
            glGetTextureLevelParameteriv(GLuint(target), 0, GL_TEXTURE_INTERNAL_FORMAT, &targetFormat);
            eligible = targetW == cam.width && targetH == cam.height;
        }
    }
    std::vector<unsigned char> inputs;
    if (eligible) {
        // Everything the pass reads but the sky's rotation, compared byte for byte: the target,
        // the program variant (extinction, level of detail), the folded texture and its version
        // (a spread rebuild swaps it), the uniforms, the extinction table when compiled in, and
        // the camera block the shader reads (time zeroed: the pass does not read it).
        auto put = [&inputs](const void* data, size_t n) {
            const auto* b = static_cast<const unsigned char*>(data);
            inputs.insert(inputs.end(), b, b + n);
        };
        const GLint ids[] = {target, targetW, targetH, targetFormat, GLint(p.id()), GLint(fold_[foldFront_].id()), foldBuilds_, foldFront_,
                             ctx.attenuatedLater ? 1 : 0, lod0 ? 1 : 0};
        put(ids, sizeof ids);
        put(&airglow, sizeof airglow);
        put(&airglowR2, sizeof airglowR2);
        put(&lp, sizeof lp);
        put(&lpR2, sizeof lpR2);
        put(&texelsPerRadU, sizeof texelsPerRadU);
        if (!ctx.attenuatedLater) put(extinction_.data(), extinction_.size() * sizeof(float));
        const CameraBlock block = makeCameraBlock(cam, 0.0);
        put(&block, sizeof block);
    }
    const double tolerancePx = v.get(nightkeys::reuseTolerancePx);
    auto close = [&](const glm::dmat3& kept) {
        if (kept == R) return true;
        if (!(tolerancePx > 0.0)) return false;
        const double pxPerRad = maxPixelsPerRadian(cam);
        return std::isfinite(pxPerRad) && rotationAngle(kept, R) * pxPerRad < tolerancePx;
    };
    if (eligible && kept_.valid && kept_.bytes == inputs && close(kept_.rotation) && keptImage_.id() != 0) {
        glCopyImageSubData(keptImage_.id(), GL_TEXTURE_2D, 0, 0, 0, 0, GLuint(target), GL_TEXTURE_2D, 0, 0, 0, 0, targetW, targetH, 1);
        lastReused_ = true;
        lastUnblended_ = false;
        ++reuseHits_;
        last_ = {std::move(inputs), R, true};
        return;
    }

    // Filtering across the cube's faces (global state: restored after the draw).
    const GLboolean seamless = glIsEnabled(GL_TEXTURE_CUBE_MAP_SEAMLESS);
    if (!direct_ && !seamless) glEnable(GL_TEXTURE_CUBE_MAP_SEAMLESS);
    // Over the processor's black target the blend (dst = L + dst T, dst = 0) gives L exactly, and
    // the alpha 1 the clear wrote is what welkin_output writes: the same pixels without reading
    // the target (~0.8 trivial pass on llvmpipe). The processor restores its blend state before
    // the next element.
    lastUnblended_ = fast_ && ctx.nothingBehind;
    if (lastUnblended_) glDisable(GL_BLEND);
    ctx.drawFullscreen();
    if (!direct_ && !seamless) glDisable(GL_TEXTURE_CUBE_MAP_SEAMLESS);
    if (!eligible) return;
    // Kept only when the previous frame's pass had the same inputs (a still or slowly turning
    // sky): a turning camera or fast time would pay the copy every frame for nothing.
    if (last_.valid && last_.bytes == inputs && close(last_.rotation)) {
        if (keptImage_.id() == 0 || keptImage_.width() != targetW || keptImage_.height() != targetH || keptImage_.internalFormat() != unsigned(targetFormat))
            keptImage_ = gl::Texture2D(targetW, targetH, unsigned(targetFormat));
        glCopyImageSubData(GLuint(target), GL_TEXTURE_2D, 0, 0, 0, 0, keptImage_.id(), GL_TEXTURE_2D, 0, 0, 0, 0, targetW, targetH, 1);
        kept_ = {inputs, R, true};
        ++reuseKeeps_;
    }
    last_ = {std::move(inputs), R, true};
}

void NightSky::reuseForget() {
    keptImage_ = gl::Texture2D();
    kept_ = ReuseInputs{};
    last_ = ReuseInputs{};
}

size_t NightSky::reuseBytes() const {
    if (keptImage_.id() == 0) return 0;
    const size_t texel = keptImage_.internalFormat() == GL_RGBA32F ? 16 : keptImage_.internalFormat() == GL_RGBA16F ? 8 : 4;
    return size_t(keptImage_.width()) * size_t(keptImage_.height()) * texel;
}

double NightSky::rotationAngle(const glm::dmat3& a, const glm::dmat3& b) {
    // b = D a with D a rotation by t: b - a = (D - I) a, whose singular values are 2 sin(t/2)
    // twice and 0, so its Frobenius norm is 2 sqrt(2) sin(t/2); a unit direction moves by the
    // chord 2 sin(t/2), an angle t (exact to rounding for small t, unlike acos of the trace).
    double f2 = 0.0;
    for (int c = 0; c < 3; ++c)
        for (int r = 0; r < 3; ++r) f2 += (b[c][r] - a[c][r]) * (b[c][r] - a[c][r]);
    return 2.0 * std::asin(std::min(1.0, std::sqrt(f2) / (2.0 * std::sqrt(2.0))));
}

double NightSky::maxPixelsPerRadian(const Camera& cam) {
    // 1 % margin: a direction near the edge moved by the rotation may pass where the scale is a
    // little larger (over the ~1e-4 rad the tolerance allows, a pinhole's f / cos^2 grows < 1e-3).
    constexpr double kMargin = 1.01;
    if (cam.projection == Projection::Perspective) {
        // A pinhole's scale f / cos^2(off-axis angle) is largest at the point farthest from the
        // principal point: a corner of the image (any host's off-axis projection too).
        double best = 0.0;
        for (const glm::dvec2 c : {glm::dvec2(0, 0), glm::dvec2(cam.width, 0), glm::dvec2(0, cam.height), glm::dvec2(cam.width, cam.height)}) {
            const auto d = cam.directionAt(c);
            const auto s = d ? cam.pixelScale(*d) : std::nullopt;
            if (!s) return std::numeric_limits<double>::infinity();
            best = std::max(best, (*s)[1]);
        }
        return kMargin * best;
    }
    // The fisheye: R / (pi/2) px/rad radially, R theta / ((pi/2) sin theta) along the azimuth,
    // largest at the horizon: R = min(size) / 2.
    if (cam.projection == Projection::Fisheye) return kMargin * 0.5 * std::min(cam.width, cam.height);
    return std::numeric_limits<double>::infinity();  // equirect (unbounded at the poles), cube faces
}

void NightSky::doRelease() {
    for (auto& row : programs_)
        for (auto& programs : row) programs.releasePrograms();
    mwTexture_ = gl::Texture2D();
    zodiTexture_ = gl::Texture2D();
    zodiLon_ = std::nan("");
    cube_ = gl::TextureCube();
    zodiCube_ = gl::TextureCube();
    fold_[0] = gl::Texture2D();
    fold_[1] = gl::Texture2D();
    foldFbo_ = gl::Framebuffer();
    foldProgram_ = gl::Program();
    foldFront_ = 0;
    foldStage_ = -1;
    foldLon_[0] = foldLon_[1] = foldTargetLon_ = std::nan("");
    zodiBaked_[0].clear();
    zodiBaked_[1].clear();
    cubeFbo_ = gl::Framebuffer();
    cubeProgram_ = gl::Program();
    cubeBuiltFor_ = NightCubeInputs{};
    mwCpu_.clear();
    mwLoaded_ = false;
    mwPath_.clear();
    extinction_.clear();
    reuseForget();
}

void NightSky::doStats(nlohmann::json& root) const {
    auto& j = root["nightsky"];
    j["airglow_zenith_cd_m2"] = zenith_.airglow;
    j["zodiacal_zenith_cd_m2"] = zenith_.zodiacal;
    j["milky_way_zenith_cd_m2"] = zenith_.milkyWay;
    j["light_pollution_zenith_cd_m2"] = zenith_.lightPollution;
    const double total = zenith_.airglow + zenith_.zodiacal + zenith_.milkyWay + zenith_.lightPollution;
    j["background_cd_m2"] = total;
    j["zenith_mag_arcsec2"] = total > 0 ? surfaceBrightnessMag(total) : 99.0;
    j["milky_way_loaded"] = mwLoaded_;
    j["drawn"] = drawn_;
    j["skipped_invisible"] = skippedInvisible_;      // skipped: the previous frame's exposure cannot show it
    j["invisible_bound_codes"] = invisibleBoundCodes_;  // the most the pass could change a displayed pixel, 8-bit codes (0: no exposure known)
    j["milky_way_gain_cd_m2"] = mwGain_;  // cd/m^2 = gain x Y^0.5 + floor
    j["zodiacal_unit_cd_m2"] = zodiacalUnitCdM2();
    j["direct_lookup"] = direct_;  // true: the per-pixel reference path, else the ICRS cube map
    j["cube_size"] = direct_ ? 0 : kNightCubeSize;
    j["cube_builds"] = cubeBuilds_;            // the Milky Way's cube (once, and on a key change)
    j["zodiacal_cube_builds"] = zodiCubeBuilds_;  // the zodiacal light's (the Sun's longitude moved 0.1 deg)
    j["cube_build_ms"] = cubeBuildMs_;  // the last builds, CPU wall time (no glFinish: GL work may be queued)
    j["zodiacal_cube_build_ms"] = zodiCubeBuildMs_;
    j["fold_builds"] = foldBuilds_;            // the folded texture (per-pixel path): first build and rebuilds
    j["fold_in_progress"] = foldStage_ >= 0;   // a rebuild spread over frames is under way
    j["reused"] = lastReused_;                 // the last frame copied the kept image instead of drawing
    j["reuse_hits"] = reuseHits_;              // frames that copied it (since init)
    j["reuse_keeps"] = reuseKeeps_;            // drawn frames whose image was kept
    j["reuse_bytes"] = reuseBytes();           // the kept texture (one target-size RGBA32F image; 0: none held)
}

}  // namespace welkin::elements

WELKIN_ELEMENT_DESCRIPTOR(nightsky) {
    static const welkin::ElementDescriptor d{
        "nightsky", "the diffuse night sky: the Milky Way (stellarium-data panorama, calibrated), airglow, zodiacal light, light pollution (Bortle class)",
        welkin::Layer::Background, true, [] { return std::make_unique<welkin::elements::NightSky>(); }};
    return d;
}
