// Earth orientation: precession-nutation, obliquity and sidereal time, Fast (own series) and
// Precise (ERFA) paths.
#include <welkin/astro/earth.hpp>

#include "earth_nutation_table.hpp"

#include <erfa.h>

#include <array>
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

// The five Delaunay arguments (IERS Conventions 2003, Simon et al. 1994; the polynomial forms of
// ERFA fal03..faom03, so that the Fast path follows the Precise one far from J2000) and the
// powers e^{ik a}, |k| <= 4, from which every series term's sin/cos is formed: 10 sincos for
// the whole of nutation and the CIO locator instead of one per term.
struct Delaunay {
    struct Cx {
        double c, s;
    };
    Cx pw[5][5];
    explicit Delaunay(double t) {
        const double args[5] = {
            std::fmod(485868.249036 + t * (1717915923.2178 + t * (31.8792 + t * (0.051635 + t * -0.00024470))), kTurnArcsec) * kArcsec,
            std::fmod(1287104.793048 + t * (129596581.0481 + t * (-0.5532 + t * (0.000136 + t * -0.00001149))), kTurnArcsec) * kArcsec,
            std::fmod(335779.526232 + t * (1739527262.8478 + t * (-12.7512 + t * (-0.001037 + t * 0.00000417))), kTurnArcsec) * kArcsec,
            std::fmod(1072260.703692 + t * (1602961601.2090 + t * (-6.3706 + t * (0.006593 + t * -0.00003169))), kTurnArcsec) * kArcsec,
            std::fmod(450160.398036 + t * (-6962890.5431 + t * (7.4722 + t * (0.007702 + t * -0.00005939))), kTurnArcsec) * kArcsec};
        for (int a = 0; a < 5; ++a) {
            pw[a][0] = {1.0, 0.0};
            pw[a][1] = {std::cos(args[a]), std::sin(args[a])};
            for (int k = 2; k < 5; ++k) pw[a][k] = mul(pw[a][k - 1], pw[a][1]);
        }
    }
    static Cx mul(const Cx& a, const Cx& b) { return {a.c * b.c - a.s * b.s, a.s * b.c + a.c * b.s}; }
    // cos and sin of  l*l + lp*l' + f*F + d*D + om*Omega.
    Cx term(int l, int lp, int f, int d, int om) const {
        const int mult[5] = {l, lp, f, d, om};
        Cx z{1.0, 0.0};
        for (int a = 0; a < 5; ++a) {
            if (mult[a] == 0) continue;
            Cx w = pw[a][mult[a] < 0 ? -mult[a] : mult[a]];
            if (mult[a] < 0) w.s = -w.s;
            z = mul(z, w);
        }
        return z;
    }
};

// IAU 2000B nutation with the IAU 2006 J2-rate and precession-rate adjustments (as eraNut06a
// applies to 2000A), radians.
Nutation nutation2000B(const Delaunay& fa, double t) {
    double dp = 0, de = 0;
    // Smallest terms first for a slightly better rounding.
    for (int i = int(std::size(detail::kNutation2000B)) - 1; i >= 0; --i) {
        const detail::NutationTerm& k = detail::kNutation2000B[i];
        const Delaunay::Cx z = fa.term(k.l, k.lp, k.f, k.d, k.om);
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
Nutation nutation2000B(double t) { return nutation2000B(Delaunay(t), t); }

// The CIO locator s (IAU 2006, IERS Conventions 2010 Table 5.2d) truncated to its luni-solar
// terms above 0.2 uas (the series of ERFA s06 without the planetary and smallest terms): s + XY/2
// in microarcseconds as polynomial + sum_j t^j sum (S sin + C cos).
struct CioTerm {
    signed char l, lp, f, d, om;
    double s, c;  // uas
};
constexpr CioTerm kCio0[] = {
    {0, 0, 0, 0, 1, -2640.73, 0.39}, {0, 0, 0, 0, 2, -63.53, 0.02}, {0, 0, 2, -2, 3, -11.75, -0.01},
    {0, 0, 2, -2, 1, -11.21, -0.01}, {0, 0, 2, -2, 2, 4.57, 0.00},  {0, 0, 2, 0, 3, -2.02, 0.00},
    {0, 0, 2, 0, 1, -1.98, 0.00},    {0, 0, 0, 0, 3, 1.72, 0.00},   {0, 1, 0, 0, 1, 1.41, 0.01},
    {0, 1, 0, 0, -1, 1.26, 0.01},    {1, 0, 0, 0, -1, 0.63, 0.00},  {1, 0, 0, 0, 1, 0.63, 0.00},
    {0, 1, 2, -2, 3, -0.46, 0.00},   {0, 1, 2, -2, 1, -0.45, 0.00}, {0, 0, 4, -4, 4, -0.36, 0.00},
    {0, 0, 2, 0, 0, -0.32, 0.00},    {0, 0, 2, 0, 2, -0.28, 0.00},  {1, 0, 2, 0, 3, -0.27, 0.00},
    {1, 0, 2, 0, 1, -0.26, 0.00},    {0, 0, 2, -2, 0, 0.21, 0.00},
};
constexpr CioTerm kCio1[] = {{0, 0, 0, 0, 2, -0.07, 3.57}, {0, 0, 0, 0, 1, 1.73, -0.03}, {0, 0, 2, -2, 3, 0.00, 0.48}};
constexpr CioTerm kCio2[] = {
    {0, 0, 0, 0, 1, 743.52, -0.17}, {0, 0, 2, -2, 2, 56.91, 0.06}, {0, 0, 2, 0, 2, 9.84, -0.01},
    {0, 0, 0, 0, 2, -8.85, 0.01},   {0, 1, 0, 0, 0, -6.38, -0.05}, {1, 0, 0, 0, 0, -3.07, 0.00},
    {0, 1, 2, -2, 2, 2.23, 0.00},   {0, 0, 2, 0, 1, 1.67, 0.00},   {1, 0, 2, 0, 2, 1.30, 0.00},
    {0, 1, -2, 2, -2, 0.93, 0.00},  {1, 0, 0, -2, 0, 0.68, 0.00},  {0, 0, 2, -2, 1, -0.55, 0.00},
    {1, 0, -2, 0, -2, 0.53, 0.00},  {0, 0, 0, 2, 0, -0.27, 0.00},  {1, 0, 0, 0, 1, -0.27, 0.00},
    {1, 0, -2, -2, -2, -0.26, 0.00}, {1, 0, 0, 0, -1, -0.25, 0.00}, {1, 0, 2, 0, 1, 0.22, 0.00},
    {2, 0, 0, -2, 0, -0.21, 0.00},  {2, 0, -2, 0, -1, 0.20, 0.00},
};
constexpr CioTerm kCio3[] = {{0, 0, 0, 0, 1, 0.30, -23.42}, {0, 0, 2, -2, 2, -0.03, -1.46}, {0, 0, 2, 0, 2, -0.01, -0.25}, {0, 0, 0, 0, 2, 0.00, 0.23}};
constexpr CioTerm kCio4[] = {{0, 0, 0, 0, 1, -0.26, -0.01}};

template <size_t N>
double cioSeries(const Delaunay& fa, const CioTerm (&terms)[N]) {
    double w = 0;
    for (size_t i = N; i-- > 0;) {
        const CioTerm& k = terms[i];
        const Delaunay::Cx z = fa.term(k.l, k.lp, k.f, k.d, k.om);
        w += k.s * z.s + k.c * z.c;
    }
    return w;
}

// The CIO locator's series part, s + XY/2 (rad), at `t` (TT centuries from J2000).
double cioPolynomial(const Delaunay& fa, double t) {
    const double w0 = 94.00 + cioSeries(fa, kCio0), w1 = 3808.65 + cioSeries(fa, kCio1);
    const double w2 = -122.68 + cioSeries(fa, kCio2), w3 = -72574.11 + cioSeries(fa, kCio3);
    const double w4 = 27.98 + cioSeries(fa, kCio4), w5 = 15.62;
    return (w0 + (w1 + (w2 + (w3 + (w4 + w5 * t) * t) * t) * t) * t) * 1e-6 * kArcsec;
}

// Greenwich apparent sidereal time the CIO way (as ERFA gst06): GAST = ERA - EO, with the
// equation of the origins EO from the bias-precession-nutation matrix and the CIO locator s
// (`sPoly` = s + XY/2 from cioPolynomial()).
double gastFromCio(double era, const glm::dmat3& npb, double sPoly) {
    auto r = [&](int i, int j) { return npb[j][i]; };  // row i, column j
    const double x = r(2, 0), y = r(2, 1);
    const double s = sPoly - x * y / 2.0;
    const double ax = x / (1.0 + r(2, 2));
    const double xs = 1.0 - ax * x, ys = -ax * y, zs = -x;
    const double p = r(0, 0) * xs + r(0, 1) * ys + r(0, 2) * zs;
    const double q = r(1, 0) * xs + r(1, 1) * ys + r(1, 2) * zs;
    const double eo = (p != 0 || q != 0) ? s - std::atan2(q, p) : s;
    return wrap(era - eo);
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

EarthOrientation earthOrientation(const TimeScales& ts, Path path) { return earthOrientation(ts, path, nullptr); }

EarthOrientation earthOrientation(const TimeScales& ts, Path path, EarthSeriesCache* cache) {
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
        std::array<double, 3> v;
        const double span = EarthSeriesCache::kReuseDays / 36525.0;
        if (!cache || !cache->reuse(t, span, v)) {
            const Delaunay fa(t);
            const Nutation n = nutation2000B(fa, t);
            v = {n.dpsi, n.deps, cioPolynomial(fa, t)};
            if (cache) cache->record(t, span, v);
        }
        eo.nutation = {v[0], v[1]};
        eo.celestialToTrueOfDate = fwMatrix(a.gamb, a.phib, a.psib + eo.nutation.dpsi, a.epsa + eo.nutation.deps);
        eo.meanObliquity = a.epsa;
        const double era = earthRotationAngle(ts);
        eo.gmst = gmstFromEra(era, t);
        eo.gast = gastFromCio(era, eo.celestialToTrueOfDate, v[2]);
    }
    eo.trueObliquity = eo.meanObliquity + eo.nutation.deps;
    return eo;
}

}  // namespace welkin::astro
