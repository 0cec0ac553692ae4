#include <welkin/elements/halo.hpp>
#include <welkin/embedded/halo_shaders.hpp>
#include <welkin/generators/lights.hpp>
#include <welkin/gl/shader.hpp>
#include <welkin/keys.hpp>

namespace welkin::elements {

Halo::Halo() : SkyElement("halo") {
    // Options: keys with defaults, declared when the element is added (settable with --var).
    option(halokeys::radius, 22.0 * halokeys::kDeg);
    option(halokeys::width, 1.5 * halokeys::kDeg);
    option(halokeys::gain, 0.02);
    // What it reads from the world (for `welkin vars` and the docs).
    reads(keys::sunDirection);
    reads(generators::lightkeys::sunIlluminance);
    reads(generators::lightkeys::sunTransmittance);
}

void Halo::doInit(InitContext& ctx) {
    declareOptions(ctx.vars);  // also when used without a SkyProcessor
    // The shared Sun/Moon lights (one instance per SkyVars, whoever asks first).
    addGenerator(generators::AtmosphereLights::obtain(ctx.vars));
    programs_ = gl::ProjectionPrograms(gl::ProgramBuilder("Halo")
                                           .fullscreenVertex()
                                           .fragment("engine/camera.glsl", gl::engineShader("camera.glsl"))
                                           .fragment("engine/composite.glsl", gl::engineShader("composite.glsl"))
                                           .fragment("halo/halo.frag.glsl", embedded::halo_shaders("halo.frag.glsl")));
    programs_.get(Projection::Perspective);  // shader errors surface in init(), naming file and line
}

void Halo::doRender(const FrameContext& ctx) {
    const SkyVars& v = ctx.vars;
    // Sunlight at the observer, lux per channel: reddened and dimmed by the air, 0 below the horizon.
    const glm::dvec3 E = v.get(generators::lightkeys::sunIlluminance) * v.get(generators::lightkeys::sunTransmittance);
    if (E == glm::dvec3(0.0)) return;  // nothing to draw: costs nothing
    const gl::Program& p = programs_.get(ctx.camera.projection);
    p.use();
    p.set("u_sun", glm::vec3(glm::normalize(v.get(keys::sunDirection))));
    p.set("u_radius", float(v.get(halokeys::radius)));
    p.set("u_width", float(v.get(halokeys::width)));
    p.set("u_peak", glm::vec3(E * v.get(halokeys::gain)));
    ctx.drawFullscreen();
}

void Halo::doRelease() { programs_.releasePrograms(); }

}  // namespace welkin::elements

WELKIN_ELEMENT_DESCRIPTOR(halo) {
    static const welkin::ElementDescriptor d{"halo", "the 22-degree ice halo around the Sun (the element template)",
                                             welkin::Layer::Foreground, false,
                                             [] { return std::make_unique<welkin::elements::Halo>(); }};
    return d;
}
