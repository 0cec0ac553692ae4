// Test helper: a CPU cloud texture (the density twin's cpu::Image, RGBA float texels) uploaded as
// the GL texture the cloud shaders sample (RGBA32F, linear, repeating like the generators' own).
#pragma once
#include <welkin/generators/cloud_density.hpp>
#include <welkin/gl/objects.hpp>

#include <epoxy/gl.h>

namespace welkin::test {

inline gl::Texture uploadCloudTexture(const generators::cpu::Image& im, bool is3D) {
    gl::Texture tex = is3D ? gl::Texture(gl::Texture3D(im.w, im.h, im.d, GL_RGBA32F)) : gl::Texture(gl::Texture2D(im.w, im.h, GL_RGBA32F));
    tex.upload(GL_RGBA, GL_FLOAT, im.rgba.data());
    tex.setFilter(GL_LINEAR);
    tex.setWrap(GL_REPEAT);
    return tex;
}

}  // namespace welkin::test
