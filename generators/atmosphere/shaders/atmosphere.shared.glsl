// The sky model's optical functions and LUT parameterisations, one source for GLSL and C++
// (welkin/glsl_cpp.hpp): atmosphere.glsl includes it and wraps the functions that need the
// planet's radii with versions of the same name that read them from its uniform block; the CPU
// twins (sky_model.hpp) compile it in double and pass a SkyModel's radii.
//
// Geometry: R = ground radius, Ht = top - ground (m), h = height above the ground (m), mu =
// cos(view zenith), muS = cos(light zenith), nu = cos(view-light angle); r^2 - R^2 is always
// computed as h (2R + h) so rays grazing the ground keep their precision in float. LUT sizes are
// texels as reals (vec2(width, height)).

const real ATM_PI = 3.141592653589793;

// Spherical Fibonacci direction i of n (z up): equal-area, deterministic.
vec3 atm_fibonacciDirection(int i, int n) {
    const real golden = ATM_PI * (3.0 - sqrt(5.0));
    real z = 1.0 - (2.0 * real(i) + 1.0) / real(n);
    real rr = sqrt(max(1.0 - z * z, 0.0));
    real phi = golden * real(i);
    return vec3(rr * cos(phi), rr * sin(phi), z);
}

// A density profile (Bruneton 2017's two layers, clamped to [0, 1]) packed as three vec4:
// a = (width0, exp0, scale0 (1/m), linear0 (1/m)), b = (constant0, exp1, scale1, linear1),
// c = (constant1, 0, 0, 0); layer 0 below width0, layer 1 above.
real atm_profileDensity(vec4 a, vec4 b, vec4 c, real h) {
    real d = h < a.x ? a.y * exp(a.z * h) + a.w * h + b.x : b.y * exp(b.z * h) + b.w * h + c.x;
    return clamp(d, 0.0, 1.0);
}

real atm_rho2(real R, real h) { return h * (2.0 * R + h); }

real distanceToTop(real R, real Ht, real h, real mu) {
    real r = R + h;
    // r^2 mu^2 - (r^2 - Rt^2) with r^2 - Rt^2 = (h - Ht)(2R + h + Ht).
    real disc = r * r * mu * mu - (h - Ht) * (2.0 * R + h + Ht);
    return max(-r * mu + sqrt(max(disc, 0.0)), 0.0);
}
real distanceToBottom(real R, real h, real mu) {
    real r = R + h;
    real disc = r * r * mu * mu - atm_rho2(R, h);
    return max(-r * mu - sqrt(max(disc, 0.0)), 0.0);
}
bool rayIntersectsGround(real R, real h, real mu) {
    real r = R + h;
    return mu < 0.0 && r * r * mu * mu - atm_rho2(R, h) >= 0.0;
}
// Height at distance t along the ray (r_t - R without cancellation).
real heightAt(real R, real h, real mu, real t) {
    real r = R + h;
    real q = t * t + 2.0 * r * mu * t + atm_rho2(R, h);  // r_t^2 - R^2
    real rt = sqrt(max(q + R * R, 0.0));
    return q / (rt + R);
}

// Texel-centre mapping of [0, 1] onto a LUT axis of `size` texels, and its inverse.
real texCoordFromUnit(real x, real size) { return 0.5 / size + x * (1.0 - 1.0 / size); }
real unitFromTexCoord(real u, real size) { return (u - 0.5 / size) / (1.0 - 1.0 / size); }

// Transmittance LUT (Bruneton 2017): x = distance to the top between its extremes, y = rho / H.
vec2 transmittanceUv(real R, real Ht, real h, real mu, vec2 size) {
    real H = sqrt(max(Ht * (2.0 * R + Ht), 0.0));
    h = clamp(h, 0.0, Ht);
    real rho = sqrt(max(atm_rho2(R, h), 0.0));
    real d = distanceToTop(R, Ht, h, mu);
    real dMin = Ht - h, dMax = rho + H;
    real xMu = dMax > dMin ? (d - dMin) / (dMax - dMin) : 0.0;
    return vec2(texCoordFromUnit(clamp(xMu, 0.0, 1.0), size.x), texCoordFromUnit(rho / H, size.y));
}
vec2 transmittanceHMu(real R, real Ht, vec2 uv, vec2 size) {
    real H = sqrt(max(Ht * (2.0 * R + Ht), 0.0));
    real xMu = clamp(unitFromTexCoord(uv.x, size.x), 0.0, 1.0), xR = clamp(unitFromTexCoord(uv.y, size.y), 0.0, 1.0);
    real rho = H * xR;
    real r = sqrt(rho * rho + R * R);
    real h = rho * rho / (r + R);  // r - R without cancellation
    real dMin = Ht - h, dMax = rho + H;
    real d = dMin + xMu * (dMax - dMin);
    real mu = d == 0.0 ? 1.0 : clamp((H * H - rho * rho - d * d) / (2.0 * r * d), -1.0, 1.0);
    return vec2(h, mu);
}

// Multiple-scattering LUT. mu_s axis: u = 1/2 + atan(mu_s / a) / (2 atan(1 / a)), denser than
// linear around the horizon (the terminator sweeps the low atmosphere there: twilight) by
// 1 / (a atan(1 / a)): a = 0.25 (3 times) from 64 texels up, a = 0.15 (4.7 times) for narrower
// LUTs (low), which need the texels at the terminator more. With 64 texels a = 0.15 left too few
// for a high Sun: the sky at Sun 60 deg was 2 % RMS off from interpolation along mu_s alone (1 %
// with a = 0.25 or with twice the texels); at Sun 0 to -4 deg the RMS moved by 0.1 point (medium
// 1.8-2.4 %). Height axis: v = sqrt(h / thickness), dense near the ground where the aerosols are.
real atm_msA(real width) { return width >= 63.5 ? 0.25 : 0.15; }
vec2 multiScatteringUv(real Ht, real h, real muS, vec2 size) {
    real a = atm_msA(size.x);
    real x = 0.5 + 0.5 * atan(clamp(muS, -1.0, 1.0) / a) / atan(1.0 / a);
    return vec2(texCoordFromUnit(clamp(x, 0.0, 1.0), size.x), texCoordFromUnit(sqrt(clamp(h / Ht, 0.0, 1.0)), size.y));
}
vec2 multiScatteringHMuS(real Ht, vec2 uv, vec2 size) {
    real a = atm_msA(size.x);
    real x = clamp(unitFromTexCoord(uv.x, size.x), 0.0, 1.0);
    real muS = clamp(a * tan((2.0 * x - 1.0) * atan(1.0 / a)), -1.0, 1.0);
    real y = clamp(unitFromTexCoord(uv.y, size.y), 0.0, 1.0);
    return vec2(y * y * Ht, muS);
}

// The zenith angle of the observer's horizon, and sin(theta_H / 2) of it.
real atm_horizonZenith(real R, real h) {
    real r = R + h;
    return acos(clamp(-sqrt(max(atm_rho2(R, max(h, 0.0)), 0.0)) / r, -1.0, 1.0));
}
real atm_horizonS(real R, real h) {
    real r = R + h;
    real muH = -sqrt(max(atm_rho2(R, max(h, 0.0)), 0.0)) / r;  // cos of the horizon's zenith angle
    return sqrt(clamp(0.5 - 0.5 * muH, 0.0, 1.0));
}

// Sky-view LUT. Latitude: the upper half (rows H/2 .. H-1) covers [horizon, zenith], the lower
// half (rows H/2-1 .. 0) covers [horizon, nadir]; within each half x = sqrt(distance from the
// horizon / span) is spread over the half's texel centres, so both halves have a row exactly at
// the horizon. The distance is measured in s = sin(theta / 2) (theta: view zenith angle), which
// is within 1.4x of linear in theta and costs one square root per pixel instead of an acos:
// s = sqrt((1 - mu) / 2). Azimuth: u = sin(azimuth / 2) = sqrt((1 - cos azimuth) / 2), from the
// cosine without an atan, twice as dense as linear at the light's vertical plane (where the
// aureole is) and coarse only opposite the light, where the sky is smooth in azimuth.
// sH = atm_horizonS(R, h).
vec2 skyViewUvS(real sH, real mu, real cosAz, vec2 size) {
    real s = sqrt(clamp(0.5 - 0.5 * mu, 0.0, 1.0));
    real half_ = floor(size.y / 2.0);
    bool sky = s <= sH;
    real x = sqrt(clamp(sky ? (sH - s) / sH : (s - sH) / (1.0 - sH), 0.0, 1.0));
    real dv = (x * (half_ - 1.0) + 0.5) / size.y;
    real v = sky ? 0.5 + dv : 0.5 - dv;
    return vec2(texCoordFromUnit(sqrt(clamp(0.5 - 0.5 * cosAz, 0.0, 1.0)), size.x), v);
}
// Inverse (texel centre -> view): returns (mu, azimuth in [0, pi]).
vec2 skyViewMuAzS(real sH, vec2 uv, vec2 size) {
    real half_ = floor(size.y / 2.0);
    real s;
    if (uv.y >= 0.5) {
        real x = clamp(((uv.y - 0.5) * size.y - 0.5) / (half_ - 1.0), 0.0, 1.0);
        s = sH - x * x * sH;
    } else {
        real x = clamp(((0.5 - uv.y) * size.y - 0.5) / (half_ - 1.0), 0.0, 1.0);
        s = sH + x * x * (1.0 - sH);
    }
    return vec2(clamp(1.0 - 2.0 * s * s, -1.0, 1.0), 2.0 * asin(clamp(unitFromTexCoord(uv.x, size.x), 0.0, 1.0)));
}
// For an observer above the atmosphere (h > Ht): the distance along a ray of cos zenith mu to
// where it enters the air (> 0), or -1.0 when it misses it (upwards, or passing above the top).
real atm_entryFromSpace(real R, real Ht, real h, real mu) {
    real r = R + h;
    real disc = r * r * mu * mu - (h - Ht) * (2.0 * R + h + Ht);
    if (mu >= 0.0 || disc < 0.0) return -1.0;
    return -r * mu - sqrt(disc);
}
// The cosine of the angle between a view (cos zenith mu, its sine sinV, azimuth az from the
// light's) and the light (cos zenith muS, its sine sinS), clamped into [-1, 1].
real atm_cosViewLight(real mu, real sinV, real az, real muS, real sinS) { return clamp(sinV * sinS * cos(az) + mu * muS, -1.0, 1.0); }
// A sky-view-parameterised texel's view (uv its centre, size the table's: the sky-view LUT, its
// keyframe blend, the aerial-perspective volume's slices) for a light at cos zenith muS: (mu,
// azimuth from the light in [0, pi], nu = cos of the angle to the light). sH = atm_horizonS(R, h).
vec3 skyViewTexelViewS(real sH, vec2 uv, vec2 size, real muS) {
    vec2 ma = skyViewMuAzS(sH, uv, size);
    real sinV = sqrt(max(1.0 - ma.x * ma.x, 0.0)), sinS = sqrt(max(1.0 - muS * muS, 0.0));
    return vec3(ma.x, ma.y, atm_cosViewLight(ma.x, sinV, ma.y, muS, sinS));
}
// The sky-irradiance sum's sample (i, j) of nz x na: the midpoint rule in x = cos^2 zenith over
// [0, 1] and in the azimuth from the light over [0, pi] (E = int L cos(theta) dOmega over the upper
// hemisphere, cos(theta) dOmega = 0.5 dx dphi; the half circle stands for both sides of the
// light's vertical plane). Returns (mu, sin of the zenith angle, azimuth); every sample weighs
// atm_irradianceWeight(nz, na) = 0.5 (1 / nz) (pi / na) 2.
vec3 atm_irradianceSample(int i, int j, int nz, int na) {
    real x = (real(i) + 0.5) / real(nz);
    return vec3(sqrt(x), sqrt(max(1.0 - x, 0.0)), (real(j) + 0.5) / real(na) * ATM_PI);
}
real atm_irradianceWeight(int nz, int na) { return ATM_PI / real(nz * na); }

// Phase functions (1/sr): Rayleigh; Mie of asymmetry g as Henyey-Greenstein (kind 0) or
// Cornette-Shanks (kind 1).
real rayleighPhase(real nu) { return 3.0 / (16.0 * ATM_PI) * (1.0 + nu * nu); }
real miePhase(real nu, real g, int kind) {
    real g2 = g * g;
    real d = max(1.0 + g2 - 2.0 * g * nu, 1e-12);
    real denom = d * sqrt(d);
    if (kind == 0) return (1.0 - g2) / (4.0 * ATM_PI * denom);
    return 3.0 / (8.0 * ATM_PI) * (1.0 - g2) * (1.0 + nu * nu) / ((2.0 + g2) * denom);
}

// Keeps v inside the half (sky or ground) of a sky-view LUT of `size` texels that it started in:
// the halves are never blended.
vec2 skyViewClampHalf(vec2 uv, vec2 size) {
    real half_ = floor(size.y / 2.0);
    uv.y = uv.y >= 0.5 ? clamp(uv.y, (half_ + 0.5) / size.y, 1.0 - 0.5 / size.y)
                       : clamp(uv.y, 0.5 / size.y, (half_ - 0.5) / size.y);
    return uv;
}

// Sample spacing along a ray: s in [0, 1] -> fraction of the ray, dense at the perigee fraction
// p (p = 0: dense at the origin, p = 1: dense at the end).
real atm_warp(real s, real p) {
    if (s < p) {
        real a = (p - s) / p;
        return p - p * a * a;
    }
    real a = p < 1.0 ? (s - p) / (1.0 - p) : 0.0;
    return p + (1.0 - p) * a * a;
}
// (1 - exp(-sigmaT dt)) / sigmaT per channel, the integral of exp(-sigmaT s) over a segment of
// length dt (m); its limit dt where sigmaT dt is at most ATM_SEGMENT_LINEAR (in float below 1e-4
// the difference 1 - exp(-x) has lost its digits; the double twin defines 1e-7 before the include).
#ifndef ATM_SEGMENT_LINEAR
#define ATM_SEGMENT_LINEAR 1e-4
#endif
vec3 atm_segmentFactor(vec3 sigmaT, real dt) {
    vec3 x = sigmaT * dt;
    return mix(vec3(dt), (1.0 - exp(-x)) / max(sigmaT, vec3(1e-30)), greaterThan(x, vec3(ATM_SEGMENT_LINEAR)));
}
// Where along a ray of length d its lowest point lies, as a fraction in [0, 1].
real atm_perigeeFraction(real R, real h, real mu, real d) { return d <= 0.0 ? 0.0 : clamp(-(R + h) * mu / d, 0.0, 1.0); }

// The fraction of a light's disk (angular radius, rad) above the planet's horizon at height h
// seen at cos zenith muS: smoothstep(-a, a, muS - cos(horizon)), a = sin(horizon) x radius.
real atm_lightAboveHorizon(real R, real h, real muS, real angularRadius) {
    h = max(h, 0.0);
    real r = R + h;
    real sinH = R / r;
    real cosH = -sqrt(max(atm_rho2(R, h), 0.0)) / r;
    real a = sinH * angularRadius;
    real f = clamp((muS - cosH + a) / (2.0 * a), 0.0, 1.0);
    return f * f * (3.0 - 2.0 * f);
}

// Visible fraction of a limb-darkened disk (linear law, u = 0.6) of angular radius rs behind a
// dark disk of radius ro, centres d apart (radians, small angles; rs > 0): the sky's eclipse
// (atmosphere.glsl's atm_eclipseAt(); C++: cpu::eclipseFraction()). The rings the Moon's limb does
// not cut are integrated exactly, the cut band r in [|R - D|, min(1, R + D)] with `nodes` nodes
// (cosine-spaced), so the thin crescent before second contact keeps its light (uniform rings lost
// it). astro::eclipseVisibleFraction() (welkin_astro: any u) is the same rule written apart, the
// reference the tests compare this with.
real atm_limbFluxInside(real a) {
    real c = max(1.0 - a * a, 0.0);
    return 0.2 * a * a + 0.2 * (1.0 - c * sqrt(c));
}
real atm_eclipseFraction(real rs, real ro, real d, int nodes) {
    real R = ro / rs, D = d / rs;
    if (D >= 1.0 + R) return 1.0;
    if (R >= D + 1.0) return 0.0;
    real lo = abs(R - D), hi = min(1.0, R + D);
    real visible = atm_limbFluxInside(clamp(D - R, 0.0, 1.0)) + atm_limbFluxInside(1.0) - atm_limbFluxInside(hi);
    if (D > 1e-7 && hi > lo) {
        real half_ = 0.5 * (hi - lo), band = 0.0;
        // The nodes' cos(s) and sin(s), s = pi (i + 0.5) / nodes, by the angle-addition recurrence:
        // two transcendentals per call instead of two per node (llvmpipe does not fold them out of
        // the loop; the eclipse sky evaluates this at every step of its rays). Rounding drift over
        // 24 steps ~1e-6 in float, far below the rule's own 1e-3.
        real dS = ATM_PI / real(nodes);
        real cs = cos(0.5 * dS), sn = sin(0.5 * dS);
        real cd = cos(dS), sd = sin(dS);
        for (int i = 0; i < nodes; ++i) {
            real r = lo + half_ * (1.0 - cs);
            real w = (1.0 - 0.6 * (1.0 - sqrt(max(1.0 - r * r, 0.0)))) * r;
            real a = max(R + D - r, 0.0) * max(R - D + r, 0.0), b = max(r + D - R, 0.0) * (r + D + R);
            band += w * (1.0 - 2.0 * atan(sqrt(a), sqrt(b)) / ATM_PI) * sn;
            real c2 = cs * cd - sn * sd;
            sn = sn * cd + cs * sd;
            cs = c2;
        }
        visible += band * half_ * ATM_PI / real(nodes);
    }
    return clamp(visible / atm_limbFluxInside(1.0), 0.0, 1.0);
}
// The visible fraction of the Sun (centre sunPos, radius sunRadius, m) seen from the point p behind
// the Moon (moonPos, moonRadius), all in one frame (m): their angular radii and separation from p,
// then atm_eclipseFraction().
real atm_eclipseVisibleAt(vec3 p, vec3 moonPos, real moonRadius, vec3 sunPos, real sunRadius, int nodes) {
    vec3 m = moonPos - p;
    vec3 s = sunPos - p;
    real dm = length(m);
    real ds = length(s);
    real ro = asin(min(moonRadius / dm, 1.0));
    real rs = sunRadius / ds;
    real d = 2.0 * asin(min(0.5 * length(m / dm - s / ds), 1.0));
    return atm_eclipseFraction(rs, ro, d, nodes);
}

// ---- The directional multiple-scattering field's spherical harmonics ---------------------------
// SH bands L (SkyQuality::shBands: GLSL, the pass's program defines it; C++, kShMaxBands, the
// arrays' size, each call taking its field's L), ATM_SH_COEFFICIENTS = (L + 1)(L + 2) / 2 real
// SH even in y, coefficient (l, m) at index l (l + 1) / 2 + m.
#ifndef ATM_SH_BANDS
#define ATM_SH_BANDS 4
#endif
#define ATM_SH_COEFFICIENTS ((ATM_SH_BANDS + 1) * (ATM_SH_BANDS + 2) / 2)
// N_lm = sqrt((2l + 1) / (4 pi) (l - m)! / (l + m)!), times sqrt(2) for m > 0, at l (l + 1) / 2 + m
// (l <= 6), to 8 decimals: float's precision for the large ones, only 4 digits of N_66 (3e-5). The
// basis reads N_lm through ATM_SH_N(k), this table unless the includer defines it: a constant
// that differs by precision, like ATM_SEGMENT_LINEAR (the C++ twin's is exact in double).
const real ATM_SH_NORM[28] = ARRAY_OF(real, 28) 0.28209479, 0.48860251, 0.48860251, 0.63078313, 0.36418281, 0.18209141,
    0.74635267, 0.30469720, 0.09635371, 0.03933624, 0.84628438, 0.26761862, 0.06307831, 0.01685839, 0.00596034,
    0.93560258, 0.24157155, 0.04565273, 0.00931882, 0.00219647, 0.00069458, 1.01710724, 0.22195100, 0.03509353,
    0.00584892, 0.00106786, 0.00022767, 0.00006572 END_ARRAY;
#ifndef ATM_SH_N
#define ATM_SH_N(k) ATM_SH_NORM[k]
#endif

// The basis at a unit vector (an array in a struct: both languages return it).
struct AtmShBasis {
    real y[ATM_SH_COEFFICIENTS];
};
// The real SH of bands l <= `bands` (<= ATM_SH_BANDS) that are even in y, at a unit vector given
// x and z: N_lm P_l^m(z) / sin^m * Re((x + i y)^m), the associated Legendre function (no
// Condon-Shortley phase) by its recurrence in l; Re((x + i y)^m) = sin^m cos(m phi) is even in y,
// so y's sign does not matter. C++: cpu::shBasis().
AtmShBasis atm_shBasis(real x, real z, int bands) {
    AtmShBasis o;
    real y = sqrt(max(0.0, 1.0 - x * x - z * z));
    real cm = 1.0, sm = 0.0, pmm = 1.0;  // Re and Im of (x + i y)^m; P_m^m / sin^m = (2m - 1)!!
    for (int mm = 0; mm <= bands; ++mm) {
        real a = pmm, b = 0.0;  // P_l^m / sin^m and P_(l-1)^m / sin^m
        for (int l = mm; l <= bands; ++l) {
            int k = l * (l + 1) / 2 + mm;
            o.y[k] = ATM_SH_N(k) * a * cm;
            real next = (real(2 * l + 1) * z * a - real(l + mm) * b) / real(l + 1 - mm);
            b = a;
            a = next;
        }
        pmm *= real(2 * mm + 1);
        real c = x * cm - y * sm;
        sm = x * sm + y * cm;
        cm = c;
    }
    return o;
}
// The Mie band factor of band l (cpu::PhaseMoments::mie) from the block's packing (AtmosphereBlock
// shFactors, shFactors2): f1 = (Mie l1, Mie l2, Rayleigh l2, delta-M fraction), f2 = Mie l3 .. l6;
// band 0 is 1 - the delta-M fraction.
real atm_shMieBand(int l, vec4 f1, vec4 f2) {
    if (l == 0) return 1.0 - f1.w;
    if (l == 1) return f1.x;
    if (l == 2) return f1.y;
    if (l == 3) return f2.x;
    if (l == 4) return f2.y;
    if (l == 5) return f2.z;
    return f2.w;
}

// The eclipse's multiple-scattering weight along a view ray (nu: the cosine of its angle to the
// Sun): the orders >= 2 take mix(f, f + D, w), w = 1 - F (1 - sin(angle)) (docs/eclipse.md). A
// ray near the shadow's axis gathers, through the forward peak of the aerosol's phase function,
// light scattered in the air along the axis, as dark as the point itself; through the rest of the
// scattering (Rayleigh's, the aerosol's broad part) and across the axis, the kernel's average.
// F = atm_eclForwardShare(): the delta-M forward fraction `forward` times the aerosol's share of
// the scattering at the ground (sM, sR: Mie and Rayleigh scattering coefficients there, one
// channel), over 0.16 (kEclipseForwardShare: that of Atmosphere::earthClear(), whose sky the
// weight sin(angle) fitted), clamped to 1. C++: eclipseMsAxisWeight().
real atm_eclForwardShare(real forward, real sM, real sR) { return min(1.0, forward * sM / max(sM + sR, 1e-30) / 0.16); }
real atm_eclMsAxisWeight(real nu, real F) { return 1.0 - F * (1.0 - sqrt(max(1.0 - nu * nu, 0.0))); }
// Hazy air (docs/eclipse.md, "Hazy air"): H = atm_eclHaze(sM) is 0 up to 1.1 x the aerosol's
// scattering at the ground of Atmosphere::earthClear() (7.5e-5 /m, green: kEclipseHazeClearMie)
// and 1 from 4 x it (aerosol optical depth 0.4, Atmosphere::earthHazy()).
// The weight at every Sun's elevation (docs/eclipse.md, "One model at three places", refitted on
// a ring of directions: "The ring of directions"). X = 1 / max(muS, 0.05), the air mass of the
// shadowed column along the axis towards the Sun and the umbra's elongation on the ground
// (Burgos 7, Reykjavik 2.4, Luxor 1.0):
// - G = 1 - exp(-23.6 (X - 1)) (kEclipseColumnRate): how much of the clear sky's light gathered
//   near the axis came along that column: 0.22 with the Sun 81.8 deg up (Luxor), >= 0.99 with
//   the Sun below 56 deg.
// - Towards the Sun (nu > 0) the shadow's dark footprint lies along the Sun's azimuth, X times as
//   long as wide: s is the lesser of sin(angle to the Sun) and the view's offset from that
//   footprint, sqrt(cosRing^2 + (0.47 mu X)^2) (kEclipseFootprintMu), raised to 0.85 (1 + 0.40 H)
//   (kEclipseSunwardPower, kEclipseHazeSunwardPower); the axis' share is max(F, H) G, and
//   w' = max(1 - max(F, H) G (1 - s), 0). Away from the Sun (the axis runs into the ground) w' = 1:
//   the refit on the ring put the share there at 0 (it was 0.54 F).
// - E = (X - 1)^2 / ((X - 1)^2 + 2.26^2) (kEclipseRingElongation): how much of the sunlit ring lies
//   across the axis rather than all around: the hazy ring's directional lobe is scaled by it.
// With haze the ring's gather R = 0.50 (kEclipseHazeRingShare) x mix(1, the mean of a
// Henyey-Greenstein lobe of asymmetry 0.4 (kEclipseHazeRingG) at the view's cosines +-cosRing
// with the two horizontal directions across the axis, x 4 pi, E); and every view takes the low
// views' gain (kEclipseLowView*). The weight is w' mix(1, R, H) x gain. The constants are fitted
// at once at Burgos, Reykjavik and Luxor (29 directions, totality and the partial phases, on
// Atmosphere::earthClear() and earthHazy(); docs/eclipse.md) with the kernel's length
// cpu::eclipseMsLength(). C++: cpu::eclipseMsWeight().
real atm_eclHaze(real sM) { return clamp((sM / 7.5e-5 - 1.1) / 2.9, 0.0, 1.0); }
real atm_eclHgLobe(real c, real g) {
    real d = max(1.0 + g * g - 2.0 * g * c, 1e-12);
    return (1.0 - g * g) / (d * sqrt(d));
}
real atm_eclMsWeight(real nu, real mu, real muS, real cosRing, real F, real H) {
    real X = 1.0 / max(muS, 0.05);
    real G = 1.0 - exp(-23.6 * (X - 1.0));
    real E = (X - 1.0) * (X - 1.0) / ((X - 1.0) * (X - 1.0) + 2.26 * 2.26);
    real w = 1.0;
    if (nu > 0.0) {
        real s = sqrt(max(1.0 - nu * nu, 0.0));
        real off = 0.47 * mu * X;
        s = min(s, sqrt(cosRing * cosRing + off * off));
        s = pow(max(s, 1e-6), 0.85 * (1.0 + 0.40 * H));
        w = max(1.0 - max(F, H) * G * (1.0 - s), 0.0);
    }
    real R = 0.50 * (1.0 + (0.5 * (atm_eclHgLobe(cosRing, 0.4) + atm_eclHgLobe(-cosRing, 0.4)) - 1.0) * E);
    // The low views' gain (docs/eclipse.md, "The ring of directions"): x = mu / 0.34, the gain
    // 1 + 0.88 (1 - 0.23 H) (x e^(1 - x))^2.1, 1.88 at 20 deg up on clear air.
    real x = max(mu, 0.0) / 0.34;
    real low = 1.0 + 0.88 * (1.0 - 0.23 * H) * pow(x * exp(1.0 - x), 2.1);
    return w * mix(1.0, R, H) * low;
}
// cosRing for a view of cosines mu (to the zenith) and nu (to the Sun), the Sun's muS.
real atm_eclCosRing(real mu, real muS, real nu) {
    real sinMu = sqrt(max(1.0 - mu * mu, 0.0)), sinMuS = sqrt(max(1.0 - muS * muS, 0.0));
    real cosAz = sinMu * sinMuS > 1e-9 ? clamp((nu - mu * muS) / (sinMu * sinMuS), -1.0, 1.0) : 1.0;
    return sinMu * sqrt(max(1.0 - cosAz * cosAz, 0.0));
}
