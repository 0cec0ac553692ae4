// The reference integrator for a solar eclipse (see eclipse_reference.hpp for the method).
#include <welkin/error.hpp>
#include <welkin/generators/eclipse_reference.hpp>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>

namespace welkin::atmosphere {

using namespace welkin::generators;

namespace {
constexpr double kPi = std::numbers::pi;

void check(const char* member, int v, int lo, int hi) {
    if (v < lo || v > hi)
        throw Error(std::string("EclipseReferenceOptions: ") + member + " " + std::to_string(v) + " not in [" + std::to_string(lo) + ", " +
                    std::to_string(hi) + "]");
}

// Distance from p along unit w to the top of the atmosphere (or the ground, `ground` set);
// c the planet's centre.
double exitDistance(const SkyModel& m, const glm::dvec3& p, const glm::dvec3& w, const glm::dvec3& c, bool& ground) {
    const glm::dvec3 o = p - c;
    const double b = glm::dot(o, w), oo = glm::dot(o, o);
    const double discG = b * b - (oo - m.bottomRadius * m.bottomRadius);
    ground = false;
    if (discG >= 0.0) {
        const double t = -b - std::sqrt(discG);
        if (t > 0.0) {
            ground = true;
            return t;
        }
    }
    const double discT = b * b - (oo - m.topRadius * m.topRadius);
    return discT > 0.0 ? std::max(-b + std::sqrt(discT), 0.0) : 0.0;
}
}  // namespace

void EclipseReferenceOptions::validate() const {
    check("viewSteps", viewSteps, 8, 4096);
    check("gatherZenith", gatherZenith, 2, 256);
    check("gatherAzimuth", gatherAzimuth, 3, 512);
    check("gatherSteps", gatherSteps, 8, 4096);
    check("rings", rings, 8, 4096);
}

EclipseReferenceRadiance eclipseReferenceRadiance(const SkyModel& m, const Lut2D& T, const cpu::MsField& MS, double h,
                                                  const glm::dvec3& view, const glm::dvec3& sun, const cpu::EclipseGeometry& g,
                                                  const EclipseReferenceOptions& o) {
    o.validate();
    if (view.z < 0.0) throw Error("eclipseReferenceRadiance: view must point above the horizon (mu >= 0)");
    const double Ht = m.topRadius - m.bottomRadius;
    h = std::clamp(h, 0.0, Ht);
    const glm::dvec3 c(0.0, 0.0, -(m.bottomRadius + h));  // the planet's centre, observer at the origin
    const cpu::PhaseMoments moments = cpu::phaseMoments(m, MS.bands);
    auto vis = [&](const glm::dvec3& p) { return o.eclipse ? cpu::eclipseAt(g, p, o.rings).x : 1.0; };
    auto heightOf = [&](const glm::dvec3& p) { return glm::length(p - c) - m.bottomRadius; };
    auto sunT = [&](const glm::dvec3& p, double hp) {
        const double muS = std::clamp(glm::dot(glm::normalize(p - c), sun), -1.0, 1.0);
        return cpu::transmittanceToLight(m, T, std::max(hp, 0.0), muS, m.sunAngularRadius);
    };
    auto phases = [&](double cosTheta) {
        return std::pair{rayleighPhase(cosTheta), miePhase(cosTheta, m.mieG, m.miePhase)};
    };
    EclipseReferenceRadiance out;
    bool groundV = false;
    const double d = exitDistance(m, glm::dvec3(0.0), view, c, groundV);
    const auto [pR0, pM0] = phases(glm::dot(view, sun));
    glm::dvec3 thr(1.0);
    const int nDir = o.gatherZenith * o.gatherAzimuth;
    const double dOmega = 4.0 * kPi / nDir;
    for (int k = 0; k < o.viewSteps; ++k) {
        const double dt = d / o.viewSteps, t = (k + 0.5) * dt;
        const glm::dvec3 p = t * view;
        const double hp = heightOf(p);
        const glm::dvec3 sR = m.scatteringRayleigh(hp), sM = m.scatteringMie(hp), sigmaT = m.extinction(hp);
        const glm::dvec3 seg = (glm::dvec3(1.0) - glm::exp(-sigmaT * dt)) / glm::max(sigmaT, glm::dvec3(1e-30));
        // Order 1.
        const glm::dvec3 single = (sR * pR0 + sM * pM0) * sunT(p, hp) * vis(p);
        // The gather at p: order-1 radiance from every direction, eclipsed and clear.
        glm::dvec3 J2(0.0), J2clear(0.0), fluence(0.0), fluenceClear(0.0);
        for (int i = 0; i < o.gatherZenith; ++i) {
            const double wz = -1.0 + 2.0 * (i + 0.5) / o.gatherZenith, sz = std::sqrt(std::max(1.0 - wz * wz, 0.0));
            for (int j = 0; j < o.gatherAzimuth; ++j) {
                const double a = 2.0 * kPi * (j + 0.5) / o.gatherAzimuth;
                const glm::dvec3 w(sz * std::cos(a), sz * std::sin(a), wz);
                bool ground = false;
                const double dg = exitDistance(m, p, w, c, ground);
                const auto [pR, pM] = phases(glm::dot(w, sun));  // light from the Sun turned into -w
                glm::dvec3 L(0.0), Lc(0.0), tg(1.0);
                const double ds = dg / o.gatherSteps;
                for (int s = 0; s < o.gatherSteps && dg > 0.0; ++s) {
                    const glm::dvec3 q = p + (s + 0.5) * ds * w;
                    const double hq = heightOf(q);
                    const glm::dvec3 sT = m.extinction(hq);
                    const glm::dvec3 segq = (glm::dvec3(1.0) - glm::exp(-sT * ds)) / glm::max(sT, glm::dvec3(1e-30));
                    const glm::dvec3 src = (m.scatteringRayleigh(hq) * pR + m.scatteringMie(hq) * pM) * sunT(q, hq) * segq * tg;
                    L += src * vis(q);
                    Lc += src;
                    tg *= glm::exp(-sT * ds);
                }
                if (ground) {
                    const glm::dvec3 q = p + dg * w;
                    const double muSg = std::clamp(glm::dot(glm::normalize(q - c), sun), -1.0, 1.0);
                    const glm::dvec3 e = tg * cpu::transmittanceToLight(m, T, 0.0, muSg, m.sunAngularRadius) * std::max(muSg, 0.0) *
                                         m.groundAlbedo / kPi;
                    L += e * vis(q);
                    Lc += e;
                }
                const auto [vR, vM] = phases(glm::dot(w, view));  // arriving along -w, scattered into -view
                J2 += (sR * vR + sM * vM) * L * dOmega;
                J2clear += (sR * vR + sM * vM) * Lc * dOmega;
                fluence += L;
                fluenceClear += Lc;
            }
        }
        const glm::dvec3 rho = fluence / glm::max(fluenceClear, glm::dvec3(1e-300));
        const glm::dvec3 up = glm::normalize(p - c);
        const double muP = std::clamp(glm::dot(up, view), -1.0, 1.0), muSp = std::clamp(glm::dot(up, sun), -1.0, 1.0);
        const glm::dvec3 msClear = cpu::msInscatter(m, MS, moments, hp, muP, muSp, glm::dot(view, sun), sR, sM);
        const glm::dvec3 second = o.eclipse ? J2 : J2clear;
        const glm::dvec3 higher = glm::max(msClear - J2clear, glm::dvec3(0.0)) * (o.eclipse ? rho : glm::dvec3(1.0));
        out.single += thr * single * seg;
        out.multiple += thr * (second + higher) * seg;
        out.second += thr * second * seg;
        out.higher += thr * higher * seg;
        thr *= glm::exp(-sigmaT * dt);
    }
    out.radiance = out.single + out.multiple;
    return out;
}

}  // namespace welkin::atmosphere
