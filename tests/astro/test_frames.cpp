// Earth orientation, frames, aberration and refraction: Meeus worked examples and ERFA.
#include <welkin/astro/frames.hpp>
#include <welkin/error.hpp>

#include "test_frames_reference.hpp"

#include <catch2/catch.hpp>
#include <erfa.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>

using namespace welkin;
using namespace welkin::astro;
using namespace welkin::astro::testref;

namespace {
double hms(double h, double m, double s) { return (h + m / 60.0 + s / 3600.0) * 15.0 * kDeg; }
double dms(double d, double m, double s) { return (std::abs(d) + m / 60.0 + s / 3600.0) * kDeg * (d < 0 ? -1 : 1); }
double wrapPi(double a) { return std::remainder(a, 2.0 * std::numbers::pi); }
const Path kPaths[] = {Path::Fast, Path::Precise};
}  // namespace

TEST_CASE("Sidereal time: Meeus examples 12.a and 12.b", "[cpu][astro]") {
    for (Path path : kPaths) {
        // 12.a: 1987 April 10, 0h UT: mean 13h10m46.3668s, apparent 13h10m46.1351s.
        TimeScales a = timeScales(UtcInstant::parse("1987-04-10T00:00:00Z"));
        // Meeus uses the IAU 1982 GMST and IAU 1980 nutation; the IAU 2006/2000 values differ by
        // a few ms of time (tolerance 5 ms = 0.075").
        CHECK(std::abs(wrapPi(gmst(a, path) - hms(13, 10, 46.3668))) < 0.005 * 15 * kArcsec);
        CHECK(std::abs(wrapPi(gast(a, path) - hms(13, 10, 46.1351))) < 0.005 * 15 * kArcsec);
        // 12.b: 1987 April 10, 19h21m00s UT: mean 8h34m57.0896s.
        TimeScales b = timeScales(UtcInstant::parse("1987-04-10T19:21:00Z"));
        CHECK(std::abs(wrapPi(gmst(b, path) - hms(8, 34, 57.0896))) < 0.005 * 15 * kArcsec);
    }
}

TEST_CASE("Nutation and obliquity: Meeus example 22.a", "[cpu][astro]") {
    // 1987 April 10, 0h TD: dpsi = -3.788", deps = +9.443", eps0 = 23 26 27.407, eps = 23 26 36.850.
    TimeScales ts = timeScalesFromTT(toJulianDate(DateTime{1987, 4, 10}));
    for (Path path : kPaths) {
        Nutation n = nutation(ts, path);
        // Meeus's IAU 1980 series against IAU 2000: the models differ by up to ~0.02" (and Meeus
        // rounds to 1 mas).
        CHECK(n.dpsi / kArcsec == Approx(-3.788).margin(0.02));
        CHECK(n.deps / kArcsec == Approx(9.443).margin(0.02));
        EarthOrientation eo = earthOrientation(ts, path);
        // IAU 2006 obliquity at J2000 is 84381.406" against Lieske's 84381.448": 0.042" apart.
        CHECK(eo.meanObliquity == Approx(dms(23, 26, 27.407)).margin(0.05 * kArcsec));
        CHECK(eo.trueObliquity == Approx(dms(23, 26, 36.850)).margin(0.06 * kArcsec));
    }
}

TEST_CASE("Horizontal coordinates: Meeus example 13.b (Venus from Washington)", "[cpu][astro]") {
    // 1987 April 10, 19h21m00s UT; USNO: lat +38 55 17, lon 77 03 56 W; Venus apparent
    // RA 23h09m16.641s, Dec -6 43 11.61. Meeus: A = 68.0337 deg (from the south), h = 15.1249 deg.
    Site usno{dms(38, 55, 17), -dms(77, 3, 56), 0.0, 0.0};  // no refraction, as Meeus
    TimeScales ts = timeScales(UtcInstant::parse("1987-04-10T19:21:00Z"));
    for (Path path : kPaths) {
        ObserverFrame f = observerFrame(usno, ts, path);
        Topocentric v = topocentric(f, hms(23, 9, 16.641), dms(-6, 43, 11.61), 0.0);  // geocentric, as Meeus
        // Meeus rounds to 1e-4 deg and his GAST (IAU 1980) differs by ~0.2 ms: 2e-4 deg.
        CHECK(v.azimuthRad / kDeg == Approx(68.0337 + 180.0).margin(2e-4));
        CHECK(v.altitudeRad / kDeg == Approx(15.1249).margin(2e-4));
        CHECK(v.altitudeGeometricRad == v.altitudeRad);
    }
}

TEST_CASE("Earth orientation: Fast path against ERFA IAU 2006/2000A, 1900-2100", "[cpu][astro]") {
    std::mt19937_64 rng(2026);
    std::uniform_real_distribution<double> jd(toJulianDate(DateTime{1900, 1, 1}).value(), toJulianDate(DateTime{2100, 1, 1}).value());
    double maxNpb = 0, maxGast = 0, maxGmst = 0, maxDpsi = 0, maxDeps = 0, maxVel = 0;
    for (int i = 0; i < 500; ++i) {
        double v = jd(rng);
        TimeScales ts = timeScales(JulianDate{std::floor(v - 0.5) + 0.5, v - 0.5 - std::floor(v - 0.5)}.normalized());
        double rnpb[3][3];
        eraPnm06a(ts.tt.day, ts.tt.fraction, rnpb);
        glm::dmat3 ref = glm::transpose(glm::dmat3(rnpb[0][0], rnpb[0][1], rnpb[0][2], rnpb[1][0], rnpb[1][1], rnpb[1][2], rnpb[2][0], rnpb[2][1], rnpb[2][2]));
        EarthOrientation fast = earthOrientation(ts, Path::Fast);
        EarthOrientation precise = earthOrientation(ts, Path::Precise);
        // The Precise path is ERFA's own matrix (to rounding).
        REQUIRE(rotationDifference(precise.celestialToTrueOfDate, ref) < 1e-6 * kArcsec);
        REQUIRE(std::abs(wrapPi(precise.gast - eraGst06a(ts.ut1.day, ts.ut1.fraction, ts.tt.day, ts.tt.fraction))) < 1e-6 * kArcsec);
        maxNpb = std::max(maxNpb, rotationDifference(fast.celestialToTrueOfDate, ref));
        maxGast = std::max(maxGast, std::abs(wrapPi(fast.gast - precise.gast)));
        maxGmst = std::max(maxGmst, std::abs(wrapPi(fast.gmst - eraGmst06(ts.ut1.day, ts.ut1.fraction, ts.tt.day, ts.tt.fraction))));
        maxDpsi = std::max(maxDpsi, std::abs(fast.nutation.dpsi - precise.nutation.dpsi));
        maxDeps = std::max(maxDeps, std::abs(fast.nutation.deps - precise.nutation.deps));
        maxVel = std::max(maxVel, glm::length(earthVelocity(ts, Path::Fast) - earthVelocity(ts, Path::Precise)));
    }
    std::printf("astro fast vs ERFA 1900-2100 (500 instants): NPB %.4f\", GAST %.4f\", GMST %.2g\", dpsi %.4f\", deps %.4f\", "
                "Earth velocity %.4f\" of aberration\n",
                maxNpb / kArcsec, maxGast / kArcsec, maxGmst / kArcsec, maxDpsi / kArcsec, maxDeps / kArcsec, maxVel / kArcsec);
    // IAU 2000B is documented at 1 mas against 2000A over 1995-2050; allow 3 mas over 1900-2100.
    CHECK(maxNpb < 0.003 * kArcsec);
    CHECK(maxGast < 0.003 * kArcsec);
    CHECK(maxGmst < 1e-6 * kArcsec);  // same IAU 2006 formula
    CHECK(maxDpsi < 0.003 * kArcsec);
    CHECK(maxDeps < 0.003 * kArcsec);
    // Keplerian Earth + Jupiter/Saturn reflex + circular Moon: velocity error (in units of c, i.e.
    // the aberration error in radians) below 0.05".
    CHECK(maxVel < 0.05 * kArcsec);
}

TEST_CASE("Earth orientation far from J2000: years -2000 and +6000", "[cpu][astro]") {
    // Both paths extrapolate the same IAU 2006 polynomials (the model's validity, not the code,
    // limits the accuracy there: see the doc); the Fast path must still follow the Precise one.
    for (int year : {-2000, 6000}) {
        TimeScales ts = timeScales(UtcInstant::parse((year < 0 ? "-2000" : "6000") + std::string("-03-21T06:00:00Z")));
        EarthOrientation fast = earthOrientation(ts, Path::Fast);
        EarthOrientation precise = earthOrientation(ts, Path::Precise);
        double dNpb = rotationDifference(fast.celestialToTrueOfDate, precise.celestialToTrueOfDate);
        double dGast = std::abs(wrapPi(fast.gast - precise.gast));
        std::printf("astro fast vs ERFA year %d: NPB %.3f\", GAST %.3f\"\n", year, dNpb / kArcsec, dGast / kArcsec);
        // 2000B truncation grows with the t-dependent terms it drops: documented bound 0.1".
        CHECK(dNpb < 0.1 * kArcsec);
        // GAST: both paths go the CIO way (ERA - equation of the origins); the Fast path's
        // truncated CIO locator and 2000B nutation: documented bound 0.1" there too.
        CHECK(dGast < 0.1 * kArcsec);
        // The whole chain stays finite at the extremes, with the same bound between the paths.
        Site site{51.5 * kDeg, -0.1 * kDeg, 10.0};
        glm::dvec3 sirius = directionFromRaDec(hms(6, 45, 8.92), dms(-16, 42, 58.0));
        Topocentric tf = topocentricFromIcrs(observerFrame(site, ts, Path::Fast), sirius);
        Topocentric tp = topocentricFromIcrs(observerFrame(site, ts, Path::Precise), sirius);
        CHECK(std::isfinite(tf.altitudeRad));
        CHECK(std::isfinite(tf.azimuthRad));
        std::printf("astro fast vs precise year %d: Sirius from London %.3f\"\n", year, angleBetween(tf.enu, tp.enu) / kArcsec);
        // Aberration differs most (Keplerian Earth vs eraEpv00, both extrapolated): 0.1".
        CHECK(angleBetween(tf.enu, tp.enu) < 0.1 * kArcsec);
        CHECK(std::isfinite(fast.gast));
    }
}

TEST_CASE("Earth orientation: the series reused along their secant within 5 minutes match full evaluations", "[cpu][astro]") {
    // As a frame loop with time running at 600x (20 s of TT per frame at 30 frames/s) does:
    // EarthSeriesCache extrapolates nutation and the CIO locator along the secant of its last two
    // full evaluations. Bound: 0.5 |f''| dt (dt + D), dt, D <= 300 s; the fastest nutation terms
    // (13.66 d, 0.23"; 9.13 d, 0.03"; 27.6 d, 0.07") give |f''| < 0.1"/day^2, so < 2e-6" — checked
    // at 1e-5" (5x margin for the smaller terms not summed). A wrong or missing slope fails it:
    // holding the value for 300 s errs by |f'| x 300 s ~ 3e-4".
    EarthSeriesCache cache;
    const UtcInstant start = UtcInstant::parse("2026-08-12T17:00:00Z");
    double worstNpb = 0, worstGast = 0, worstDpsi = 0;
    int reused = 0, full = 0;
    for (int frame = 0; frame < 400; ++frame) {  // 8000 s: 26 spans of 5 minutes
        const TimeScales ts = timeScales(start.plusSeconds(20.0 * frame));
        const bool wasValid = cache.valid;
        const double before = cache.t;
        const EarthOrientation cached = earthOrientation(ts, Path::Fast, &cache);
        const EarthOrientation fresh = earthOrientation(ts, Path::Fast);
        (wasValid && cache.t == before ? reused : full)++;
        worstNpb = std::max(worstNpb, rotationDifference(cached.celestialToTrueOfDate, fresh.celestialToTrueOfDate));
        worstGast = std::max(worstGast, std::abs(wrapPi(cached.gast - fresh.gast)));
        worstDpsi = std::max(worstDpsi, std::abs(cached.nutation.dpsi - fresh.nutation.dpsi));
    }
    std::printf("earth series reuse over 400 frames: %d full, %d reused; NPB %.2e\", GAST %.2e\", dpsi %.2e\"\n", full, reused,
                worstNpb / kArcsec, worstGast / kArcsec, worstDpsi / kArcsec);
    CHECK(worstNpb < 1e-5 * kArcsec);
    CHECK(worstGast < 1e-5 * kArcsec);
    CHECK(worstDpsi < 1e-5 * kArcsec);
    // The reuse happens: two full evaluations per 15 frames (300 s / 20 s), not one per frame.
    CHECK(reused > 300);
    // A jump beyond the span evaluates in full and is exact.
    const TimeScales far = timeScales(UtcInstant::parse("2027-08-02T10:00:00Z"));
    const EarthOrientation jumped = earthOrientation(far, Path::Fast, &cache);
    const EarthOrientation exact = earthOrientation(far, Path::Fast);
    CHECK(jumped.gast == exact.gast);
    CHECK(jumped.nutation.dpsi == exact.nutation.dpsi);
}

TEST_CASE("Apparent place of a star: Meeus example 23.a (theta Persei)", "[cpu][astro]") {
    // theta Per, J2000 (FK5): RA 2h44m11.986s, Dec +49 13 42.48, pm +0.03425 s/yr in RA and
    // -0.0895"/yr in Dec; 2028 November 13.19 TD. Meeus: apparent RA 2h46m14.390s,
    // Dec +49 21 07.45 (IAU 1976 precession, 1980 nutation, Ron-Vondrak aberration).
    TimeScales ts = timeScalesFromTT(JulianDate{2462088.5, 0.19});
    const double ra0 = hms(2, 44, 11.986), dec0 = dms(49, 13, 42.48);
    const double years = ts.yearsTT();
    // Proper motion along RA and Dec (as Meeus, linear in the angles over 28.9 years).
    glm::dvec3 p = directionFromRaDec(ra0 + 0.03425 * 15 * kArcsec * years, dec0 - 0.0895 * kArcsec * years);
    for (Path path : kPaths) {
        // Geocentric observer: Earth's velocity only.
        glm::dvec3 app = aberrate(p, earthVelocity(ts, path), path);
        glm::dvec3 tod = celestialToTrueOfDate(ts, path) * app;
        double ra, dec;
        raDecFromDirection(tod, ra, dec);
        // Differences of models: IAU 1976 vs 2006 precession over 29 years (~0.01"), the frame
        // bias (FK5 vs ICRS, ~0.02"), IAU 1980 vs 2000 nutation (~0.02"), Meeus's rounding:
        // 0.1" in Dec and 0.01 s (0.1") in RA.
        CHECK(std::abs(wrapPi(ra - hms(2, 46, 14.390))) < 0.01 * 15 * kArcsec);
        CHECK(std::abs(dec - dms(49, 21, 7.45)) < 0.1 * kArcsec);
    }
}

TEST_CASE("WGS84 site position against ERFA eraGd2gc", "[cpu][astro]") {
    for (double lat : {-90.0, -45.0, 0.0, 38.9, 90.0})
        for (double lon : {-180.0, -77.0, 0.0, 180.0})
            for (double h : {-400.0, 0.0, 8848.0}) {
                Site s{lat * kDeg, lon * kDeg, h};
                double xyz[3];
                REQUIRE(eraGd2gc(1, s.longitudeRad, s.latitudeRad, h, xyz) == 0);
                CHECK(glm::length(siteItrs(s) - glm::dvec3(xyz[0], xyz[1], xyz[2])) < 1e-6);  // 1 um: rounding
            }
    CHECK_THROWS_AS(observerFrame(Site{2.0, 0, 0}, timeScales(UtcInstant::parse("2000-01-01")), Path::Fast), Error);
    CHECK_THROWS_AS(observerFrame(Site{0, 0, 0, -1.0}, timeScales(UtcInstant::parse("2000-01-01")), Path::Fast), Error);
}

TEST_CASE("Glue: fixed ICRS sources against ERFA eraAtco13 (1900-2100, random sites)", "[cpu][astro]") {
    std::mt19937_64 rng(99);
    std::uniform_real_distribution<double> u01(0.0, 1.0);
    const double jd0 = toJulianDate(DateTime{1900, 1, 1}).value(), jd1 = toJulianDate(DateTime{2100, 1, 1}).value();
    double maxOff[2] = {0, 0}, maxOn[2] = {0, 0}, maxOutsideDrift = 0;
    int nOn = 0;
    const double drift0 = toJulianDate(DateTime{1960, 1, 1}).value(), drift1 = toJulianDate(DateTime{1972, 1, 1}).value();
    for (int i = 0; i < 400; ++i) {
        double v = jd0 + (jd1 - jd0) * u01(rng);
        JulianDate utc = JulianDate{std::floor(v - 0.5) + 0.5, v - 0.5 - std::floor(v - 0.5)}.normalized();
        // Include the extremes: poles and the antimeridian.
        double lat = i % 10 == 0 ? 90.0 : i % 10 == 1 ? -90.0 : std::asin(2 * u01(rng) - 1) / kDeg;
        double lon = i % 10 == 2 ? 180.0 : i % 10 == 3 ? -180.0 : 360.0 * u01(rng) - 180.0;
        Site site{lat * kDeg, lon * kDeg, 3000.0 * u01(rng), 0.0, 30.0 * u01(rng) - 10.0};
        // DUT1 as IERS keeps it (|UT1-UTC| < 0.9 s), passed to both sides.
        const double dut1 = 1.8 * u01(rng) - 0.9;
        TimeScales ts = timeScales(utc, dut1);
        double ra = 2 * std::numbers::pi * u01(rng), dec = std::asin(2 * u01(rng) - 1);
        glm::dvec3 icrs = directionFromRaDec(ra, dec);
        for (int p = 0; p < 2; ++p) {
            Path path = kPaths[p];
            // Refraction off: every altitude.
            Site dry = site;
            ObserverFrame f = observerFrame(dry, ts, path);
            Topocentric t = topocentricFromIcrs(f, icrs);
            glm::dvec3 ref = atco13Enu(ra, dec, 0, 0, utc, site, 0.0, dut1);
            maxOff[p] = std::max(maxOff[p], angleBetween(t.enu, ref));
            if (p == 1 && (v < drift0 || v > drift1)) maxOutsideDrift = std::max(maxOutsideDrift, angleBetween(t.enu, ref));
            // Refraction on (the Green model ERFA uses, above 25 deg where welkin uses it alone).
            Site wet = site;
            wet.pressureHpa = 700.0 + 330.0 * u01(rng);
            ObserverFrame fw = observerFrame(wet, ts, path);
            Topocentric tw = topocentricFromIcrs(fw, icrs);
            if (tw.altitudeGeometricRad > 25.5 * kDeg) {
                glm::dvec3 refw = atco13Enu(ra, dec, 0, 0, utc, wet, wet.pressureHpa, dut1);
                maxOn[p] = std::max(maxOn[p], angleBetween(tw.enu, refw));
                nOn += p;
            }
        }
    }
    std::printf("astro glue vs eraAtco13 (400 sources): precise %.4f\" (refraction off; %.4f\" outside 1960-1972), %.4f\" "
                "(on, %d above 25 deg); fast %.4f\" / %.4f\"\n",
                maxOff[1] / kArcsec, maxOutsideDrift / kArcsec, maxOn[1] / kArcsec, nOn, maxOff[0] / kArcsec, maxOn[0] / kArcsec);
    // 1960-1972 (UTC drift era): eraUtcut1 forms UT1 with TAI-UTC taken at the start of the day
    // while eraUtctai uses the instant, so ERFA's UT1 is off UTC + DUT1 by up to 2.6 ms (0.04");
    // welkin keeps UT1 = UTC. Elsewhere the two chains agree to a few milliarcseconds.
    CHECK(maxOutsideDrift < 0.005 * kArcsec);
    // Target from issue 3: the Precise glue adds no error beyond 1". ERFA's CIO-based chain and
    // ours (equinox-based, same IAU 2006/2000A) agree to micro-arcseconds; what remains is UT1 and
    // TT before 1960/after the table where eraDat and our Delta T model differ (TT only).
    CHECK(maxOff[1] < 1.0 * kArcsec);
    CHECK(maxOn[1] < 1.0 * kArcsec);
    CHECK(nOn > 50);
    // The Fast path: 2000B nutation (~1 mas), analytic Earth velocity (< 0.05"), first-order
    // aberration (< 0.002"), no light deflection (< 0.02" beyond 20 deg from the Sun, 1.75" at
    // the limb): documented bound 2" near the Sun, checked here at 2".
    CHECK(maxOff[0] < 2.0 * kArcsec);
    CHECK(maxOn[0] < 2.0 * kArcsec);
}

TEST_CASE("Zenith, nadir and diurnal parallax", "[cpu][astro]") {
    TimeScales ts = timeScales(UtcInstant::parse("2026-03-20T18:00:00Z"));
    for (double lat : {-90.0, -33.0, 0.0, 52.0, 90.0}) {
        Site site{lat * kDeg, 180.0 * kDeg, 0.0};
        ObserverFrame f = observerFrame(site, ts, Path::Fast);
        // The ENU up vector in true-of-date axes is the zenith: RA = LAST, Dec = geodetic latitude.
        Topocentric z = topocentric(f, f.lastRad, site.latitudeRad, 0.0);
        CHECK(z.altitudeRad == Approx(std::numbers::pi / 2).margin(1e-9));
        CHECK(z.enu.z == Approx(1.0).margin(1e-12));
        Topocentric n = topocentric(f, f.lastRad + std::numbers::pi, -site.latitudeRad, 0.0);
        CHECK(n.altitudeRad == Approx(-std::numbers::pi / 2).margin(1e-9));
        CHECK(std::isfinite(n.azimuthRad));
        CHECK(std::isfinite(z.azimuthRad));
        // The Moon on the geocentric horizon drops by its horizontal parallax atan(rho / d)
        // (rho: the site's geocentric distance; the geodetic/geocentric vertical differ by < 0.2 deg).
        double d = 384400e3;
        double rho = glm::length(siteItrs(site));
        glm::dvec3 eastTod = glm::transpose(f.trueOfDateToEnu) * glm::dvec3(1, 0, 0);
        glm::dvec3 horizon = glm::normalize(eastTod - glm::dot(eastTod, glm::normalize(f.sitePositionTod)) * glm::normalize(f.sitePositionTod));
        double ra, dec;
        raDecFromDirection(horizon, ra, dec);
        Topocentric m = topocentric(f, ra, dec, d);
        // Angle between the geocentric direction and the topocentric one is the parallax.
        glm::dvec3 geo = glm::normalize(f.trueOfDateToEnu * horizon);
        CHECK(angleBetween(geo, m.enuGeometric) == Approx(std::atan(rho / d)).epsilon(1e-9));
        CHECK(m.distanceMeters == Approx(std::sqrt(d * d + rho * rho)).epsilon(1e-9));
    }
}

TEST_CASE("Refraction: models, bounds, monotonicity and inverse", "[cpu][astro]") {
    const double P = 1010.0, T = 10.0;
    // Meeus ch. 16 (Bennett 1982): R = 1 / tan(h0 + 7.31 / (h0 + 4.4)) arcmin for an apparent
    // altitude h0; ex. 16.a-style values: h0 = 0.5 deg -> 28.75'. Saemundsson's inverse formula
    // agrees with Bennett's to 0.1' (Meeus), so our R(geometric) must match within 0.15'.
    for (double h0 : {0.0, 0.5, 1.0, 2.0, 5.0, 10.0, 14.0}) {
        double bennett = 1.0 / std::tan((h0 + 7.31 / (h0 + 4.4)) * kDeg) / 60.0 * kDeg;
        double geometric = geometricFromApparentAltitude(h0 * kDeg, P, T);
        CHECK(std::abs((h0 * kDeg - geometric) - bennett) < 0.15 / 60.0 * kDeg);
    }
    CHECK(1.0 / std::tan((0.5 + 7.31 / 4.9) * kDeg) == Approx(28.75).margin(0.01));
    // Above 25 deg: Green's model with ERFA's constants (eraRefco, dry air, 0.55 um).
    double A, B;
    eraRefco(1013.25, 10.0, 0.0, 0.55, &A, &B);
    for (double h : {26.0, 35.0, 45.0, 60.0, 80.0}) {
        double tz = 1.0 / std::tan(h * kDeg);
        double w = B * tz * tz;
        double erfa = (A + w) * tz / (1.0 + (A + 3 * w) / std::pow(std::sin(h * kDeg), 2));
        CHECK(std::abs(refraction(h * kDeg, 1013.25, 10.0) - erfa) < 1e-4 * kArcsec);
    }
    // Standard refraction at 45 deg is ~58" (Explanatory Supplement).
    CHECK(refraction(45 * kDeg, 1013.25, 10.0) / kArcsec == Approx(58.0).margin(1.0));
    // Bounded, finite, and monotonic pieces: R non-increasing in h above -1 deg, non-decreasing
    // below (fading to 0 at -5 deg); h + R(h) strictly increasing (invertible) everywhere.
    double prevApparent = -1e9;
    double maxR = 0;
    for (double h = -90.0; h <= 90.0; h += 0.01) {
        double r = refraction(h * kDeg, P, T);
        REQUIRE(std::isfinite(r));
        REQUIRE(r >= 0.0);
        maxR = std::max(maxR, r);
        double app = h * kDeg + r;
        REQUIRE(app > prevApparent);
        prevApparent = app;
        if (h > -1.0) REQUIRE(refraction((h + 0.01) * kDeg, P, T) <= r + 1e-15);
        if (h < -1.0 && h > -5.0) REQUIRE(refraction((h - 0.01) * kDeg, P, T) <= r + 1e-15);
    }
    CHECK(maxR < 1.0 * kDeg);
    CHECK(refraction(-2.0 * kDeg, P, T) > 0.0);
    CHECK(refraction(-2.0 * kDeg, P, T) < refraction(-1.0 * kDeg, P, T));
    CHECK(refraction(-5.2 * kDeg, P, T) == 0.0);
    CHECK(refraction(10.0 * kDeg, 0.0, T) == 0.0);
    CHECK(refraction(90.0 * kDeg, P, T) < 1e-3 * kArcsec);
    // Pressure and temperature scaling: proportional to P, and colder air refracts more.
    CHECK(refraction(5 * kDeg, 2 * P, T) == Approx(2 * refraction(5 * kDeg, P, T)).epsilon(1e-12));
    CHECK(refraction(5 * kDeg, P, -20) > refraction(5 * kDeg, P, 30));
    // Extreme conditions stay finite and invertible.
    for (double p : {0.0, 500.0, 1013.25, 2000.0})
        for (double t : {-100.0, 10.0, 100.0})
            for (double a = -10.0; a <= 90.0; a += 0.5) {
                double g = geometricFromApparentAltitude(a * kDeg, p, t);
                REQUIRE(std::isfinite(g));
                if (a > -4.0 || p == 0.0) CHECK(apparentFromGeometricAltitude(g, p, t) == Approx(a * kDeg).margin(1e-9));
            }
    CHECK_THROWS_AS(refraction(std::nan(""), P, T), Error);
}

TEST_CASE("Refraction against the Pulkovo refraction tables", "[cpu][astro]") {
    // Pulkovo tables (5th ed., 1985) for 1013.25 hPa, +15 deg C, 0.59 um, dry air, as quoted by
    // the hp41programs refraction page: R = 111.7" at apparent 27 deg, 1217.4" (20'17.4") at
    // 1 deg 30', 1977.97" (32'58") on the horizon.
    auto r = [](double apparentDeg) {
        double a = apparentDeg * kDeg;
        return (a - geometricFromApparentAltitude(a, 1013.25, 15.0)) / kArcsec;
    };
    // Above 25 deg Green's model: 0.5" covers the wavelength (0.55 vs 0.59 um, 0.2%).
    CHECK(r(27.0) == Approx(111.7).margin(0.5));
    // Low altitudes: Saemundsson/Bennett's fit differs from the tables by 1-3% near the horizon,
    // less than the night-to-night variation of the real lapse rate there: 30" and 2'.
    CHECK(r(1.5) == Approx(1217.4).margin(30.0));
    CHECK(r(0.0) == Approx(1977.97).margin(120.0));
}
