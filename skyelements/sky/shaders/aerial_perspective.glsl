// Aerial perspective for a host's shaders: in-scattered radiance (cd/m^2) and transmittance
// between the observer and a point of the host's scene, from the sky's aerial-perspective volume
// (generators/sky_luts.hpp, AerialPerspectiveLut; Sun light only).
//
// Include after generators/atmosphere.glsl (welkin::elements::aerialPerspectiveGlslChunks()
// returns both in order) and bind: the atmosphere block (WELKIN_BINDING_ATMOSPHERE_UBO:
// welkin::elements::AerialPerspective::bindResources() does it), the two volumes on units
// WELKIN_BINDING_AERIAL_INSCATTER_LUT and WELKIN_BINDING_AERIAL_TRANSMITTANCE_LUT, and set the
// uniforms below (bindResources() too). Then, in the host's fragment shader:
//
//   vec3 T;
//   vec3 inscatter = welkin_aerialPerspective(worldDirEnu, distanceMetres, T);
//   colour = colour * T + inscatter;     // colour in cd/m^2 (or scale inscatter to your units)
layout(binding = WELKIN_BINDING_AERIAL_INSCATTER_LUT) uniform sampler3D welkin_apInscatter;
layout(binding = WELKIN_BINDING_AERIAL_TRANSMITTANCE_LUT) uniform sampler3D welkin_apTransmittance;
uniform vec3 welkin_apSunDir;        // unit ENU
uniform vec3 welkin_apSunE;          // Sun's illuminance above the atmosphere, lux per channel
uniform float welkin_apH;            // observer height, m (clamped into the atmosphere)
uniform float welkin_apMaxDistance;  // m, distance of the last slice
uniform float welkin_apInvScale;     // 1 / kLutScale

vec3 welkin_aerialPerspective(vec3 dir, float distanceM, out vec3 transmittance) {
    vec3 size = vec3(textureSize(welkin_apInscatter, 0));
    float mu = clamp(dir.z, -1.0, 1.0);
    vec2 a = dir.xy, b = welkin_apSunDir.xy;
    float cosAz = dot(a, b) * inversesqrt(max(dot(a, a) * dot(b, b), 1e-30));  // 0 at the zenith: any azimuth
    vec2 uv = skyViewClampHalf(skyViewUvS(atm_horizonS(welkin_apH), mu, cosAz, size.xy), size.xy);
    // Slice k holds the values at d_k = D ((k + 1) / N)^2.
    float w = sqrt(max(distanceM, 0.0) / welkin_apMaxDistance) * size.z;
    float f = clamp(w, 0.0, 1.0);  // before the first slice: linear in distance from the observer
    float z = (clamp(w - 1.0, 0.0, size.z - 1.0) + 0.5) / size.z;
    vec3 L = texture(welkin_apInscatter, vec3(uv, z)).rgb * welkin_apInvScale * welkin_apSunE;
    vec3 T = texture(welkin_apTransmittance, vec3(uv, z)).rgb;
    float lin = w < 1.0 ? f * f : 1.0;  // d / d_0 when d < d_0
    transmittance = mix(vec3(1.0), T, lin);
    return L * lin;
}
