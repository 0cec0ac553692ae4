// welkin's lighting for a host's shaders (docs/lighting.md). Uniforms set by welkin::bindLighting()
// (welkin/lighting.hpp); every vector in the functions below is in the observer's ENU frame
// (x east, y north, z up): convert the host's world vectors with welkin_toEnu().
uniform vec3 welkin_sh9[9];            // irradiance-convolved SH, E_lm = A_l L_lm, lux
uniform samplerCube welkin_specularCube;  // GGX-prefiltered radiance, cd/m^2; mip k: roughness k / (mips - 1)
uniform float welkin_specularMips;     // number of mips of welkin_specularCube
uniform mat3 welkin_enuFromWorld;      // host world axes -> ENU

vec3 welkin_toEnu(vec3 worldVector) { return welkin_enuFromWorld * worldVector; }

// Irradiance (lux) of the environment (sky, clouds, ground; not the Sun's and Moon's direct
// light) on a surface of unit normal n: sum E_lm Y_lm(n). Lambertian radiance: albedo / pi x E.
vec3 welkin_shIrradiance(vec3 n) {
    vec3 e = welkin_sh9[0] * 0.282094792;
    e += welkin_sh9[1] * (0.488602512 * n.y) + welkin_sh9[2] * (0.488602512 * n.z) + welkin_sh9[3] * (0.488602512 * n.x);
    e += welkin_sh9[4] * (1.092548431 * n.x * n.y) + welkin_sh9[5] * (1.092548431 * n.y * n.z);
    e += welkin_sh9[6] * (0.315391565 * (3.0 * n.z * n.z - 1.0)) + welkin_sh9[7] * (1.092548431 * n.x * n.z);
    e += welkin_sh9[8] * (0.546274215 * (n.x * n.x - n.y * n.y));
    return max(e, vec3(0.0));
}

// Prefiltered radiance (cd/m^2) around the reflected direction r (unit) for a perceptual
// roughness in [0, 1] (GGX alpha = roughness^2): multiply by the split-sum's DFG term.
vec3 welkin_specularRadiance(vec3 r, float roughness) {
    float lod = clamp(roughness, 0.0, 1.0) * (welkin_specularMips - 1.0);
    return textureLod(welkin_specularCube, vec3(r.x, r.z, -r.y), lod).rgb;
}

// The same, under the shorter name of the API plan (docs/lighting.md).
vec3 welkin_specular(vec3 r, float roughness) { return welkin_specularRadiance(r, roughness); }
