// The weather map generator (publishes clouds.weather_map, RGBA16F, layout in cloud_keys.hpp):
// cloud shapes kept as data (CloudShape), generated from clouds.seed or edited from C++, drawn on
// the GPU as instanced ellipses (each 9 times, offset by the map's extent, so the map repeats
// without seams), noise-edged, max-blended; or an artist's image (clouds.weather_map_file).
// Animation over the simulated time (time.jd_utc, seconds since the first run):
//  - constant wind: clouds.weather_offset_m = its value at the first run - wind x elapsed time
//    (the map slides east with a positive east wind: uv = (xy + offset) / extent); no re-render;
//    the cirrus likewise: clouds.cirrus_offset_m - clouds.cirrus_wind_m_s (default: the wind) x t;
//  - a 2-D flow field (clouds.flow_file image, or setFlow() from C++) advects each cloud's
//    centre (RK4, sub-steps <= 30 s) and the map is re-rendered when clouds moved.
//
//   auto wm = welkin::generators::WeatherMap::obtain(vars);   // one per SkyVars; add it in doInit
//   wm->add({.centre = {5000, 8000}, .semiAxes = {1500, 900}, .density = 0.9});
//   wm->setFlow([](glm::dvec2 p, double t) { return glm::dvec2(3.0, 0.0); });   // m/s
//
// Map coordinates: metres in [0, extent)^2 of one tile, m = world ENU (x, y) + offset (mod extent).
// Defaults: extent 40 km (512 texels: 78 m each, 8 texels across the smallest default cloud of
// 600 m semi-axis; the tile repeats ~4 times out to the 160 km horizon distance of a 2 km layer,
// and the noise shapes hide it), 48 clouds of 600-3000 m semi-axes (~10 % of the map at density
// > 0.2 with seed 1: scattered cumulus; raise clouds.cloud_count for more).
#pragma once
#include <welkin/element.hpp>
#include <welkin/gl/objects.hpp>
#include <welkin/image.hpp>

#include <cstdint>
#include <functional>
#include <memory>
#include <vector>

namespace welkin::generators {

struct CloudShape {
    glm::dvec2 centre{0.0};        ///< map coordinates, m (wrapped into [0, extent) when drawn)
    glm::dvec2 semiAxes{1000.0};   ///< m, > 0
    double rotation = 0.0;         ///< of the first semi-axis from east, counter-clockwise, rad
    double density = 1.0;          ///< weather R at the core, [0, 1]; 0: dissolved
    double baseFraction = 0.0;     ///< weather G: cloud base as a fraction of the layer, [0, 1]
    double topFraction = 1.0;      ///< weather B: cloud top, [baseFraction, 1]
    double rain = 0.0;             ///< weather A at the core, [0, 1]
    uint32_t seed = 0;             ///< shape of its noisy edge
};

/// Defaults of the generator's keys (when undeclared).
inline constexpr double kDefaultWeatherExtentM = 40000.0;
inline constexpr int kDefaultCloudCount = 48;
inline constexpr double kDefaultCloudSizeMinM = 600.0;
inline constexpr double kDefaultCloudSizeMaxM = 3000.0;

class WeatherMap : public Generator {
public:
    /// A velocity field over the map: (map position m, seconds since the first run) -> m/s.
    using Flow = std::function<glm::dvec2(glm::dvec2, double)>;

    /// `size` texels per edge of the generated map (16..4096).
    explicit WeatherMap(int size = 512);
    static std::shared_ptr<WeatherMap> obtain(SkyVars& vars);

    // --- The shapes: generated at the first run from clouds.seed, clouds.cloud_count and the size
    // range (after any add()ed before it; none if setClouds() was called before it), regenerated
    // when one of these keys or the extent changes; edits re-render at the next run -----------------
    const std::vector<CloudShape>& clouds() const { return shapes_; }
    /// Adds a shape (checked: semi-axes > 0, fractions and densities in [0, 1]); returns its index.
    size_t add(const CloudShape& shape);
    /// Moves shape `i` by `delta` m.
    void move(size_t i, glm::dvec2 delta);
    /// Scales shape i's semi-axes by `factor` (> 0).
    void grow(size_t i, double factor);
    /// Lowers shape i's density and rain by `amount` (>= 0), not below 0 (0: gone from the map).
    void dissolve(size_t i, double amount);
    /// Replaces all shapes (each checked as by add()).
    void setClouds(std::vector<CloudShape> shapes);
    /// The flow field that advects the centres (empty: none; replaces clouds.flow_file's).
    void setFlow(Flow flow);
    /// The map's texture (valid after a run).
    const gl::Texture2D& texture() const { return tex_; }
    int size() const { return size_; }
    /// Seconds of simulated time since the first run (at the last run).
    double elapsedSeconds() const { return elapsed_; }

private:
    void doRun(SkyVars& vars, const Logger& log) override;
    void doRelease() override;
    void doDeclare(SkyVars& vars) override;
    void render(double extent);
    void loadArtist(const std::string& path);
    void advect(double t0, double t1, double extent);
    int size_;
    std::vector<CloudShape> shapes_;
    bool generated_ = false, dirty_ = true;
    int genSeed_ = -1, genCount_ = -1;
    double genMin_ = 0, genMax_ = 0, genExtent_ = 0;
    Flow flow_, fileFlow_;
    bool userFlow_ = false;
    std::string flowPath_, artistPath_;
    bool started_ = false;
    glm::dvec2 jd0_{0.0}, offset0_{0.0}, cirrusOffset0_{0.0};
    double elapsed_ = 0.0, lastT_ = 0.0;
    gl::Texture2D tex_;
    gl::Framebuffer fbo_;
    gl::Program prog_, resolve_;
    gl::Buffer ssbo_;
    gl::VertexArray vao_;
};

namespace cpu {
/// The shapes a seed makes (the generator's own list at its first run).
std::vector<CloudShape> generateClouds(uint32_t seed, int count, double sizeMin, double sizeMax, double extent);
/// One shape's contribution (R density, G 1 - base, B top, A rain; before the max blend) at map
/// position `m` (m) of the shape drawn at `centre`; 0 outside it. Density and rain fade over the
/// noisy edge; G and B are weighted by the fade too (the cloud thins towards its rim: domes;
/// weatherTexel() resolves top < base to their mean).
glm::dvec4 shapeTexel(const CloudShape& s, glm::dvec2 m, glm::dvec2 centre);
/// The map's texel (i, j) as the GPU draws it (max over shapes and the 9 tile offsets, G flipped
/// back to the base fraction, top < base resolved to their mean), `size` texels over `extent` m.
glm::dvec4 weatherTexel(const std::vector<CloudShape>& shapes, int i, int j, int size, double extent);
/// Velocity of an image flow field at map position m (bilinear, repeat; R east, G north encoded
/// 0.5 + 0.5 v, times `scale` m/s). The image's top row is the map's north edge.
glm::dvec2 flowAt(const Image& flow, double scale, glm::dvec2 m, double extent);
/// An artist's weather map (clouds.weather_map_file) as RGBA floats in [0, 1], rows south to
/// north (the image's top row is the north edge; a 3-channel image gets A = 0, channels beyond
/// 4 are ignored, values outside [0, 1] are clamped). Throws welkin::Error naming the key and
/// `path` for fewer than 3 channels, an empty image or a non-finite value in R, G, B or A.
std::vector<float> weatherMapTexels(const Image& image, const std::string& path);
/// Checks a flow image (clouds.flow_file): at least 2 channels, R and G finite everywhere.
/// Throws welkin::Error naming the key and `path`.
void checkFlowImage(const Image& image, const std::string& path);
}  // namespace cpu

}  // namespace welkin::generators
