// A test element: a uniform field of radiance (linear sRGB, cd/m^2) over the whole image, opaque
// (transmittance 0, or the one given), for tests that need a known scene or something behind the sky.
//
//   p.emplace<test::UniformField>(glm::vec3(1e-4f));           // a dark night's worth of light
//   p.add(std::make_unique<test::UniformField>(L, "backdrop")); // under another name
//   p.add(std::make_unique<test::UniformField>(L, "veil", glm::vec3(0.5f)));  // half of what is behind shows
#pragma once
#include <welkin/element.hpp>
#include <welkin/gl/shader.hpp>

#include <glm/glm.hpp>

#include <string>

namespace welkin::test {

class UniformField final : public SkyElement {
public:
    explicit UniformField(glm::vec3 radiance, std::string name = "field", glm::vec3 transmittance = glm::vec3(0.0f))
        : SkyElement(std::move(name)), radiance_(radiance), transmittance_(transmittance) {}
    void setRadiance(glm::vec3 r) { radiance_ = r; }

private:
    void doInit(InitContext&) override {
        program_ = gl::ProgramBuilder("UniformField")
                       .fullscreenVertex()
                       .fragment("engine/composite.glsl", gl::engineShader("composite.glsl"))
                       .fragment("field.frag", "uniform vec3 u_L; uniform vec3 u_T; void main() { welkin_output(u_L, u_T); }")
                       .build();
    }
    void doRender(const FrameContext& ctx) override {
        program_.set("u_L", radiance_);
        program_.set("u_T", transmittance_);
        program_.use();
        ctx.drawFullscreen();
    }
    void doRelease() override { program_ = {}; }
    glm::vec3 radiance_, transmittance_;
    gl::Program program_;
};

}  // namespace welkin::test
