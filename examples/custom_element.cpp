// Writing your own element: a "Halo" that draws a faint ring 22 degrees around the Sun (an ice
// halo). It shows the whole contract: the keys it reads, GLSL assembled from the engine's chunks,
// radiance plus transmittance output, options checked at the API boundary.
// Usage: example_custom_element OUT.png      (walkthrough: docs/writing-an-element.md)
#include <welkin/element.hpp>
#include <welkin/elements/grid.hpp>
#include <welkin/error.hpp>
#include <welkin/gl/context.hpp>
#include <welkin/gl/projection_programs.hpp>
#include <welkin/gl/shader.hpp>
#include <welkin/image.hpp>
#include <welkin/keys.hpp>
#include <welkin/processor.hpp>

#include <cstdio>
#include <numbers>
#include <string>

namespace {

constexpr double kDeg = std::numbers::pi / 180;

// [element]
struct HaloOptions {
    double radiusRad = 22 * kDeg;      ///< ring radius, radians, (0, pi/2]
    double widthRad = 1.5 * kDeg;      ///< ring width (Gaussian sigma), radians, (0, 0.2]
    double luminanceCdM2 = 2000.0;     ///< peak luminance, cd/m^2, [0, 1e6]
};

class Halo final : public welkin::SkyElement {
public:
    explicit Halo(const HaloOptions& o = {}) : SkyElement("halo"), options_(o) {
        check("radiusRad", o.radiusRad, 0, std::numbers::pi / 2);
        check("widthRad", o.widthRad, 0, 0.2);
        if (!(o.luminanceCdM2 >= 0 && o.luminanceCdM2 <= 1e6))
            throw welkin::Error("Halo: luminanceCdM2 " + std::to_string(o.luminanceCdM2) + " not in [0, 1e6]");
        reads(welkin::keys::sunDirection);  // declared for tools and documentation
    }

private:
    // Options are checked at the API boundary: one line naming the member and the range.
    static void check(const char* name, double v, double lo, double hi) {
        if (!(v > lo && v <= hi))
            throw welkin::Error(std::string("Halo: ") + name + " " + std::to_string(v) + " not in (" + std::to_string(lo) +
                                ", " + std::to_string(hi) + "]");
    }

    // The element's own GLSL. In a library element this is a .glsl file beside the class,
    // embedded at build time; the engine's chunks come first.
    static constexpr const char* kFragment = R"(
uniform vec3 u_sun;        // unit vector to the Sun, ENU
uniform float u_radius;    // radians
uniform float u_width;     // radians
uniform float u_luminance; // cd/m^2
void main() {
    vec3 dir;
    if (!welkin_viewDirection(welkin_pixel(), dir)) discard;
    float angle = acos(clamp(dot(dir, u_sun), -1.0, 1.0));
    float ring = exp(-0.5 * pow((angle - u_radius) / u_width, 2.0));
    // Emits light and hides nothing: transmittance 1.
    welkin_output(vec3(1.0, 0.97, 0.93) * u_luminance * ring, vec3(1.0));
}
)";

    void doInit(welkin::InitContext& ctx) override {
        // Declaring a key shares it with every other element that declares it.
        ctx.vars.declare(welkin::keys::sunDirection, glm::dvec3(0, 0, 1));
        // One program per camera projection, compiled on first use (camera.glsl then runs only
        // that projection's code).
        programs_ = welkin::gl::ProjectionPrograms(welkin::gl::ProgramBuilder("Halo")
                                                       .fullscreenVertex()
                                                       .fragment("engine/camera.glsl", welkin::gl::engineShader("camera.glsl"))
                                                       .fragment("engine/composite.glsl", welkin::gl::engineShader("composite.glsl"))
                                                       .fragment("halo.frag.glsl", kFragment));
    }
    void doRender(const welkin::FrameContext& ctx) override {
        const welkin::gl::Program& program_ = programs_.get(ctx.camera.projection);
        program_.set("u_sun", glm::vec3(ctx.vars.get(welkin::keys::sunDirection)));
        program_.set("u_radius", float(options_.radiusRad));
        program_.set("u_width", float(options_.widthRad));
        program_.set("u_luminance", float(options_.luminanceCdM2));
        program_.use();
        ctx.drawFullscreen();
    }
    void doRelease() override { programs_.releasePrograms(); }

    HaloOptions options_;
    welkin::gl::ProjectionPrograms programs_;
};
// [element]

}  // namespace

int main(int argc, char** argv) {
    if (argc != 2) {
        std::fprintf(stderr, "usage: %s OUT.png\n", argv[0]);
        return 2;
    }
    try {
        welkin::Logger log;
        auto context = welkin::gl::HeadlessContext::create({}, log);
        welkin::SkyProcessor sky(welkin::SkyVars::earth(), log);
        sky.add(std::make_unique<Halo>());
        sky.add(std::make_unique<welkin::elements::Grid>());
        welkin::Camera camera;
        camera.projection = welkin::Projection::Fisheye;
        camera.width = camera.height = 256;
        sky.setCamera(camera);
        // Equinox, local noon at 50 deg N: the Sun stands ~40 deg up in the south (the processor's
        // astronomy step writes keys::sunDirection each frame).
        sky.setObserver({.latitudeRad = 50 * kDeg, .longitudeRad = 0.0, .heightMeters = 0.0});
        sky.setTime(welkin::UtcInstant::parse("2026-03-20T12:07:00Z"));
        sky.setExposure({.ev100 = 10});
        sky.renderFrame();
        welkin::writeImage(sky.readToneMapped(), argv[1]);
        std::printf("%s\n", argv[1]);
    } catch (const welkin::Error& e) {
        std::fprintf(stderr, "example_custom_element: %s\n", e.what());
        return 1;
    }
    return 0;
}
