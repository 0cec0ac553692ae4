// SkyProcessor::stats(): the --stats JSON (inputs, per element and generator cost).
#include "tone_mapper.hpp"
#include <welkin/processor.hpp>

#include <nlohmann/json.hpp>

#include <numbers>

namespace welkin {

namespace {
constexpr double kPi = std::numbers::pi;
}

nlohmann::json SkyProcessor::stats() const {
    using nlohmann::json;
    json j;
    j["time"] = time_.toIso();
    j["observer"] = {{"lat_deg", observer_.latitudeRad * 180 / kPi},
                     {"lon_deg", observer_.longitudeRad * 180 / kPi},
                     {"height_m", observer_.heightMeters}};
    j["camera"] = {{"projection", std::string(toString(camera_.projection))},
                   {"width", camera_.width},
                   {"height", camera_.height},
                   {"az_deg", camera_.azimuthRad * 180 / kPi},
                   {"alt_deg", camera_.altitudeRad * 180 / kPi},
                   {"fov_deg", camera_.verticalFovRad * 180 / kPi}};
    j["exposure"] = {{"automatic", exposure_.automatic}, {"ev100", lastEv100()}};
    if (exposure_.automatic) {
        const glm::dvec2 a = adaptationLuminance();
        j["exposure"]["adaptation_cd_m2"] = a.x;           // the cones' adaptation luminance
        j["exposure"]["scotopic_adaptation_cd_m2"] = a.y;  // the rods' (scotopic cd/m^2)
    }
    j["timing_includes_gpu"] = options_.timing;
    // Every generator's cost in the order they run, and their own quantities (astronomy: Sun, Moon).
    json gensAll = json::array();
    for (Generator* g : generatorOrder()) {
        gensAll.push_back({{"name", g->name()}, {"runs", g->runCount()}, {"last_ms", g->timing().lastMs}, {"total_ms", g->timing().totalMs}});
        g->stats(j);
    }
    j["generators"] = gensAll;
    json el = json::array();
    for (auto& e : elements_) {
        json gens = json::array();
        for (auto& g : e->generators())
            gens.push_back({{"name", g->name()}, {"runs", g->runCount()}, {"last_ms", g->timing().lastMs}, {"total_ms", g->timing().totalMs}});
        el.push_back({{"name", e->name()},
                      {"init_ms", e->initTiming().lastMs},
                      {"update_ms", e->updateTiming().lastMs},
                      {"render_ms", e->renderTiming().lastMs},
                      {"scene_ms", e->sceneTiming().lastMs},  // applyToScene(): its passes over the host's scene
                      {"generators", gens}});
    }
    j["elements"] = el;
    for (auto& e : elements_) e->stats(j);
    lightingStats(j);
    j["frame_ms"] = frameMs_;
    j["generators_ms"] = generatorsMs_;
    j["tonemap_ms"] = toneMapMs_;
    j["tonemap_srgb_target"] = toneMapper_->lastSrgbTarget();  // the last display pass let the target encode sRGB (GL_FRAMEBUFFER_SRGB)
    j["apply_to_scene_ms"] = sceneMs_;  // the last applyToScene(), every element's passes
    if (camera_.host) {
        const glm::dvec3 e = camera_.eyeEnuMeters();
        j["camera"]["host_matrices"] = true;
        j["camera"]["eye_enu_m"] = {e.x, e.y, e.z};
    }
    j["camera"]["depth"] = {{"reversed_z", camera_.depth.reversedZ}, {"zero_to_one", camera_.depth.zeroToOne}};
    j["frames"] = frames_;
    return j;
}

}  // namespace welkin
