// CPU twin of shaders/cloud_density.glsl (double precision, the same formulas) and the
// CloudLayerBlock's construction from the keys.
#include <welkin/check.hpp>
#include <welkin/error.hpp>
#include <welkin/generators/cloud_density.hpp>
#include <welkin/generators/cloud_keys.hpp>
#include <welkin/generators/lights.hpp>
#include <welkin/gl/bindings.hpp>

#include <epoxy/gl.h>

#include <algorithm>
#include <cmath>

namespace welkin::generators {

namespace {
double wrapMod(double v, double period) {
    double m = std::fmod(v, period);
    return m < 0 ? m + period : m;
}
double sat(double v) { return std::clamp(v, 0.0, 1.0); }
double smooth(double e0, double e1, double x) {
    double t = sat((x - e0) / (e1 - e0));
    return t * t * (3.0 - 2.0 * t);
}
}  // namespace

CloudLayerBlock CloudLayerBlock::make(double planetRadius, double bottom, double top, double coverage, double detailScale,
                                      double scatteringPerM, double cirrusHeight, double cirrusCoverage, double weatherExtent,
                                      glm::dvec2 weatherOffset, glm::dvec3 noiseScroll, double basePeriod, double detailPeriod,
                                      double curlPeriod, std::optional<glm::dvec2> cirrusOffset, double cloudType) {
    const char* w = "CloudLayerBlock::make()";
    checkRange(w, "planetRadius (m)", planetRadius, 1e3, 1e9);
    checkRange(w, "bottom (m)", bottom, 0.0, 2e4);
    checkRange(w, "top (m)", top, bottom + 100.0, 2.5e4);
    checkRange(w, "coverage", coverage, 0.0, 1.0);
    checkRange(w, "detailScale", detailScale, 0.0, 4.0);
    checkRange(w, "scatteringPerM (1/m)", scatteringPerM, 0.0, 1.0);
    checkRange(w, "cirrusHeight (m)", cirrusHeight, top, 2e4);
    checkRange(w, "cirrusCoverage", cirrusCoverage, 0.0, 1.0);
    checkRange(w, "weatherExtent (m)", weatherExtent, 1e3, 1e6);
    checkRange(w, "basePeriod (m)", basePeriod, 5e2, 1e5);
    checkRange(w, "detailPeriod (m)", detailPeriod, 5e1, 2e4);
    checkRange(w, "curlPeriod (m)", curlPeriod, 1e3, 1e6);
    checkRange(w, "cloudType", cloudType, 0.0, 1.0);
    for (int i = 0; i < 2; ++i) checkRange(w, "weatherOffset (m)", weatherOffset[i], -1e12, 1e12);
    for (int i = 0; i < 3; ++i) checkRange(w, "noiseScroll (m)", noiseScroll[i], -1e12, 1e12);
    const glm::dvec2 co = cirrusOffset.value_or(weatherOffset);
    for (int i = 0; i < 2; ++i) checkRange(w, "cirrusOffset (m)", co[i], -1e12, 1e12);
    CloudLayerBlock b{};
    b.radii[0] = float(planetRadius);
    b.radii[1] = float(planetRadius + bottom);
    b.radii[2] = float(planetRadius + top);
    b.radii[3] = float(planetRadius + cirrusHeight);
    b.shape[0] = float(coverage);
    b.shape[1] = float(detailScale);
    b.shape[2] = float(scatteringPerM);
    b.shape[3] = float(cirrusCoverage);
    // Offsets reduced in double before the float conversion: the keys allow 1e12 m of drift.
    b.weather[0] = float(wrapMod(weatherOffset.x, weatherExtent));
    b.weather[1] = float(wrapMod(weatherOffset.y, weatherExtent));
    b.weather[2] = float(weatherExtent);
    b.weather[3] = float(1.0 / weatherExtent);
    b.noise[0] = float(basePeriod);
    b.noise[1] = float(detailPeriod);
    b.noise[2] = float(curlPeriod);
    b.noise[3] = float(cloudType);
    for (int i = 0; i < 3; ++i) {
        b.scrollBase[i] = float(wrapMod(noiseScroll[i], basePeriod));
        b.scrollDetail[i] = float(wrapMod(noiseScroll[i], detailPeriod));
    }
    b.cirrus[0] = float(wrapMod(co.x, curlPeriod));
    b.cirrus[1] = float(wrapMod(co.y, curlPeriod));
    return b;
}

CloudLayerBlock CloudLayerBlock::from(const SkyVars& vars) {
    validateCloudLayer(vars);
    const glm::dvec2 off = vars.getOr(cloudkeys::weatherOffset, glm::dvec2(0.0));
    return make(vars.getOr(lightkeys::planetRadius, 6360e3), vars.getOr(cloudkeys::bottom, 2000.0), vars.getOr(cloudkeys::top, 3000.0),
                vars.getOr(cloudkeys::coverage, 0.5), vars.getOr(cloudkeys::detailScale, 1.0), vars.getOr(cloudkeys::scattering, 0.05),
                vars.getOr(cloudkeys::cirrusHeight, 9000.0), vars.getOr(cloudkeys::cirrusCoverage, 0.3),
                vars.getOr(cloudkeys::weatherExtent, 40000.0), off, glm::dvec3(off, 0.0),
                vars.getOr(cloudkeys::noiseBasePeriod, kDefaultNoiseBasePeriodM),
                vars.getOr(cloudkeys::noiseDetailPeriod, kDefaultNoiseDetailPeriodM), vars.getOr(cloudkeys::curlPeriod, kDefaultCurlPeriodM),
                vars.getOr(cloudkeys::cirrusOffset, off), vars.getOr(cloudkeys::cloudType, 1.0));
}

void bindCloudTextures(const SkyVars& vars) {
    const std::pair<const Key<TextureRef>*, int> list[] = {{&cloudkeys::weatherMap, gl::binding::kCloudWeatherMap},
                                                           {&cloudkeys::noiseBase, gl::binding::kCloudNoiseBase},
                                                           {&cloudkeys::noiseDetail, gl::binding::kCloudNoiseDetail},
                                                           {&cloudkeys::curlNoise, gl::binding::kCloudCurlNoise},
                                                           {&cloudkeys::pathLut, gl::binding::kCloudPathLut}};
    for (const auto& [key, unit] : list)
        if (vars.has(*key)) glBindTextureUnit(GLuint(unit), vars.get(*key).id);
}

namespace cpu {

glm::dvec4 Image::texel(int x, int y, int z) const {
    x = ((x % w) + w) % w;
    y = ((y % h) + h) % h;
    z = ((z % d) + d) % d;
    const float* p = &rgba[(size_t(z) * size_t(h) * size_t(w) + size_t(y) * size_t(w) + size_t(x)) * 4];
    return {p[0], p[1], p[2], p[3]};
}

glm::dvec4 Image::sample2D(glm::dvec2 uv) const {
    // GL linear filtering: texel centres at (i + 0.5) / size.
    const double fx = uv.x * w - 0.5, fy = uv.y * h - 0.5;
    const double x0 = std::floor(fx), y0 = std::floor(fy);
    const double ax = fx - x0, ay = fy - y0;
    const int ix = int(wrapMod(x0, w)), iy = int(wrapMod(y0, h));
    return glm::mix(glm::mix(texel(ix, iy), texel(ix + 1, iy), ax), glm::mix(texel(ix, iy + 1), texel(ix + 1, iy + 1), ax), ay);
}

glm::dvec4 Image::sample3D(glm::dvec3 uvw) const {
    const double fx = uvw.x * w - 0.5, fy = uvw.y * h - 0.5, fz = uvw.z * d - 0.5;
    const double x0 = std::floor(fx), y0 = std::floor(fy), z0 = std::floor(fz);
    const double ax = fx - x0, ay = fy - y0, az = fz - z0;
    const int ix = int(wrapMod(x0, w)), iy = int(wrapMod(y0, h)), iz = int(wrapMod(z0, d));
    auto plane = [&](int z) {
        return glm::mix(glm::mix(texel(ix, iy, z), texel(ix + 1, iy, z), ax), glm::mix(texel(ix, iy + 1, z), texel(ix + 1, iy + 1, z), ax),
                        ay);
    };
    return glm::mix(plane(iz), plane(iz + 1), az);
}

double remap(double v, double lo, double hi, double newLo, double newHi) { return (v - lo) / (hi - lo) * (newHi - newLo) + newLo; }

double cloudAltitude(const CloudLayerBlock& b, glm::dvec3 p) {
    const double R = b.radii[0];
    const glm::dvec3 q = p + glm::dvec3(0, 0, R);
    // |q| - R = (|q|^2 - R^2) / (|q| + R), with |q|^2 - R^2 = x^2 + y^2 + z^2 + 2 R z: no cancellation.
    return (glm::dot(p, p) + 2.0 * R * p.z) / (glm::length(q) + R);
}

glm::dvec2 weatherUv(const CloudLayerBlock& b, glm::dvec3 p) {
    return (glm::dvec2(p.x, p.y) + glm::dvec2(b.weather[0], b.weather[1])) * double(b.weather[3]);
}

glm::dvec2 heightGradient(double a, double wb, double wt, double type) {
    // Two cloud types, blended by `type` (clouds.cloud_type), as Schneider & Vos 2015 and
    // Schneider (GPU Pro 7, 2016) select a vertical density gradient per cloud type:
    // - stratocumulus (0): a sheet between the weather map's base wb and top wt (Papp eq. 5.2's
    //   H_scale), full within 10 % of its thickness above the base and rounded over its top 35 %;
    // - cumulus (1): every base at the layer's bottom, the lifting condensation level that the
    //   fair-weather cumulus of one air mass share (WMO International Cloud Atlas 2017, "Cumulus":
    //   "flat bases"); the weather map's top wt (its domes) is the tower's height. Full density
    //   within 7 % of the height above the base (a sharp, flat base), then a long taper over
    //   50-100 % of the height: the coverage remap cuts ever more of the Perlin-Worley shape
    //   upwards, leaving rounded turrets (cauliflower tops) rather than a flat lid.
    const double tS = (a - wb) / std::max(wt - wb, 1e-3);
    const double tC = a / std::max(wt, 1e-3);
    const double pS = smooth(0.0, kScBaseRamp, tS) * (1.0 - smooth(kScTopStart, 1.0, tS));
    const double pC = smooth(0.0, kCuBaseRamp, tC) * (1.0 - smooth(kCuTopStart, 1.0, tC));
    const double t = sat(glm::mix(tS, tC, type));
    // H_gradient (Papp eq. 5.3): denser upwards in the cloud, 0.75 at its base to 1 at its top.
    return {glm::mix(pS, pC, type) * (0.75 + 0.25 * t), t};
}

double cloudDensity(const CloudLayerBlock& b, const CloudTextures& t, glm::dvec3 p, CloudLod lod) {
    const double h = cloudAltitude(b, p);
    const double bottom = double(b.radii[1]) - double(b.radii[0]), top = double(b.radii[2]) - double(b.radii[0]);
    if (h < bottom || h > top) return 0.0;
    const double a = (h - bottom) / (top - bottom);  // Papp eq. 5.1: altitude fraction in the layer
    const glm::dvec4 w = t.weather.sample2D(weatherUv(b, p));
    // Coverage (Papp eq. 5.4): the weather map's density scaled by clouds.coverage.
    const double cov = sat(w.r) * sat(double(b.shape[0]));
    if (cov <= 0.0) return 0.0;
    const glm::dvec2 hg = heightGradient(a, sat(w.g), sat(w.b), sat(double(b.noise[3])));
    if (hg.x <= 0.0) return 0.0;
    // Base shape (Schneider & Vos 2015): the Perlin-Worley R eroded by its Worley fBm GBA,
    // remap(R, fbm - 1, 1, 0, 1); then stretched from its measured range [kShapeLo, kShapeHi] to
    // [0, 1] so that the coverage cut below bites (see kShapeLo), times the height gradient.
    const glm::dvec3 pb = (glm::dvec3(p.x, p.y, h) + glm::dvec3(b.scrollBase[0], b.scrollBase[1], b.scrollBase[2])) / double(b.noise[0]);
    const glm::dvec4 n = t.base.sample3D(pb);
    const double fbm = 0.625 * n.g + 0.25 * n.b + 0.125 * n.a;
    const double pw = remap(n.r, fbm - 1.0, 1.0, 0.0, 1.0);
    const double shape = sat(remap(pw, kShapeLo, kShapeHi, 0.0, 1.0)) * hg.x;
    // Coverage cut into the shape: remap(shape, 1 - cov, 1, 0, 1) * cov = shape - (1 - cov): where
    // the weather map is thin only the shape's highest lobes survive (billowy edges).
    const double base = std::max(shape + cov - 1.0, 0.0);
    if (lod == CloudLod::Cheap || base <= 0.0) return base;
    // Erosion by the detail noise (Papp eq. 5.5, in Schneider's remap form): the Worley fBm near
    // the cloud's base (eroding the cells' cores leaves wisps), its inverse above (eroding the cell
    // borders leaves round billows: cauliflower), switching over the lowest 1/kDetailFlip of the
    // cloud; strength kErosion x clouds.detail_scale.
    const glm::dvec3 pd =
        (glm::dvec3(p.x, p.y, h) + glm::dvec3(b.scrollDetail[0], b.scrollDetail[1], b.scrollDetail[2])) / double(b.noise[1]);
    const glm::dvec4 dn = t.detail.sample3D(pd);
    const double dfbm = 0.625 * dn.r + 0.25 * dn.g + 0.125 * dn.b;
    const double mod = glm::mix(dfbm, 1.0 - dfbm, sat(hg.y * kDetailFlip));
    const double e = std::min(kErosion * double(b.shape[1]) * mod, 0.9);
    return sat((base - e) / (1.0 - e));
}

namespace {
// Both roots of |r + t d| = s, near first, cancellation-free (Numerical Recipes 5.6); the twin of
// cld_sphereRoots() in the GLSL. No root: x > y.
glm::dvec2 sphereRoots(double r, double mu, double s) {
    const double b = r * mu, c = (r - s) * (r + s);
    const double disc = b * b - c;
    if (disc < 0.0) return {1.0, -1.0};
    const double q = -(b + (b >= 0.0 ? std::sqrt(disc) : -std::sqrt(disc)));
    const double t2 = q != 0.0 ? c / q : 0.0;
    return {std::min(q, t2), std::max(q, t2)};
}
}  // namespace

glm::dvec2 shellIntersect(double R, double rb, double rt, double r, double mu) {
    const glm::dvec2 miss(-1.0, -1.0);
    const glm::dvec2 g = sphereRoots(r, mu, R), lb = sphereRoots(r, mu, rb), lt = sphereRoots(r, mu, rt);
    if (r < rb) {
        if (r >= R && mu < 0.0 && g.x <= g.y) return miss;  // the ground comes first
        return {lb.y, lt.y};
    }
    if (r <= rt) {
        if (mu < 0.0 && lb.x <= lb.y) return {0.0, lb.x};  // leaves through the base
        return {0.0, lt.y};
    }
    if (mu >= 0.0 || lt.x > lt.y) return miss;
    if (lb.x <= lb.y) return {lt.x, lb.x};
    return {lt.x, lt.y};
}

glm::dvec2 cloudShellIntersect(const CloudLayerBlock& b, double r, double mu) {
    return shellIntersect(b.radii[0], b.radii[1], b.radii[2], r, mu);
}

double cirrusDensity(const CloudLayerBlock& b, const Image& curl, glm::dvec2 xy) {
    const double cc = sat(double(b.shape[3]));
    if (cc <= 0.0) return 0.0;
    // The curl noise's RG (a divergence-free field, encoded 0.5 + 0.5 v) advects the lookup of
    // its B (the fBm potential): streaky, sheared fibres (SevenSky's high-altitude map, Papp 6.3).
    const glm::dvec2 uv = (xy + glm::dvec2(b.cirrus[0], b.cirrus[1])) / double(b.noise[2]);
    const glm::dvec4 c = curl.sample2D(uv);
    const glm::dvec2 warp = (glm::dvec2(c.r, c.g) * 2.0 - 1.0) * 0.05;
    const double n = curl.sample2D(uv + warp).b;
    return sat(n + cc - 1.0);
}

}  // namespace cpu
}  // namespace welkin::generators
