#include <welkin/elements/sky_offline.hpp>

#include <epoxy/gl.h>

namespace welkin::elements {

// The caller's element inside the processor: forwards every call, never releases it.
class OfflineRenderer::Borrowed final : public SkyElement {
public:
    Borrowed(SkyElement& e, const OfflineRenderer& r) : SkyElement(e.name()), e_(e), r_(r) {}
    SkyElement& target() { return e_; }

private:
    void doInit(InitContext& ctx) override {
        if (!e_.initialized()) e_.init(ctx);
        for (auto& g : e_.generators()) addGenerator(g);
    }
    void doUpdate(const FrameContext& ctx) override { e_.update(ctx); }
    void doRender(const FrameContext& ctx) override {
        FrameContext c = ctx;
        c.nothingBehind = ctx.nothingBehind && r_.nothingBehind;
        e_.render(c);
    }
    void doResize(int w, int h) override { e_.resize(w, h); }
    void doRelease() override {}
    void doStats(nlohmann::json& root) const override { e_.stats(root); }
    SkyElement& e_;
    const OfflineRenderer& r_;
};

OfflineRenderer::OfflineRenderer(SkyVars& vars, const Logger& log) : vars_(vars), log_(log) {}

OfflineRenderer::~OfflineRenderer() = default;

void OfflineRenderer::draw(SkyElement& e, const Camera& camera, bool finish) {
    if (!processor_) {
        // Times with glFinish around every call (the processor's timing option): the figures
        // then include the GPU work whether or not `finish` is asked.
        processor_ = std::make_unique<SkyProcessor>(BorrowedVars{vars_}, log_,
                                                    ProcessorOptions{.timing = true, .astronomy = false, .timeAndPlace = false});
        processor_->setAnimationTime(0.0);
    }
    if (current_ != &e) {
        if (proxy_) processor_->remove(proxy_->name());
        auto p = std::make_unique<Borrowed>(e, *this);
        proxy_ = p.get();
        processor_->add(std::move(p));
        current_ = &e;
    }
    processor_->setCamera(camera);
    if (!e.initialized() && proxy_->initialized()) {
        // The caller released its element since: bring the proxy back too.
        proxy_->release();
    }
    processor_->setGeneratorsPaused(!runGenerators);
    if (finish) glFinish();
    processor_->renderFrame();
    generatorsMs_ = processor_->lastGeneratorsMs();
    drawMs_ = proxy_->updateTiming().lastMs + proxy_->renderTiming().lastMs;
}

Image OfflineRenderer::render(SkyElement& e, const Camera& camera, bool finish) {
    draw(e, camera, finish);
    return processor_->readHdr();
}

void OfflineRenderer::release() {
    if (processor_) processor_->release();
}

}  // namespace welkin::elements
