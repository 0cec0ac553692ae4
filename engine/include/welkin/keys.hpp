// The engine's well-known SkyVars keys. Elements add their own beside their class.
//
//   vars.set(welkin::keys::observerLatitude, glm::radians(35.9));
//   glm::dvec3 sun = vars.get(welkin::keys::sunDirection);   // unit vector, world ENU frame
//
// World frame: a local East-North-Up frame at the observer (x = east, y = north, z = up).
// Azimuth is measured from north through east; altitude from the horizon, up positive.
#pragma once
#include <welkin/vars.hpp>

#include <numbers>

namespace welkin::keys {

inline constexpr double kPi = std::numbers::pi;

// --- Time and observer (written by SkyProcessor from its Observer and UtcInstant) ---------------
/// Julian date on the UTC scale as (day, fraction), days.
inline const Key<glm::dvec2> timeJdUtc{"time.jd_utc", "Julian date (UTC) as day + fraction, days"};
/// The instant in ISO 8601 UTC.
inline const Key<std::string> timeIso{"time.iso", "instant, ISO 8601 UTC"};
/// Geodetic latitude, radians, [-pi/2, pi/2] (north positive).
inline const Key<double> observerLatitude{"observer.latitude_rad", Range{-kPi / 2, kPi / 2}, "geodetic latitude, rad"};
/// Longitude, radians, [-pi, pi] (east positive).
inline const Key<double> observerLongitude{"observer.longitude_rad", Range{-kPi, kPi}, "longitude east positive, rad"};
/// Height above the WGS84 ellipsoid, metres, [-1e4, 1e9].
inline const Key<double> observerHeight{"observer.height_m", Range{-1e4, 1e9}, "height above the ellipsoid, m"};

// --- Light sources (written by the processor's astronomy step) ---------------------------------
/// Unit vector towards the Sun's centre (topocentric, refracted), world ENU frame.
inline const Key<glm::dvec3> sunDirection{"sun.direction", Range{-1, 1}, "unit vector to the Sun, ENU"};
/// Unit vector towards the Moon's centre (topocentric, refracted), world ENU frame.
inline const Key<glm::dvec3> moonDirection{"moon.direction", Range{-1, 1}, "unit vector to the Moon, ENU"};

// --- Light at the observer (shared world state) ---------------------------------------------------
// Written by the atmosphere's lights generator (generators/atmosphere, lights.hpp: the Sun's and
// the Moon's light above the air and through it), the clouds (their photometry) and the astronomy
// (eclipses); read by any element and by SkyLighting (welkin/lighting.hpp). Per linear-sRGB channel;
// Y is the photometric quantity.
/// The Sun's illuminance above the atmosphere on a surface facing it, lux per channel.
inline const Key<glm::dvec3> sunIlluminance{"lights.sun_illuminance", Range{0, 1e7}, "Sun's illuminance above the atmosphere, per channel", "lx"};
/// The atmosphere's transmittance from the observer towards the Sun, [0, 1] (0 below the horizon).
inline const Key<glm::dvec3> sunTransmittance{"lights.sun_transmittance", Range{0, 1}, "transmittance observer -> Sun (0 below the horizon)"};
/// The Sun's disk mean radiance, unreddened, cd/m^2.
inline const Key<glm::dvec3> sunDiskRadiance{"lights.sun_disk_radiance", Range{0, 1e12}, "Sun's disk mean radiance, unreddened", "cd/m^2"};
/// The Moon's illuminance above the atmosphere (its colour, phase and any lunar eclipse), lux per channel.
inline const Key<glm::dvec3> moonIlluminance{"lights.moon_illuminance", Range{0, 1e6}, "Moon's illuminance above the atmosphere, per channel (its colour, phase and lunar eclipses)", "lx"};
/// The atmosphere's transmittance from the observer towards the Moon, [0, 1].
inline const Key<glm::dvec3> moonTransmittance{"lights.moon_transmittance", Range{0, 1}, "transmittance observer -> Moon"};
/// The Moon's disk mean radiance (whole disk), unreddened, cd/m^2.
inline const Key<glm::dvec3> moonDiskRadiance{"lights.moon_disk_radiance", Range{0, 1e6}, "Moon's disk mean radiance (whole disk), unreddened", "cd/m^2"};
/// The clouds' transmittance along the ray from the observer to the Sun, [0, 1] (written by a
/// clouds element from its photometry; absent, or 1, without clouds).
inline const Key<double> sunCloudTransmittance{"lights.sun_cloud_transmittance", Range{0, 1}, "clouds' transmittance along the ray to the Sun (1: no clouds)"};
/// The clouds' transmittance along the ray from the observer to the Moon, [0, 1].
inline const Key<double> moonCloudTransmittance{"lights.moon_cloud_transmittance", Range{0, 1}, "clouds' transmittance along the ray to the Moon (1: no clouds)"};
/// Fraction of the Sun's flux not hidden by the Moon's disk as seen by the observer (a solar
/// eclipse; limb-darkened disk), [0, 1]; 1 outside eclipses. Written by the astronomy.
inline const Key<double> sunEclipseFraction{"sun.eclipse_fraction", Range{0, 1}, "fraction of the Sun's flux not hidden by the Moon (solar eclipse; 1 outside eclipses)"};
/// Fraction of sunlight reaching the Moon (the Earth's umbra and penumbra, the shadow enlarged
/// 2 % by the atmosphere), [0, 1]; 1 outside lunar eclipses. Written by the astronomy.
inline const Key<double> moonEclipseFactor{"moon.eclipse_factor", Range{0, 1}, "fraction of sunlight reaching the Moon (lunar eclipse; 1 outside eclipses)"};

// --- Rendering --------------------------------------------------------------------------------
/// Quality preset: 0 low, 1 medium (default), 2 high, 3 reference.
inline const EnumKey<int> quality{"render.quality", {{"low", 0}, {"medium", 1}, {"high", 2}, {"reference", 3}}, "quality preset: low, medium, high or reference (as int levels 0-3 in C++)"};
/// Manual exposure, EV100, [-20, 30] (used when exposureAuto is false).
inline const Key<double> exposureEv100{"exposure.ev100", Range{-20, 30}, "exposure value at ISO 100"};
/// The frames are shown one after another while the time and the camera move (welkin view, a
/// host's game loop): an element may spread its work over frames (the Clouds' direction cache).
/// false (the default, welkin render): every frame is complete on its own.
inline const Key<bool> interactive{"render.interactive", "frames shown one after another as time and camera move (welkin view, a game loop): elements may spread work over frames; false: every frame complete (welkin render)"};
/// The host draws its own scene under the sky and asks for welkin's effects over it
/// (SkyProcessor::applyToScene() sets it on its first call): elements build what those need
/// (the Sky its aerial-perspective volume). false (the default): nothing is built for a host scene.
inline const Key<bool> hostScene{"render.host_scene", "the host draws its own scene and asks for effects over it (SkyProcessor::applyToScene() sets it): the Sky builds its aerial-perspective volume"};
/// Automatic exposure: the eye's adaptation to the scene (eye.adaptation, welkin/eye.hpp) or a camera's log-average.
inline const Key<bool> exposureAuto{"exposure.auto", "automatic exposure: the eye's adaptation (eye.*) or a camera's log-average"};
/// The exposure of the frame before this one: display value before the curve per cd/m^2
/// (docs/eye.md, "A bound for what an element cannot show"). Written by SkyProcessor before the
/// elements' update of every frame, only for displayed frames (render.interactive: welkin view, a
/// game loop; an offline frame's HDR image keeps every term): with a manual exposure the frame's
/// own, 1 / (1.2 x 2^EV100); with the automatic one the eye's state that the previous frame's
/// tone map used, read back one frame late without waiting, and only while frames follow each
/// other (the eye's state valid, the animation time advanced by 0 < dt <= 1 s since that frame,
/// its read-back arrived); 0 (unknown) otherwise: not interactive, the first frame, a still
/// render, after resetAdaptation(). An element may skip a pass whose largest radiance this
/// exposure cannot show (eye::displaySlopeBound()): the displayed image moves by under half an
/// 8-bit code, the HDR frame by that pass.
inline const Key<double> exposurePrevious{"exposure.previous_scale", Range{0, 1e30},
                                          "exposure of the previous frame, display value per cd/m^2 (0: unknown); elements skip what it cannot show"};
/// The diffuse night sky's luminance at the zenith above the air, cd/m^2 (airglow, zodiacal
/// light, Milky Way, light pollution): written by an element that draws it (nightsky), read by
/// any that depends on the sky's darkness (the Stars' limiting magnitude).
inline const Key<double> nightBackground{"nightsky.background_cd_m2", Range{0, 1e4}, "the night sky's luminance at the zenith above the air (airglow, zodiacal light, Milky Way, light pollution); Stars' limiting magnitude adds it"};

}  // namespace welkin::keys
