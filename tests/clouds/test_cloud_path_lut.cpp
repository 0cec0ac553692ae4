// The cloud-path LUT: GPU texels against the analytic ray-sphere crossing, below, inside and
// above the layer; the mapping's round trip.
#include <catch2/catch.hpp>

#include "clouds/cloud_test_util.hpp"
#include "gl_test_context.hpp"

#include <welkin/embedded/clouds_shaders.hpp>
#include <welkin/generators/cloud_density.hpp>
#include <welkin/generators/cloud_keys.hpp>
#include <welkin/gl/bindings.hpp>
#include <welkin/gl/shader.hpp>
#include <welkin/generators/cloud_path_lut.hpp>
#include <welkin/generators/lights.hpp>

#include <cmath>

using namespace welkin;
using namespace welkin::generators;

TEST_CASE("Cloud-path LUT mapping round-trips", "[cpu][clouds]") {
    for (double mu : {-1.0, -0.3, -1e-3, 0.0, 2e-4, 0.5, 1.0}) CHECK(cloudPathMu(cloudPathX(mu)) == Approx(mu).margin(1e-12));
    for (double h : {0.0, 700.0, 1500.0, 2000.0, 3999.0, 4000.0, 30000.0, 54000.0})
        CHECK(cloudPathAltitude(cloudPathY(h, 1500.0, 4000.0), 1500.0, 4000.0) == Approx(h).margin(1e-9));
    // The thirds: the layer's base and top at y = 1/3 and 2/3.
    CHECK(cloudPathY(1500.0, 1500.0, 4000.0) == Approx(1.0 / 3.0));
    CHECK(cloudPathY(4000.0, 1500.0, 4000.0) == Approx(2.0 / 3.0));
}

TEST_CASE("Cloud-path LUT: texels match the analytic crossing below, inside and above", "[gl][clouds]") {
    test::glContext();
    SkyVars vars;
    vars.declare(cloudkeys::bottom, 1500.0);
    vars.declare(cloudkeys::top, 4000.0);
    vars.declare(lightkeys::planetRadius, 6360e3);
    const int W = 64, H = 30;
    CloudPathLut lut(W, H);
    lut.run(vars, test::testLogger(), true);
    const cpu::Image im = test::toImage(lut.texture());
    int below = 0, inside = 0, above = 0, misses = 0;
    double worst = 0;
    for (int j = 0; j < H; ++j)
        for (int i = 0; i < W; ++i) {
            const glm::dvec2 ref = cpu::cloudPathTexel(i, j, W, H, 6360e3, 1500.0, 4000.0);
            const glm::dvec4 g = im.texel(i, j);
            const double h = cloudPathAltitude(double(j) / (H - 1), 1500.0, 4000.0);
            if (ref.y < 0) {
                ++misses;
                CHECK(g.y < 0);
                continue;
            }
            (h < 1500.0 ? below : h <= 4000.0 ? inside : above) += 1;
            // Computed in double on the GPU, stored as float: relative 6e-8 of distances up to
            // ~1000 km (0.06 m); 1e-6 relative + 1 mm is the float storage with margin.
            worst = std::max(worst, std::abs(g.x - ref.x) / (1e-3 + 1e-6 * ref.x));
            worst = std::max(worst, std::abs(g.y - ref.y) / (1e-3 + 1e-6 * ref.y));
        }
    INFO("worst error / tolerance " << worst);
    CHECK(worst <= 1.0);
    CHECK(below > 100);
    CHECK(inside > 100);
    CHECK(above > 100);
    CHECK(misses > 100);  // looking into the ground from below, upwards from above
    // Physical facts, independent of the twin: straight up from the ground the path is the layer
    // itself (1500 m to 4000 m); straight down from the top of the LUT (54 km) it is the layer
    // seen from above: entry 50 000 m, exit 52 500 m.
    CHECK(im.texel(W - 1, 0).x == Approx(1500.0).margin(1e-3));
    CHECK(im.texel(W - 1, 0).y == Approx(4000.0).margin(1e-3));
    CHECK(im.texel(0, H - 1).x == Approx(50000.0).margin(1e-2));
    CHECK(im.texel(0, H - 1).y == Approx(52500.0).margin(1e-2));
}

TEST_CASE("Cloud-path LUT: cloudPathLookup() in GLSL reads the texel of (h, mu)", "[gl][clouds]") {
    test::glContext();
    SkyVars vars;
    vars.declare(cloudkeys::bottom, 1500.0);
    vars.declare(cloudkeys::top, 4000.0);
    vars.declare(lightkeys::planetRadius, 6360e3);
    const int W = 32, H = 12;
    CloudPathLut lut(W, H);
    lut.run(vars, test::testLogger(), true);
    // Query exactly at texel centres (the mapping inverted on the CPU): the lookup must return
    // that texel (mapping, texel-centring and orientation all agree between C++ and GLSL).
    std::vector<glm::vec4> q;
    std::vector<glm::dvec2> ref;
    for (int j = 0; j < H; ++j)
        for (int i = 0; i < W; ++i) {
            q.emplace_back(float(cloudPathAltitude(double(j) / (H - 1), 1500.0, 4000.0)), float(cloudPathMu(double(i) / (W - 1))), 0.f, 0.f);
            ref.push_back(cpu::cloudPathTexel(i, j, W, H, 6360e3, 1500.0, 4000.0));
        }
    static const char* kMain = R"(
layout(local_size_x = 64) in;
layout(std430, binding = 4) readonly buffer Q { vec4 qs[]; };
layout(std430, binding = 5) writeonly buffer O { vec4 os[]; };
uniform int u_count;
void main() {
    int i = int(gl_GlobalInvocationID.x);
    if (i >= u_count) return;
    os[i] = vec4(cloudPathLookup(qs[i].x, qs[i].y), 0.0, 0.0);
}
)";
    gl::Program prog = gl::ProgramBuilder("CloudPathLookupTest")
                           .compute("generators/cloud_density.glsl", embedded::clouds_shaders("cloud_density.glsl"))
                           .compute("generators/cloud_path.glsl", embedded::clouds_shaders("cloud_path.glsl"))
                           .compute("test_main.glsl", kMain)
                           .build();
    const CloudLayerBlock block = CloudLayerBlock::from(vars);
    gl::Buffer ubo(sizeof block, &block);
    ubo.bindBase(GL_UNIFORM_BUFFER, gl::binding::kCloudUbo);
    const size_t bytes = q.size() * sizeof(glm::vec4);
    gl::Buffer in(bytes, q.data()), out(bytes);
    in.bindBase(GL_SHADER_STORAGE_BUFFER, 4);
    out.bindBase(GL_SHADER_STORAGE_BUFFER, 5);
    lut.texture().bind(gl::binding::kCloudPathLut);
    prog.use();
    prog.set("u_count", int(q.size()));
    glDispatchCompute(GLuint((q.size() + 63) / 64), 1, 1);
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    std::vector<glm::vec4> got(q.size());
    glGetNamedBufferSubData(out.id(), 0, GLsizeiptr(bytes), got.data());
    glUseProgram(0);
    int hits = 0;
    for (size_t k = 0; k < q.size(); ++k) {
        if (ref[k].y < 0) {
            CHECK(got[k].y < 0);
            continue;
        }
        ++hits;
        // The float mapping lands within ~1e-6 texel of the centre; next to a miss (-1) or a
        // steep horizon texel that weight still moves the value: 1e-3 relative + 1 m covers it
        // (a wrong texel would be off by tens of percent).
        CHECK(std::abs(got[k].x - ref[k].x) <= 1.0 + 1e-3 * ref[k].x);
        CHECK(std::abs(got[k].y - ref[k].y) <= 1.0 + 1e-3 * ref[k].y);
    }
    CHECK(hits > 100);
}
