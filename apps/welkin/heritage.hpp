// `welkin demo heritage`: the two sites, the Sun's day at each (from welkin's astronomy), the
// day the rising Sun lines up with a building's axis, and the demo's cameras.
//
//   using namespace welkin::heritage;
//   const SiteInfo& k = site("kalabsha");
//   Date d = equinoxDate(nextEquinox(UtcInstant::parse("2026-11-26T00:00:00Z")));  // 2027-03-20
//   SunDay day = sunDay(k, d);                     // sunrise, culmination, sunset, night (UTC)
//   SunPosition p = sunPosition(k, day.noon);      // apparent azimuth/altitude, degrees
//   Alignment a = alignmentDays(k, 2027, k.axisAzimuthDeg);   // a.days: both crossings of the year
//   host::FlyCamera cam = viewCamera(k, "noon");   // the outside view, world metres
//
// Definitions (all from welkin::astro, the Fast path the sky itself uses by default):
//  * sunrise/sunset: the Sun's upper limb on the sea-level horizon, i.e. its centre's geometric
//    (airless) altitude at -0.8333 deg (34' of standard refraction + 16' of semi-diameter), as in
//    almanacs (astro::findDayEvents);
//  * noon: the culmination, the maximum of the Sun's geometric altitude between sunrise and sunset;
//  * night: two hours after the end of astronomical twilight (centre at -18 deg);
//  * equinox: the Sun's apparent geocentric ecliptic longitude (true equinox and ecliptic of
//    date) crossing 0 deg (March) or 180 deg (September); the demo's default date is the UTC date
//    of the next one;
//  * a day is the site's local mean solar day: from local mean midnight, UTC 00:00 minus
//    longitude / 15 deg hours;
//  * alignment: the rising Sun's apparent azimuth (at sunrise as defined above) equals the axis'
//    azimuth. Over a year the sunrise azimuth swings between its solstice extremes; an azimuth
//    inside that range is met on two days (one as the azimuth decreases towards the June
//    solstice, one as it increases), an azimuth outside it on none (then the closest day).
#pragma once
#include <welkin/astro/frames.hpp>
#include <welkin/time.hpp>

#include <welkin_host/host_app.hpp>

#include <string>
#include <string_view>
#include <vector>

namespace welkin::heritage {

/// A civil date (proleptic Gregorian).
struct Date {
    int year = 2000, month = 1, day = 1;
    std::string iso() const;  ///< "YYYY-MM-DD"
    bool operator==(const Date&) const = default;
};
/// "YYYY-MM-DD" with year in [1000, 3000] (the range the demo accepts); throws welkin::Error
/// naming --date otherwise.
Date parseDate(const std::string& text);
/// The calendar date `days` after `d` (may be negative).
Date addDays(const Date& d, int days);

/// A camera in the building's own frame: +x along its axis (out through Kalabsha's gateway;
/// towards Kiti's apse), +z to the right of it, y up; metres.
struct LocalView {
    double x = 0, y = 0, z = 0;                    ///< eye, metres
    double targetX = 0, targetY = 0, targetZ = 0;  ///< looked-at point, metres
    double verticalFovDeg = 50;                    ///< (0, 179)
};

struct SiteInfo {
    std::string id;         ///< "kalabsha", "kiti"
    std::string title;      ///< for the printed lines
    std::string buildingNode;  ///< the glTF node of the building
    std::string modelFile;  ///< in the assets folder
    double latitudeDeg = 0, longitudeDeg = 0, heightM = 0;
    /// The building's axis, degrees from north through east: Kalabsha's from the sanctuary out
    /// through the gateway, Kiti's from the door to the apse. The model is turned to it.
    double axisAzimuthDeg = 90;
    std::string axisName;   ///< "Kalabsha's axis", "the apse of Kiti's church"
    LocalView outside;      ///< sunrise, noon, sunset and night
    LocalView inside;       ///< at noon
    bool hasAlignmentView = false;
    LocalView alignment;    ///< at the aligned sunrise, looking out along the axis
};

/// The demo's sites: "kalabsha" then "kiti".
const std::vector<SiteInfo>& sites();
/// Throws welkin::Error naming --site and listing the sites (and "all").
const SiteInfo& site(std::string_view id);
astro::Site astroSite(const SiteInfo& s);

/// The Sun's apparent geocentric ecliptic longitude, radians in [0, 2 pi).
double sunEclipticLongitudeRad(const UtcInstant& t);
/// The first equinox after `t` (to about a second).
UtcInstant nextEquinox(const UtcInstant& t);
/// `t` rounded to the nearest whole second (the demo renders and prints such instants).
inline UtcInstant roundToSecond(const UtcInstant& t) {
    const double s = t.utc().second;
    return t.plusSeconds(static_cast<double>(static_cast<long long>(s + 0.5)) - s);
}
inline Date dateOf(const UtcInstant& t) { return {t.utc().year, t.utc().month, t.utc().day}; }

struct SunDay {
    UtcInstant sunrise, noon, sunset, night;
};
/// The Sun's day at the site on the local date `d`. Throws welkin::Error if the Sun does not
/// rise or set that day (not at these sites).
SunDay sunDay(const SiteInfo& s, const Date& d);

struct SunPosition {
    double azimuthDeg = 0;   ///< apparent, topocentric, from north through east, [0, 360)
    double altitudeDeg = 0;  ///< apparent (refracted), topocentric
};
SunPosition sunPosition(const astro::Site& site, const UtcInstant& t);
inline SunPosition sunPosition(const SiteInfo& s, const UtcInstant& t) { return sunPosition(astroSite(s), t); }

/// Sunrise (as defined above) on local date `d` and the Sun's apparent azimuth then.
struct Sunrise {
    Date date;
    UtcInstant time;
    double azimuthDeg = 0;
};
Sunrise sunriseOn(const astro::Site& site, const Date& d);

struct Alignment {
    double axisAzimuthDeg = 0;
    /// The days of `year` whose sunrise azimuth is closest to the axis where it crosses it (two
    /// for an axis inside the yearly range, in date order), or the single closest day.
    std::vector<Sunrise> days;
    bool exact = true;  ///< false: the axis lies outside the year's sunrise azimuths
    double minAzimuthDeg = 0, maxAzimuthDeg = 0;  ///< the year's range of sunrise azimuths
};
/// Sunrise azimuths of every day of `year` (a coarse scan from the Sun's declination, refined
/// with the events search around each crossing). axisAzimuthDeg in (0, 180): a rising direction.
Alignment alignmentDays(const astro::Site& site, int year, double axisAzimuthDeg);

/// The instant after sunrise on `d` when the Sun's centre is `apparentAltitudeDeg` up (the whole
/// disk just clear of the horizon for 0.5).
UtcInstant sunAtAltitude(const astro::Site& site, const Date& d, double apparentAltitudeDeg);

/// A building-frame point to the Y-up world (x east, y up, -z north), for a building turned to
/// `axisAzimuthDeg`.
glm::dvec3 toWorld(const SiteInfo& s, double x, double y, double z);
/// The fly camera of a LocalView.
host::FlyCamera camera(const SiteInfo& s, const LocalView& v);

}  // namespace welkin::heritage
