// CPU double-precision twins of the real-time sky passes (see sky_model.hpp): the optical
// functions and LUT parameterisations are atmosphere.shared.glsl compiled in double (the GPU's own
// text, welkin/glsl_cpp.hpp), the transmittance and multiple-scattering marches
// atmosphere_march.shared.glsl, the view-ray march (integrate(), msInscatter(), groundIrradiance(),
// the aerial-perspective slice) atmosphere_view.shared.glsl, the SH basis atmosphere.shared.glsl.
#include <welkin/astro/astro_keys.hpp>
#include <welkin/error.hpp>
#include <welkin/generators/sky_model.hpp>
#include <welkin/glsl_cpp.hpp>

#include "sky_model_access.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <numbers>

namespace welkin::glsl::dp::atmosphere_shared {
#define ATM_SEGMENT_LINEAR 1e-7  // atm_segmentFactor()'s linear limit: double keeps 1 - exp(-x) to here
#define ATM_SH_BANDS 6           // the SH arrays' size (kShMaxBands); each field passes its own L
// The SH normalisation N_lm in double (the shader's table has 8 decimals, float's precision):
// sqrt((2l + 1) / (4 pi) (l - m)! / (l + m)!), times sqrt(2) for m > 0, at k = l (l + 1) / 2 + m.
real atm_shNormExact(int k) {
    static const auto table = [] {
        std::array<real, 28> t{};
        for (int l = 0; l <= 6; ++l) {
            real ratio = 1.0;  // (l - m)! / (l + m)!
            for (int mm = 0; mm <= l; ++mm) {
                if (mm > 0) ratio /= real((l + mm) * (l - mm + 1));
                t[size_t(l * (l + 1) / 2 + mm)] = std::sqrt((2 * l + 1) / (4.0 * std::numbers::pi) * ratio) * (mm > 0 ? std::numbers::sqrt2 : 1.0);
            }
        }
        return t;
    }();
    return table[size_t(k)];
}
#define ATM_SH_N(k) atm_shNormExact(k)
#include "atmosphere.shared.glsl"
static_assert(ATM_SH_COEFFICIENTS == generators::cpu::kShMaxCoefficients);
}  // namespace welkin::glsl::dp::atmosphere_shared

// The LUT marches: atmosphere_march.shared.glsl (the passes' text) as members of SkyMarch, whose
// other members are what the marches call of the atmosphere: the GLSL block wrappers' twins on a
// SkyModel and its transmittance LUT (SkyModelAccess, shared with the clouds' SkyShadowMarch).
namespace welkin::glsl::dp::atmosphere_shared {
struct SkyMarch : SkyModelAccess {
    const generators::Lut2D* psi = nullptr;     // the multiple-scattering LUT (atm_incidentRadiance())
    const generators::Lut2D* ground = nullptr;  // the ground-irradiance row, or empty (atm_incidentRadiance())
    real atm_perigeeFraction(real h, real mu, real d) const { return atmosphere_shared::atm_perigeeFraction(m.bottomRadius, h, mu, d); }
    real miePhase(real nu) const { return atmosphere_shared::miePhase(nu, m.mieG, m.miePhase); }
    vec3 atm_msLutAt(real h, real muS) const { return psi->sample(generators::multiScatteringUv(m, h, muS, psi->width, psi->height)); }
    vec3 atm_groundSkyAt(real muS) const {
        return ground->texels.empty() ? vec3(0.0) : ground->sample({generators::multiScatteringUv(m, 0.0, muS, ground->width, 2).x, 0.5});
    }
    // The view-ray march's (atmosphere_view.shared.glsl): its multiple-scattering field (psi,
    // ground and, when directional, the SH tables), the phase moments packed as AtmosphereBlock
    // packs them, and a solar eclipse's geometry (the march's origin at the observer).
    const generators::cpu::MsField* ms = nullptr;
    bool directional = false;
    vec4 shLo = vec4(0.0), shHi = vec4(0.0);
    const generators::cpu::EclipseGeometry* eclipse = nullptr;
    vec3 eclView = vec3(0.0, 0.0, 1.0);
    bool atm_msDirectional() const { return directional; }
    int atm_shBands() const { return ms->bands; }
    vec4 atm_shFactorsLo() const { return shLo; }
    vec4 atm_shFactorsHi() const { return shHi; }
    vec2 atm_msUv(real h, real muS) const { return generators::multiScatteringUv(m, h, muS, psi->width, psi->height); }
    vec3 atm_msLutUv(vec2 uv) const { return psi->sample(uv); }
    vec3 atm_shLutAt(vec2 uv, int k) const { return ms->sh[size_t(k)].sample(uv); }
    vec3 atm_shGroundAt(real muS) const { return atm_groundSkyAt(muS); }
    bool atm_eclipseMarch() const { return eclipse != nullptr; }
    vec2 atm_eclipseAlong(real t) const { return generators::cpu::eclipseAt(*eclipse, t * eclView); }
    // The weight, unless the geometry forces it (EclipseGeometry::msWeightOverride: model fitting).
    real atm_eclMsWeight(real nu, real mu, real muS, real cosRing, real F, real H) const {
        return eclipse && eclipse->msWeightOverride >= 0.0 ? eclipse->msWeightOverride
                                                           : atmosphere_shared::atm_eclMsWeight(nu, mu, muS, cosRing, F, H);
    }
#define ATM_USE_TRANSMITTANCE
#define ATM_MARCH_INCIDENT
#include "atmosphere_march.shared.glsl"
#include "atmosphere_view.shared.glsl"
#undef ATM_MARCH_INCIDENT
#undef ATM_USE_TRANSMITTANCE
};
// A view-ray march through the field MS (T may be null where no sample reads the light).
SkyMarch viewMarch(const generators::SkyModel& m, const generators::Lut2D* T, const generators::cpu::MsField& MS,
                   const generators::cpu::PhaseMoments& pm) {
    SkyMarch s{{m, T}, &MS.psi, &MS.ground};
    s.ms = &MS;
    s.directional = MS.directional;
    s.shLo = vec4(pm.mie[1], pm.mie[2], pm.rayleigh[2], pm.forward);
    s.shHi = vec4(pm.mie[3], pm.mie[4], pm.mie[5], pm.mie[6]);
    return s;
}
}  // namespace welkin::glsl::dp::atmosphere_shared

namespace welkin::generators {

namespace shared = glsl::dp::atmosphere_shared;

namespace {
constexpr double kPi = std::numbers::pi;
double safeSqrt(double x) { return std::sqrt(std::max(x, 0.0)); }
}  // namespace

// --- Density ----------------------------------------------------------------------------------

double DensityProfile::density(double h) const {
    // Packed as the GLSL block packs it (AtmosphereBlock::profiles).
    const DensityLayer &l0 = layers[0], &l1 = layers[1];
    return shared::atm_profileDensity({l0.width, l0.expTerm, l0.expScale, l0.linearTerm},
                                      {l0.constantTerm, l1.expTerm, l1.expScale, l1.linearTerm}, {l1.constantTerm, 0.0, 0.0, 0.0}, h);
}

DensityProfile DensityProfile::exponential(double scaleHeightM) {
    DensityProfile p;
    p.layers[1] = {0.0, 1.0, -1.0 / scaleHeightM, 0.0, 0.0};
    return p;
}

DensityProfile DensityProfile::tent(double centreM, double halfWidthM) {
    DensityProfile p;
    // Rising from 0 at centre - halfWidth to 1 at centre, then falling to 0 at centre + halfWidth.
    p.layers[0] = {centreM, 0.0, 0.0, 1.0 / halfWidthM, 1.0 - centreM / halfWidthM};
    p.layers[1] = {0.0, 0.0, 0.0, -1.0 / halfWidthM, 1.0 + centreM / halfWidthM};
    return p;
}

glm::dvec3 SkyModel::extinction(double h) const {
    return rayleighScattering * rayleighDensity.density(h) + mieExtinction * mieDensity.density(h) +
           absorptionExtinction * absorptionDensity.density(h);
}

void SkyModel::validate() const {
    auto fail = [](const char* what, double v, const char* range) {
        char buf[160];
        std::snprintf(buf, sizeof buf, "SkyModel: %s %g not in %s", what, v, range);
        throw Error(buf);
    };
    if (!(bottomRadius >= 1e3 && bottomRadius <= 1e9)) fail("bottomRadius", bottomRadius, "[1e3, 1e9] m");
    if (!(topRadius > bottomRadius && topRadius <= bottomRadius + 1e7)) fail("topRadius", topRadius, "(bottomRadius, bottomRadius + 1e7] m");
    if (!(mieG > -1 && mieG < 1)) fail("mieG", mieG, "(-1, 1)");
    if (miePhase != 0 && miePhase != 1) fail("miePhase", miePhase, "{0, 1}");
    for (int c = 0; c < 3; ++c) {
        if (!(rayleighScattering[c] >= 0 && rayleighScattering[c] < 1)) fail("rayleighScattering", rayleighScattering[c], "[0, 1) 1/m");
        if (!(mieScattering[c] >= 0 && mieScattering[c] < 1)) fail("mieScattering", mieScattering[c], "[0, 1) 1/m");
        if (!(mieExtinction[c] >= mieScattering[c] && mieExtinction[c] < 1)) fail("mieExtinction", mieExtinction[c], "[mieScattering, 1) 1/m");
        if (!(absorptionExtinction[c] >= 0 && absorptionExtinction[c] < 1)) fail("absorptionExtinction", absorptionExtinction[c], "[0, 1) 1/m");
        if (!(groundAlbedo[c] >= 0 && groundAlbedo[c] <= 1)) fail("groundAlbedo", groundAlbedo[c], "[0, 1]");
        if (!(solarIlluminance[c] >= 0 && solarIlluminance[c] < 1e7)) fail("solarIlluminance", solarIlluminance[c], "[0, 1e7) lx");
    }
    if (!(sunAngularRadius > 0 && sunAngularRadius < 0.1)) fail("sunAngularRadius", sunAngularRadius, "(0, 0.1) rad");
}

// --- Quality presets --------------------------------------------------------------------------

SkyQuality SkyQuality::preset(int quality) {
    SkyQuality q;
    switch (quality) {
    case 0:  // low: small LUTs, few samples, fp16
        q.keyframePrefill = true;
        q.transmittanceW = 128, q.transmittanceH = 32, q.transmittanceSteps = 24;
        q.multiScatteringMuS = 32, q.multiScatteringSize = 8, q.multiScatteringDirections = 32, q.multiScatteringSteps = 12;
        q.skyViewW = 96, q.skyViewH = 54, q.skyViewSteps = 16;
        q.aerialSize = 16, q.aerialSteps = 1;
        q.raymarchSteps = 24, q.halfFloat = true, q.shDirections = 64;
        q.irradianceAzimuth = 16, q.irradianceZenith = 8;
        q.keyframeChunks = 4;
        break;
    case 1:  // medium (default): Hillaire 2020 sizes; sample counts chosen so that rebuilding
             // every LUT costs <= 10 frames while the error stays <= 4 % RMS (skyelements/sky/README.md)
        q.transmittanceSteps = 40, q.multiScatteringDirections = 32, q.shDirections = 64;
        q.keyframeChunks = 12;  // 9 rows of the sky view per part
        q.keyframePrefill = true;
        break;
    case 2:  // high: larger LUTs and more samples, fp32
        q.transmittanceW = 256, q.transmittanceH = 128, q.transmittanceSteps = 128;
        q.multiScatteringMuS = 64, q.multiScatteringSize = 32, q.multiScatteringDirections = 128, q.multiScatteringSteps = 32, q.shDirections = 256;
        q.skyViewW = 256, q.skyViewH = 192, q.skyViewSteps = 64;
        q.aerialSize = 32, q.aerialSteps = 4;
        q.raymarchSteps = 96, q.shIterations = 1, q.shIterationDirections = 128, q.shIterationSteps = 16, q.shBands = 6;
        q.irradianceAzimuth = 64, q.irradianceZenith = 32;
        q.keyframeChunks = 48;  // 4 rows of the sky view per part
        q.keyframePrefill = true;
        break;
    case 3:  // reference: every pixel ray-marched with many steps
        q.transmittanceW = 512, q.transmittanceH = 128, q.transmittanceSteps = 256;
        q.multiScatteringMuS = 128, q.multiScatteringSize = 32, q.multiScatteringDirections = 256, q.multiScatteringSteps = 64, q.shDirections = 512;
        q.skyViewW = 256, q.skyViewH = 192, q.skyViewSteps = 64;
        q.aerialSize = 32, q.aerialSteps = 8;
        q.raymarchSteps = 256, q.perPixel = true, q.bakedMiePhase = false, q.shIterations = 1, q.shIterationDirections = 128, q.shIterationSteps = 16;
        q.shBands = 6;
        q.irradianceAzimuth = 64, q.irradianceZenith = 32;
        break;
    default: {
        char buf[96];
        std::snprintf(buf, sizeof buf, "SkyQuality::preset(): %d not in [0, 3] (low, medium, high, reference)", quality);
        throw Error(buf);
    }
    }
    return q;
}

SkyQuality SkyQuality::tiny() {
    SkyQuality q;
    q.transmittanceW = 64, q.transmittanceH = 16, q.transmittanceSteps = 24;
    q.multiScatteringMuS = 16, q.multiScatteringSize = 4, q.multiScatteringDirections = 16, q.multiScatteringSteps = 8, q.shDirections = 32;
    q.skyViewW = 32, q.skyViewH = 24, q.skyViewSteps = 12;
    q.aerialSize = 8, q.aerialSteps = 1;
    q.raymarchSteps = 16;
    q.irradianceAzimuth = 8, q.irradianceZenith = 4;
    return q;
}

// --- Lut2D ------------------------------------------------------------------------------------

glm::dvec3 Lut2D::sample(glm::dvec2 uv) const {
    double x = std::clamp(uv.x * width - 0.5, 0.0, double(width - 1));
    double y = std::clamp(uv.y * height - 0.5, 0.0, double(height - 1));
    int x0 = std::min(int(x), width - 1), y0 = std::min(int(y), height - 1);
    int x1 = std::min(x0 + 1, width - 1), y1 = std::min(y0 + 1, height - 1);
    double fx = x - x0, fy = y - y0;
    return glm::mix(glm::mix(at(x0, y0), at(x1, y0), fx), glm::mix(at(x0, y1), at(x1, y1), fx), fy);
}

// --- Parameterisations (atmosphere.shared.glsl) ---------------------------------------------

double texCoordFromUnit(double x, int size) { return shared::texCoordFromUnit(x, double(size)); }
double unitFromTexCoord(double u, int size) { return shared::unitFromTexCoord(u, double(size)); }

namespace {
double thickness(const SkyModel& m) { return m.topRadius - m.bottomRadius; }
glm::dvec2 size2(int w, int hgt) { return {double(w), double(hgt)}; }
}  // namespace

glm::dvec2 transmittanceUv(const SkyModel& m, double h, double mu, int w, int hgt) {
    return shared::transmittanceUv(m.bottomRadius, thickness(m), h, mu, size2(w, hgt));
}
glm::dvec2 transmittanceHMu(const SkyModel& m, glm::dvec2 uv, int w, int hgt) {
    return shared::transmittanceHMu(m.bottomRadius, thickness(m), uv, size2(w, hgt));
}
glm::dvec2 multiScatteringUv(const SkyModel& m, double h, double muS, int w, int hgt) {
    return shared::multiScatteringUv(thickness(m), h, muS, size2(w, hgt));
}
glm::dvec2 multiScatteringHMuS(const SkyModel& m, glm::dvec2 uv, int w, int hgt) {
    return shared::multiScatteringHMuS(thickness(m), uv, size2(w, hgt));
}
glm::dvec2 skyViewUv(const SkyModel& m, double h, double mu, double azimuth, int w, int hgt) {
    return skyViewUvCos(m, h, mu, std::cos(azimuth), w, hgt);
}
double skyViewHorizonS(const SkyModel& m, double h) { return shared::atm_horizonS(m.bottomRadius, h); }
glm::dvec2 skyViewUvCos(const SkyModel& m, double h, double mu, double cosAzimuth, int w, int hgt) {
    return shared::skyViewUvS(skyViewHorizonS(m, h), mu, cosAzimuth, size2(w, hgt));
}
glm::dvec2 skyViewMuAz(const SkyModel& m, double h, glm::dvec2 uv, int w, int hgt) {
    return shared::skyViewMuAzS(skyViewHorizonS(m, h), uv, size2(w, hgt));
}

// --- Phase functions (atmosphere.shared.glsl) --------------------------------------------------

double rayleighPhase(double nu) { return shared::rayleighPhase(nu); }
double miePhase(double nu, double g, int kind) { return shared::miePhase(nu, g, kind); }

namespace cpu {

// --- Geometry ---------------------------------------------------------------------------------

double distanceToTop(const SkyModel& m, double h, double mu) { return shared::distanceToTop(m.bottomRadius, thickness(m), h, mu); }
double distanceToBottom(const SkyModel& m, double h, double mu) { return shared::distanceToBottom(m.bottomRadius, h, mu); }
bool rayIntersectsGround(const SkyModel& m, double h, double mu) { return shared::rayIntersectsGround(m.bottomRadius, h, mu); }
double heightAt(const SkyModel& m, double h, double mu, double t) { return shared::heightAt(m.bottomRadius, h, mu, t); }

namespace {
double warp(double s, double p) { return shared::atm_warp(s, p); }
double perigeeFraction(const SkyModel& m, double h, double mu, double d) { return shared::atm_perigeeFraction(m.bottomRadius, h, mu, d); }
}  // namespace

glm::dvec3 transmittanceToTop(const SkyModel& m, double h, double mu, int steps) {
    return shared::SkyMarch{{m}}.transmittanceToTop(h, mu, steps);
}

Lut2D transmittanceLut(const SkyModel& m, const SkyQuality& q) {
    Lut2D lut{q.transmittanceW, q.transmittanceH, {}};
    lut.texels.resize(size_t(lut.width) * lut.height);
    for (int y = 0; y < lut.height; ++y)
        for (int x = 0; x < lut.width; ++x) {
            glm::dvec2 hm = transmittanceHMu(m, {(x + 0.5) / lut.width, (y + 0.5) / lut.height}, lut.width, lut.height);
            lut.at(x, y) = transmittanceToTop(m, hm.x, hm.y, q.transmittanceSteps);
        }
    return lut;
}

glm::dvec3 transmittanceFromLut(const SkyModel& m, const Lut2D& T, double h, double mu) {
    return T.sample(transmittanceUv(m, h, mu, T.width, T.height));
}

glm::dvec3 transmittanceToLight(const SkyModel& m, const Lut2D& T, double h, double muS, double angularRadius) {
    return transmittanceFromLut(m, T, h, muS) * shared::atm_lightAboveHorizon(m.bottomRadius, h, muS, angularRadius);
}

// --- Multiple scattering ------------------------------------------------------------------------

namespace {
glm::dvec3 fibonacciDirection(int i, int n) { return shared::atm_fibonacciDirection(i, n); }
glm::dvec3 segmentFactor(const glm::dvec3& sigmaT, double dt) { return shared::atm_segmentFactor(sigmaT, dt); }
}  // namespace

glm::dvec3 fibonacciDirectionPublic(int i, int n) { return fibonacciDirection(i, n); }
glm::dvec3 segmentFactorPublic(const glm::dvec3& s, double dt) { return segmentFactor(s, dt); }
double warpPublic(double s, double p) { return warp(s, p); }
double perigeeFractionPublic(const SkyModel& m, double h, double mu, double d) { return perigeeFraction(m, h, mu, d); }

glm::dvec3 multiScatteringTexel(const SkyModel& m, const SkyQuality& q, const Lut2D& T, double h, double muS) {
    return shared::SkyMarch{{m, &T}}.atm_multiScatteringTexel(h, muS, q.multiScatteringDirections, q.multiScatteringSteps, m.sunAngularRadius);
}

Lut2D multiScatteringLut(const SkyModel& m, const SkyQuality& q, const Lut2D& T) {
    const int w = q.multiScatteringMuS, n = q.multiScatteringSize;
    Lut2D lut{w, n, {}};
    lut.texels.resize(size_t(w) * n);
    for (int y = 0; y < n; ++y)
        for (int x = 0; x < w; ++x) {
            glm::dvec2 hm = multiScatteringHMuS(m, {(x + 0.5) / w, (y + 0.5) / n}, w, n);
            lut.at(x, y) = multiScatteringTexel(m, q, T, hm.x, hm.y);
        }
    return lut;
}


// --- Directional multiple scattering (SH l <= 4) -------------------------------------------------

// Delta-M for the Mie forward peak beyond band L: a fraction f = kDeltaScale * Lambda_(L+1) of the
// Mie scattering is treated as not scattered (it stays in the beam: scattered light travels with
// extinction sigma_t - f sigma_M, the SH convolution uses Lambda_l - f). Delta-M proper takes
// f = Lambda_(L+1); half of it matched the reference integrator best over the whole sky (measured
// at L = 4 on the Earth clear atmosphere against the reference, Sun 60 .. -4 deg: f = 0.3..0.4
// Lambda_5 leaves the low-Sun sky 1-2 % too dark, 0.6..0.7 Lambda_5 makes the horizon 10-16 % too
// bright).
constexpr double kDeltaScale = 0.5;
// Gaussian window exp(-c l^2) on the Mie bands, c = kShWindow / L^2 (see msInscatter()).
constexpr double kShWindow = 0.48;
PhaseMoments phaseMoments(const SkyModel& m, int bands) {
    if (bands < kShMinBands || bands > kShMaxBands) {
        char buf[96];
        std::snprintf(buf, sizeof buf, "phaseMoments(): SH bands %d not in [%d, %d]", bands, kShMinBands, kShMaxBands);
        throw Error(buf);
    }
    // Called once per marched ray: the last result per thread is kept (Simpson's rule below).
    thread_local struct {
        double g = -2.0;
        int kind = -1, bands = -1;
        PhaseMoments pm;
    } cache;
    if (cache.g == m.mieG && cache.kind == m.miePhase && cache.bands == bands) return cache.pm;
    PhaseMoments pm;
    constexpr int n = kShMaxBands + 2;
    auto& l = pm.lambda;
    l[0] = 1.0;
    for (int k = 1; k < n; ++k) l[k] = l[k - 1] * m.mieG;  // Henyey-Greenstein: Lambda_l = g^l
    if (m.miePhase == 1) {
        // Cornette-Shanks: no closed form used; Simpson's rule on 4000 intervals (peaked phase),
        // Legendre polynomials by their recurrence.
        const int steps = 4000;
        std::array<double, n> s{};
        for (int i = 0; i <= steps; ++i) {
            double t = -1.0 + 2.0 * i / steps, w = (i == 0 || i == steps) ? 1 : (i % 2 ? 4 : 2);
            double p = miePhase(t, m.mieG, 1) * w;
            double P0 = 1.0, P1 = t;
            s[0] += p, s[1] += p * t;
            for (int k = 2; k < n; ++k) {
                double P2 = ((2 * k - 1) * t * P1 - (k - 1) * P0) / k;
                s[k] += p * P2;
                P0 = P1, P1 = P2;
            }
        }
        for (int k = 1; k < n; ++k) l[k] = 2 * kPi * s[k] * (2.0 / steps) / 3.0;
    }
    pm.forward = kDeltaScale * l[size_t(bands) + 1];
    const double c = kShWindow / (double(bands) * bands);
    for (int k = 0; k <= bands; ++k) pm.mie[size_t(k)] = (l[size_t(k)] - pm.forward) * std::exp(-c * k * k);
    // Rayleigh: Lambda_0 = 1, Lambda_2 = 1/10, 0 otherwise (no window: exact at l <= 2).
    pm.rayleigh[0] = 1.0;
    pm.rayleigh[2] = 0.1;
    cache.g = m.mieG, cache.kind = m.miePhase, cache.bands = bands;
    cache.pm = pm;
    return pm;
}

std::array<double, kShMaxCoefficients> shBasis(double x, double z) {
    const auto b = shared::atm_shBasis(x, z, kShMaxBands);  // the SH passes' text
    std::array<double, kShMaxCoefficients> Y{};
    std::copy(std::begin(b.y), std::end(b.y), Y.begin());
    return Y;
}

namespace {
// Radiance per lux arriving at (h, mu_s) from direction v (local frame: x towards the light, z up):
// single scattering with the phase functions plus Hillaire's isotropic higher orders along the
// ray (delta-M extinction for the scattered light), and the ground lit by the direct light and
// by `ground`'s sky irradiance. The gather shared by the SH and ground-irradiance texels.
glm::dvec3 incidentRadiance(const SkyModel& m, int steps, const Lut2D& T, const Lut2D& psi, const Lut2D& ground, double h,
                            double muS, const glm::dvec3& v, double fDelta) {
    return shared::SkyMarch{{m, &T}, &psi, &ground}.atm_incidentRadiance(h, muS, v, steps, m.sunAngularRadius, fDelta);  // the SH pass's text
}
}  // namespace

glm::dvec3 groundIrradianceTexel(const SkyModel& m, const SkyQuality& q, const Lut2D& T, const Lut2D& psi, double muS) {
    // Equal-area (Fibonacci) directions of the upper hemisphere: z uniform in (0, 1], each
    // carrying a solid angle 2 pi / n; the rays leave the ground, so none returns to it.
    const int n = q.shDirections;
    const double fDelta = phaseMoments(m, q.shBands).forward;
    const double golden = kPi * (3.0 - std::sqrt(5.0));
    const Lut2D none;
    glm::dvec3 E(0.0);
    for (int i = 0; i < n; ++i) {
        double z = 1.0 - (i + 0.5) / n, rr = safeSqrt(1.0 - z * z), phi = golden * i;
        glm::dvec3 v(rr * std::cos(phi), rr * std::sin(phi), z);
        E += incidentRadiance(m, q.multiScatteringSteps, T, psi, none, 0.0, muS, v, fDelta) * z;
    }
    return E * (2.0 * kPi / n);
}

glm::dvec3 groundIrradianceIterationTexel(const SkyModel& m, const SkyQuality& q, const Lut2D& T, const MsField& prev,
                                          double muS) {
    const int n = q.shIterationDirections;
    const double golden = kPi * (3.0 - std::sqrt(5.0));
    const double sinS = safeSqrt(1.0 - muS * muS);
    glm::dvec3 E(0.0);
    for (int i = 0; i < n; ++i) {
        double z = 1.0 - (i + 0.5) / n, rr = safeSqrt(1.0 - z * z), phi = golden * i;
        double x = rr * std::cos(phi), nu = x * sinS + z * muS;
        Scattering s = integrate(m, T, prev, 0.0, z, muS, nu, 1e30, q.shIterationSteps, false, m.sunAngularRadius);
        E += radiance(m, s, nu) * z;
    }
    return E * (2.0 * kPi / n);
}

glm::dvec3 groundIrradiance(const SkyModel& m, const Lut2D& T, const Lut2D& ground, double muS, double lightAngularRadius) {
    shared::SkyMarch s{{m, &T}, nullptr, &ground};
    s.directional = !ground.texels.empty();
    return s.atm_groundIrradiance(muS, lightAngularRadius);  // atmosphere.glsl's text
}

ShCoefficients shTexel(const SkyModel& m, const SkyQuality& q, const Lut2D& T, const Lut2D& psi, const Lut2D& ground, double h,
                       double muS) {
    const int n = q.shDirections, nc = shCoefficients(q.shBands);
    ShCoefficients c{};
    const double fDelta = phaseMoments(m, q.shBands).forward;
    for (int i = 0; i < n; ++i) {
        glm::dvec3 v = cpu::fibonacciDirectionPublic(i, n);
        glm::dvec3 L = incidentRadiance(m, q.multiScatteringSteps, T, psi, ground, h, muS, v, fDelta);
        auto Y = shBasis(v.x, v.z);
        for (int k = 0; k < nc; ++k) c[k] += L * Y[k];
    }
    for (auto& x : c) x *= 4.0 * kPi / n;
    return c;
}

MsField msField(const SkyModel& m, const SkyQuality& q, const Lut2D& T) {
    MsField f;
    f.psi = cpu::multiScatteringLut(m, q, T);
    f.directional = q.directionalMs;
    f.bands = q.shBands;
    if (!f.directional) return f;
    const int w = q.multiScatteringMuS, n = q.multiScatteringSize, nc = shCoefficients(q.shBands);
    f.sh.resize(size_t(nc));
    f.ground = {w, 1, std::vector<glm::dvec3>(size_t(w))};
    for (int x = 0; x < w; ++x)
        f.ground.at(x, 0) = groundIrradianceTexel(m, q, T, f.psi, multiScatteringHMuS(m, {(x + 0.5) / w, 0.0}, w, 2).y);
    for (auto& l : f.sh) {
        l.width = w;
        l.height = n;
        l.texels.resize(size_t(w) * n);
    }
    for (int y = 0; y < n; ++y)
        for (int x = 0; x < w; ++x) {
            glm::dvec2 hm = multiScatteringHMuS(m, {(x + 0.5) / w, (y + 0.5) / n}, w, n);
            auto c = shTexel(m, q, T, f.psi, f.ground, hm.x, hm.y);
            for (int k = 0; k < nc; ++k) f.sh[size_t(k)].at(x, y) = c[size_t(k)];
        }
    for (int it = 0; it < std::min(q.shIterations, 1); ++it) {  // as the GPU: at most one second pass
        MsField next = f;
        for (int y = 0; y < n; ++y)
            for (int x = 0; x < w; ++x) {
                glm::dvec2 hm = multiScatteringHMuS(m, {(x + 0.5) / w, (y + 0.5) / n}, w, n);
                auto c = shIterationTexel(m, q, T, f, hm.x, hm.y);
                for (int k = 0; k < nc; ++k) next.sh[size_t(k)].at(x, y) = c[size_t(k)];
            }
        for (int x = 0; x < w; ++x)
            next.ground.at(x, 0) =
                groundIrradianceIterationTexel(m, q, T, f, multiScatteringHMuS(m, {(x + 0.5) / w, 0.0}, w, 2).y);
        f = std::move(next);
    }
    return f;
}

ShCoefficients shIterationTexel(const SkyModel& m, const SkyQuality& q, const Lut2D& T, const MsField& prev, double h,
                                double muS) {
    const int n = q.shIterationDirections, nc = shCoefficients(prev.bands);
    ShCoefficients c{};
    const glm::dvec3 sun(safeSqrt(1.0 - muS * muS), 0.0, muS);
    for (int i = 0; i < n; ++i) {
        glm::dvec3 v = fibonacciDirection(i, n);
        double nu = glm::dot(v, sun);
        Scattering s = integrate(m, T, prev, h, v.z, muS, nu, 1e30, q.shIterationSteps, false, m.sunAngularRadius);
        glm::dvec3 L = radiance(m, s, nu);
        auto Y = shBasis(v.x, v.z);
        for (int k = 0; k < nc; ++k) c[k] += L * Y[k];
    }
    for (auto& x : c) x *= 4.0 * kPi / n;
    return c;
}

glm::dvec3 msInscatter(const SkyModel& m, const MsField& f, const PhaseMoments& moments, double h, double mu, double muS,
                       double nu, const glm::dvec3& sR, const glm::dvec3& sM) {
    return shared::viewMarch(m, nullptr, f, moments).msInscatter(h, mu, muS, nu, sR, sM);  // the view march's text
}

// --- Single + multiple scattering along a ray ----------------------------------------------------

namespace {
Scattering fromShared(const shared::SkyMarch::Scattering& s) { return {s.smooth_, s.mieNoPhase, s.transmittance, s.hitGround}; }
}  // namespace

Scattering integrate(const SkyModel& m, const Lut2D& T, const MsField& MS, double h, double mu, double muS, double nu,
                     double maxDistance, int steps, bool quadratic, double lightAngularRadius, int groundMode) {
    shared::SkyMarch s = shared::viewMarch(m, &T, MS, phaseMoments(m, MS.bands));
    return fromShared(s.integrateScattering(h, mu, muS, nu, maxDistance, steps, quadratic, lightAngularRadius, groundMode));  // the shaders' text
}

void aerialSlice(const SkyModel& m, const Lut2D& T, const MsField& MS, double h, double mu, double muS, double nu, double t0,
                 double t1, int substeps, bool groundAir, glm::dvec3& L, glm::dvec3& thr, glm::dvec3& thrD) {
    shared::SkyMarch s = shared::viewMarch(m, &T, MS, phaseMoments(m, MS.bands));
    s.atm_aerialSlice(h, mu, muS, nu, t0, t1, substeps, m.sunAngularRadius, groundAir, rayleighPhase(nu), miePhase(nu, m.mieG, m.miePhase),
                      L, thr, thrD);  // the aerial-perspective pass's text
}

double eclipseFraction(double rs, double ro, double d, int rings) {
    // The shader's text (atmosphere.shared.glsl); astro::eclipseVisibleFraction() is the same rule
    // written apart (the tests' reference).
    return shared::atm_eclipseFraction(rs, ro, d, rings);
}

glm::dvec2 eclipseAt(const EclipseGeometry& g, const glm::dvec3& p, int rings) {
    const double f = shared::atm_eclipseVisibleAt(p, g.moonPos, g.moonRadius, g.sunPos, g.sunRadius, rings);  // the shader's text
    return {f, std::clamp(f + (g.ms ? g.ms->sample(p) : 0.0), 0.0, 1.0)};
}

double EclipseMsTable::sample(const glm::dvec3& p) const {
    if (n < 2 || !(halfExtentMeters > 0.0) || d.size() != size_t(n) * n) return 0.0;
    const glm::dvec2 uv = (glm::dvec2(glm::dot(p, e1), glm::dot(p, e2)) - centre) / (2.0 * halfExtentMeters) + 0.5;
    if (uv.x < 0.0 || uv.x > 1.0 || uv.y < 0.0 || uv.y > 1.0) return 0.0;
    const double x = std::clamp(uv.x * n - 0.5, 0.0, n - 1.0), y = std::clamp(uv.y * n - 0.5, 0.0, n - 1.0);
    const int i0 = std::min(int(x), n - 2), j0 = std::min(int(y), n - 2);
    const double fx = x - i0, fy = y - j0;
    auto at = [&](int i, int j) { return double(d[size_t(j) * n + i]); };
    return (1 - fy) * ((1 - fx) * at(i0, j0) + fx * at(i0 + 1, j0)) + fy * ((1 - fx) * at(i0, j0 + 1) + fx * at(i0 + 1, j0 + 1));
}

double eclipseMsLength(const EclipseGeometry& g) {
    // The umbra's cone (tangent to the Sun and the Moon on the same side) at the observer's
    // distance behind the Moon along the axis, and the observer's distance from the axis.
    const glm::dvec3 axis = glm::normalize(g.sunPos - g.moonPos);
    const double behind = glm::dot(g.moonPos, axis);
    const double umbra = g.moonRadius - behind * (g.sunRadius - g.moonRadius) / glm::length(g.sunPos - g.moonPos);
    const double fromAxis = glm::length(g.moonPos - behind * axis);
    const double edge = std::max(umbra - fromAxis, kEclipseMsEdgeMinMeters);
    return kEclipseMsLengthMeters * std::pow(edge / kEclipseMsEdgeMeters, kEclipseMsEdgePower);
}

// The field's arithmetic, in units of work (EclipseMsTableBuilder::step): the radial fraction in
// chunks of kRadialChunk points, the grid of the fraction, each line of each of the three
// Gaussians' two blur passes (the accumulation with the last column), the fourth Gaussian on the
// coarse grid, D. eclipseMsTable() runs every unit at once, EclipseSkyLut a few per frame.
namespace {
constexpr int kMsRadial = 2048;
constexpr int kMsRadialChunk = 64;
constexpr int kMsGridChunk = 16;  // rows of the fraction's grid per unit
constexpr double kMsSigma[3] = {0.35, 1.0, 2.2}, kMsWeight[3] = {0.4256, 0.4770, 0.0967};
constexpr double kMsSigma4 = 4.5, kMsWeight4 = 0.0007;
// One fraction on the radial grid, in blur taps (its share of the work; measured 2026-11-28:
// a radial point ~0.55 us, a row tap ~1.1 ns on this machine, load 2-5).
constexpr double kMsRadialTaps = 500.0;

// The blur's taps for one sigma (texels): half-width R, weights and their running sum.
struct MsKernel {
    int R = -1;  // < 0: no blur (sigma < 0.25 texels): a copy
    std::vector<double> w, cum;
    MsKernel() = default;
    MsKernel(double sigmaTexels, int N) {
        if (sigmaTexels < 0.25) return;
        R = std::min(int(std::ceil(3.0 * sigmaTexels)), N - 1);
        w.resize(size_t(2 * R + 1));
        cum.assign(size_t(2 * R + 2), 0.0);
        for (int k = -R; k <= R; ++k) w[size_t(k + R)] = std::exp(-0.5 * (k / sigmaTexels) * (k / sigmaTexels));
        for (int k = 0; k <= 2 * R; ++k) cum[size_t(k) + 1] = cum[size_t(k)] + w[size_t(k)];
    }
    // One line of the separable blur of the N x N grid `in` into `out` (alongRows: a row, else a
    // column). Each output texel: the taps inside the grid (k in [lo, hi]), renormalised at the
    // grid's edge by their summed weight; contiguous along the line (the columns' pass reads the
    // transposed stride), no test per tap.
    void line(const std::vector<double>& in, std::vector<double>& out, bool alongRows, int N, int ln) const {
        const size_t along = alongRows ? 1 : size_t(N), across = alongRows ? size_t(N) : 1;
        const double* src = in.data() + size_t(ln) * across;
        double* dst = out.data() + size_t(ln) * across;
        if (R < 0) {
            for (int i = 0; i < N; ++i) dst[size_t(i) * along] = src[size_t(i) * along];
            return;
        }
        for (int i = 0; i < N; ++i) {
            const int lo = std::max(-R, -i), hi = std::min(R, N - 1 - i);
            double sum = 0.0;
            const double* wk = w.data() + (lo + R);
            const double* s = src + size_t(i + lo) * along;
            for (int k = 0; k <= hi - lo; ++k) sum += wk[k] * s[size_t(k) * along];
            dst[size_t(i) * along] = sum / (cum[size_t(hi + R) + 1] - cum[size_t(lo + R)]);  // renormalised at the grid's edge
        }
    }
    double taps(int N) const { return double(N) * double(R < 0 ? 1 : 2 * R + 1); }
};
}  // namespace

struct EclipseMsTableBuilder::State {
    EclipseGeometry g0;
    double lengthMeters = 0, verticalMeters = 0, texel = 0, dRho = 0;
    std::vector<double> radial, f, acc, tmp, b;
    MsKernel rows[3], cols[3], rows4, cols4;
};

EclipseMsTableBuilder::EclipseMsTableBuilder(const EclipseGeometry& g, double lengthMeters, int n, double halfExtentMeters,
                                             double verticalMeters)
    : s_(std::make_unique<State>()) {
    if (!(lengthMeters > 0.0) || n < 8 || !(halfExtentMeters > 0.0)) throw Error("eclipseMsTable: length, n or extent out of range");
    State& s = *s_;
    t_.n = n;
    t_.halfExtentMeters = halfExtentMeters;
    // The shadow's axis: from the Moon's centre towards the Sun's.
    const glm::dvec3 a = glm::normalize(g.sunPos - g.moonPos), up(0.0, 0.0, 1.0);
    const glm::dvec3 c = glm::cross(a, up);
    t_.e1 = glm::length(c) > 1e-6 ? glm::normalize(c) : glm::dvec3(1.0, 0.0, 0.0);
    t_.e2 = glm::normalize(glm::cross(t_.e1, a));
    t_.centre = {glm::dot(g.moonPos, t_.e1), glm::dot(g.moonPos, t_.e2)};
    s.g0 = g;
    s.g0.ms = nullptr;
    s.lengthMeters = lengthMeters;
    s.verticalMeters = verticalMeters;
    s.texel = 2.0 * halfExtentMeters / n;
    // The plane is perpendicular to the axis through the Sun's and the Moon's centres, so the
    // fraction on it depends only on the distance from the axis: evaluated on a radial grid of
    // kMsRadial points out to the grid's corner (~0.4 km apart at the defaults) and interpolated
    // linearly (the fraction rises from the umbra's edge as the crescent's width^1.5, so the
    // interpolation errs by < 1e-5 of the Sun's light; eight times fewer fraction evaluations
    // than one per texel: the table's cost on the CPU, docs/eclipse.md "Frame cost").
    s.dRho = halfExtentMeters * std::sqrt(2.0) / (kMsRadial - 1);
    s.radial.resize(kMsRadial);
    s.f.resize(size_t(n) * n);
    s.acc.assign(size_t(n) * n, 0.0);
    s.tmp.resize(size_t(n) * n);
    s.b.resize(size_t(n) * n);
    // The kernel: the air around a point lies in the horizontal layer (isotropic there, radial mass
    // beyond r ~ exp(-r / L): second-order light from a layer falls as exp(-r / L) / r per unit
    // area) and spreads `verticalMeters` in height. Four Gaussians whose mass beyond r follows
    // exp(-r / L) within 25 % out to r = 10 L (a least-squares fit of the tail in ratio; three here,
    // a fourth of sigma 4.5 L and weight 0.0007, on a grid 4 times coarser: at full resolution it
    // was ~half of the blur's taps, the table's cost on the CPU in the first band's frame;
    // docs/eclipse.md "Frame cost"). Projected
    // onto the plane: a horizontal displacement h maps to (h.e1, h.e2), a vertical one to (0, up.e2).
    const glm::dvec3 hAcross = glm::normalize(glm::cross(up, t_.e1));
    const double h2 = std::abs(glm::dot(hAcross, t_.e2)), u2 = std::abs(glm::dot(up, t_.e2));
    for (int k = 0; k < 3; ++k) {
        const double sg = kMsSigma[k] * lengthMeters;
        s.rows[k] = MsKernel(sg / s.texel, n);
        s.cols[k] = MsKernel(std::hypot(sg * h2, verticalMeters * u2) / s.texel, n);
    }
    const int cblk = n % 4 == 0 ? 4 : 1, m = n / cblk;
    const double s4 = kMsSigma4 * lengthMeters, texelC = s.texel * cblk;
    s.rows4 = MsKernel(s4 / texelC, m);
    s.cols4 = MsKernel(std::hypot(s4 * h2, verticalMeters * u2) / texelC, m);
    // The units of work: radial chunks, grid chunks, 3 x (n row lines + n column lines), the
    // fourth Gaussian, D.
    units_ = kMsRadial / kMsRadialChunk + (n + kMsGridChunk - 1) / kMsGridChunk + 6 * n + 2;
    for (int u = 0; u < units_; ++u) totalWork_ += unitWork(u);
}

EclipseMsTableBuilder::~EclipseMsTableBuilder() = default;
EclipseMsTableBuilder::EclipseMsTableBuilder(EclipseMsTableBuilder&&) noexcept = default;
EclipseMsTableBuilder& EclipseMsTableBuilder::operator=(EclipseMsTableBuilder&&) noexcept = default;

double EclipseMsTableBuilder::unitWork(int u) const {
    const State& s = *s_;
    const int n = t_.n, nr = kMsRadial / kMsRadialChunk, ng = (n + kMsGridChunk - 1) / kMsGridChunk;
    if (u < nr) return kMsRadialChunk * kMsRadialTaps;
    u -= nr;
    if (u < ng) return double(kMsGridChunk) * n * 2.0;
    u -= ng;
    if (u < 6 * n) {
        const int k = u / (2 * n);
        return (u % (2 * n) < n ? s.rows[k] : s.cols[k]).taps(n) + (u % (2 * n) == 2 * n - 1 ? double(n) * n : 0.0);
    }
    u -= 6 * n;
    const int m = n % 4 == 0 ? n / 4 : n;
    if (u == 0) return double(n) * n * 5.0 + double(m) * (s.rows4.taps(m) + s.cols4.taps(m));  // averaging, blur, bilinear back
    return double(n) * n * 2.0;  // D
}

void EclipseMsTableBuilder::step() {
    if (finished()) return;
    State& s = *s_;
    const int n = t_.n, nr = kMsRadial / kMsRadialChunk, ng = (n + kMsGridChunk - 1) / kMsGridChunk;
    int u = next_++;
    work_ += unitWork(u);
    if (u < nr) {
        for (int k = u * kMsRadialChunk; k < (u + 1) * kMsRadialChunk; ++k) {
            const glm::dvec2 q = t_.centre + glm::dvec2(k * s.dRho, 0.0);
            s.radial[size_t(k)] = eclipseAt(s.g0, q.x * t_.e1 + q.y * t_.e2).x;
        }
        return;
    }
    u -= nr;
    if (u < ng) {
        const double half = t_.halfExtentMeters;
        for (int j = u * kMsGridChunk; j < std::min((u + 1) * kMsGridChunk, n); ++j)
            for (int i = 0; i < n; ++i) {
                const double x = std::min(std::hypot((i + 0.5) * s.texel - half, (j + 0.5) * s.texel - half) / s.dRho, double(kMsRadial - 1));
                const int k0 = std::min(int(x), kMsRadial - 2);
                const double w = x - k0;
                s.f[size_t(j) * n + i] = (1.0 - w) * s.radial[size_t(k0)] + w * s.radial[size_t(k0) + 1];
            }
        return;
    }
    u -= ng;
    if (u < 6 * n) {
        const int k = u / (2 * n), l = u % (2 * n);
        if (l < n) {
            s.rows[k].line(s.f, s.tmp, true, n, l);
        } else {
            s.cols[k].line(s.tmp, s.b, false, n, l - n);
            if (l == 2 * n - 1)
                for (size_t i = 0; i < s.acc.size(); ++i) s.acc[i] += kMsWeight[k] * s.b[i];
        }
        return;
    }
    u -= 6 * n;
    if (u == 0) {
        // The fourth, widest Gaussian (sigma 4.5 L: >= 14 texels at L >= 30 km) on the grid averaged
        // over blocks of c x c texels, blurred there and interpolated back bilinearly (a 1/c^2 of its
        // taps; its weight is 0.07 % of the kernel, so the block's error is far below the model's).
        const int c = n % 4 == 0 ? 4 : 1, m = n / c;
        std::vector<double> fc(size_t(m) * m, 0.0), tc(size_t(m) * m), bc(size_t(m) * m);
        for (int j = 0; j < n; ++j)
            for (int i = 0; i < n; ++i) fc[size_t(j / c) * m + size_t(i / c)] += s.f[size_t(j) * n + i] / double(c * c);
        for (int ln = 0; ln < m; ++ln) s.rows4.line(fc, tc, true, m, ln);
        for (int ln = 0; ln < m; ++ln) s.cols4.line(tc, bc, false, m, ln);
        for (int j = 0; j < n; ++j) {
            const double y = std::clamp((j + 0.5) / c - 0.5, 0.0, m - 1.0);
            const int j0 = std::min(int(y), std::max(m - 2, 0)), j1 = std::min(j0 + 1, m - 1);
            const double fy = y - j0;
            for (int i = 0; i < n; ++i) {
                const double x = std::clamp((i + 0.5) / c - 0.5, 0.0, m - 1.0);
                const int i0 = std::min(int(x), std::max(m - 2, 0)), i1 = std::min(i0 + 1, m - 1);
                const double fx = x - i0;
                auto at = [&](int ii, int jj) { return bc[size_t(jj) * m + size_t(ii)]; };
                s.acc[size_t(j) * n + i] += kMsWeight4 * ((1 - fy) * ((1 - fx) * at(i0, j0) + fx * at(i1, j0)) + fy * ((1 - fx) * at(i0, j1) + fx * at(i1, j1)));
            }
        }
        return;
    }
    // D, faded to 0 over the outer 15 % of the grid (where the renormalised blur is biased).
    t_.d.resize(size_t(n) * n);
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            const double e = std::max(std::abs((i + 0.5) / n - 0.5), std::abs((j + 0.5) / n - 0.5)) * 2.0;  // 0 centre, 1 edge
            const double fade = std::clamp((1.0 - e) / 0.15, 0.0, 1.0);
            const size_t k = size_t(j) * n + i;
            t_.d[k] = float((s.acc[k] - s.f[k]) * fade);
        }
    s_.reset();  // the scratch grids are not needed any more
}

void EclipseMsTableBuilder::advance(double work) {
    const double target = work_ + work;
    while (!finished() && work_ < target) step();
}

EclipseMsTable EclipseMsTableBuilder::take() {
    if (!finished()) throw Error("EclipseMsTableBuilder::take: the table is not finished");
    return std::move(t_);
}

EclipseMsTable eclipseMsTable(const EclipseGeometry& g, double lengthMeters, int n, double halfExtentMeters, double verticalMeters) {
    EclipseMsTableBuilder b(g, lengthMeters, n, halfExtentMeters, verticalMeters);
    while (!b.finished()) b.step();
    return b.take();
}

double eclipseMsAxisWeight(const SkyModel& m, double forward, double nu) {
    // The shader's text (atmosphere.shared.glsl), at the ground's scattering in green (the
    // channel the view march reads too).
    return shared::atm_eclMsAxisWeight(nu, shared::atm_eclForwardShare(forward, m.scatteringMie(0.0).g, m.scatteringRayleigh(0.0).g));
}

double eclipseMsWeight(const SkyModel& m, double forward, double nu, double mu, double muS, double cosRing) {
    // The shader's text, at the ground's scattering in green (as the view march reads it).
    const double sM = m.scatteringMie(0.0).g, sR = m.scatteringRayleigh(0.0).g;
    return shared::atm_eclMsWeight(nu, mu, muS, cosRing, shared::atm_eclForwardShare(forward, sM, sR), shared::atm_eclHaze(sM));
}

double eclipseHaze(const SkyModel& m) { return shared::atm_eclHaze(m.scatteringMie(0.0).g); }

Scattering integrateEclipse(const SkyModel& m, const Lut2D& T, const MsField& MS, double h, const glm::dvec3& viewDir,
                            const glm::dvec3& sunDir, const EclipseGeometry& g, int steps, bool quadratic, double lightAngularRadius,
                            int groundMode) {
    const double mu = std::clamp(viewDir.z, -1.0, 1.0), muS = std::clamp(sunDir.z, -1.0, 1.0);
    const double nu = std::clamp(glm::dot(viewDir, sunDir), -1.0, 1.0);
    shared::SkyMarch s = shared::viewMarch(m, &T, MS, phaseMoments(m, MS.bands));
    s.eclipse = &g;  // the march's origin: the observer
    s.eclView = viewDir;
    return fromShared(s.integrateScattering(h, mu, muS, nu, 1e30, steps, quadratic, lightAngularRadius, groundMode));  // the shaders' text
}

glm::dvec3 radiance(const SkyModel& m, const Scattering& s, double nu) {
    return s.smooth + s.mieNoPhase * miePhase(nu, m.mieG, m.miePhase);
}

SkyViewTexel skyViewTexel(const SkyModel& m, const SkyQuality& q, const Lut2D& T, const MsField& MS, double h, double muS,
                          glm::dvec2 uv, double lightAngularRadius) {
    const glm::dvec3 view = shared::skyViewTexelViewS(skyViewHorizonS(m, h), uv, size2(q.skyViewW, q.skyViewH), muS);  // the pass's text
    const double mu = view.x, nu = view.z;
    Scattering s = integrate(m, T, MS, h, mu, muS, nu, 1e30, q.skyViewSteps, true, lightAngularRadius, uv.y >= 0.5 ? 0 : 1);
    return {s.smooth, s.mieNoPhase};
}

glm::dvec3 skyViewSample(const SkyModel& m, const Lut2D& smooth, const Lut2D& mie, double h, double mu, double az, double nu) {
    const glm::dvec2 uv = shared::skyViewClampHalf(skyViewUv(m, h, mu, az, smooth.width, smooth.height), size2(smooth.width, smooth.height));
    return smooth.sample(uv) + mie.sample(uv) * miePhase(nu, m.mieG, m.miePhase);
}

glm::dvec3 skyRadiance(const SkyModel& m, const Lut2D& T, const MsField& MS, double h, const glm::dvec3& viewDir,
                       const glm::dvec3& lightDir, const glm::dvec3& E, int steps, double lightAngularRadius) {
    const double R = m.bottomRadius, Ht = m.topRadius - R;
    double mu = viewDir.z, muS = lightDir.z, nu = glm::dot(viewDir, lightDir);
    h = std::max(h, 0.0);
    if (h > Ht) {
        // Observer above the atmosphere: move to where the ray enters it, if it does.
        const double t = shared::atm_entryFromSpace(R, Ht, h, mu);  // the sky shader's text
        if (t < 0.0) return glm::dvec3(0.0);
        double r = R + h;
        double rt = m.topRadius;
        mu = (r * mu + t) / rt;
        muS = (r * muS + t * nu) / rt;
        h = Ht;
    }
    Scattering s = integrate(m, T, MS, h, mu, muS, nu, 1e30, steps, false, lightAngularRadius);
    return radiance(m, s, nu) * E;
}

}  // namespace cpu

}  // namespace welkin::generators
