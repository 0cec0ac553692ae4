// Helpers of the cloud generators' tests: GL textures with known contents and their CPU copies,
// and a compute pass evaluating GLSL functions at points.
#pragma once
#include <welkin/generators/cloud_density.hpp>
#include <welkin/gl/objects.hpp>

#include <cstdint>
#include <vector>

namespace welkin::test {

/// Deterministic texel values in [0, 1] (integer hash, Wang 1997 style mixing).
inline float hashUnit(uint32_t x) {
    x ^= x >> 16;
    x *= 0x7feb352dU;
    x ^= x >> 15;
    x *= 0x846ca68bU;
    x ^= x >> 16;
    return float(x & 0xffffffU) / float(0xffffff);
}

/// Reads level 0 of `t` into a cpu::Image (RGBA float, as the GPU sees it after quantisation).
inline generators::cpu::Image toImage(const gl::Texture& t) {
    generators::cpu::Image im;
    im.w = t.width();
    im.h = t.height();
    im.d = t.depth();
    im.rgba = t.readRgbaFloat(0);
    return im;
}

}  // namespace welkin::test
