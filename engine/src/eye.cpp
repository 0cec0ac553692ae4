#include <welkin/color.hpp>
#include <welkin/error.hpp>
#include <welkin/eye.hpp>
#include <welkin/glsl_cpp.hpp>
#include <welkin/keys.hpp>

#include <algorithm>
#include <cmath>
#include <sstream>
#include <string>

namespace welkin::glsl::dp::eye_shared {
#include "../shaders/eye_thresholds.shared.glsl"
#include "../shaders/eye_srgb.shared.glsl"
#include "../shaders/eye_curves.shared.glsl"
}  // namespace welkin::glsl::dp::eye_shared

namespace welkin::eye {

namespace {
// The camera's calibration: the log-average maps to 12.5 / (1.2 * 100) = 0.104 before the curve
// (reflected-light meter constant K = 12.5, ISO 100, saturation-based exposure 1 / (1.2 * 2^EV)).
constexpr double kCameraKey = 12.5 / (1.2 * 100.0);
// Cones in their Weber range: log10 t = log10 La - 1.255, so K / t = kCameraKey / La with
// K = kCameraKey * 10^-1.255.
const double kTvi = kCameraKey * std::pow(10.0, -1.255);

std::string shown(double v) {
    std::ostringstream o;
    o << v;
    return o.str();
}

double smoothstep(double a, double b, double x) {
    double t = std::clamp((x - a) / (b - a), 0.0, 1.0);
    return t * t * (3 - 2 * t);
}
}  // namespace

void declareKeys(SkyVars& v) {
    v.declare(welkin::keys::exposureEv100, 15.0);
    v.declare(welkin::keys::exposureAuto, false);
    v.declare(::welkin::keys::exposurePrevious, 0.0);  // written by SkyProcessor each frame (publishPreviousExposure)
    v.declare(keys::compensation, 0.0);
    v.declare(keys::curve, 0);
    v.declare(keys::adaptation, true);
    v.declare(keys::adaptationMin, Defaults::adaptationMin);
    v.declare(keys::adaptationMax, Defaults::adaptationMax);
    v.declare(keys::coneTime, Defaults::coneTime);
    v.declare(keys::rodTime, Defaults::rodTime);
    v.declare(keys::strength, Defaults::strength);
    v.declare(keys::mesopic, true);
    v.declare(keys::scotopicBelow, Defaults::scotopicBelow);
    v.declare(keys::photopicAbove, Defaults::photopicAbove);
    v.declare(keys::rodChromaticity, glm::dvec2(Defaults::rodX, Defaults::rodY));
}

double coneThresholdLog10(double La) {
    if (!(La > 0)) throw Error("eye::coneThresholdLog10(): adaptation luminance " + shown(La) + " not > 0");
    return glsl::dp::eye_shared::welkin_coneThresholdLog10(La);  // the adaptation pass's text
}

double rodThresholdLog10(double Las) {
    if (!(Las > 0)) throw Error("eye::rodThresholdLog10(): adaptation luminance " + shown(Las) + " not > 0");
    return glsl::dp::eye_shared::welkin_rodThresholdLog10(Las);  // the adaptation pass's text
}

double scotopicLuminance(const glm::dvec3& rgb) {
    const glm::dvec3 xyz = color::linearSrgbToXyz(rgb);
    if (!(xyz.x > 0) || !(xyz.y > 0)) return 0.0;
    return std::max(0.0, xyz.y * (1.33 * (1.0 + (xyz.y + xyz.z) / xyz.x) - 1.68));
}

double scotopicPerPhotopicWhite() { return scotopicLuminance(glm::dvec3(1.0)); }

Adaptation adapt(Adaptation s, Adaptation target, double dt, double coneTime, double rodTime) {
    if (!(dt >= 0)) throw Error("eye::adapt(): dt " + shown(dt) + " not >= 0");
    for (double L : {s.cone, s.rod, target.cone, target.rod})
        if (!(L > 0) || !std::isfinite(L)) throw Error("eye::adapt(): luminance " + shown(L) + " not a finite value > 0");
    auto step = [dt](double from, double to, double tau) {
        if (tau <= 0) return to;
        if (dt == 0) return from;
        const double f = 1.0 - std::exp(-dt / tau);
        return std::exp(std::log(from) + (std::log(to) - std::log(from)) * f);
    };
    s.cone = step(s.cone, target.cone, coneTime);
    s.rod = step(s.rod, target.rod, target.rod > s.rod ? coneTime : rodTime);
    return s;
}

double eyeExposure(const Adaptation& a) {
    const double cones = kTvi / std::pow(10.0, coneThresholdLog10(a.cone));
    const double rods = kTvi * scotopicPerPhotopicWhite() / std::pow(10.0, rodThresholdLog10(a.rod));
    return std::max(cones, rods);
}

double eyeExposure(const Adaptation& a, double strength) {
    if (!(strength >= 0.0 && strength <= 1.0)) throw Error("eye::eyeExposure(): strength " + shown(strength) + " not in [0, 1]");
    return std::exp((1.0 - strength) * std::log(cameraExposure(a.cone)) + strength * std::log(eyeExposure(a)));
}

double eyeExposureScale() { return kTvi; }

double cameraExposure(double La) { return exposureFromEv100(std::clamp(std::log2(La * 100.0 / 12.5), -20.0, 30.0)); }

double ev100FromExposure(double exposure) { return -std::log2(1.2 * exposure); }
double exposureFromEv100(double ev100) { return 1.0 / (1.2 * std::exp2(ev100)); }

double steadyEv100(double La, double Las, double strength) { return ev100FromExposure(eyeExposure({La, Las}, strength)); }

double rodWeight(double Y, double lo, double hi) {
    if (!(Y > 0)) return 1.0;
    return 1.0 - smoothstep(std::log10(lo), std::log10(hi), std::log10(Y));
}

glm::dvec3 rodColor(glm::dvec2 xy) {
    const glm::dvec3 rgb = color::xyzToLinearSrgb(glm::dvec3(xy.x / xy.y, 1.0, (1.0 - xy.x - xy.y) / xy.y));
    return rgb / color::luminance(rgb);  // Y = 1 by the luminance row the shaders use (the matrices round to ~2e-6)
}

glm::dvec3 mesopicColor(const glm::dvec3& rgb, double lo, double hi, glm::dvec2 rodXy) {
    const double w = rodWeight(color::luminance(rgb), lo, hi);
    const glm::dvec3 rods = rodColor(rodXy) * (scotopicLuminance(rgb) / scotopicPerPhotopicWhite());
    return rgb * (1.0 - w) + rods * w;
}

glm::dvec3 acesFit(glm::dvec3 x) { return glsl::dp::eye_shared::welkin_aces(x); }  // the tone map's text

glm::dvec3 hable(glm::dvec3 x) {
    return glsl::dp::eye_shared::welkin_hable(x);  // the tone map's text
}

glm::dvec3 reinhardLuminance(glm::dvec3 x) {
    const double Y = color::luminance(x);
    return glm::clamp(x / (1.0 + Y), 0.0, 1.0);
}

namespace {
// The mesopic map's largest Jacobian row sum (infinity norm) over non-negative linear sRGB
// colours, by forward differences (the direction an added radiance moves a pixel) on a grid:
// chromaticities r + g + b = 1 in steps of 1/48, the luminance at 33 places of the rod weight's
// ramp (the Jacobian depends on the chromaticity and the place in the ramp only: V' is
// homogeneous of degree 1, the weight's derivative in Y is its derivative in log Y over Y).
double mesopicJacobianBound(double lo, double hi, glm::dvec2 rodXy) {
    constexpr int kN = 48, kT = 32;
    double best = 1.0;  // the photopic end: the identity
    for (int i = 0; i <= kN; ++i)
        for (int j = 0; i + j <= kN; ++j) {
            const glm::dvec3 chroma(double(i) / kN, double(j) / kN, double(kN - i - j) / kN);
            const double Yc = color::luminance(chroma);
            for (int k = 0; k <= kT; ++k) {
                const double lY = std::log10(lo) + (std::log10(hi) - std::log10(lo)) * double(k) / kT;
                const glm::dvec3 c = chroma * (std::pow(10.0, lY) / Yc);
                const glm::dvec3 m0 = mesopicColor(c, lo, hi, rodXy);
                glm::dmat3 J(0.0);
                for (int s = 0; s < 3; ++s) {
                    glm::dvec3 cs = c;
                    const double h = 1e-7 * (c.r + c.g + c.b);
                    cs[s] += h;
                    J[s] = (mesopicColor(cs, lo, hi, rodXy) - m0) / h;  // column s: d M / d c_s
                }
                for (int r = 0; r < 3; ++r) best = std::max(best, std::abs(J[0][r]) + std::abs(J[1][r]) + std::abs(J[2][r]));
            }
        }
    return best;
}
}  // namespace

double displaySlopeBound(int curve, bool mesopic, double lo, double hi, glm::dvec2 rodXy) {
    // The curves' largest slope of srgbEncode(curve(x)) over x >= 0 (sampled every 1e-6 below 0.2
    // and in steps of 1e-4 relative above: ACES 3.8383 at x = 0.0146, Hable 9.9038 at x = 0.0041,
    // where each meets the sRGB encoding's linear segment), rounded up; Reinhard on luminance:
    // its Jacobian's row sums are 1 / (1 + Y) + x_i / (1 + Y)^2 <= 2 where x_i / (1 + Y) <= 1
    // (unclipped), times the encoding's 12.92; none: the encoding's 12.92.
    static constexpr double kCurveSlope[4] = {3.85, 9.91, 2.0 * 12.92, 12.92};
    const double s = kCurveSlope[std::clamp(curve, 0, 3)];
    if (!mesopic) return s;
    if (!(lo > 0.0 && hi > lo)) throw Error("eye::displaySlopeBound(): mesopic limits " + shown(lo) + ", " + shown(hi) + " not 0 < lo < hi");
    struct Memo {
        double lo = 0, hi = 0;
        glm::dvec2 xy{0.0};
        double g = 0;
    };
    static thread_local Memo memo;
    if (memo.g == 0 || memo.lo != lo || memo.hi != hi || memo.xy != rodXy) memo = {lo, hi, rodXy, 1.1 * mesopicJacobianBound(lo, hi, rodXy)};
    return s * memo.g;
}

double srgbEncode(double x) { return x < 0.0031308 ? 12.92 * x : 1.055 * std::pow(x, 1.0 / 2.4) - 0.055; }

double srgbEncodeFast(double x) {
    return glsl::dp::eye_shared::welkin_srgbEncodeFast(glm::dvec3(x)).x;  // the tone map's text
}

}  // namespace welkin::eye
