// A host's ground under welkin's clouds: the host registers the CloudShadowMap generator, binds
// the map with CloudShadowMap::bindForHost() and calls welkin_cloudShadow() (cloud_shadow.glsl) in
// its own shader. Here the "scene" is the ground seen from straight above over the shadow map's
// square (x east to the right, y north up), a grey Lambertian surface (albedo 0.2) lit by the
// direct sunlight (the Sun's illuminance above the air x the air's transmittance x sin(elevation),
// shadowed by the clouds) and the sky's diffuse illuminance (sky.diffuse_irradiance). Writes the
// ground's radiance, exposed so that a sunlit patch is 0.8, as an sRGB PNG.
// Usage: example_cloud_shadow_host OUT.png [ISO-8601 time] [clouds.preset]
#include <welkin/elements/registry.hpp>
#include <welkin/generators/cloud_shadow.hpp>
#include <welkin/generators/lights.hpp>
#include <welkin/generators/sky_luts.hpp>
#include <welkin/gl/context.hpp>
#include <welkin/gl/objects.hpp>
#include <welkin/gl/shader.hpp>
#include <welkin/image.hpp>
#include <welkin/keys.hpp>
#include <welkin/processor.hpp>

#include <epoxy/gl.h>

#include <cmath>
#include <cstdio>
#include <numbers>
#include <string>

int main(int argc, char** argv) {
    if (argc < 2 || argc > 4) {
        std::fprintf(stderr, "usage: %s OUT.png [ISO-8601 time] [clouds.preset]\n", argv[0]);
        return 2;
    }
    try {
        using namespace welkin;
        Logger log;
        auto context = gl::HeadlessContext::create({}, log);
        SkyProcessor sky(SkyVars::earth(), log, ProcessorOptions{.timing = true});
        for (const auto& name : elements::expandElementList("default,clouds")) sky.add(elements::makeElement(name));
        // The host's part 1: the shadow generator, run by the processor with the others (only
        // when the light, the weather map, its offset or the layer changed).
        auto shadow = generators::CloudShadowMap::obtain(sky.vars());
        sky.addGenerator(shadow);
        if (argc > 3) sky.vars().setFromString("clouds.preset", argv[3]);

        constexpr double deg = std::numbers::pi / 180;
        sky.setObserver({.latitudeRad = 35.9 * deg, .longitudeRad = 14.5 * deg, .heightMeters = 0});
        sky.setTime(UtcInstant::parse(argc > 2 ? argv[2] : "2026-06-21T16:00:00Z"));
        Camera camera;
        camera.width = 64, camera.height = 36;  // the sky frame itself is not used here
        sky.setCamera(camera);
        sky.setExposure({.automatic = true});
        sky.setAnimationTime(0.0);
        sky.renderFrame();  // update(): every generator, the shadow map included

        // The host's part 2: its own shader with welkin_cloudShadow().
        const int n = 512;
        gl::Program prog = gl::ProgramBuilder("ground")
                               .fullscreenVertex()
                               .fragment("cloud_shadow.glsl", std::string(generators::CloudShadowMap::hostGlsl()))
                               .fragment("ground.glsl", R"(
uniform float u_extent;   // m
uniform float u_groundZ;  // ENU z of the ground (-observer height), m
uniform vec3 u_direct;    // direct horizontal illuminance without clouds, lux (linear sRGB)
uniform vec3 u_diffuse;   // the sky's diffuse horizontal illuminance, lux
out vec4 o_radiance;
void main() {
    vec2 xy = (gl_FragCoord.xy / vec2(512.0) - 0.5) * u_extent;
    float s = welkin_cloudShadow(vec3(xy, u_groundZ));
    o_radiance = vec4(0.2 / 3.14159265 * (u_direct * s + u_diffuse), 1.0);  // cd/m^2
})")
                               .build();
        gl::Texture2D target(n, n, GL_RGBA32F);
        gl::Framebuffer fbo = gl::Framebuffer::create();
        fbo.attach(GL_COLOR_ATTACHMENT0, target);
        gl::VertexArray vao = gl::VertexArray::create();
        const SkyVars& v = sky.vars();
        const glm::dvec3 sun = v.get(keys::sunDirection);
        const glm::dvec3 direct = v.get(generators::lightkeys::sunIlluminance) * v.get(generators::lightkeys::sunTransmittance) * std::max(sun.z, 0.0);
        const glm::dvec3 diffuse = v.getOr(generators::skykeys::diffuseIrradiance, glm::dvec3(0.0));
        fbo.bind();
        glViewport(0, 0, n, n);
        prog.use();
        prog.set("u_extent", float(v.get(generators::cloudkeys::shadowExtent)));
        prog.set("u_groundZ", float(-v.get(keys::observerHeight)));
        prog.set("u_direct", glm::vec3(direct));
        prog.set("u_diffuse", glm::vec3(diffuse));
        generators::CloudShadowMap::bindForHost(v, prog.id());
        vao.bind();
        glDrawArrays(GL_TRIANGLES, 0, 3);
        std::vector<float> px = target.readRgbaFloat();
        glBindFramebuffer(GL_FRAMEBUFFER, 0);

        // Exposure: the sunlit ground (no cloud) maps to 0.8; sRGB encoding.
        const double lit = 0.2 / std::numbers::pi * (0.2126 * (direct.x + diffuse.x) + 0.7152 * (direct.y + diffuse.y) + 0.0722 * (direct.z + diffuse.z));
        const double k = lit > 0 ? 0.8 / lit : 1.0;
        Image out{n, n, 3, std::vector<float>(size_t(n) * n * 3)};
        auto encode = [](double x) { x = std::clamp(x, 0.0, 1.0); return float(x <= 0.0031308 ? 12.92 * x : 1.055 * std::pow(x, 1 / 2.4) - 0.055); };
        for (int y = 0; y < n; ++y)
            for (int x = 0; x < n; ++x)
                for (int c = 0; c < 3; ++c) out.at(x, y, c) = encode(k * px[(size_t(n - 1 - y) * n + x) * 4 + c]);  // top row first
        writeImage(out, argv[1]);
        const glm::dvec3 L = v.get(generators::cloudkeys::shadowLight);
        std::printf("%s: ground over %.0f km, light elevation %.1f deg, azimuth %.1f deg; shadow map %.2f ms (last run, CPU clock with glFinish)\n",
                    argv[1], v.get(generators::cloudkeys::shadowExtent) / 1000, std::asin(L.z) / deg,
                    std::atan2(L.x, L.y) / deg, shadow->timing().lastMs);
    } catch (const welkin::Error& e) {
        std::fprintf(stderr, "example_cloud_shadow_host: %s\n", e.what());
        return 1;
    }
    return 0;
}
