// Cloud-path LUT generator (GPU pass cloud_path_lut.glsl; CPU twin cpu::cloudPathTexel).
#include <welkin/check.hpp>
#include <welkin/embedded/clouds_shaders.hpp>
#include <welkin/generators/cloud_density.hpp>
#include <welkin/generators/cloud_keys.hpp>
#include <welkin/generators/cloud_path_lut.hpp>
#include <welkin/generators/lights.hpp>
#include <welkin/gl/bindings.hpp>
#include <welkin/gl/shader.hpp>
#include <welkin/glsl_cpp.hpp>

#include <epoxy/gl.h>

#include <algorithm>
#include <cmath>

namespace welkin::glsl::dp::cloud_path_shared {
#include "cloud_path.shared.glsl"
}  // namespace welkin::glsl::dp::cloud_path_shared

namespace welkin::generators {

// The mapping: cloud_path.shared.glsl (the shaders' text) in double.
static_assert(kCloudPathAboveM == CLOUD_PATH_ABOVE_M);
double cloudPathX(double mu) { return glsl::dp::cloud_path_shared::cloudPathX(mu); }
double cloudPathMu(double x) { return glsl::dp::cloud_path_shared::cloudPathMu(x); }
double cloudPathY(double h, double bottom, double top) { return glsl::dp::cloud_path_shared::cloudPathY(h, bottom, top); }
double cloudPathAltitude(double y, double bottom, double top) { return glsl::dp::cloud_path_shared::cloudPathAltitude(y, bottom, top); }

CloudPathLut::CloudPathLut(int width, int height) : Generator("clouds.path_lut"), w_(width), h_(height) {
    checkRange("CloudPathLut", "width", width, 3, 8192);
    checkRange("CloudPathLut", "height", height, 3, 8192);
    input(cloudkeys::bottom, {.optional = true});
    input(cloudkeys::top, {.optional = true});
    input(lightkeys::planetRadius, {.optional = true});
    output(cloudkeys::pathLut);
}

std::shared_ptr<CloudPathLut> CloudPathLut::obtain(SkyVars& vars) {
    static const Key<std::shared_ptr<CloudPathLut>> kShared{"generators.cloud_path_lut"};
    return vars.obtain<CloudPathLut>(kShared, [] { return std::make_shared<CloudPathLut>(); });
}

void CloudPathLut::doRelease() {
    tex_ = {};
    prog_ = {};
}

void CloudPathLut::doRun(SkyVars& vars, const Logger&) {
    validateCloudLayer(vars);
    const double R = vars.getOr(lightkeys::planetRadius, 6360e3);
    const double bottom = vars.getOr(cloudkeys::bottom, 2000.0), top = vars.getOr(cloudkeys::top, 3000.0);
    if (!tex_) {
        tex_ = gl::Texture2D(w_, h_, GL_RG32F);
        tex_.setFilter(GL_LINEAR);
        tex_.setWrap(GL_CLAMP_TO_EDGE);
    }
    if (!prog_)
        prog_ = gl::ProgramBuilder("CloudPathLut")
                    .compute("generators/cloud_density.glsl", embedded::clouds_shaders("cloud_density.glsl"))
                    .compute("generators/cloud_path.glsl", embedded::clouds_shaders("cloud_path.glsl"))
                    .compute("generators/cloud_path_lut.glsl", embedded::clouds_shaders("cloud_path_lut.glsl"))
                    .build();
    prog_.use();
    prog_.set("u_size", glm::ivec2(w_, h_));
    glProgramUniform1d(prog_.id(), prog_.location("u_planetRadius"), R);
    glProgramUniform1d(prog_.id(), prog_.location("u_bottom"), bottom);
    glProgramUniform1d(prog_.id(), prog_.location("u_top"), top);
    glBindImageTexture(gl::binding::kLutImage, tex_.id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RG32F);
    glDispatchCompute(GLuint((w_ + 7) / 8), GLuint((h_ + 7) / 8), 1);
    glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_SHADER_IMAGE_ACCESS_BARRIER_BIT | GL_TEXTURE_UPDATE_BARRIER_BIT);
    glBindImageTexture(gl::binding::kLutImage, 0, 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RG32F);
    glUseProgram(0);
    vars.publish(cloudkeys::pathLut, tex_.ref());
}

namespace cpu {
glm::dvec2 cloudPathTexel(int i, int j, int width, int height, double planetRadius, double bottom, double top) {
    const double mu = cloudPathMu(double(i) / double(width - 1));
    const double h = cloudPathAltitude(double(j) / double(height - 1), bottom, top);
    return shellIntersect(planetRadius, planetRadius + bottom, planetRadius + top, planetRadius + h, mu);
}
}  // namespace cpu

}  // namespace welkin::generators
