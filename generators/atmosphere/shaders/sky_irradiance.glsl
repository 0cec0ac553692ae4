// Sky irradiance pass (compute, SKY_IRRADIANCE_GROUPS workgroups, each summing its share of the
// samples; the CPU adds the groups' partial sums): diffuse horizontal illuminance at the observer
// from the Sun's and the Moon's sky-view LUTs (midpoint rule in cos^2 zenith and azimuth: the
// samples and their weight are atmosphere.shared.glsl's atm_irradianceSample() and
// atm_irradianceWeight(), which cpuDiffuseIrradiance() sums in another order), the direct
// horizontal illuminance of each light through the
// transmittance LUT, and the zenith radiance. Needs atmosphere.glsl (ATM_USE_TRANSMITTANCE).
layout(local_size_x = 64) in;
layout(binding = WELKIN_BINDING_SUN_VIEW_LUT) uniform sampler2D u_sunSmooth;
layout(binding = WELKIN_BINDING_SUN_VIEW_MIE_LUT) uniform sampler2D u_sunMie;
layout(binding = WELKIN_BINDING_MOON_VIEW_LUT) uniform sampler2D u_moonSmooth;
layout(binding = WELKIN_BINDING_MOON_VIEW_MIE_LUT) uniform sampler2D u_moonMie;
// o_result: sun diffuse, moon diffuse (group 0's share), sun direct, moon direct, zenith (sun),
// zenith (moon); o_partial[2 g], [2 g + 1]: group g's sun and moon diffuse sums (g >= 1).
layout(std430, binding = WELKIN_BINDING_SKY_IRRADIANCE_SSBO) buffer Result { vec4 o_result[6]; vec4 o_partial[2 * SKY_IRRADIANCE_GROUPS]; };
uniform float u_h;
uniform vec3 u_sunDir, u_moonDir;  // unit ENU
uniform vec3 u_sunE, u_moonE;      // lux per channel
uniform int u_nz, u_na;
uniform float u_invScale;
#ifdef SKY_IRRADIANCE_ECLIPSE
// A solar eclipse: the Sun's tables are sky.eclipse_view_lut (absolute azimuth u = az / 2 pi, the
// sky view's latitude), summed over the whole circle of azimuth; u_sunDir is the full ENU
// direction. (The direct light's visible fraction, sun.eclipse_fraction, is applied on the CPU:
// it changes every frame of a partial phase, the tables only every ~2 s.)
vec3 eclipseSample(float mu, float az, float nu) {
    vec2 size = vec2(textureSize(u_sunSmooth, 0));
    vec2 uv = vec2(az * (0.5 / ATM_PI), skyViewClampHalf(skyViewUv(u_h, mu, 0.0, size), size).y);
    return (texture(u_sunSmooth, uv).rgb + texture(u_sunMie, uv).rgb * miePhase(nu)) * u_invScale;
}
#endif
shared vec3 s_sun[64];
shared vec3 s_moon[64];

void main() {
    uint id = gl_LocalInvocationID.x;
    vec3 sumSun = vec3(0.0), sumMoon = vec3(0.0);
    float sinS = sqrt(max(1.0 - u_sunDir.z * u_sunDir.z, 0.0));
    float sinM = sqrt(max(1.0 - u_moonDir.z * u_moonDir.z, 0.0));
    int total = u_nz * u_na;
    uint group = gl_WorkGroupID.x;
    for (int k = int(group * 64u + id); k < total; k += 64 * SKY_IRRADIANCE_GROUPS) {
        // The sample's direction and weight: atmosphere.shared.glsl, as cpuDiffuseIrradiance().
        vec3 smp = atm_irradianceSample(k / u_na, k % u_na, u_nz, u_na);
        float mu = smp.x, sinV = smp.y, az = smp.z;
        float nuS = atm_cosViewLight(mu, sinV, az, u_sunDir.z, sinS);
        float nuM = atm_cosViewLight(mu, sinV, az, u_moonDir.z, sinM);
#ifdef SKY_IRRADIANCE_ECLIPSE
        // (j + 0.5) / na of the whole circle: the same weight per sample as the half circle's.
        float azE = 2.0 * az;
        vec3 dirE = vec3(sinV * sin(azE), sinV * cos(azE), mu);
        sumSun += eclipseSample(mu, azE, clamp(dot(dirE, u_sunDir), -1.0, 1.0));
#else
        sumSun += skyViewSample(u_sunSmooth, u_sunMie, u_h, mu, az, nuS, u_invScale);
#endif
        sumMoon += skyViewSample(u_moonSmooth, u_moonMie, u_h, mu, az, nuM, u_invScale);
    }
    s_sun[id] = sumSun;
    s_moon[id] = sumMoon;
    barrier();
    if (id == 0u) {
        vec3 a = vec3(0.0), b = vec3(0.0);
        for (int i = 0; i < 64; ++i) {
            a += s_sun[i];
            b += s_moon[i];
        }
        float w = atm_irradianceWeight(u_nz, u_na);
        o_partial[2u * group] = vec4(a * w * u_sunE, 0.0);
        o_partial[2u * group + 1u] = vec4(b * w * u_moonE, 0.0);
        if (group != 0u) return;
        o_result[0] = vec4(0.0);  // the sums are the CPU's (o_partial)
        o_result[1] = vec4(0.0);
        o_result[2] = vec4(transmittanceToLight(u_h, u_sunDir.z, atm_solarIlluminance.w) * max(u_sunDir.z, 0.0) * u_sunE, 0.0);
        o_result[3] = vec4(transmittanceToLight(u_h, u_moonDir.z, 0.0045) * max(u_moonDir.z, 0.0) * u_moonE, 0.0);
#ifdef SKY_IRRADIANCE_ECLIPSE
        vec3 zs = eclipseSample(1.0, 0.0, u_sunDir.z) * u_sunE;
#else
        vec3 zs = skyViewSample(u_sunSmooth, u_sunMie, u_h, 1.0, 0.0, u_sunDir.z, u_invScale) * u_sunE;
#endif
        vec3 zm = skyViewSample(u_moonSmooth, u_moonMie, u_h, 1.0, 0.0, u_moonDir.z, u_invScale) * u_moonE;
        o_result[4] = vec4(zs, 0.0);
        o_result[5] = vec4(zm, 0.0);
    }
}
