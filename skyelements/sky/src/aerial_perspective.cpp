#include <welkin/elements/aerial_perspective.hpp>
#include <welkin/embedded/atmosphere_shaders.hpp>
#include <welkin/embedded/sky_shaders.hpp>
#include <welkin/error.hpp>
#include <welkin/generators/sky_luts.hpp>
#include <welkin/gl/shader.hpp>
#include <welkin/keys.hpp>

#include <epoxy/gl.h>

#include <algorithm>

namespace welkin::elements {

using namespace welkin::generators;

std::vector<std::pair<std::string, std::string>> aerialPerspectiveGlslChunks() {
    return {{"generators/atmosphere.glsl", std::string(embedded::atmosphere_shaders("atmosphere.glsl"))},
            {"sky/aerial_perspective.glsl", std::string(embedded::sky_shaders("aerial_perspective.glsl"))}};
}

void AerialPerspective::bindResources(const SkyVars& vars, const gl::Program& program) {
    if (!vars.getOr(skykeys::aerialVolume, false) && !vars.getOr(keys::hostScene, false))
        throw Error("AerialPerspective: the Sky does not build the aerial-perspective volume: set sky.aerial_volume = true "
                    "(SkyOptions::aerialPerspective, --var sky.aerial_volume=true)");
    if (!vars.has(skykeys::aerialInscatter))
        throw Error("AerialPerspective: the sky's aerial-perspective volume does not exist yet (render a frame with the Sky element first)");
    SkyModel m = SkyModel::fromVars(vars);
    const SkyQuality q = SkyQuality::preset(effectiveQuality(vars));
    AtmosphereBlock block = AtmosphereBlock::from(m, q.shBands);
    if (!ubo_) ubo_ = gl::Buffer(sizeof block);
    ubo_.update(&block, sizeof block);
    ubo_.bindBase(GL_UNIFORM_BUFFER, gl::binding::kAtmosphereUbo);
    glBindTextureUnit(gl::binding::kAerialInscatterLut, vars.get(skykeys::aerialInscatter).id);
    glBindTextureUnit(gl::binding::kAerialTransmittanceLut, vars.get(skykeys::aerialTransmittance).id);
    glm::dvec3 sun = vars.getOr(keys::sunDirection, glm::dvec3(0, 0, 1));
    const double Ht = m.topRadius - m.bottomRadius;
    glProgramUniform3f(program.id(), program.location("welkin_apSunDir"), float(sun.x), float(sun.y), float(sun.z));
    glm::vec3 E(vars.getOr(lightkeys::sunIlluminance, m.solarIlluminance));
    glProgramUniform3f(program.id(), program.location("welkin_apSunE"), E.x, E.y, E.z);
    glProgramUniform1f(program.id(), program.location("welkin_apH"), float(std::clamp(vars.getOr(keys::observerHeight, 0.0), 0.0, Ht)));
    glProgramUniform1f(program.id(), program.location("welkin_apMaxDistance"), float(q.aerialMaxDistance));
    glProgramUniform1f(program.id(), program.location("welkin_apInvScale"), float(1.0 / kLutScale));
}

void AerialPerspective::apply(const SkyVars& vars, const Camera& camera, const HostDepth& depth, unsigned framebuffer) {
    if (camera.projection != Projection::Perspective) throw Error("AerialPerspective::apply(): camera must be perspective");
    depth.validate("AerialPerspective::apply()");
    if (!program_) {
        auto b = gl::ProgramBuilder("AerialPerspective");
        b.fullscreenVertex()
            .fragment("engine/camera.glsl", gl::engineShader("camera.glsl"))
            .fragment("engine/composite.glsl", gl::engineShader("composite.glsl"));
        for (auto& [name, text] : aerialPerspectiveGlslChunks()) b.fragment(name, text);
        program_ = b.fragment("sky/aerial_apply.frag.glsl", embedded::sky_shaders("aerial_apply.frag.glsl")).build();
        cameraUbo_ = gl::Buffer(sizeof(CameraBlock));
        vao_ = gl::VertexArray::create();
    }
    CameraBlock cb = makeCameraBlock(camera, 0.0, depth);
    cameraUbo_.update(&cb, sizeof cb);
    cameraUbo_.bindBase(GL_UNIFORM_BUFFER, gl::binding::kCameraUbo);
    bindResources(vars, program_);
    glBindTextureUnit(gl::binding::kSceneDepth, depth.depthTexture);
    program_.use();
    glBindFramebuffer(GL_FRAMEBUFFER, framebuffer);
    glViewport(0, 0, camera.width, camera.height);
    glEnable(GL_BLEND);
    glBlendFuncSeparate(GL_ONE, GL_SRC1_COLOR, GL_ZERO, GL_ONE);
    glDisable(GL_DEPTH_TEST);
    vao_.bind();
    glDrawArrays(GL_TRIANGLES, 0, 3);
    glDisable(GL_BLEND);
}

void AerialPerspective::release() {
    program_ = {};
    ubo_ = {};
    cameraUbo_ = {};
    vao_ = {};
}

}  // namespace welkin::elements
