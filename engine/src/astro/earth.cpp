// Earth orientation: precession-nutation, obliquity and sidereal time, Fast (own series) and
// Precise (ERFA) paths.
#include <welkin/astro/earth.hpp>

#include "earth_nutation_table.hpp"

#include <erfa.h>

#include <cmath>
#include <iterator>
#include <numbers>

namespace welkin::astro {

namespace {

constexpr double kTwoPi = 2.0 * std::numbers::pi;
constexpr double kArcsec = std::numbers::pi / (180.0 * 3600.0);
constexpr double kTurnArcsec = 1296000.0;

double wrap(double a) {
    double w = std::fmod(a, kTwoPi);
    return w < 0 ? w + kTwoPi : w;
}

glm::dmat3 fromRows(const glm::dvec3& r0, const glm::dvec3& r1, const glm::dvec3& r2) {
    return glm::transpose(glm::dmat3(r0, r1, r2));
}

glm::dmat3 fromErfa(const double r[3][3]) {
    return fromRows({r[0][0], r[0][1], r[0][2]}, {r[1][0], r[1][1], r[1][2]}, {r[2][0], r[2][1], r[2][2]});
}

// IAU 2006 precession: Fukushima-Williams angles including the frame bias (Hilton et al. 2006,
// as in ERFA pfw06), arcseconds; t = TT centuries since J2000.
struct FWAngles {
    double gamb, phib, psib, epsa;
};
FWAngles fukushimaWilliams(double t) {
    FWAngles a;
    a.gamb = (-0.052928 + (10.556378 + (0.4932044 + (-0.00031238 + (-0.000002788 + 0.0000000260 * t) * t) * t) * t) * t) * kArcsec;
    a.phib = (84381.412819 + (-46.811016 + (0.0511268 + (0.00053289 + (-0.000000440 - 0.0000000176 * t) * t) * t) * t) * t) * kArcsec;
    a.psib = (-0.041775 + (5038.481484 + (1.5584175 + (-0.00018522 + (-0.000026452 - 0.0000000148 * t) * t) * t) * t) * t) * kArcsec;
    a.epsa = (84381.406 + (-46.836769 + (-0.0001831 + (0.00200340 + (-0.000000576 - 0.0000000434 * t) * t) * t) * t) * t) * kArcsec;
    return a;
}

// The Fukushima-Williams composition: R1(-eps) R3(-psi) R1(phi) R3(gamma).
glm::dmat3 fwMatrix(double gamb, double phib, double psi, double eps) {
    return rotationX(-eps) * rotationZ(-psi) * rotationX(phib) * rotationZ(gamb);
}

// IAU 2000B nutation with the IAU 2006 J2-rate and precession-rate adjustments (as eraNut06a
// applies to 2000A), radians.
Nutation nutation2000B(double t) {
    // Delaunay arguments (IERS Conventions 2003, Simon et al. 1994; the polynomial forms of ERFA
    // fal03..faom03 so that the Fast path follows the Precise one far from J2000), radians.
    const double l = std::fmod(485868.249036 + t * (1717915923.2178 + t * (31.8792 + t * (0.051635 + t * -0.00024470))), kTurnArcsec) * kArcsec;
    const double lp = std::fmod(1287104.793048 + t * (129596581.0481 + t * (-0.5532 + t * (0.000136 + t * -0.00001149))), kTurnArcsec) * kArcsec;
    const double f = std::fmod(335779.526232 + t * (1739527262.8478 + t * (-12.7512 + t * (-0.001037 + t * 0.00000417))), kTurnArcsec) * kArcsec;
    const double d = std::fmod(1072260.703692 + t * (1602961601.2090 + t * (-6.3706 + t * (0.006593 + t * -0.00003169))), kTurnArcsec) * kArcsec;
    const double om = std::fmod(450160.398036 + t * (-6962890.5431 + t * (7.4722 + t * (0.007702 + t * -0.00005939))), kTurnArcsec) * kArcsec;
    // sin/cos of every term's argument from the powers e^{ik a} of the five arguments (|k| <= 4
    // in this table): 10 sincos instead of 77 (the Fast path's cost is dominated by this series).
    struct Cx {
        double c, s;
    };
    const double args[5] = {l, lp, f, d, om};
    Cx pw[5][5];
    for (int a = 0; a < 5; ++a) {
        pw[a][0] = {1.0, 0.0};
        pw[a][1] = {std::cos(args[a]), std::sin(args[a])};
        for (int k = 2; k < 5; ++k) {
            const Cx& p = pw[a][k - 1];
            pw[a][k] = {p.c * pw[a][1].c - p.s * pw[a][1].s, p.s * pw[a][1].c + p.c * pw[a][1].s};
        }
    }
    auto power = [&](int a, int m) {
        Cx z = pw[a][m < 0 ? -m : m];
        if (m < 0) z.s = -z.s;
        return z;
    };
    double dp = 0, de = 0;
    // Smallest terms first for a slightly better rounding.
    for (int i = int(std::size(detail::kNutation2000B)) - 1; i >= 0; --i) {
        const detail::NutationTerm& k = detail::kNutation2000B[i];
        const int mult[5] = {k.l, k.lp, k.f, k.d, k.om};
        Cx z{1.0, 0.0};
        for (int a = 0; a < 5; ++a) {
            if (mult[a] == 0) continue;
            const Cx w = power(a, mult[a]);
            z = {z.c * w.c - z.s * w.s, z.s * w.c + z.c * w.s};
        }
        dp += (k.ps + k.pst * t) * z.s + k.pc * z.c;
        de += (k.ec + k.ect * t) * z.c + k.es * z.s;
    }
    const double u2r = kArcsec * 1e-7;
    // Fixed offsets standing in for the omitted planetary terms (McCarthy & Luzum 2003).
    double dpsi = dp * u2r - 0.135e-3 * kArcsec;
    double deps = de * u2r + 0.388e-3 * kArcsec;
    // IAU 2006 adjustments: J2 secular variation and the precession-rate factor.
    const double fj2 = -2.7774e-6 * t;
    dpsi *= 1.0 + 0.4697e-6 + fj2;
    deps *= 1.0 + fj2;
    return {dpsi, deps};
}

// Equation of the equinoxes, complementary terms (largest of IERS 2003 Table 5.2e, > 0.5 uas), rad.
double eqeqComplementary(double t) {
    const double om = std::fmod(450160.398036 + t * (-6962890.5431 + t * (7.4722 + t * (0.007702 + t * -0.00005939))), kTurnArcsec) * kArcsec;
    const double f = std::fmod(335779.526232 + t * (1739527262.8478 + t * (-12.7512 + t * (-0.001037 + t * 0.00000417))), kTurnArcsec) * kArcsec;
    const double d = std::fmod(1072260.703692 + t * (1602961601.2090 + t * (-6.3706 + t * (0.006593 + t * -0.00003169))), kTurnArcsec) * kArcsec;
    const double fd = 2.0 * (f - d);
    const double s = 2640.96e-6 * std::sin(om) - 0.39e-6 * std::cos(om) + 63.52e-6 * std::sin(2.0 * om) +
                     11.75e-6 * std::sin(fd + 3.0 * om) + 11.21e-6 * std::sin(fd + om) - 4.55e-6 * std::sin(fd + 2.0 * om) -
                     0.87e-6 * t * std::sin(om);
    return s * kArcsec;
}

double gmstFromEra(double era, double t) {
    return wrap(era + (0.014506 + (4612.156534 + (1.3915817 + (-0.00000044 + (-0.000029956 - 0.0000000368 * t) * t) * t) * t) * t) * kArcsec);
}

}  // namespace

glm::dmat3 rotationX(double a) {
    const double s = std::sin(a), c = std::cos(a);
    return fromRows({1, 0, 0}, {0, c, s}, {0, -s, c});
}
glm::dmat3 rotationY(double a) {
    const double s = std::sin(a), c = std::cos(a);
    return fromRows({c, 0, -s}, {0, 1, 0}, {s, 0, c});
}
glm::dmat3 rotationZ(double a) {
    const double s = std::sin(a), c = std::cos(a);
    return fromRows({c, s, 0}, {-s, c, 0}, {0, 0, 1});
}

glm::dvec3 directionFromRaDec(double ra, double dec) {
    const double cd = std::cos(dec);
    return {cd * std::cos(ra), cd * std::sin(ra), std::sin(dec)};
}

void raDecFromDirection(const glm::dvec3& v, double& ra, double& dec) {
    const double r = std::hypot(v.x, v.y);
    ra = r > 0 ? wrap(std::atan2(v.y, v.x)) : 0.0;
    dec = (r > 0 || v.z != 0) ? std::atan2(v.z, r) : 0.0;
}

double meanObliquity(const TimeScales& ts) { return fukushimaWilliams(ts.centuriesTT()).epsa; }

Nutation nutation(const TimeScales& ts, Path path) {
    if (path == Path::Precise) {
        Nutation n;
        eraNut06a(ts.tt.day, ts.tt.fraction, &n.dpsi, &n.deps);
        return n;
    }
    return nutation2000B(ts.centuriesTT());
}

double earthRotationAngle(const TimeScales& ts) {
    // ERA = 2 pi (0.7790572732640 + 1.00273781191135448 Du), Du = UT1 - J2000; split for precision.
    const double du = ts.daysUT1();
    const double frac = std::fmod(ts.ut1.fraction, 1.0) + std::fmod(ts.ut1.day - kJ2000, 1.0);
    return wrap(kTwoPi * (frac + 0.7790572732640 + 0.00273781191135448 * du));
}

double gmst(const TimeScales& ts, Path path) {
    if (path == Path::Precise) return eraGmst06(ts.ut1.day, ts.ut1.fraction, ts.tt.day, ts.tt.fraction);
    return gmstFromEra(earthRotationAngle(ts), ts.centuriesTT());
}

double gast(const TimeScales& ts, Path path) { return earthOrientation(ts, path).gast; }

glm::dmat3 celestialToTrueOfDate(const TimeScales& ts, Path path) { return earthOrientation(ts, path).celestialToTrueOfDate; }

EarthOrientation earthOrientation(const TimeScales& ts, Path path) {
    EarthOrientation eo;
    const double t = ts.centuriesTT();
    if (path == Path::Precise) {
        double gamb, phib, psib, epsa;
        eraPfw06(ts.tt.day, ts.tt.fraction, &gamb, &phib, &psib, &epsa);
        eraNut06a(ts.tt.day, ts.tt.fraction, &eo.nutation.dpsi, &eo.nutation.deps);
        double r[3][3];
        eraFw2m(gamb, phib, psib + eo.nutation.dpsi, epsa + eo.nutation.deps, r);
        eo.celestialToTrueOfDate = fromErfa(r);
        eo.meanObliquity = epsa;
        eo.gmst = eraGmst06(ts.ut1.day, ts.ut1.fraction, ts.tt.day, ts.tt.fraction);
        eo.gast = eraGst06(ts.ut1.day, ts.ut1.fraction, ts.tt.day, ts.tt.fraction, r);
    } else {
        const FWAngles a = fukushimaWilliams(t);
        eo.nutation = nutation2000B(t);
        eo.celestialToTrueOfDate = fwMatrix(a.gamb, a.phib, a.psib + eo.nutation.dpsi, a.epsa + eo.nutation.deps);
        eo.meanObliquity = a.epsa;
        eo.gmst = gmstFromEra(earthRotationAngle(ts), t);
        eo.gast = wrap(eo.gmst + eo.nutation.dpsi * std::cos(a.epsa) + eqeqComplementary(t));
    }
    eo.trueObliquity = eo.meanObliquity + eo.nutation.deps;
    return eo;
}

}  // namespace welkin::astro
