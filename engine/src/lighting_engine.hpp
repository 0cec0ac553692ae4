// SkyLighting's machinery, owned by SkyProcessor (welkin/lighting.hpp is the public side): the
// environment capture into a cube map, the SH projection, SevenSky's light map and axis lights,
// the GGX prefilter, the directional lights; time-sliced in the interactive path.
#pragma once
#include <welkin/gl/objects.hpp>
#include <welkin/lighting.hpp>
#include <welkin/log.hpp>

#include <nlohmann/json_fwd.hpp>

#include <string>
#include <vector>

namespace welkin {

class SkyProcessor;

class LightingEngine {
public:
    LightingEngine() = default;
    ~LightingEngine();
    LightingEngine(const LightingEngine&) = delete;
    LightingEngine& operator=(const LightingEngine&) = delete;

    /// Declares the lighting.* option keys with their defaults.
    static void declareKeys(SkyVars& vars);
    /// Called at the end of SkyProcessor::update(): runs what is due (nothing when lighting.enabled
    /// is false, or when no key changed since the last capture).
    void step(SkyProcessor& processor, SkyVars& vars, bool timing);
    /// Frees the GL resources (context current); the next step() recaptures.
    void release();
    const SkyLighting& result() const { return out_; }
    /// The exposure is the tone map's, which runs after update(): refreshed when read.
    void setEv100(double ev100) const;
    void stats(nlohmann::json& root) const;

private:
    struct Stage {
        double frameMs = 0, refreshMs = 0;
        int runs = 0;
    };
    void ensureResources(const LightingOptions& o);
    int totalSlices() const { return 6 + 1 + (mips_ - 1); }
    void runSlice(SkyProcessor& processor, int slice, bool timing);
    void captureFace(SkyProcessor& processor, int face);
    void reduce(bool timing);
    void prefilter(int mip);
    void pollReadback(bool wait);
    void updateDirectionalLights(const SkyVars& vars);
    std::vector<uint64_t> snapshot(const SkyVars& vars, std::vector<std::string>& names) const;
    void bump() const { ++out_.revision; }

    mutable SkyLighting out_;  // mutable: ev100 follows the tone map, refreshed when read
    int size_ = 0, mips_ = 0;
    gl::TextureCube work_, specular_;
    gl::Texture2D face_, lightMap_;
    gl::Framebuffer faceFbo_, cubeFbo_;
    gl::Buffer ssbo_, faceUbo_, texels_;
    std::vector<int> texelOffsets_;  // per level of the radiance cube: first entry in texels_ (-1: not tabulated)
    int sourceLevel(int mip) const;
    gl::Program shProgram_, mapProgram_, prefilterProgram_;
    void* fence_ = nullptr;  // GLsync of the last reduction, until read back

    // The cycle: -1 idle, else the next slice to run; the key versions it captures.
    int nextSlice_ = -1;
    std::vector<std::string> capturedNames_, cycleNames_;
    std::vector<uint64_t> capturedVersions_, cycleVersions_;
    bool captured_ = false;
    int cycleFrameCount_ = 0;

    Stage capture_, sh_, map_, prefilterStage_;
    int facesCaptured_ = 0, refreshes_ = 0, readbacks_ = 0;
    double lastRefreshTotalMs_ = 0, cycleTotalMs_ = 0;
    int lastRefreshFrames_ = 0;
    bool enabled_ = false;
};

}  // namespace welkin
