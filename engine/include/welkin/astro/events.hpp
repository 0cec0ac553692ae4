// Rise, set and twilight times of the Sun, rise and set of the Moon, and the Moon's quarters.
//
//   using namespace welkin::astro;
//   Site site{glm::radians(52.5), glm::radians(13.4), 34.0};
//   DayEvents ev = findDayEvents(site, UtcInstant::parse("2026-06-21T00:00:00Z"), Path::Fast);
//   if (ev.sunrise) std::cout << ev.sunrise->toIso();       // first sunrise in the next 24 h
//   if (ev.polar == PolarState::Day) ...                      // midnight Sun: no rise, no set
//   UtcInstant full = nextMoonQuarter(UtcInstant::parse("2026-06-21T00:00:00Z"), MoonQuarter::Full, Path::Fast);
//
// Definitions (geometric = airless, topocentric centre of the body):
//   sunrise/sunset       geometric altitude of the Sun's centre = -0.8333 deg (upper limb on the
//                        horizon with the standard 34' refraction and 16' semi-diameter)
//   civil/nautical/astronomical dawn and dusk: geometric altitude of the centre = -6/-12/-18 deg
//   moonrise/moonset     topocentric geometric altitude of the centre = -34' - topocentric
//                        semi-diameter (parallax included by working topocentrically)
// The search samples the altitude every 10 minutes over the window and refines each sign change
// by bisection to 0.01 s; a sample triple that brackets an extremum close to the threshold is
// examined too (golden-section search for the extremum), so grazing events near the poles are not
// missed. The observer's height does not lower the horizon (no dip): events refer to a sea-level
// astronomical horizon, as in almanacs.
#pragma once
#include <welkin/astro/bodies.hpp>

#include <optional>

namespace welkin::astro {

enum class PolarState { None, Day, Night };
const char* toString(PolarState p);  // "none", "day", "night"

/// First occurrence of each event in [start, start + hours).
struct DayEvents {
    std::optional<UtcInstant> sunrise, sunset;
    std::optional<UtcInstant> civilDawn, civilDusk;
    std::optional<UtcInstant> nauticalDawn, nauticalDusk;
    std::optional<UtcInstant> astronomicalDawn, astronomicalDusk;
    std::optional<UtcInstant> moonrise, moonset;
    /// Day: the Sun's upper limb stays above the horizon (-0.8333 deg) the whole window; Night: it
    /// stays below; None otherwise.
    PolarState polar = PolarState::None;
};

/// Events in the `hours` (1 .. 48) starting at `start`. Throws welkin::Error for an invalid site or
/// a date outside the ephemerides' range.
DayEvents findDayEvents(const Site& site, const UtcInstant& start, Path path, double hours = 24.0);

/// A rising (+1) or setting (-1) crossing of `body`'s topocentric geometric centre altitude
/// through `thresholdRad`, first one in [start, start + hours); for the Moon the threshold is
/// lowered by its topocentric semi-diameter when `moonLimb` is true.
std::optional<UtcInstant> findCrossing(const Site& site, const UtcInstant& start, Path path, Body body, double thresholdRad,
                                       int direction, double hours = 24.0, bool moonLimb = false);

enum class MoonQuarter { New = 0, FirstQuarter = 1, Full = 2, LastQuarter = 3 };
const char* toString(MoonQuarter q);  // "new_moon", "first_quarter", "full_moon", "last_quarter"
/// First instant at or after `start` when the Moon's apparent geocentric ecliptic longitude minus
/// the Sun's is 0, 90, 180 or 270 deg (Meeus ch. 49 definition), to about a second.
UtcInstant nextMoonQuarter(const UtcInstant& start, MoonQuarter q, Path path);

}  // namespace welkin::astro
