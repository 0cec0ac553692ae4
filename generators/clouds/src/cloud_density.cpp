// CPU twin of shaders/cloud_density.glsl: its maths, cloud_density.shared.glsl, compiled in double
// (welkin/glsl_cpp.hpp) on read-back textures; and the CloudLayerBlock's construction from the keys.
#include <welkin/check.hpp>
#include <welkin/error.hpp>
#include <welkin/generators/cloud_density.hpp>
#include <welkin/generators/cloud_keys.hpp>
#include <welkin/generators/lights.hpp>
#include <welkin/glsl_cpp.hpp>
#include <welkin/gl/bindings.hpp>

#include <epoxy/gl.h>

#include <algorithm>
#include <cmath>

// The density's maths: cloud_density.shared.glsl in double, on cpu::Image as the samplers.
namespace welkin::glsl::dp::cloud_density_shared {
using sampler2D = generators::cpu::Image;
using sampler3D = generators::cpu::Image;
inline vec4 textureLod(const sampler2D& s, vec2 uv, real) { return s.sample2D(uv); }
inline vec4 textureLod(const sampler3D& s, vec3 uvw, real) { return s.sample3D(uvw); }
#include "cloud_density.shared.glsl"
}  // namespace welkin::glsl::dp::cloud_density_shared

namespace welkin::generators {

// The header's constants are the shared file's (one set of numbers for GLSL and C++).
static_assert(kShapeLo == CLD_SHAPE_LO && kShapeHi == CLD_SHAPE_HI && kCuBaseRamp == CLD_CU_BASE &&
              kCuTopStart == CLD_CU_TOP0 && kScBaseRamp == CLD_SC_BASE && kScTopStart == CLD_SC_TOP0 &&
              kErosion == CLD_EROSION && kDetailFlip == CLD_DETAIL_FLIP);
static_assert(int(CloudLod::Cheap) == CLOUD_LOD_CHEAP && int(CloudLod::Full) == CLOUD_LOD_FULL);

namespace {
double wrapMod(double v, double period) {
    double m = std::fmod(v, period);
    return m < 0 ? m + period : m;
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

namespace {
using glsl::dp::cloud_density_shared::CloudLayer;
CloudLayer layer(const CloudLayerBlock& b) {
    auto v = [](const float* f) { return glm::dvec4(f[0], f[1], f[2], f[3]); };
    return {v(b.radii), v(b.shape), v(b.weather), v(b.noise), v(b.scrollBase), v(b.scrollDetail), v(b.cirrus)};
}
}  // namespace

double remap(double v, double lo, double hi, double newLo, double newHi) {
    return glsl::dp::cloud_density_shared::cld_remap(v, lo, hi, newLo, newHi);
}
double cloudAltitude(const CloudLayerBlock& b, glm::dvec3 p) { return glsl::dp::cloud_density_shared::cld_layerAltitude(layer(b), p); }
glm::dvec2 weatherUv(const CloudLayerBlock& b, glm::dvec3 p) { return glsl::dp::cloud_density_shared::cld_layerWeatherUv(layer(b), p); }
glm::dvec2 heightGradient(double a, double wb, double wt, double type) {
    return glsl::dp::cloud_density_shared::cloudHeightGradient(a, wb, wt, type);
}
double cloudDensity(const CloudLayerBlock& b, const CloudTextures& t, glm::dvec3 p, CloudLod lod) {
    return glsl::dp::cloud_density_shared::cld_layerDensity(layer(b), t.weather, t.base, t.detail, p, int(lod));
}
glm::dvec2 shellIntersect(double R, double rb, double rt, double r, double mu) {
    return glsl::dp::cloud_density_shared::cloudShellIntersectRadii(R, rb, rt, r, mu);
}
glm::dvec2 cloudShellIntersect(const CloudLayerBlock& b, double r, double mu) {
    return shellIntersect(b.radii[0], b.radii[1], b.radii[2], r, mu);
}
double cloudDepthAlong(const CloudLayerBlock& b, const CloudTextures& t, glm::dvec3 p, glm::dvec3 dir, int n, double maxDist) {
    return glsl::dp::cloud_density_shared::cld_layerDepthAlong(layer(b), t.weather, t.base, t.detail, p, dir, n, maxDist);
}
double cirrusDensity(const CloudLayerBlock& b, const Image& curl, glm::dvec2 xy) {
    return glsl::dp::cloud_density_shared::cld_layerCirrus(layer(b), curl, xy);
}

}  // namespace cpu
}  // namespace welkin::generators
