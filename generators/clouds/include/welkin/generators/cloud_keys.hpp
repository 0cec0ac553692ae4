// The clouds' shared SkyVars keys: one declaration for the cloud generators (noise, weather map,
// cloud-path LUT, shadow map), the Clouds element and any element that reads the clouds (the
// Rainbow reads the rain). Names follow SevenSky's Clouds variables (Papp 2018, fig. 6.6):
// VOLUMETRIC_CLOUDS_FROM/TO -> clouds.bottom_m/top_m, Coverage -> clouds.coverage,
// AltoCoverage -> clouds.cirrus_coverage, DetailScale -> clouds.detail_scale, Scattering ->
// clouds.scattering_per_m, RainDensity -> clouds.rain_density, CloudOffset -> clouds.weather_offset_m,
// WEATHER_MAP / NOISE_DETAIL_MAP / HIGH_ALTITUDE_CLOUD_MAP / CLOUD_PATH_LUT -> the texture keys.
//
//   vars.set(welkin::generators::cloudkeys::bottom, 1500.0);          // m above the ground
//   vars.set(welkin::generators::cloudkeys::coverage, 0.6);           // [0, 1]
//   welkin::TextureRef w = vars.get(welkin::generators::cloudkeys::weatherMap);
//   welkin::generators::validateCloudLayer(vars);                      // throws on bottom >= top
//
// World frame: ENU at the observer (x east, y north, z up), metres. Heights are above the ground
// (the planet's sphere, lightkeys::planetRadius), not above the observer.
//
// The weather map (clouds.weather_map, 2-D, RGBA, linear, GL_REPEAT in both directions) covers
// a square of clouds.weather_extent_m on a side, tiled without seams over the whole planet's
// tangent plane. A ground point at ENU (x, y) metres reads it at
//     uv = (vec2(x, y) + clouds.weather_offset_m) / clouds.weather_extent_m      (repeat)
// Channels (SevenSky's R, G, B plus rain):
//     R  cloud density W_density in [0, 1] (0: no cloud)
//     G  W_H^bottom in [0, 1]: where the cloud's base sits, as a fraction of the layer
//        (0 = clouds.bottom_m, 1 = clouds.top_m)
//     B  W_H^top in [0, 1]: where its top sits (same fraction; B >= G where R > 0)
//     A  rain density of the cloud in [0, 1] (0: dry); the rain rate under it is
//        A * clouds.rain_density * kRainRateAtFullDensityMmH, falling from the cloud's base
#pragma once
#include <welkin/vars.hpp>

namespace welkin::generators {

namespace cloudkeys {
// --- The cumulus layer (a spherical shell) ------------------------------------------------------
inline const Key<double> bottom{"clouds.bottom_m", Range{0, 2e4}, "base of the volumetric cloud layer above the ground (SevenSky VOLUMETRIC_CLOUDS_FROM)"};
inline const Key<double> top{"clouds.top_m", Range{1e2, 2.5e4}, "top of the volumetric cloud layer above the ground (SevenSky VOLUMETRIC_CLOUDS_TO); > clouds.bottom_m"};
inline const Key<double> coverage{"clouds.coverage", Range{0, 1}, "volumetric cloud coverage: 0 clear, 1 the weather map's density (SevenSky Coverage, eq. 5.4)"};
inline const Key<double> detailScale{"clouds.detail_scale", Range{0, 4}, "strength of the erosion by the detail noise (SevenSky DetailScale)"};
inline const Key<double> cloudType{"clouds.cloud_type", Range{0, 1}, "height gradient of the cumulus layer: 0 stratocumulus (a sheet between the weather map's base and top), 1 cumulus (flat bases at clouds.bottom_m, tapered tops); between: a blend (Schneider 2015)"};
inline const Key<double> scattering{"clouds.scattering_per_m", Range{0, 1}, "scattering coefficient of cloud at density 1 (SevenSky Scattering); single-scattering albedo ~1", "1/m"};
// --- Cirrus ---------------------------------------------------------------------------------------
inline const Key<double> cirrusCoverage{"clouds.cirrus_coverage", Range{0, 1}, "high-altitude cirrus coverage (SevenSky AltoCoverage)"};
inline const Key<glm::dvec2> cirrusWind{"clouds.cirrus_wind_m_s", Range{-200, 200}, "wind at the cirrus' height (east, north), moving clouds.cirrus_offset_m; undeclared: clouds.wind_m_s", "m/s"};
inline const Key<glm::dvec2> cirrusOffset{"clouds.cirrus_offset_m", Range{-1e12, 1e12}, "the cirrus' offset on the curl noise (as clouds.weather_offset_m; written by the weather-map generator); undeclared: clouds.weather_offset_m"};
inline const Key<double> cirrusHeight{"clouds.cirrus_height_m", Range{4e3, 2e4}, "height of the cirrus layer above the ground"};
// --- Rain -------------------------------------------------------------------------------------------
inline const Key<double> rainDensity{"clouds.rain_density", Range{0, 1}, "rain from the raining clouds of the weather map (SevenSky RainDensity): rate = weather A x this x 20 mm/h; 0 dry"};
// --- Weather map and its motion -----------------------------------------------------------------
inline const Key<TextureRef> weatherMap{"clouds.weather_map", "weather map: R density, G base, B top (fractions of the layer), A rain density; repeat"};
inline const Key<double> weatherExtent{"clouds.weather_extent_m", Range{1e3, 1e6}, "side of the square the weather map covers (it repeats)"};
inline const Key<glm::dvec2> weatherOffset{"clouds.weather_offset_m", Range{-1e12, 1e12}, "the weather map's offset: uv = (ENU xy + offset) / extent (SevenSky CloudOffset)"};
inline const Key<std::string> weatherFile{"clouds.weather_map_file", "an artist's weather map image (OpenImageIO; RGBA as clouds.weather_map); empty: generated"};
inline const Key<int> seed{"clouds.seed", Range{0, 2147483647}, "seed of the generated weather map and noise"};
inline const Key<glm::dvec2> wind{"clouds.wind_m_s", Range{-200, 200}, "constant wind (east, north) moving the clouds", "m/s"};
// --- Noise and LUT textures ---------------------------------------------------------------------
inline const Key<TextureRef> noiseBase{"clouds.noise_base", "3-D tileable base noise: R Perlin-Worley, GBA Worley fBm at 2x, 4x, 8x (128^3 default)"};
inline const Key<TextureRef> noiseDetail{"clouds.noise_detail", "3-D tileable detail noise: RGB Worley fBm at three frequencies (32^3 default)"};
inline const Key<TextureRef> curlNoise{"clouds.curl_noise", "2-D tileable curl noise for the cirrus (SevenSky HIGH_ALTITUDE_CLOUD_MAP)"};
inline const Key<TextureRef> pathLut{"clouds.path_lut", "cloud-path LUT: entry and exit distances of the cloud shell by view zenith and altitude (SevenSky CLOUD_PATH_LUT)"};
// --- Noise tiling (the density function's scales; generators/clouds, cloud_density.hpp) -----------
inline const Key<double> noiseBasePeriod{"clouds.noise_base_period_m", Range{5e2, 1e5}, "horizontal and vertical period of the 3-D base noise (one tile of clouds.noise_base)", "m"};
inline const Key<double> noiseDetailPeriod{"clouds.noise_detail_period_m", Range{5e1, 2e4}, "period of the 3-D detail noise (one tile of clouds.noise_detail)", "m"};
inline const Key<double> curlPeriod{"clouds.curl_period_m", Range{1e3, 1e6}, "period of the 2-D curl noise on the cirrus layer (one tile of clouds.curl_noise)", "m"};
// --- Weather-map generator (generators/clouds/weather_map.hpp) -----------------------------------
inline const Key<int> cloudCount{"clouds.cloud_count", Range{0, 4096}, "number of cloud shapes generated on the weather map (one tile)"};
inline const Key<double> cloudSizeMin{"clouds.cloud_size_min_m", Range{50, 1e5}, "smallest semi-axis of a generated cloud shape", "m"};
inline const Key<double> cloudSizeMax{"clouds.cloud_size_max_m", Range{50, 1e5}, "largest semi-axis of a generated cloud shape; >= clouds.cloud_size_min_m", "m"};
inline const Key<std::string> flowFile{"clouds.flow_file", "image of a 2-D velocity field over one weather-map tile (OpenImageIO; R east, G north encoded 0.5 + 0.5 v, v in [-1, 1] x clouds.flow_scale_m_s); empty: none"};
inline const Key<double> flowScale{"clouds.flow_scale_m_s", Range{0, 200}, "velocity of a flow-image value of 1", "m/s"};
inline const Key<TextureRef> shadowMap{"clouds.shadow_map", "transmittance of the light through the clouds over the ground around the observer"};
// --- Cloud shadows (generators/clouds/cloud_shadow.hpp) -----------------------------------------
inline const Key<double> shadowExtent{"clouds.shadow_extent_m", Range{1e3, 5e5}, "side of the square of ground, centred below the observer, that clouds.shadow_map covers"};
inline const Key<int> shadowResolution{"clouds.shadow_resolution", Range{16, 2048}, "texels per side of clouds.shadow_map"};
/// With render.interactive, a shadow map whose light (or wind offset) moved is rebuilt over this
/// many frames into a second texture (a 1/N of its rows per frame) and shown when complete
/// (clouds.sky_shadow too, into its own second table); meanwhile the last complete map and the
/// light it was built for stay published. 1: rebuilt whole in the frame (renders always are).
inline const Key<int> shadowSlices{"clouds.shadow_slices", Range{1, 64}, "frames over which a moving light's cloud shadow map and the sky's cloud shadow are rebuilt with render.interactive (1: whole each frame)"};
inline const Key<int> shadowSteps{"clouds.shadow_steps", Range{1, 256}, "march steps through the cumulus layer per shadow-map texel"};
inline const Key<glm::dvec3> shadowLight{"clouds.shadow_light_direction", Range{-1, 1}, "unit vector (ENU) to the light clouds.shadow_map was built for (the Sun, or the Moon at night; elevation clamped to >= 0)"};
inline const Key<glm::dvec2> shadowOffset{"clouds.shadow_offset_m", Range{-1e12, 1e12}, "clouds.weather_offset_m when clouds.shadow_map was built (the host's lookup shifts by the change since)"};
}  // namespace cloudkeys

/// Rain rate under a weather-map cloud of rain density 1 when clouds.rain_density is 1, mm/h:
/// a heavy shower (rain rates: light < 2.5, moderate 2.5-10, heavy 10-50 mm/h; AMS glossary).
inline constexpr double kRainRateAtFullDensityMmH = 20.0;

/// Checks the combination of the layer's keys (when declared): clouds.bottom_m + 100 m <=
/// clouds.top_m < clouds.cirrus_height_m. Throws welkin::Error with a one-line message naming
/// both keys and their values.
void validateCloudLayer(const SkyVars& vars);

}  // namespace welkin::generators
