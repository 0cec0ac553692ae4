// The eye: how welkin's tone map adapts to the scene like a human observer (docs/eye.md).
//
//   sky.vars().set(welkin::keys::exposureAuto, true);        // or sky.setExposure({.automatic = true})
//   sky.vars().set(welkin::eye::keys::rodTime, 30.0);        // dark adaptation time constant, s
//   sky.vars().set(welkin::eye::keys::curve, 1);             // Hable's filmic curve
//   double ev = welkin::eye::steadyEv100(1e-3, 2.6e-3);      // a moonlit sky: -2.8 EV100 (a camera: -7)
//
// The model (every function below is the CPU twin of what the tone map does on the GPU):
//  * Sensitivity: Ferwerda, Pattanaik, Shirley & Greenberg 1996's threshold-versus-intensity
//    curves for cones (photopic luminance) and rods (scotopic luminance). The exposure is set as
//    their "just noticeable difference" matching prescribes (Ward 1994; Ferwerda 1996): the scale
//    is inversely proportional to the threshold of the more sensitive system, anchored so that in
//    daylight (cones in their Weber range) it equals a camera's log-average exposure. Below the
//    Weber ranges the thresholds stop falling as fast as the luminance, so a darker scene
//    displays darker: a moonless night is darker than a moonlit one, darker than twilight.
//  * Adaptation luminance: the log-average of the frame (photopic, and scotopic for the rods),
//    kept within [eye.adaptation_min_cd_m2, eye.adaptation_max_cd_m2].
//  * Time: the cone and rod adaptation states approach their targets exponentially in log
//    luminance (Pattanaik, Tumblin, Yee & Greenberg 2000; Durand & Dorsey 2000); cones with
//    eye.cone_time_s, rods with eye.rod_time_s when the scene darkens (dark adaptation) and
//    with the cones' constant when it brightens (light adaptation is fast).
//  * Colour: per pixel, below eye.photopic_cd_m2 down to eye.scotopic_cd_m2 the colour blends
//    (smoothstep in log10 luminance) into the rod percept, the scotopic luminance V' (Larson,
//    Rushmeier & Piatko 1997) shown in the rod hue eye.rod_chromaticity (blue shift, Jensen et
//    al. 2001): monochrome and bluish in scotopic light, unchanged in photopic light.
//  * Curve: exposure.curve, the ACES fit (Narkowicz 2015, default), Hable's filmic curve (2010),
//    Reinhard's L/(1+L) on luminance (hue-preserving), or none (clip).
#pragma once
#include <welkin/vars.hpp>

#include <glm/glm.hpp>

namespace welkin::eye {

namespace keys {
/// Added brightness for automatic exposure, EV, [-10, 10].
inline const Key<double> compensation{"exposure.compensation_ev", Range{-10, 10}, "added brightness for automatic exposure, EV", "EV"};
/// Display curve: 0 ACES fit (Narkowicz), 1 Hable filmic, 2 Reinhard on luminance, 3 none (clip).
inline const EnumKey<int> curve{"exposure.curve", {{"aces", 0}, {"hable", 1}, {"reinhard", 2}, {"none", 3}}, "display curve: aces (ACES fit), hable (filmic), reinhard (on luminance) or none (clip); levels 0-3 in C++"};
/// Automatic exposure follows the eye (TVI model); false: a camera's log-average exposure.
inline const Key<bool> adaptation{"eye.adaptation", "automatic exposure follows the eye's sensitivity (Ferwerda 1996 TVI); false: camera"};
/// Lowest adaptation luminance, cd/m^2 (absolute threshold of the dark-adapted eye ~1e-6).
inline const Key<double> adaptationMin{"eye.adaptation_min_cd_m2", Range{1e-8, 1e8}, "lowest adaptation luminance"};
/// Highest adaptation luminance, cd/m^2.
inline const Key<double> adaptationMax{"eye.adaptation_max_cd_m2", Range{1e-8, 1e8}, "highest adaptation luminance"};
/// Time constant of the cones (and of any light adaptation), s, [0, 3600]; 0: instantaneous.
inline const Key<double> coneTime{"eye.cone_time_s", Range{0, 3600}, "cone adaptation time constant (and light adaptation)"};
/// Time constant of the rods' dark adaptation, s, [0, 3600]; 0: instantaneous.
inline const Key<double> rodTime{"eye.rod_time_s", Range{0, 3600}, "rod dark-adaptation time constant"};
/// How much of the eye's darkening at low light the display shows, [0, 1]: the exposure is
/// camera^(1 - s) x eye^s (in log, a mix of the camera's log-average exposure, which shows every
/// scene at mid-grey, and the TVI model's). 1: Ferwerda's full threshold matching, for a display
/// viewed in a lit room (a moonless night nearly black); 0: a camera. Daylight is the same for all.
inline const Key<double> strength{"eye.strength", Range{0, 1}, "share of the eye's low-light darkening shown (0 camera, 1 Ferwerda's full TVI matching)"};
/// Per-pixel photopic -> mesopic -> scotopic colour (loss of saturation, blue shift).
inline const Key<bool> mesopic{"eye.mesopic", "per-pixel mesopic/scotopic colour: desaturation and blue shift"};
/// Below this luminance a pixel is seen by rods only, cd/m^2.
inline const Key<double> scotopicBelow{"eye.scotopic_cd_m2", Range{1e-8, 1e8}, "fully scotopic below this luminance"};
/// Above this luminance a pixel is seen by cones only, cd/m^2.
inline const Key<double> photopicAbove{"eye.photopic_cd_m2", Range{1e-8, 1e8}, "fully photopic above this luminance"};
/// CIE xy chromaticity of the rod percept (the blue shift).
inline const Key<glm::dvec2> rodChromaticity{"eye.rod_chromaticity", Range{0.01, 0.9}, "CIE xy of the rod percept (blue shift)"};
}  // namespace keys

/// The keys' defaults (docs/eye.md gives their sources).
struct Defaults {
    static constexpr double adaptationMin = 1e-6, adaptationMax = 1e6;
    static constexpr double coneTime = 0.4, rodTime = 120.0;
    static constexpr double scotopicBelow = 1e-3, photopicAbove = 3.0;
    static constexpr double rodX = 0.25, rodY = 0.25;
    /// 0.6: a moonless night ~4 stops darker than day on the display (6.6 at 1), dark but with its
    /// Milky Way and faint stars above the display curve's toe; the order of scenes is kept.
    static constexpr double strength = 0.6;
};

/// Declares the keys above (and exposure.ev100 / exposure.auto) with their defaults.
void declareKeys(SkyVars& vars);

/// Ferwerda 1996: log10 of the cone (photopic) threshold, cd/m^2, at adaptation luminance `La` (> 0).
double coneThresholdLog10(double La);
/// Ferwerda 1996: log10 of the rod (scotopic) threshold, scotopic cd/m^2, at scotopic `Las` (> 0).
double rodThresholdLog10(double Las);

/// Scotopic luminance V' (scotopic cd/m^2) of a linear sRGB colour (Y in cd/m^2), Larson et al.
/// 1997: V' = Y (1.33 (1 + (Y + Z) / X) - 1.68), >= 0.
double scotopicLuminance(const glm::dvec3& linearSrgb);
/// V' / Y of the sRGB (D65) white: scotopic over photopic luminance of a grey (~2.57).
double scotopicPerPhotopicWhite();

/// The adaptation state: cone (photopic) and rod (scotopic) luminances, cd/m^2 and scotopic cd/m^2.
struct Adaptation {
    double cone = 1.0;
    double rod = 1.0;
};

/// Exponential approach in log luminance: after `dt` seconds the log of `state` has moved
/// 1 - exp(-dt / tau) of the way to the target's. Cones with `coneTime`; rods with `rodTime`
/// when darkening, `coneTime` when brightening. tau = 0 jumps. dt >= 0; luminances finite, > 0.
Adaptation adapt(Adaptation state, Adaptation target, double dt, double coneTime, double rodTime);

/// The scale from scene luminance (cd/m^2) to the display value before the curve, for the
/// adapted eye: max(K / t_cone(cone), K (V'/Y)_white / t_rod(rod)), K chosen so that cones in
/// their Weber range give the camera's 12.5 / (1.2 * 100 * La) (the log-average at 0.104).
double eyeExposure(const Adaptation& a);
/// The tone map's automatic exposure: cameraExposure(a.cone)^(1 - strength) x eyeExposure(a)^strength,
/// strength in [0, 1] (eye.strength).
double eyeExposure(const Adaptation& a, double strength);
/// K of eyeExposure(): 12.5 / (1.2 * 100) * 10^-1.255.
double eyeExposureScale();
/// A camera's automatic exposure for log-average luminance `La`: 0.104 / La (EV100 in [-20, 30]).
double cameraExposure(double La);
/// EV100 equivalent of an exposure scale (manual exposure is 1 / (1.2 * 2^EV100)).
double ev100FromExposure(double exposure);
double exposureFromEv100(double ev100);
/// The steady state's EV100 for a scene of log-average photopic `La` and scotopic `Las`.
double steadyEv100(double La, double Las, double strength = Defaults::strength);

/// Rod weight of a pixel of luminance `Y`: 1 at or below `scotopicBelow`, 0 at or above
/// `photopicAbove`, smoothstep in log10 Y between.
double rodWeight(double Y, double scotopicBelow, double photopicAbove);
/// Linear sRGB of the rod percept per unit photopic-equivalent luminance (Y = 1), from CIE xy.
glm::dvec3 rodColor(glm::dvec2 xy);
/// The perceived colour of a pixel before exposure: mix(rgb, rodColor * V' / (V'/Y)_white, w).
glm::dvec3 mesopicColor(const glm::dvec3& linearSrgb, double scotopicBelow, double photopicAbove, glm::dvec2 rodXy);

/// The display curves, per channel on exposed values (>= 0) -> [0, 1] linear.
glm::dvec3 acesFit(glm::dvec3 x);
glm::dvec3 hable(glm::dvec3 x);
glm::dvec3 reinhardLuminance(glm::dvec3 x);

/// A bound on how much the tone map's displayed value (sRGB-encoded, [0, 1]) can move when the
/// exposed linear colour (cd/m^2 x exposure) grows by d in every channel at most, d >= 0: the
/// displayed value moves by at most d x displaySlopeBound(...) in any channel (an element that
/// adds less than 0.5 / 255 / (exposure x this) cd/m^2 changes no pixel by half an 8-bit code).
/// The product of the display curve's largest slope through the sRGB encoding (`curve`, the
/// exposure.curve levels: ACES fit 3.84, Hable 9.90, Reinhard on luminance <= 2 x 12.92, none
/// 12.92; each rounded up) and, with the mesopic colour, the mesopic map's largest Jacobian row
/// sum over non-negative colours and every luminance (4.84 at the default limits and rod hue;
/// computed on a grid of chromaticities x rod weights, x 1.1 for between its nodes; cached for
/// the last arguments). docs/eye.md "A bound for what an element cannot show".
double displaySlopeBound(int curve, bool mesopic, double scotopicBelow, double photopicAbove, glm::dvec2 rodXy);

/// The sRGB transfer function (IEC 61966-2-1), linear [0, 1] -> encoded [0, 1]: 12.92 x below
/// 0.0031308, 1.055 x^(1/2.4) - 0.055 above.
double srgbEncode(double linear);
/// The tone map's twin of srgbEncode() (engine/shaders/tonemap.frag.glsl): the power law as a
/// (3, 3) rational in sqrt(x), no pow per channel; within 6e-6 of srgbEncode() on [0, 1].
double srgbEncodeFast(double linear);

}  // namespace welkin::eye
