// Star catalogues and the per-frame star transform for the GPU.
//
//   using namespace welkin::astro;
//   std::vector<Star> stars = loadKStarsCatalogue();                  // /usr/share/kstars/stars.dat
//   std::vector<Star> bsc = loadYaleBrightStarCatalogue("catalog");    // BSC5 fixed-width
//   std::vector<Star> hyg = loadHygCsv("hygdata_v3.csv");
//
//   ObserverFrame f = observerFrame(site, timeScales(instant), Path::Fast);
//   StarFrame sf = starFrame(f);               // one rotation + uniforms per frame, <= 5 us
//   // GPU, per star (attributes: p0 = starDirectionJ2000(s), pm = starProperMotion(s)):
//   //   vec3 p = normalize(p0 + years * pm);        // proper motion, years = sf.yearsSinceJ2000
//   //   p = normalize(p + aberration);               // annual + diurnal aberration (ICRS axes)
//   //   vec3 enu = icrsToEnu * p;                    // precession-nutation, Earth rotation, site
//   //   then refraction from enu.z (the sky shader's own; see refraction() for the model)
//
// Nothing is computed per star on the CPU per frame. Accuracy of this recipe against ERFA's
// eraAtco13 (no refraction, no parallax): see docs/astronomy-time-and-frames.md and
// tests/astro/test_stars.cpp.
#pragma once
#include <welkin/astro/frames.hpp>

#include <string>
#include <vector>

namespace welkin::astro {

/// One star. Positions are ICRS (= J2000 to < 0.02") at epoch J2000.0.
struct Star {
    double raJ2000Rad = 0;       ///< right ascension, rad [0, 2 pi)
    double decJ2000Rad = 0;      ///< declination, rad [-pi/2, pi/2]
    float pmRaMasPerYear = 0;    ///< proper motion in RA times cos(dec) (mu_alpha*), mas/yr
    float pmDecMasPerYear = 0;   ///< proper motion in Dec, mas/yr
    float magnitudeV = 0;        ///< visual magnitude (V, or Hipparcos Hp for kstars)
    float colorBV = 0;           ///< B - V colour index, mag (0 when unknown)
    int hip = 0;                 ///< Hipparcos number, 0 when unknown
    int hd = 0;                  ///< Henry Draper number, 0 when unknown
    std::string name;            ///< proper name ("Sirius") or designation ("alp CMa"); may be empty
};

/// Default location of kstars-data's Hipparcos/Tycho text catalogue.
inline constexpr const char* kKStarsCatalogue = "/usr/share/kstars/stars.dat";

/// kstars-data's binary named-star file (32-byte starData records with HD numbers).
inline constexpr const char* kKStarsNamedStars = "/usr/share/kstars/namedstars.dat";

/// kstars-data `stars.dat` (plain text, one star per line: RA hhmmss.ss, Dec +ddmmss.s,
/// pmRA* and pmDec in mas/yr, parallax, magnitude, B-V, spectral type, flags, then
/// ", genetive name, long name"). Lines starting with '#' are comments. `maxMagnitude` keeps only
/// stars at least that bright. stars.dat has no HIP/HD numbers: if `namedstars.dat` exists in the
/// same directory, the HD numbers of the ~1600 named stars are taken from it
/// (attachKStarsHdNumbers). Throws welkin::Error "file:line: message" for a malformed line and
/// naming the file if it cannot be read.
std::vector<Star> loadKStarsCatalogue(const std::string& path = kKStarsCatalogue, double maxMagnitude = 99);

/// Reads kstars' binary `namedstars.dat` (little-endian "SK" v1 file: field table, HTM trixel
/// index, 32-byte records RA/Dec (epoch J1991.25)/pm/parallax/HD/mag/B-V) and sets `hd` on the
/// nearest star of `stars` within 6" of a record (carried to J2000.0 by its proper motion) whose
/// magnitude agrees within 1 mag (stars.dat and namedstars.dat differ by up to ~5" and, for
/// variables, ~0.7 mag). Returns how many stars
/// received an HD number. Throws welkin::Error naming the file for a truncated or foreign file.
int attachKStarsHdNumbers(std::vector<Star>& stars, const std::string& namedStarsPath = kKStarsNamedStars);

/// Every record of a kstars binary star file (namedstars.dat, unnamedstars.dat; the format above)
/// as a Star at J2000.0 (carried from J1991.25 by its proper motion): position, proper motion,
/// magnitude, B-V and HD number (0 when absent); no name. Same errors as attachKStarsHdNumbers.
std::vector<Star> loadKStarsBinaryStars(const std::string& path);

/// Yale Bright Star Catalogue, 5th revised edition (Hoffleit & Warren 1991, CDS V/50 `catalog`),
/// fixed-width 197-byte records: HR 1-4, Name 5-14, HD 26-31, RA J2000 76-83 (hh mm ss.s),
/// Dec J2000 84-90 (+dd mm ss), Vmag 103-107, B-V 110-114, pmRA 149-154 and pmDE 155-160 (arcsec/yr,
/// pmRA already times cos dec). Records without a J2000 position (the novae and the
/// non-stellar entries) are skipped. Throws welkin::Error "file:line: message" for a malformed line.
std::vector<Star> loadYaleBrightStarCatalogue(const std::string& path, double maxMagnitude = 99);

/// HYG database CSV (astronexus). Columns are found by header name: ra (hours) and dec (degrees)
/// required, optional pmra/pmdec (mas/yr, pmra = mu_alpha*), mag, ci (B-V), hip, hd, proper, bf.
/// The Sun (id 0 / proper "Sol", distance 0) is skipped. Throws welkin::Error "file:line: message".
std::vector<Star> loadHygCsv(const std::string& path, double maxMagnitude = 99);

/// Same parsers on in-memory text (`sourceName` is used in error messages).
std::vector<Star> parseKStarsCatalogue(const std::string& text, const std::string& sourceName, double maxMagnitude = 99);
std::vector<Star> parseYaleBrightStarCatalogue(const std::string& text, const std::string& sourceName, double maxMagnitude = 99);
std::vector<Star> parseHygCsv(const std::string& text, const std::string& sourceName, double maxMagnitude = 99);
/// loadKStarsBinaryStars() on the bytes of a kstars binary star file held in memory.
std::vector<Star> parseKStarsBinaryStars(const std::string& bytes, const std::string& sourceName);

/// ICRS unit vector of a star at J2000.0 (the per-star vertex attribute p0).
glm::dvec3 starDirectionJ2000(const Star& star);
/// Proper motion as a tangent vector in ICRS axes, rad per Julian year (attribute pm): the
/// direction at `years` from J2000.0 is normalize(p0 + years * pm) (linear space motion without
/// parallax and radial velocity: < 0.1" error over +-200 years for all but a handful of stars).
glm::dvec3 starProperMotion(const Star& star);

/// Per-frame uniforms for the star shader.
struct StarFrame {
    glm::dmat3 icrsToEnu{1.0};      ///< one rotation: ICRS -> observer ENU (bias-precession-
                                    ///< nutation, GAST, site latitude/longitude)
    glm::dvec3 aberration{0.0};     ///< observer's velocity / c in ICRS axes (|v| ~ 1e-4):
                                    ///< p_apparent = normalize(p + aberration)
    double yearsSinceJ2000 = 0;     ///< Julian years of TT since J2000.0, for proper motion
};
/// From an observer frame (already holds everything; this is a copy of three fields).
StarFrame starFrame(const ObserverFrame& frame);
/// From scratch: what `welkin bench astro` times (Fast path target <= 5 us).
StarFrame starFrame(const Site& site, const TimeScales& ts, Path path);
/// Just the rotation: ICRS unit vectors -> the observer's ENU frame.
glm::dmat3 starMatrix(const Site& site, const TimeScales& ts, Path path);

/// CPU reference of the shader recipe above for one star (double precision, no refraction):
/// ENU unit vector.
glm::dvec3 starEnu(const StarFrame& frame, const glm::dvec3& p0, const glm::dvec3& pm);

}  // namespace welkin::astro
