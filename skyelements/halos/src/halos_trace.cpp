// The crystal ray tracer of the Halos element (contract in welkin/elements/halos.hpp).
#include <welkin/cache.hpp>
#include <welkin/elements/halos.hpp>
#include <welkin/error.hpp>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <mutex>
#include <thread>
#include <unistd.h>

namespace welkin::elements::halos {

// --- Closed forms ----------------------------------------------------------------------------------

double iceRefractiveIndex(double nm) {
    // Cauchy fit through (656.3 nm, 1.3072) and (486.1 nm, 1.3136): B = 0.0064 / (1/0.4861^2 -
    // 1/0.6563^2) um^2, A = 1.3072 - B / 0.6563^2.
    const double l2a = 1.0 / (0.6563 * 0.6563), l2b = 1.0 / (0.4861 * 0.4861);
    const double B = (1.3136 - 1.3072) / (l2b - l2a);
    const double A = 1.3072 - B * l2a;
    const double um = nm * 1e-3;
    return A + B / (um * um);
}

double minimumDeviationRad(double n, double apexRad) { return 2.0 * std::asin(std::min(1.0, n * std::sin(0.5 * apexRad))) - apexRad; }

double bravaisIndex(double n, double e) { return std::sqrt(n * n - std::sin(e) * std::sin(e)) / std::cos(e); }

double parhelionAzimuthRad(double n, double h) {
    const double np = bravaisIndex(n, h);
    const double s = np * std::sin(M_PI / 6.0);
    if (s >= 1.0) return std::nan("");
    return 2.0 * std::asin(s) - M_PI / 3.0;
}

double parhelionDistanceRad(double n, double h) {
    const double az = parhelionAzimuthRad(n, h);
    const double c = std::sin(h) * std::sin(h) + std::cos(h) * std::cos(h) * std::cos(az);
    return std::acos(std::clamp(c, -1.0, 1.0));
}

double circumzenithalElevationRad(double n, double h) {
    const double s2 = n * n - std::cos(h) * std::cos(h);
    if (s2 >= 1.0) return std::nan("");
    return std::asin(std::sqrt(std::max(s2, 0.0)));
}

double circumzenithalCutoffRad(double n) { return std::acos(std::sqrt(n * n - 1.0)); }

// --- The crystal ---------------------------------------------------------------------------------

namespace {

// splitmix64: a small deterministic generator, one stream per chunk of rays.
struct Rng {
    uint64_t s;
    uint64_t next() {
        uint64_t z = (s += 0x9e3779b97f4a7c15ull);
        z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
        z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
        return z ^ (z >> 31);
    }
    double uniform() { return double(next() >> 11) * 0x1.0p-53; }  // [0, 1)
    double gauss() {
        const double u1 = std::max(uniform(), 1e-300), u2 = uniform();
        return std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * M_PI * u2);
    }
};

// A hexagonal prism of side a = 1 centred on the origin, c-axis z: faces 0-5 the sides (outward
// normals at k x 60 deg, distance sqrt(3)/2), 6 the top, 7 the bottom (distance = half length).
struct Prism {
    glm::dvec3 n[8];
    double d[8];
    double area[8];
    double halfLen;
    explicit Prism(double aspect) {
        halfLen = aspect;  // length 2a x aspect with a = 1
        for (int k = 0; k < 6; ++k) {
            const double t = k * M_PI / 3.0;
            n[k] = {std::cos(t), std::sin(t), 0.0};
            d[k] = std::sqrt(3.0) / 2.0;
            area[k] = 2.0 * halfLen;  // side 1 x length 2 halfLen
        }
        n[6] = {0, 0, 1};
        n[7] = {0, 0, -1};
        d[6] = d[7] = halfLen;
        area[6] = area[7] = 1.5 * std::sqrt(3.0);
    }
    // Projected area seen along propagation direction dir (crystal frame).
    double projected(const glm::dvec3& dir) const {
        double s = 0;
        for (int f = 0; f < 8; ++f) s += area[f] * std::max(0.0, -glm::dot(n[f], dir));
        return s;
    }
    // A uniform point on face f.
    glm::dvec3 pointOn(int f, Rng& r) const {
        if (f < 6) {
            const glm::dvec3 t(-n[f].y, n[f].x, 0.0);
            return n[f] * d[f] + t * (r.uniform() - 0.5) + glm::dvec3(0, 0, (2.0 * r.uniform() - 1.0) * halfLen);
        }
        const int k = std::min(int(r.uniform() * 6.0), 5);
        const double a0 = k * M_PI / 3.0 + M_PI / 6.0, a1 = a0 + M_PI / 3.0;  // vertices between the side normals
        // The hexagon's vertices lie at distance 1 (side a = 1) at 30 + k 60 deg.
        const glm::dvec2 v0(std::cos(a0), std::sin(a0)), v1(std::cos(a1), std::sin(a1));
        double u = r.uniform(), v = r.uniform();
        if (u + v > 1.0) {
            u = 1.0 - u;
            v = 1.0 - v;
        }
        const glm::dvec2 q = v0 * u + v1 * v;
        return {q.x, q.y, f == 6 ? halfLen : -halfLen};
    }
    // Distance to the face the ray leaves by (from inside), and that face.
    double exit(const glm::dvec3& p, const glm::dvec3& dir, int& face) const {
        double best = 1e300;
        face = -1;
        for (int f = 0; f < 8; ++f) {
            const double dn = glm::dot(dir, n[f]);
            if (dn <= 1e-12) continue;
            const double t = (d[f] - glm::dot(p, n[f])) / dn;
            if (t < best) {
                best = t;
                face = f;
            }
        }
        return std::max(best, 0.0);
    }
};

// Unpolarised Fresnel reflectance for cosine of incidence cosi > 0 and eta = n1 / n2 (1 on total
// internal reflection); cost gets the cosine of the refracted ray.
double fresnel(double cosi, double eta, double& cost) {
    const double s2 = eta * eta * std::max(0.0, 1.0 - cosi * cosi);
    if (s2 >= 1.0) {
        cost = 0;
        return 1.0;
    }
    cost = std::sqrt(1.0 - s2);
    const double rs = (eta * cosi - cost) / (eta * cosi + cost);
    const double rp = (cosi - eta * cost) / (cosi + eta * cost);
    return 0.5 * (rs * rs + rp * rp);
}
// Refraction of dir through a face of normal m pointing against dir (dot(dir, m) = -cosi).
glm::dvec3 refract(const glm::dvec3& dir, const glm::dvec3& m, double eta, double cosi, double cost) {
    return glm::normalize(eta * dir + (eta * cosi - cost) * m);
}

// An orthonormal frame with z = c and x perpendicular, then turned by psi about c.
glm::dmat3 frameAbout(const glm::dvec3& c, const glm::dvec3& xHint, double psi) {
    glm::dvec3 x = xHint - glm::dot(xHint, c) * c;
    if (glm::length(x) < 1e-9) x = std::abs(c.x) < 0.9 ? glm::dvec3(1, 0, 0) - c.x * c : glm::dvec3(0, 1, 0) - c.y * c;
    x = glm::normalize(x);
    const glm::dvec3 y = glm::cross(c, x);
    const glm::dvec3 xr = std::cos(psi) * x + std::sin(psi) * y;
    return glm::dmat3(xr, glm::cross(c, xr), c);  // columns: the crystal's axes in the world
}

// A crystal orientation: the crystal-to-world rotation.
glm::dmat3 sampleOrientation(const Population& pop, Rng& r) {
    const double s = pop.tiltRad;
    switch (pop.orientation) {
    case Orientation::Random: {
        // Shoemake's uniform random unit quaternion.
        const double u1 = r.uniform(), u2 = 2 * M_PI * r.uniform(), u3 = 2 * M_PI * r.uniform();
        const double a = std::sqrt(1 - u1), b = std::sqrt(u1);
        const double qx = a * std::sin(u2), qy = a * std::cos(u2), qz = b * std::sin(u3), qw = b * std::cos(u3);
        return glm::dmat3(1 - 2 * (qy * qy + qz * qz), 2 * (qx * qy + qz * qw), 2 * (qx * qz - qy * qw),
                          2 * (qx * qy - qz * qw), 1 - 2 * (qx * qx + qz * qz), 2 * (qy * qz + qx * qw),
                          2 * (qx * qz + qy * qw), 2 * (qy * qz - qx * qw), 1 - 2 * (qx * qx + qy * qy));
    }
    case Orientation::Plate: {
        const glm::dvec3 c = glm::normalize(glm::dvec3(s * r.gauss(), s * r.gauss(), 1.0));
        return frameAbout(c, glm::dvec3(1, 0, 0), 2 * M_PI * r.uniform());
    }
    case Orientation::Column: {
        const double az = 2 * M_PI * r.uniform(), el = s * r.gauss();
        const glm::dvec3 c(std::cos(el) * std::cos(az), std::cos(el) * std::sin(az), std::sin(el));
        return frameAbout(c, glm::dvec3(0, 0, 1), 2 * M_PI * r.uniform());
    }
    case Orientation::Parry: {
        const double az = 2 * M_PI * r.uniform(), el = s * r.gauss();
        const glm::dvec3 c(std::cos(el) * std::cos(az), std::cos(el) * std::sin(az), std::sin(el));
        // Side face 0's normal (the crystal x axis) vertical, up or down (the same prism), +- spread.
        return frameAbout(c, glm::dvec3(0, 0, 1), s * r.gauss() + (r.uniform() < 0.5 ? 0.0 : M_PI));
    }
    }
    return glm::dmat3(1.0);
}

// The light's propagation direction for the light at elevation h, azimuth 0 (+x), a uniform
// point of the Sun's disk (radius 0.2666 deg).
glm::dvec3 sampleIncoming(double h, Rng& r) {
    const double rad = 0.2666 * M_PI / 180.0 * std::sqrt(r.uniform()), ang = 2 * M_PI * r.uniform();
    const glm::dvec3 S(std::cos(h), 0.0, std::sin(h));
    const glm::dvec3 e1 = glm::normalize(glm::cross(glm::dvec3(0, 0, 1), S) + glm::dvec3(0, 1e-12, 0));
    const glm::dvec3 e2 = glm::cross(S, e1);
    return -glm::normalize(S + rad * (std::cos(ang) * e1 + std::sin(ang) * e2));
}

// One ray through the crystal, a random branch at every face: the exit direction (crystal
// frame). `events` counts internal events; truncated rays leave as they head.
glm::dvec3 traceRay(const Prism& P, glm::dvec3 dir, double n, Rng& r, bool& truncated) {
    truncated = false;
    // Entry face by projected area.
    double w[8], sum = 0;
    for (int f = 0; f < 8; ++f) sum += (w[f] = P.area[f] * std::max(0.0, -glm::dot(P.n[f], dir)));
    double u = r.uniform() * sum;
    int f = 0;
    for (; f < 7; ++f) {
        if (u < w[f]) break;
        u -= w[f];
    }
    glm::dvec3 p = P.pointOn(f, r);
    double cosi = -glm::dot(dir, P.n[f]), cost;
    const double R0 = fresnel(cosi, 1.0 / n, cost);
    if (r.uniform() < R0) return dir + 2.0 * cosi * P.n[f];  // external reflection
    dir = refract(dir, P.n[f], 1.0 / n, cosi, cost);
    for (int e = 0; e < kMaxEvents; ++e) {
        int g;
        p += dir * P.exit(p, dir, g);
        if (g < 0) break;
        cosi = glm::dot(dir, P.n[g]);
        const double R = fresnel(cosi, n, cost);
        if (R >= 1.0 || r.uniform() < R) {
            dir = glm::normalize(dir - 2.0 * cosi * P.n[g]);
            continue;
        }
        return refract(dir, -P.n[g], n, cosi, cost);
    }
    truncated = true;
    return dir;
}

// The exhaustive version: every branch with its weight, to `depth` events or weight 1e-6.
template <class Deposit>
void traceBranches(const Prism& P, glm::dvec3 p, glm::dvec3 dir, double n, double weight, int depth, Deposit&& deposit) {
    for (; depth < kMaxEvents; ++depth) {
        int g;
        p += dir * P.exit(p, dir, g);
        if (g < 0) break;
        double cost;
        const double cosi = glm::dot(dir, P.n[g]);
        const double R = fresnel(cosi, n, cost);
        if (R < 1.0) deposit(refract(dir, -P.n[g], n, cosi, cost), weight * (1.0 - R));
        weight *= R;
        dir = glm::normalize(dir - 2.0 * cosi * P.n[g]);
        if (weight < 1e-6) break;
    }
    deposit(dir, weight);  // what is left: where it heads
}

constexpr uint64_t kChunk = 16383;  // a multiple of 3: whole crystals per chunk
constexpr double kFixed = 4294967296.0;  // 2^32: integer accumulation, the same sums in any order

// Runs `rays` rays in chunks over threads; body(rng, chunkBegin, chunkEnd, acc, truncated) adds
// fixed-point weights to its thread's accumulator of size `cells`; returns the summed weights.
template <class Body>
std::vector<uint64_t> runChunks(uint64_t rays, uint64_t seed, std::size_t cells, int threads, uint64_t& truncated, Body body) {
    const uint64_t chunks = (rays + kChunk - 1) / kChunk;
    const int T = threads > 0 ? threads : std::max(1, int(std::thread::hardware_concurrency()));
    std::vector<std::vector<uint64_t>> acc(std::size_t(T), std::vector<uint64_t>(cells, 0));
    std::vector<uint64_t> trunc(std::size_t(T), 0);
    std::atomic<uint64_t> nextChunk{0};
    auto worker = [&](int t) {
        for (;;) {
            const uint64_t c = nextChunk++;
            if (c >= chunks) return;
            Rng r{seed * 0x9e3779b97f4a7c15ull + c * 0xd1b54a32d192ed03ull + 1};
            body(r, c * kChunk, std::min(rays, (c + 1) * kChunk), acc[std::size_t(t)], trunc[std::size_t(t)]);
        }
    };
    std::vector<std::thread> pool;
    for (int t = 1; t < T; ++t) pool.emplace_back(worker, t);
    worker(0);
    for (auto& th : pool) th.join();
    for (int t = 1; t < T; ++t)
        for (std::size_t i = 0; i < cells; ++i) acc[0][i] += acc[std::size_t(t)][i];
    truncated = 0;
    for (auto x : trunc) truncated += x;
    return std::move(acc[0]);
}

double seconds(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// Bin of a sky direction v (the light at azimuth 0) in the 2-D table.
std::size_t bin2D(const glm::dvec3& v, int ne, int na) {
    const double e = std::asin(std::clamp(v.z, -1.0, 1.0));
    const double a = std::atan2(std::abs(v.y), v.x);
    const int ie = std::clamp(int((e + 0.5 * M_PI) / M_PI * ne), 0, ne - 1);
    const int ia = std::clamp(int(a / M_PI * na), 0, na - 1);
    return std::size_t(ie) * std::size_t(na) + std::size_t(ia);
}

// Weights per bin and channel -> 1/sr (each channel normalised to its own total).
Phase2D normalise2D(const std::vector<uint64_t>& acc, int ne, int na) {
    Phase2D out;
    out.ne = ne;
    out.na = na;
    out.p.assign(std::size_t(ne) * std::size_t(na), glm::dvec3(0.0));
    glm::dvec3 total(0.0);
    for (std::size_t i = 0; i < out.p.size(); ++i)
        for (int c = 0; c < 3; ++c) total[c] += double(acc[i * 3 + std::size_t(c)]);
    for (int ie = 0; ie < ne; ++ie) {
        const double e0 = -0.5 * M_PI + ie * M_PI / ne, e1 = e0 + M_PI / ne;
        const double omega = 2.0 * (M_PI / na) * (std::sin(e1) - std::sin(e0));  // both sides of the light's vertical
        for (int ia = 0; ia < na; ++ia) {
            const std::size_t i = std::size_t(ie) * std::size_t(na) + std::size_t(ia);
            for (int c = 0; c < 3; ++c)
                out.p[i][c] = total[c] > 0 ? double(acc[i * 3 + std::size_t(c)]) / total[c] / omega : 0.0;
        }
    }
    return out;
}

}  // namespace

glm::dvec3 Phase1D::at(double theta) const {
    const int B = int(p.size());
    const double f = theta / binRad() - 0.5;
    const int i0 = std::clamp(int(std::floor(f)), 0, B - 1), i1 = std::min(i0 + 1, B - 1);
    const double t = std::clamp(f - std::floor(f), 0.0, 1.0);
    if (f < 0) return p[0];
    return p[std::size_t(i0)] * (1 - t) + p[std::size_t(i1)] * t;
}

glm::dvec3 Phase1D::integral() const {
    glm::dvec3 s(0.0);
    const double db = binRad();
    for (std::size_t i = 0; i < p.size(); ++i) s += p[i] * (2.0 * M_PI * (std::cos(i * db) - std::cos((i + 1) * db)));
    return s;
}

glm::dvec3 Phase2D::integral() const {
    glm::dvec3 s(0.0);
    for (int ie = 0; ie < ne; ++ie) {
        const double e0 = -0.5 * M_PI + ie * M_PI / ne, e1 = e0 + M_PI / ne;
        const double omega = 2.0 * (M_PI / na) * (std::sin(e1) - std::sin(e0));
        for (int ia = 0; ia < na; ++ia) s += at(ie, ia) * omega;
    }
    return s;
}

Phase1D traceRandom(const Population& pop, int bins, uint64_t rays, uint64_t seed, int threads) {
    if (bins < 1 || rays < 3) throw Error("halos: traceRandom needs bins >= 1 and rays >= 3");
    const auto t0 = std::chrono::steady_clock::now();
    const Prism P(pop.aspect);
    const double nIce[3] = {iceRefractiveIndex(kChannelNm[0]), iceRefractiveIndex(kChannelNm[1]), iceRefractiveIndex(kChannelNm[2])};
    const std::size_t B = std::size_t(bins);
    uint64_t truncated = 0;
    auto acc = runChunks(rays, seed, B * 3, threads, truncated, [&](Rng& r, uint64_t b, uint64_t e, std::vector<uint64_t>& a, uint64_t& tr) {
        for (uint64_t i = b; i < e; i += 3) {
            // One crystal, entry point and sequence of branch choices for the three channels
            // (the same random numbers: their noise is correlated, no colour speckle).
            const glm::dmat3 R = sampleOrientation(pop, r);
            const glm::dvec3 S(1, 0, 0);  // the light along +x (any direction: random crystals)
            const glm::dvec3 dIn = glm::transpose(R) * sampleIncoming(0.0, r);
            const double weight = P.projected(dIn);
            const Rng branch{r.next()};
            for (int c = 0; c < 3; ++c) {
                Rng rc = branch;
                bool t;
                const glm::dvec3 out = R * traceRay(P, dIn, nIce[c], rc, t);
                tr += t;
                const double theta = std::acos(std::clamp(glm::dot(S, -out), -1.0, 1.0));
                const std::size_t k = std::min(B - 1, std::size_t(theta / M_PI * double(B)));
                a[k * 3 + std::size_t(c)] += uint64_t(weight * kFixed);
            }
        }
    });
    Phase1D out;
    out.p.assign(B, glm::dvec3(0.0));
    glm::dvec3 total(0.0);
    for (std::size_t k = 0; k < B; ++k)
        for (int c = 0; c < 3; ++c) total[c] += double(acc[k * 3 + std::size_t(c)]);
    const double db = M_PI / double(B);
    for (std::size_t k = 0; k < B; ++k) {
        const double omega = 2.0 * M_PI * (std::cos(double(k) * db) - std::cos(double(k + 1) * db));
        for (int c = 0; c < 3; ++c) out.p[k][c] = total[c] > 0 ? double(acc[k * 3 + std::size_t(c)]) / total[c] / omega : 0.0;
    }
    out.stats = {rays, truncated, seconds(t0)};
    return out;
}

Phase2D traceOriented(const Population& pop, double h, int ne, int na, uint64_t rays, uint64_t seed, int threads) {
    if (ne < 1 || na < 1 || rays < 3) throw Error("halos: traceOriented needs ne, na >= 1 and rays >= 3");
    const auto t0 = std::chrono::steady_clock::now();
    const Prism P(pop.aspect);
    const double nIce[3] = {iceRefractiveIndex(kChannelNm[0]), iceRefractiveIndex(kChannelNm[1]), iceRefractiveIndex(kChannelNm[2])};
    uint64_t truncated = 0;
    auto acc = runChunks(rays, seed, std::size_t(ne) * std::size_t(na) * 3, threads, truncated,
                         [&](Rng& r, uint64_t b, uint64_t e, std::vector<uint64_t>& a, uint64_t& tr) {
                             for (uint64_t i = b; i < e; i += 3) {
                                 const glm::dmat3 R = sampleOrientation(pop, r);
                                 const glm::dvec3 dIn = glm::transpose(R) * sampleIncoming(h, r);
                                 const double weight = P.projected(dIn);
                                 const Rng branch{r.next()};  // the same choices for the three channels
                                 for (int c = 0; c < 3; ++c) {
                                     Rng rc = branch;
                                     bool t;
                                     const glm::dvec3 out = R * traceRay(P, dIn, nIce[c], rc, t);
                                     tr += t;
                                     a[bin2D(-out, ne, na) * 3 + std::size_t(c)] += uint64_t(weight * kFixed);
                                 }
                             }
                         });
    Phase2D out = normalise2D(acc, ne, na);
    out.stats = {rays, truncated, seconds(t0)};
    return out;
}

Phase2D traceOrientedExact(const Population& pop, double h, int ne, int na, uint64_t rays, uint64_t seed, int threads) {
    const auto t0 = std::chrono::steady_clock::now();
    const Prism P(pop.aspect);
    const double nIce[3] = {iceRefractiveIndex(kChannelNm[0]), iceRefractiveIndex(kChannelNm[1]), iceRefractiveIndex(kChannelNm[2])};
    uint64_t truncated = 0;
    const std::size_t cells = std::size_t(ne) * std::size_t(na) * 3;
    auto acc = runChunks(rays, seed, cells + 1, threads, truncated,
                         [&](Rng& r, uint64_t b, uint64_t e, std::vector<uint64_t>& a, uint64_t&) {
                             for (uint64_t i = b; i < e; ++i) {
                                 const int c = int(i % 3);
                                 const glm::dmat3 R = sampleOrientation(pop, r);
                                 glm::dvec3 dIn = glm::transpose(R) * sampleIncoming(h, r);
                                 const double weight = P.projected(dIn);
                                 a[cells] += uint64_t(weight * kFixed);  // what enters
                                 // Entry face by projected area, as traceRay().
                                 double w[8], sum = 0;
                                 for (int f = 0; f < 8; ++f) sum += (w[f] = P.area[f] * std::max(0.0, -glm::dot(P.n[f], dIn)));
                                 double u = r.uniform() * sum;
                                 int f = 0;
                                 for (; f < 7; ++f) {
                                     if (u < w[f]) break;
                                     u -= w[f];
                                 }
                                 const glm::dvec3 p = P.pointOn(f, r);
                                 auto deposit = [&](const glm::dvec3& d, double wt) {
                                     a[bin2D(-(R * d), ne, na) * 3 + std::size_t(c)] += uint64_t(weight * wt * kFixed);
                                 };
                                 double cost;
                                 const double cosi = -glm::dot(dIn, P.n[f]);
                                 const double R0 = fresnel(cosi, 1.0 / nIce[c], cost);
                                 deposit(dIn + 2.0 * cosi * P.n[f], R0);
                                 traceBranches(P, p, refract(dIn, P.n[f], 1.0 / nIce[c], cosi, cost), nIce[c], 1.0 - R0, 0, deposit);
                             }
                         });
    double left = 0;
    for (std::size_t i = 0; i < cells; ++i) left += double(acc[i]);
    const double entered = double(acc[cells]);
    acc.pop_back();
    Phase2D out = normalise2D(acc, ne, na);
    out.stats = {rays, truncated, seconds(t0), entered > 0 ? left / entered : 0.0};
    return out;
}

// --- Denoising ------------------------------------------------------------------------------------

namespace {

// Intersection-of-confidence-intervals windows over a grid of rows x cols bins (cols 1: 1-D),
// omega(row) each bin's solid angle (sr), crystals = rays / 3 (each crystal's ray is deposited
// once per channel). Windows are mirrored at the grid's edges (the tables are symmetric about the
// light's vertical at azimuths 0 and pi; at the poles and at 0 and pi scattering angle the bins'
// solid angle vanishes, so what the mirror adds there weighs little).
void denoiseGrid(std::vector<glm::dvec3>& v, int rows, int cols, const std::vector<double>& omega, double crystals) {
    constexpr double G = Denoise::kGamma, K = Denoise::kTargetRays;
    if (crystals <= 0 || rows < 1 || cols < 1) return;
    auto mirror = [](int i, int n) {
        if (n == 1) return 0;
        for (;;) {
            if (i < 0) i = -i - 1;
            else if (i >= n) i = 2 * n - 1 - i;
            else return i;
        }
    };
    glm::dvec3 before(0.0);
    for (int i = 0; i < rows; ++i)
        for (int j = 0; j < cols; ++j) before += v[std::size_t(i) * std::size_t(cols) + std::size_t(j)] * omega[std::size_t(i)];
    const std::vector<glm::dvec3> in = v;
    // Windows: the square (Chebyshev radius r <= kMaxRadius) and lines of 2r + 1 bins, r <=
    // kMaxLine, along the rows (azimuth), the columns (elevation) and the two diagonals: the
    // halos' arcs are ridges a bin or two wide, which a line along them averages and a square
    // cannot. 1-D: the line alone. Each window's estimate is weighted by its inverse variance.
    struct Dir {
        int di, dj;  // (0, 0): the square
        int R;
    };
    std::vector<Dir> dirs;
    if (cols > 1) dirs = {{0, 0, Denoise::kMaxRadius}, {0, 1, Denoise::kMaxLine}, {1, 0, Denoise::kMaxLine}, {1, 1, Denoise::kMaxLine}, {1, -1, Denoise::kMaxLine}};
    else dirs = {{1, 0, 2 * Denoise::kMaxLine}};
    for (int i = 0; i < rows; ++i) {
        for (int j = 0; j < cols; ++j) {
            glm::dvec3 fused(0.0);
            double fusedW = 0;
            for (const Dir& d : dirs) {
                glm::dvec3 s(0.0), lo(-1e300), hi(1e300), best(0.0);
                double o = 0, bestVar = 0;
                for (int r = 0; r <= d.R; ++r) {
                    auto add = [&](int di, int dj) {
                        const int a = mirror(i + di, rows), b = mirror(j + dj, cols);
                        const double w = omega[std::size_t(a)];
                        s += in[std::size_t(a) * std::size_t(cols) + std::size_t(b)] * w;
                        o += w;
                    };
                    if (r == 0) add(0, 0);
                    else if (d.di == 0 && d.dj == 0) {
                        for (int di = -r; di <= r; ++di)
                            for (int dj = -r; dj <= r; ++dj)
                                if (std::max(std::abs(di), std::abs(dj)) == r) add(di, dj);
                    } else {
                        add(r * d.di, r * d.dj);
                        add(-r * d.di, -r * d.dj);
                    }
                    if (o <= 0) {
                        bestVar = 0;
                        continue;
                    }
                    const glm::dvec3 m = s / o;
                    bool ok = true;
                    double nMin = 1e300;
                    for (int c = 0; c < 3; ++c) {
                        const double n = s[c] * crystals;  // rays in the window
                        nMin = std::min(nMin, n);
                        const double sigma = std::sqrt(std::max(n, 1.0)) / (crystals * o);
                        lo[c] = std::max(lo[c], m[c] - G * sigma);
                        hi[c] = std::min(hi[c], m[c] + G * sigma);
                        ok = ok && lo[c] <= hi[c];
                    }
                    if (!ok) break;
                    best = m;
                    bestVar = std::max(s[1] * crystals, 1.0) / ((crystals * o) * (crystals * o));
                    if (nMin >= K) break;
                }
                if (bestVar > 0) {
                    fused += best / bestVar;
                    fusedW += 1.0 / bestVar;
                }
            }
            if (fusedW > 0) v[std::size_t(i) * std::size_t(cols) + std::size_t(j)] = fused / fusedW;
        }
    }
    glm::dvec3 after(0.0);
    for (int i = 0; i < rows; ++i)
        for (int j = 0; j < cols; ++j) after += v[std::size_t(i) * std::size_t(cols) + std::size_t(j)] * omega[std::size_t(i)];
    for (auto& x : v)
        for (int c = 0; c < 3; ++c) x[c] *= after[c] > 0 ? before[c] / after[c] : 1.0;
}

}  // namespace

void denoise(Phase2D& t, uint64_t rays) {
    if (rays < 3) throw Error("halos: denoise needs rays >= 3");
    std::vector<double> omega(std::size_t(t.ne));
    for (int ie = 0; ie < t.ne; ++ie) {
        const double e0 = -0.5 * M_PI + ie * M_PI / t.ne, e1 = e0 + M_PI / t.ne;
        omega[std::size_t(ie)] = 2.0 * (M_PI / t.na) * (std::sin(e1) - std::sin(e0));
    }
    denoiseGrid(t.p, t.ne, t.na, omega, double(rays / 3));
}

void denoise(Phase1D& t, uint64_t rays) {
    if (rays < 3) throw Error("halos: denoise needs rays >= 3");
    const std::size_t B = t.p.size();
    std::vector<double> omega(B);
    const double db = t.binRad();
    for (std::size_t k = 0; k < B; ++k) omega[k] = 2.0 * M_PI * (std::cos(double(k) * db) - std::cos(double(k + 1) * db));
    denoiseGrid(t.p, int(B), 1, omega, double(rays / 3));
}

// --- The element's tables ------------------------------------------------------------------------

HaloTables::Quality HaloTables::quality(const std::string& name) {
    if (name == "low") return {"low", 180, 180, 10, 60000, 600000, 1800};
    if (name == "default") return {"default", 256, 256, 31, 600000, 3000000, 1800};
    if (name == "high") return {"high", 512, 512, 46, 4000000, 20000000, 3600};
    throw Error("halos.table_quality: '" + name + "' is not one of low, default, high");
}

uint64_t HaloTables::hash() const {
    // FNV-1a over the inputs and the code version (bump kVersion when the trace changes).
    constexpr uint64_t kVersion = 3;  // 3: the tables denoised before they are cached
    uint64_t h = 1469598103934665603ull;
    auto mixIn = [&](const void* d, std::size_t n) {
        const auto* b = static_cast<const unsigned char*>(d);
        for (std::size_t i = 0; i < n; ++i) h = (h ^ b[i]) * 1099511628211ull;
    };
    const int ints[] = {q.ne, q.na, q.slices, q.bins};
    const uint64_t rays[] = {q.raysPerSlice, q.raysRandom, kVersion};
    const double d[] = {plateAspect, columnAspect, tiltRad, iceRefractiveIndex(kChannelNm[0]), iceRefractiveIndex(kChannelNm[2])};
    mixIn(ints, sizeof ints);
    mixIn(rays, sizeof rays);
    mixIn(d, sizeof d);
    return h;
}

HaloTables HaloTables::build(const Quality& q, double plateAspect, double columnAspect, double tiltRad) {
    const auto t0 = std::chrono::steady_clock::now();
    HaloTables t;
    t.q = q;
    t.plateAspect = plateAspect;
    t.columnAspect = columnAspect;
    t.tiltRad = tiltRad;
    const std::size_t slice = std::size_t(q.ne) * std::size_t(q.na) * 3;
    const Population pops[3] = {{Orientation::Plate, plateAspect, tiltRad},
                                {Orientation::Column, columnAspect, tiltRad},
                                {Orientation::Parry, columnAspect, tiltRad}};
    std::vector<float>* dst[3] = {&t.plates, &t.columns, &t.parry};
    for (int k = 0; k < 3; ++k) {
        dst[k]->resize(slice * std::size_t(q.slices));
        for (int s = 0; s < q.slices; ++s) {
            Phase2D p = traceOriented(pops[k], t.sliceElevationRad(s), q.ne, q.na, q.raysPerSlice, uint64_t(1000 * k + s + 1));
            denoise(p, q.raysPerSlice);
            for (std::size_t i = 0; i < p.p.size(); ++i)
                for (int c = 0; c < 3; ++c) (*dst[k])[std::size_t(s) * slice + i * 3 + std::size_t(c)] = float(p.p[i][c]);
        }
    }
    Phase1D r = traceRandom({Orientation::Random, columnAspect, 0.0}, q.bins, q.raysRandom, 7777);
    denoise(r, q.raysRandom);
    t.random.resize(std::size_t(q.bins) * 3);
    for (std::size_t i = 0; i < r.p.size(); ++i)
        for (int c = 0; c < 3; ++c) t.random[i * 3 + std::size_t(c)] = float(r.p[i][c]);
    t.buildSeconds = seconds(t0);
    return t;
}

std::string HaloTables::cachePath(const HaloTables& t) {
    const std::filesystem::path dir = cacheDirectory();
    char name[64];
    std::snprintf(name, sizeof name, "halos-%016llx.bin", static_cast<unsigned long long>(t.hash()));
    return (dir / name).string();
}

namespace {
bool readTables(const std::string& path, HaloTables& t) {
    std::ifstream in(path, std::ios::binary);
    if (!in) return false;
    uint64_t h = 0;
    in.read(reinterpret_cast<char*>(&h), sizeof h);
    if (!in || h != t.hash()) return false;
    const std::size_t slice = std::size_t(t.q.ne) * std::size_t(t.q.na) * 3 * std::size_t(t.q.slices);
    for (auto* v : {&t.plates, &t.columns, &t.parry}) {
        v->resize(slice);
        in.read(reinterpret_cast<char*>(v->data()), std::streamsize(v->size() * sizeof(float)));
    }
    t.random.resize(std::size_t(t.q.bins) * 3);
    in.read(reinterpret_cast<char*>(t.random.data()), std::streamsize(t.random.size() * sizeof(float)));
    return bool(in) && in.peek() == std::char_traits<char>::eof();
}

void writeTables(const std::string& path, const HaloTables& t) {
    std::error_code ec;
    std::filesystem::create_directories(std::filesystem::path(path).parent_path(), ec);
    const std::string tmp = path + ".tmp" + std::to_string(::getpid()) + "-" +
                            std::to_string(std::hash<std::thread::id>{}(std::this_thread::get_id()));
    {
        std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
        if (!out) return;
        const uint64_t h = t.hash();
        out.write(reinterpret_cast<const char*>(&h), sizeof h);
        for (const auto* v : {&t.plates, &t.columns, &t.parry, &t.random})
            out.write(reinterpret_cast<const char*>(v->data()), std::streamsize(v->size() * sizeof(float)));
        if (!out) {
            out.close();
            std::filesystem::remove(tmp, ec);
            return;
        }
    }
    std::filesystem::rename(tmp, path, ec);  // atomic on POSIX
    if (ec) std::filesystem::remove(tmp, ec);
}
}  // namespace

const HaloTables& HaloTables::cached(const Quality& q, double plateAspect, double columnAspect, double tiltRad) {
    static std::mutex mutex;
    static std::map<uint64_t, std::unique_ptr<HaloTables>> tables;
    std::lock_guard<std::mutex> lock(mutex);
    auto t = std::make_unique<HaloTables>();
    t->q = q;
    t->plateAspect = plateAspect;
    t->columnAspect = columnAspect;
    t->tiltRad = tiltRad;
    const uint64_t h = t->hash();
    if (auto it = tables.find(h); it != tables.end()) return *it->second;
    const std::string path = cachePath(*t);
    if (readTables(path, *t)) {
        t->fromCache = true;
    } else {
        *t = build(q, plateAspect, columnAspect, tiltRad);
        writeTables(path, *t);
    }
    return *tables.emplace(h, std::move(t)).first->second;
}

std::vector<glm::vec4> HaloTables::mix(const std::array<double, 4>& weights) const {
    double sum = 0;
    for (double w : weights) sum += std::max(w, 0.0);
    const std::size_t cells = std::size_t(q.ne) * std::size_t(q.na);
    std::vector<glm::vec4> out(cells * std::size_t(q.slices), glm::vec4(0.0f));
    if (sum <= 0) return out;
    const double wp = weights[0] / sum, wc = weights[1] / sum, wr = weights[2] / sum, wy = weights[3] / sum;
    const double db = M_PI / q.bins;
    const double forward = std::cos(1.0 * haloskeys::kDeg);
    for (int s = 0; s < q.slices; ++s) {
        const double h = sliceElevationRad(s);
        const glm::dvec3 S(std::cos(h), 0.0, std::sin(h));
        for (int ie = 0; ie < q.ne; ++ie) {
            const double e = -0.5 * M_PI + (ie + 0.5) * M_PI / q.ne;
            for (int ia = 0; ia < q.na; ++ia) {
                const double a = (ia + 0.5) * M_PI / q.na;
                const glm::dvec3 v(std::cos(e) * std::cos(a), std::cos(e) * std::sin(a), std::sin(e));
                const double cosTheta = glm::dot(v, S);
                const std::size_t i = std::size_t(s) * cells + std::size_t(ie) * std::size_t(q.na) + std::size_t(ia);
                if (cosTheta > forward) continue;  // stays in the direct beam
                // The random population's 1-D table at this cell's scattering angle (linear).
                const double f = std::acos(std::clamp(cosTheta, -1.0, 1.0)) / db - 0.5;
                const int k0 = std::clamp(int(std::floor(f)), 0, q.bins - 1), k1 = std::min(k0 + 1, q.bins - 1);
                const double t = std::clamp(f - std::floor(f), 0.0, 1.0);
                for (int c = 0; c < 3; ++c) {
                    const double pr = random[std::size_t(k0) * 3 + std::size_t(c)] * (1 - t) + random[std::size_t(k1) * 3 + std::size_t(c)] * t;
                    out[i][c] = float(wp * plates[i * 3 + std::size_t(c)] + wc * columns[i * 3 + std::size_t(c)] +
                                      wy * parry[i * 3 + std::size_t(c)] + wr * pr);
                }
            }
        }
    }
    return out;
}

const HaloPreset& haloPreset(const std::string& name) {
    // Weights: plates, columns, random, parry. "common": what most cirrus halo displays show
    // (a 22 deg halo with sundogs and a faint tangent arc: many random crystals, some oriented);
    // "display": strongly oriented crystals (bright sundogs, parhelic circle, circumzenithal,
    // tangent and Parry arcs); "random": the 22 and 46 deg halos alone.
    static const std::map<std::string, HaloPreset> presets = {
        {"common", {{0.15, 0.1, 0.75, 0.0}, 0.3}},
        {"display", {{0.35, 0.3, 0.25, 0.1}, 0.6}},
        {"random", {{0.0, 0.0, 1.0, 0.0}, 0.3}},
    };
    auto it = presets.find(name);
    if (it == presets.end()) throw Error("halos.preset: '" + name + "' is not one of common, display, random");
    return it->second;
}

}  // namespace welkin::elements::halos
