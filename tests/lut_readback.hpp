// The sky's GPU LUTs read back as CPU tables, and the error measure the GPU-against-twin tests use.
//
//   const Lut2D gpu = test::readLut(luts.transmittance());          // RGBA32F texture -> Lut2D
//   CHECK(test::relErr(gpu.at(i, j), cpu.at(i, j), 1e-6) < 1e-4);  // per-channel relative error
#pragma once
#include <welkin/generators/sky_model.hpp>
#include <welkin/gl/objects.hpp>

#include <glm/glm.hpp>

#include <algorithm>
#include <cmath>
#include <vector>

namespace welkin::test {

// The texture's RGB as a double-precision table (alpha dropped), each value times `scale` (for
// LUTs stored in scaled units).
inline generators::Lut2D readLut(const gl::Texture& t, double scale = 1.0) {
    generators::Lut2D l{t.width(), t.height(), {}};
    std::vector<float> px = t.readRgbaFloat();
    l.texels.resize(size_t(l.width) * l.height);
    for (size_t i = 0; i < l.texels.size(); ++i) l.texels[i] = glm::dvec3(px[4 * i], px[4 * i + 1], px[4 * i + 2]) * scale;
    return l;
}

// The largest of the three channels' |gpu - cpu| / (|cpu| + floor): relative where the value is
// well above `floor` (same unit as the values), absolute against `floor` where it is near zero.
inline double relErr(const glm::dvec3& gpu, const glm::dvec3& cpu, double floor) {
    double e = 0;
    for (int c = 0; c < 3; ++c) e = std::max(e, std::abs(gpu[c] - cpu[c]) / (std::abs(cpu[c]) + floor));
    return e;
}

}  // namespace welkin::test
