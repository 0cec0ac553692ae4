// The reference integrator extended to a solar eclipse: the Moon's shadow seen at every point of
// a view ray by the single scattering and, through a gather over the sphere at every point, by
// the second order exactly; the higher orders scaled by the same gather (below). Double
// precision, brute force (seconds per ray): ground truth for the real-time eclipse sky
// (docs/eclipse.md), never used by it.
//
//   using namespace welkin::generators;
//   SkyModel m = SkyModel::fromVars(vars);  SkyQuality q = SkyQuality::preset(2);
//   Lut2D T = cpu::transmittanceLut(m, q);  cpu::MsField MS = cpu::msField(m, q, T);
//   cpu::EclipseGeometry g{.moonPos = vars.get(astro::keys::moonPosition), .sunPos = sun * 1.5e11};
//   auto r = atmosphere::eclipseReferenceRadiance(m, T, MS, 0.0, {0, 0, 1}, sun, g, {});
//   // r.radiance: cd/m^2 per lux of the Sun above the air (RGB)
//
// Method. Along the view ray (midpoint rule, `viewSteps`), at each point p:
//  - order 1: the Rayleigh and Mie phase x transmittance to the Sun x the Sun's limb-darkened
//    visible fraction from p (cpu::eclipseFraction with `rings` rings, the Moon's and Sun's
//    directions and sizes from p);
//  - order 2: the single-scattered radiance L1(p, w) arriving from `gatherZenith` x
//    `gatherAzimuth` directions (uniform in cos zenith and azimuth over the sphere), each a march of
//    `gatherSteps` points that see their own shadow, plus the ground's reflection of the shadowed
//    direct light; phase-weighted into the view;
//  - orders >= 3: the clear sky's (the real-time model's orders >= 2, cpu::msInscatter, less the
//    same gather's clear second order) times rho(p), the ratio of the eclipsed to the clear
//    gathered fluence of order 1 at p (the light that reaches p from the lit air, which feeds the
//    next orders). This is the approximation of the reference: exact to order 2.
// View rays must point above the horizon (mu >= 0).
#pragma once
#include <welkin/generators/sky_model.hpp>

#include <glm/glm.hpp>

namespace welkin::atmosphere {

/// Resolution of eclipseReferenceRadiance(); defaults: ~1 % numerical error (docs/eclipse.md).
struct EclipseReferenceOptions {
    int viewSteps = 64;      ///< points along the view ray, [8, 4096]
    int gatherZenith = 16;   ///< cos-zenith nodes of the gather at each point, [2, 256]
    int gatherAzimuth = 24;  ///< azimuth nodes, [3, 512]
    int gatherSteps = 32;    ///< points per gathered ray, [8, 4096]
    int rings = 128;         ///< rings of the Sun's disk in the visible fraction, [8, 4096]
    bool eclipse = true;     ///< false: the same sky without the Moon's shadow (for ratios)
    void validate() const;   ///< throws welkin::Error naming the member out of range
};

struct EclipseReferenceRadiance {
    glm::dvec3 radiance{0.0};  ///< total, per lux of the Sun above the air (cd/m^2 / lx)
    glm::dvec3 single{0.0};    ///< order 1
    glm::dvec3 multiple{0.0};  ///< orders >= 2
    glm::dvec3 second{0.0};    ///< order 2 (the exact gather; part of `multiple`)
    glm::dvec3 higher{0.0};    ///< orders >= 3 (the clear sky's scaled by the gathered fluence's ratio; part of `multiple`)
};

/// Radiance along unit ENU `view` (mu >= 0) from height h (m) with the Sun at unit ENU `sun`,
/// the Moon's shadow from `g`; T, MS: the CPU model's tables (transmittance; the clear orders >= 2).
EclipseReferenceRadiance eclipseReferenceRadiance(const generators::SkyModel& m, const generators::Lut2D& T,
                                                  const generators::cpu::MsField& MS, double h, const glm::dvec3& view,
                                                  const glm::dvec3& sun, const generators::cpu::EclipseGeometry& g,
                                                  const EclipseReferenceOptions& o);

}  // namespace welkin::atmosphere
