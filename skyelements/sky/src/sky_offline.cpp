#include <welkin/elements/sky_offline.hpp>
#include <welkin/gl/bindings.hpp>

#include <epoxy/gl.h>

#include <chrono>

namespace welkin::elements {

void OfflineRenderer::draw(SkyElement& e, const Camera& camera, bool finish) {
    using clock = std::chrono::steady_clock;
    if (!vao_) {
        vao_ = gl::VertexArray::create();
        cameraUbo_ = gl::Buffer(sizeof(CameraBlock));
    }
    if (!hdr_ || hdr_.width() != camera.width || hdr_.height() != camera.height) {
        hdr_ = gl::Texture2D(camera.width, camera.height, GL_RGBA32F);
        fbo_ = gl::Framebuffer::create();
        fbo_.attach(GL_COLOR_ATTACHMENT0, hdr_);
        fbo_.checkComplete("OfflineRenderer");
    }
    if (!e.initialized()) {
        InitContext ic{vars_, log_};
        e.init(ic);
        e.resize(camera.width, camera.height);
    }
    if (finish) glFinish();
    auto t0 = clock::now();
    if (runGenerators)
        for (auto& g : e.generators()) g->runIfDue(vars_, log_);
    if (finish) glFinish();
    auto t1 = clock::now();
    FrameContext fc{vars_, log_, camera, 0.0, &vao_};
    fc.nothingBehind = nothingBehind;  // one element over a target cleared to black
    e.update(fc);
    CameraBlock block = makeCameraBlock(camera, 0.0);
    cameraUbo_.update(&block, sizeof block);
    fbo_.bind();
    glViewport(0, 0, camera.width, camera.height);
    const float black[4] = {0, 0, 0, 1};
    glClearBufferfv(GL_COLOR, 0, black);
    cameraUbo_.bindBase(GL_UNIFORM_BUFFER, gl::binding::kCameraUbo);
    vao_.bind();
    glEnable(GL_BLEND);
    glBlendFuncSeparate(GL_ONE, GL_SRC1_COLOR, GL_ZERO, GL_ONE);
    glDisable(GL_DEPTH_TEST);
    e.render(fc);
    glDisable(GL_BLEND);
    if (finish) glFinish();
    auto t2 = clock::now();
    generatorsMs_ = std::chrono::duration<double, std::milli>(t1 - t0).count();
    drawMs_ = std::chrono::duration<double, std::milli>(t2 - t1).count();
}

Image OfflineRenderer::render(SkyElement& e, const Camera& camera, bool finish) {
    draw(e, camera, finish);
    std::vector<float> rgba = hdr_.readRgbaFloat();
    Image img;
    img.width = camera.width;
    img.height = camera.height;
    img.pixels.resize(size_t(img.width) * img.height * 3);
    for (int y = 0; y < img.height; ++y)
        for (int x = 0; x < img.width; ++x)
            for (int c = 0; c < 3; ++c) img.at(x, y, c) = rgba[(size_t(img.height - 1 - y) * img.width + x) * 4 + c];
    return img;
}

void OfflineRenderer::release() {
    hdr_ = {};
    fbo_ = {};
    cameraUbo_ = {};
    vao_ = {};
}

}  // namespace welkin::elements
