// The lunar limb's profile (mountains and valleys against the mean limb) and the second and third
// contacts of a solar eclipse corrected for it: the instants the last Baily's bead vanishes and
// the first one appears (docs/eclipse.md, "Contacts with the limb profile").
//
//   double h = welkin::astro::lunarLimbHeightMeters(30 * M_PI / 180);  // m above the mean limb
//   // The margin by which the Sun's disk (radius 0.2666 deg) sticks out past the profiled Moon
//   // (mean radius 1737.4 km at 3.7e8 m), centres 0.01 deg apart, the Sun at position angle 80 deg:
//   double m = welkin::astro::limbCoverMargin(LimbGeometry{...});  // rad; <= 0: wholly covered
//
// Used by the Planet element (the dark Moon's drawn limb: Baily's beads) and by
// findSolarEclipses() (SolarEclipseLocal::c2Limb, c3Limb). Units: metres, radians.
#pragma once

#include <array>

namespace welkin::astro {

/// The lunar limb's height above the mean limb (radius 1737.4 km), metres, at position angle
/// `paRad` (from the Moon's north pole through east; any value, taken modulo 2 pi). Not a measured
/// profile: a deterministic random one with the statistics of the measured ones: 176 harmonics
/// (k = 4..179: features of 1-45 deg of position angle, 30 km to 1400 km along the limb) with
/// amplitudes falling as 1/k (a k^-2 power spectrum, as the lunar topography's at these scales)
/// and random phases, scaled to an RMS of 1.2 km; its extremes, -4.3 and +2.7 km, are about the
/// +-2" (+-3.7 km at the mean distance) between which the limb profiles of the Watts charts
/// (Watts 1963) and of Kaguya's laser altimetry lie. Tabulated every degree (kLimbProfileSamples)
/// and interpolated linearly.
double lunarLimbHeightMeters(double paRad);
inline constexpr int kLimbProfileSamples = 360;  ///< one per degree of position angle
inline constexpr double kLimbProfileRmsMeters = 1200.0;
/// The tabulated profile, m (sample i at position angle i deg).
const std::array<float, kLimbProfileSamples>& lunarLimbProfileMeters();
/// The Moon's mean radius, m (the limb profile's zero; IAU).
inline constexpr double kMoonMeanRadiusMeters = 1737.4e3;

/// The Sun and the profiled Moon on the sky at one instant, as the observer sees them.
struct LimbGeometry {
    double separationRad = 0;   ///< between the centres
    double sunPaRad = 0;        ///< position angle of the Sun's centre seen from the Moon's, from the Moon's north pole through east
    double sunRadiusRad = 0;    ///< the Sun's apparent radius
    double moonDistanceM = 0;   ///< observer - Moon's centre, m
    bool profile = true;        ///< false: the smooth limb at kMoonMeanRadiusMeters
};
/// How far the Sun's disk sticks out past the Moon's limb, rad: the largest, over position angles
/// theta around the Moon's centre, of (the far edge of the Sun's disk along theta) - (the limb's
/// angular radius at theta). <= 0: the Sun wholly covered (between the limb-corrected C2 and C3 of
/// a total eclipse). Scanned every 0.05 deg of theta (the profile's 1 deg samples are linear
/// between: the maximum is at a sample or where the Sun's edge is steepest, within 1e-4 of the
/// profile's features). Smooth limb: separation + sun radius - moon radius exactly.
double limbCoverMargin(const LimbGeometry& g);
/// The annular counterpart: how far the profiled Moon's limb sticks out past the Sun's disk, rad
/// (the largest distance of a limb point from the Sun's centre minus the Sun's radius). <= 0: the
/// Moon wholly inside the Sun's disk (between the limb-corrected C2 and C3 of an annular eclipse).
double limbInsideMargin(const LimbGeometry& g);

}  // namespace welkin::astro
