// Helpers of the hidden timing tests ([display_timing], [night_timing]): process CPU time, a
// median, and an element that stands for the Sky's attenuation without its cost.
//
//   const double t0 = test::cpuMs();
//   p.renderFrame(); glFinish();
//   frames.push_back(test::cpuMs() - t0);        // ms of CPU, llvmpipe's threads included
//   p.emplace<test::Attenuator>();               // later elements see "something attenuates"
//
// Process CPU time, not wall time: llvmpipe's threads run in the process, and on a machine shared
// with other jobs the wall time of a frame swings by 2-5x, the CPU time it uses much less.
#pragma once
#include <welkin/element.hpp>

#include <algorithm>
#include <ctime>
#include <vector>

namespace welkin::test {

// The process's CPU time so far, milliseconds (all threads).
inline double cpuMs() {
    timespec t{};
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
    return t.tv_sec * 1e3 + t.tv_nsec * 1e-6;
}

// The median of v (the upper one of an even count); v must not be empty.
inline double medianOf(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v[v.size() / 2];
}

// Declares that it attenuates what is behind it (as the Sky does) and draws nothing. With
// `saysNothingDrawn` it also reports so (SkyElement::reportNothingDrawn()), as the Sky does on a
// frame it skips; without, the elements after it are composited as over a drawn element.
class Attenuator final : public SkyElement {
public:
    explicit Attenuator(bool saysNothingDrawn = true) : SkyElement("attenuator"), saysNothingDrawn_(saysNothingDrawn) { setAttenuatesBehind(true); }

private:
    void doInit(InitContext&) override {}
    void doRender(const FrameContext&) override {
        if (saysNothingDrawn_) reportNothingDrawn();
    }
    void doRelease() override {}
    bool saysNothingDrawn_;
};

}  // namespace welkin::test
