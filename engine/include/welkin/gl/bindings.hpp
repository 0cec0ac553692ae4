// Texture units, image units and buffer binding points that welkin's passes share (elements,
// generators, the engine): one table for C++ and GLSL, so the two cannot disagree.
// gl::ProgramBuilder's generated header defines `WELKIN_BINDING_<NAME> <value>` for every entry
// of kTable, and the C++ binds the same constant:
//
//   // GLSL (any stage assembled by ProgramBuilder):
//   layout(binding = WELKIN_BINDING_TRANSMITTANCE_LUT) uniform sampler2D u_atmTransmittance;
//   // C++:
//   glBindTextureUnit(welkin::gl::binding::kTransmittanceLut, lut.id());
//
// Units of different kinds (texture units, image units, uniform buffers, storage buffers) are
// separate name spaces in GL. Within one kind, entries that share a value belong to passes that
// never run together (the tone map's HDR input and a LUT pass's source, say). What only one
// element uses is not here: the element asks for it by name (SkyElement::textureUnit(), ...,
// <welkin/gl/private_bindings.hpp>) and the framework assigns it from the private ranges
// (kPrivate*First..kPrivate*Last), above every entry of this table; docs/writing-an-element.md.
#pragma once
#include <array>
#include <string_view>

namespace welkin::gl::binding {

// Uniform buffers (GL_UNIFORM_BUFFER binding points).
inline constexpr int kCameraUbo = 0;      ///< welkin::CameraBlock (engine/shaders/camera.glsl), bound by the processor
inline constexpr int kAtmosphereUbo = 1;  ///< the atmosphere block (generators/atmosphere/shaders/atmosphere.glsl)
inline constexpr int kCloudUbo = 2;       ///< the cloud layer's block (generators/clouds: the density function's parameters)

// Shader storage buffers (GL_SHADER_STORAGE_BUFFER binding points).
inline constexpr int kSkyIrradianceSsbo = 0;  ///< SkyIrradiance's result (generators/atmosphere/shaders/sky_irradiance.glsl)
inline constexpr int kWeatherShapesSsbo = 1;  ///< the weather map's cloud shapes (generators/clouds/shaders/weather_map.*.glsl)
inline constexpr int kLightingSsbo = 2;       ///< SkyLighting's sums (SH partials, axis lights; engine/shaders/lighting_*.comp.glsl)
inline constexpr int kMeterSsbo = 3;          ///< the eye's meter: its work groups' block sums and counter (engine/shaders/meter.comp.glsl)

// Texture units: the engine's tone map.
inline constexpr int kHdrTexture = 0;     ///< the HDR frame read by the tone map and log-luminance passes
inline constexpr int kLogLumTexture = 1;  ///< the eye's meter, 1x1 (automatic exposure: meter.comp.glsl's means)
inline constexpr int kEyeStateTexture = 2;  ///< the eye's adaptation state, 1x1 (engine/shaders/adapt.frag.glsl)
// Texture units: the sky's LUTs, the same unit wherever a LUT is sampled.
inline constexpr int kSunViewLut = 0;              ///< sky.sun_view_lut (or its total-phase variant)
inline constexpr int kSunViewMieLut = 1;           ///< sky.sun_view_mie_lut
inline constexpr int kMoonViewLut = 2;             ///< sky.moon_view_lut (or its total-phase variant)
inline constexpr int kMoonViewMieLut = 3;          ///< sky.moon_view_mie_lut
inline constexpr int kTransmittanceLut = 4;        ///< sky.transmittance_lut
inline constexpr int kMultiScatteringLut = 5;      ///< sky.multiscattering_lut
inline constexpr int kAerialInscatterLut = 6;      ///< aerial perspective in-scattering (3-D)
inline constexpr int kAerialTransmittanceLut = 7;  ///< aerial perspective transmittance (3-D)
inline constexpr int kShLut = 8;                   ///< sky.sh_lut (spherical-harmonic radiance field)
inline constexpr int kShGroundLut = 9;             ///< the SH pass's ground-reflection input
inline constexpr int kViewTransmittanceLut = 10;   ///< sky.view_transmittance_lut (1-D)
inline constexpr int kShadowLossLut = 6;           ///< sky.shadow_loss_lut (the Sky pass; shares 6 with the aerial volume: never together)
inline constexpr int kShadowLossMieLut = 7;        ///< sky.shadow_loss_mie_lut (the Sky pass; shares 7 with the aerial volume)
// Texture units: the clouds (generators/clouds, skyelements/clouds and their readers, e.g. the
// Rainbow), sampled together with the sky's LUTs above.
inline constexpr int kCloudWeatherMap = 11;   ///< clouds.weather_map
inline constexpr int kCloudNoiseBase = 12;    ///< clouds.noise_base (3-D)
inline constexpr int kCloudNoiseDetail = 13;  ///< clouds.noise_detail (3-D)
inline constexpr int kCloudCurlNoise = 14;    ///< clouds.curl_noise
inline constexpr int kCloudPathLut = 15;      ///< clouds.path_lut
inline constexpr int kCloudShadowMap = 9;     ///< clouds.shadow_map (shares 9 with the SH pass's ground input: never together)
// Texture units: other passes.
inline constexpr int kMiePhaseLut = 0;        ///< generators/optics: the 1-D phase LUT for the current drops (Rainbow; no sky view there)
inline constexpr int kMiePhaseTable = 1;      ///< generators/optics: the 2-D phase table (angle x drop radius)
inline constexpr int kSceneDepth = 0;     ///< the host's depth texture (aerial perspective applied to a scene)
inline constexpr int kCombineSource = 0;  ///< the spectral-combine pass's source LUT
inline constexpr int kTextAtlas = 0;      ///< gl::Font's glyph atlas (welkin/gl/text.hpp), bound by TextBatch::draw()
inline constexpr int kLightingCube = 0;       ///< SkyLighting's captured radiance cube, sampled by the light-map pass
// The keyframe blend passes (generators/atmosphere/shaders/light_blend.glsl): up to four tables at
// consecutive elevations (A..D), mixed with weights in elevation.
inline constexpr int kBlendA = 0;        ///< table A (sky view: smooth part; aerial: in-scattering)
inline constexpr int kBlendAMie = 1;     ///< sky view: table A's Mie part
inline constexpr int kBlendB = 2;        ///< table B (sky view: smooth part)
inline constexpr int kBlendBMie = 3;     ///< sky view: table B's Mie part
inline constexpr int kBlendC = 4;        ///< table C (sky view: smooth part)
inline constexpr int kBlendCMie = 5;     ///< sky view: table C's Mie part
inline constexpr int kBlendD = 6;        ///< table D (sky view: smooth part)
inline constexpr int kBlendDMie = 7;     ///< sky view: table D's Mie part
inline constexpr int kBlendAerialB = 1;  ///< aerial: table B's in-scattering
inline constexpr int kBlendAerialC = 2;  ///< aerial: table C's in-scattering
inline constexpr int kBlendAerialD = 3;  ///< aerial: table D's in-scattering

// Image units (glBindImageTexture): what a generator's compute pass writes.
inline constexpr int kLutImage = 0;        ///< the (first) LUT written or updated by a compute pass
inline constexpr int kSecondLutImage = 1;  ///< a second output (the aerial perspective transmittance)
inline constexpr int kLightingOutputImage = 0;  ///< SkyLighting: the light map or specular mip a pass writes
inline constexpr int kLightingSourceImage = 1;  ///< SkyLighting: the radiance cube level a pass reads
inline constexpr int kHdrImage = 0;  ///< the tone map's read of an RGBA32F HDR frame (imageLoad: half a texelFetch's cost on llvmpipe)
inline constexpr int kMeterImage = 1;  ///< the eye's meter, 1x1, written by its compute pass (engine/shaders/meter.comp.glsl)

// The private ranges (inclusive): PrivateBindings (<welkin/gl/private_bindings.hpp>) assigns an
// element's own bindings from them, and nothing in this table falls into them (checked below).
// Each fits the minimum GL 4.5 guarantees: 80 combined texture units, 8 image units, 72
// uniform-buffer and 8 storage-buffer bindings (checked against the context in the [gl] tests),
// and the processor's GL state guard covers them (engine/src/gl/state_guard.hpp).
inline constexpr int kPrivateTextureUnitFirst = 16, kPrivateTextureUnitLast = 31;
inline constexpr int kPrivateImageUnitFirst = 4, kPrivateImageUnitLast = 7;
inline constexpr int kPrivateUboFirst = 8, kPrivateUboLast = 15;
inline constexpr int kPrivateSsboFirst = 4, kPrivateSsboLast = 7;
// The former names of the private ranges ("user ranges"), kept so that existing code builds. An
// element that binds there by hand instead of asking PrivateBindings must not also ask it for
// bindings of the same kind (they would take the same values).
inline constexpr int kUserTextureUnitFirst = kPrivateTextureUnitFirst, kUserTextureUnitLast = kPrivateTextureUnitLast;
inline constexpr int kUserImageUnitFirst = kPrivateImageUnitFirst, kUserImageUnitLast = kPrivateImageUnitLast;
inline constexpr int kUserUboFirst = kPrivateUboFirst, kUserUboLast = kPrivateUboLast;
inline constexpr int kUserSsboFirst = kPrivateSsboFirst, kUserSsboLast = kPrivateSsboLast;

/// What a binding is. UserRange: an entry that is a private range's bound, not a binding.
enum class Kind { TextureUnit, ImageUnit, UniformBuffer, StorageBuffer, UserRange };

struct Entry {
    std::string_view glslName;  ///< the GLSL macro, WELKIN_BINDING_<NAME>
    int value;
    Kind kind;
};

/// Every binding above, as ProgramBuilder writes it into each stage's generated header (the
/// private ranges' bounds too, under their former GLSL names WELKIN_BINDING_USER_*).
inline constexpr std::array kTable = {
    Entry{"WELKIN_BINDING_CAMERA_UBO", kCameraUbo, Kind::UniformBuffer},
    Entry{"WELKIN_BINDING_ATMOSPHERE_UBO", kAtmosphereUbo, Kind::UniformBuffer},
    Entry{"WELKIN_BINDING_CLOUD_UBO", kCloudUbo, Kind::UniformBuffer},
    Entry{"WELKIN_BINDING_SKY_IRRADIANCE_SSBO", kSkyIrradianceSsbo, Kind::StorageBuffer},
    Entry{"WELKIN_BINDING_WEATHER_SHAPES_SSBO", kWeatherShapesSsbo, Kind::StorageBuffer},
    Entry{"WELKIN_BINDING_LIGHTING_SSBO", kLightingSsbo, Kind::StorageBuffer},
    Entry{"WELKIN_BINDING_METER_SSBO", kMeterSsbo, Kind::StorageBuffer},
    Entry{"WELKIN_BINDING_LIGHTING_CUBE", kLightingCube, Kind::TextureUnit},
    Entry{"WELKIN_BINDING_LIGHTING_OUTPUT_IMAGE", kLightingOutputImage, Kind::ImageUnit},
    Entry{"WELKIN_BINDING_LIGHTING_SOURCE_IMAGE", kLightingSourceImage, Kind::ImageUnit},
    Entry{"WELKIN_BINDING_HDR_TEXTURE", kHdrTexture, Kind::TextureUnit},
    Entry{"WELKIN_BINDING_HDR_IMAGE", kHdrImage, Kind::ImageUnit},
    Entry{"WELKIN_BINDING_METER_IMAGE", kMeterImage, Kind::ImageUnit},
    Entry{"WELKIN_BINDING_LOG_LUM_TEXTURE", kLogLumTexture, Kind::TextureUnit},
    Entry{"WELKIN_BINDING_EYE_STATE_TEXTURE", kEyeStateTexture, Kind::TextureUnit},
    Entry{"WELKIN_BINDING_SUN_VIEW_LUT", kSunViewLut, Kind::TextureUnit},
    Entry{"WELKIN_BINDING_SUN_VIEW_MIE_LUT", kSunViewMieLut, Kind::TextureUnit},
    Entry{"WELKIN_BINDING_MOON_VIEW_LUT", kMoonViewLut, Kind::TextureUnit},
    Entry{"WELKIN_BINDING_MOON_VIEW_MIE_LUT", kMoonViewMieLut, Kind::TextureUnit},
    Entry{"WELKIN_BINDING_TRANSMITTANCE_LUT", kTransmittanceLut, Kind::TextureUnit},
    Entry{"WELKIN_BINDING_MULTISCATTERING_LUT", kMultiScatteringLut, Kind::TextureUnit},
    Entry{"WELKIN_BINDING_AERIAL_INSCATTER_LUT", kAerialInscatterLut, Kind::TextureUnit},
    Entry{"WELKIN_BINDING_AERIAL_TRANSMITTANCE_LUT", kAerialTransmittanceLut, Kind::TextureUnit},
    Entry{"WELKIN_BINDING_SH_LUT", kShLut, Kind::TextureUnit},
    Entry{"WELKIN_BINDING_SH_GROUND_LUT", kShGroundLut, Kind::TextureUnit},
    Entry{"WELKIN_BINDING_VIEW_TRANSMITTANCE_LUT", kViewTransmittanceLut, Kind::TextureUnit},
    Entry{"WELKIN_BINDING_SHADOW_LOSS_LUT", kShadowLossLut, Kind::TextureUnit},
    Entry{"WELKIN_BINDING_SHADOW_LOSS_MIE_LUT", kShadowLossMieLut, Kind::TextureUnit},
    Entry{"WELKIN_BINDING_CLOUD_WEATHER_MAP", kCloudWeatherMap, Kind::TextureUnit},
    Entry{"WELKIN_BINDING_CLOUD_NOISE_BASE", kCloudNoiseBase, Kind::TextureUnit},
    Entry{"WELKIN_BINDING_CLOUD_NOISE_DETAIL", kCloudNoiseDetail, Kind::TextureUnit},
    Entry{"WELKIN_BINDING_CLOUD_CURL_NOISE", kCloudCurlNoise, Kind::TextureUnit},
    Entry{"WELKIN_BINDING_CLOUD_PATH_LUT", kCloudPathLut, Kind::TextureUnit},
    Entry{"WELKIN_BINDING_CLOUD_SHADOW_MAP", kCloudShadowMap, Kind::TextureUnit},
    Entry{"WELKIN_BINDING_MIE_PHASE_LUT", kMiePhaseLut, Kind::TextureUnit},
    Entry{"WELKIN_BINDING_MIE_PHASE_TABLE", kMiePhaseTable, Kind::TextureUnit},
    Entry{"WELKIN_BINDING_SCENE_DEPTH", kSceneDepth, Kind::TextureUnit},
    Entry{"WELKIN_BINDING_COMBINE_SOURCE", kCombineSource, Kind::TextureUnit},
    Entry{"WELKIN_BINDING_TEXT_ATLAS", kTextAtlas, Kind::TextureUnit},
    Entry{"WELKIN_BINDING_BLEND_A", kBlendA, Kind::TextureUnit},
    Entry{"WELKIN_BINDING_BLEND_A_MIE", kBlendAMie, Kind::TextureUnit},
    Entry{"WELKIN_BINDING_BLEND_B", kBlendB, Kind::TextureUnit},
    Entry{"WELKIN_BINDING_BLEND_B_MIE", kBlendBMie, Kind::TextureUnit},
    Entry{"WELKIN_BINDING_BLEND_C", kBlendC, Kind::TextureUnit},
    Entry{"WELKIN_BINDING_BLEND_C_MIE", kBlendCMie, Kind::TextureUnit},
    Entry{"WELKIN_BINDING_BLEND_D", kBlendD, Kind::TextureUnit},
    Entry{"WELKIN_BINDING_BLEND_D_MIE", kBlendDMie, Kind::TextureUnit},
    Entry{"WELKIN_BINDING_BLEND_AERIAL_B", kBlendAerialB, Kind::TextureUnit},
    Entry{"WELKIN_BINDING_BLEND_AERIAL_C", kBlendAerialC, Kind::TextureUnit},
    Entry{"WELKIN_BINDING_BLEND_AERIAL_D", kBlendAerialD, Kind::TextureUnit},
    Entry{"WELKIN_BINDING_LUT_IMAGE", kLutImage, Kind::ImageUnit},
    Entry{"WELKIN_BINDING_SECOND_LUT_IMAGE", kSecondLutImage, Kind::ImageUnit},
    Entry{"WELKIN_BINDING_USER_TEXTURE_UNIT_FIRST", kPrivateTextureUnitFirst, Kind::UserRange},
    Entry{"WELKIN_BINDING_USER_TEXTURE_UNIT_LAST", kPrivateTextureUnitLast, Kind::UserRange},
    Entry{"WELKIN_BINDING_USER_IMAGE_UNIT_FIRST", kPrivateImageUnitFirst, Kind::UserRange},
    Entry{"WELKIN_BINDING_USER_IMAGE_UNIT_LAST", kPrivateImageUnitLast, Kind::UserRange},
    Entry{"WELKIN_BINDING_USER_UBO_FIRST", kPrivateUboFirst, Kind::UserRange},
    Entry{"WELKIN_BINDING_USER_UBO_LAST", kPrivateUboLast, Kind::UserRange},
    Entry{"WELKIN_BINDING_USER_SSBO_FIRST", kPrivateSsboFirst, Kind::UserRange},
    Entry{"WELKIN_BINDING_USER_SSBO_LAST", kPrivateSsboLast, Kind::UserRange},
};

/// True if every shared binding is >= 0 and below its kind's private range.
constexpr bool sharedBelowPrivateRanges() {
    for (const Entry& e : kTable) {
        int first = 0;
        switch (e.kind) {
            case Kind::TextureUnit: first = kPrivateTextureUnitFirst; break;
            case Kind::ImageUnit: first = kPrivateImageUnitFirst; break;
            case Kind::UniformBuffer: first = kPrivateUboFirst; break;
            case Kind::StorageBuffer: first = kPrivateSsboFirst; break;
            case Kind::UserRange: continue;
        }
        if (e.value < 0 || e.value >= first) return false;
    }
    return true;
}
static_assert(sharedBelowPrivateRanges(), "a shared binding falls into a private range");

}  // namespace welkin::gl::binding
