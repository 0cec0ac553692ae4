#include <welkin_host/renderer.hpp>

#include <epoxy/gl.h>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/type_ptr.hpp>

#include <cmath>
#include <numbers>
#include <stdexcept>

namespace host {

namespace {

// Texture units the renderer uses (the cloud shadow's is WELKIN_BINDING_CLOUD_SHADOW_MAP, 9).
constexpr GLuint kUnitBrdf = 0, kUnitCube = 1, kUnitShadow = 2;

const char* kVertex = R"(#version 450 core
layout(location = 0) in vec3 a_position;
layout(location = 1) in vec3 a_normal;
layout(location = 2) in vec4 a_color;
uniform mat4 u_model;
uniform mat3 u_normalMatrix;
uniform mat4 u_viewProjection;
out vec3 v_world;
out vec3 v_normal;
out vec4 v_color;
void main() {
    vec4 w = u_model * vec4(a_position, 1.0);
    v_world = w.xyz;
    v_normal = u_normalMatrix * a_normal;
    v_color = a_color;
    gl_Position = u_viewProjection * w;
}
)";

const char* kDepthVertex = R"(#version 450 core
layout(location = 0) in vec3 a_position;
uniform mat4 u_model;
uniform mat4 u_lightViewProjection;
void main() { gl_Position = u_lightViewProjection * u_model * vec4(a_position, 1.0); }
)";
const char* kDepthFragment = R"(#version 450 core
void main() {}
)";

// The fragment shader's body (after the optional cloud-shadow chunk).
const char* kFragment = R"(
const float PI = 3.14159265358979;
in vec3 v_world;
in vec3 v_normal;
in vec4 v_color;
out vec4 o_radiance;

uniform vec3 u_eye;
uniform vec4 u_baseColor;
uniform float u_metallic;
uniform float u_roughness;
uniform vec3 u_sunDir, u_sunE;    // towards the Sun (world), lux per channel
uniform vec3 u_moonDir, u_moonE;
uniform vec2 u_cloudShadowOn;     // (Sun, Moon): 1 where the shadow map is made for that light
uniform mat4 u_worldToEnuPoint;
layout(binding = 0) uniform sampler2D u_brdf;
uniform int u_shadowLight;        // the scene's shadow map is the Sun's (1), the Moon's (2), none (0)
uniform mat4 u_shadowViewProjection;
uniform float u_shadowTexel;      // metres per shadow-map texel
layout(binding = 2) uniform sampler2DShadow u_shadowMap;

// The fraction of the light reaching p (1: lit), from the scene's shadow map: 2 x 2 filtered taps
// at a point pushed off the surface along its normal (more at grazing light) against acne.
float sceneShadow(vec3 p, vec3 n, vec3 l) {
    float NoL = clamp(dot(n, l), 0.0, 1.0);
    vec3 q = p + n * u_shadowTexel * (1.0 + 2.0 * (1.0 - NoL));
    vec4 c = u_shadowViewProjection * vec4(q, 1.0);
    vec3 s = c.xyz / c.w * 0.5 + 0.5;
    if (any(lessThan(s, vec3(0.0))) || any(greaterThan(s, vec3(1.0)))) return 1.0;  // outside the map: lit
    vec2 texel = 1.0 / vec2(textureSize(u_shadowMap, 0));
    float sum = 0.0;
    for (int k = 0; k < 4; ++k) {
        vec2 o = (vec2(k & 1, k >> 1) - 0.5) * texel;
        sum += texture(u_shadowMap, vec3(s.xy + o, s.z));
    }
    return 0.25 * sum;
}

float D_GGX(float NoH, float a) {
    float a2 = a * a;
    float d = NoH * NoH * (a2 - 1.0) + 1.0;
    return a2 / (PI * d * d);
}
float V_SmithGGXCorrelated(float NoV, float NoL, float a) {
    float a2 = a * a;
    float gv = NoL * sqrt(NoV * NoV * (1.0 - a2) + a2);
    float gl = NoV * sqrt(NoL * NoL * (1.0 - a2) + a2);
    return 0.5 / max(gv + gl, 1e-8);
}
vec3 F_Schlick(vec3 f0, float VoH) { return f0 + (1.0 - f0) * pow(1.0 - VoH, 5.0); }

// Radiance reflected towards v from a directional light of illuminance E (lux) towards l.
vec3 directLight(vec3 n, vec3 v, vec3 l, vec3 E, vec3 diffuseColor, vec3 f0, float roughness) {
    float NoL = dot(n, l);
    if (NoL <= 0.0 || max(E.r, max(E.g, E.b)) <= 0.0) return vec3(0.0);
    vec3 h = normalize(v + l);
    float NoV = max(dot(n, v), 1e-4), NoH = max(dot(n, h), 0.0), VoH = max(dot(v, h), 0.0);
    float a = max(roughness, 0.045);
    a *= a;
    vec3 spec = D_GGX(NoH, a) * V_SmithGGXCorrelated(NoV, NoL, a) * F_Schlick(f0, VoH);
    return (diffuseColor / PI + spec) * E * NoL;
}

void main() {
    vec3 n = normalize(v_normal);
    vec3 v = normalize(u_eye - v_world);
    if (dot(n, v) < 0.0) n = -n;  // a back face seen from behind (thin geometry)
    vec3 base = u_baseColor.rgb * v_color.rgb;
    float roughness = clamp(u_roughness, 0.0, 1.0);
    float metallic = clamp(u_metallic, 0.0, 1.0);
    vec3 diffuseColor = base * (1.0 - metallic);
    vec3 f0 = mix(vec3(0.04), base, metallic);

    float sunShadow = 1.0, moonShadow = 1.0;
#ifdef HOST_CLOUD_SHADOW
    float s = welkin_cloudShadow((u_worldToEnuPoint * vec4(v_world, 1.0)).xyz);
    sunShadow = mix(1.0, s, u_cloudShadowOn.x);
    moonShadow = mix(1.0, s, u_cloudShadowOn.y);
#endif
    if (u_shadowLight == 1) sunShadow *= sceneShadow(v_world, normalize(v_normal), u_sunDir);
    if (u_shadowLight == 2) moonShadow *= sceneShadow(v_world, normalize(v_normal), u_moonDir);
    vec3 L = directLight(n, v, u_sunDir, u_sunE * sunShadow, diffuseColor, f0, roughness)
           + directLight(n, v, u_moonDir, u_moonE * moonShadow, diffuseColor, f0, roughness);

    L += diffuseColor / PI * welkin_shIrradiance(welkin_toEnu(n));

    float NoV = max(dot(n, v), 1e-4);
    vec3 r = reflect(-v, n);
    vec2 ab = texture(u_brdf, vec2(NoV, roughness)).rg;
    L += welkin_specularRadiance(welkin_toEnu(r), roughness) * (f0 * ab.x + ab.y);
    o_radiance = vec4(L, 1.0);
}
)";

double radicalInverse(uint32_t bits) {
    bits = (bits << 16u) | (bits >> 16u);
    bits = ((bits & 0x55555555u) << 1u) | ((bits & 0xAAAAAAAAu) >> 1u);
    bits = ((bits & 0x33333333u) << 2u) | ((bits & 0xCCCCCCCCu) >> 2u);
    bits = ((bits & 0x0F0F0F0Fu) << 4u) | ((bits & 0xF0F0F0F0u) >> 4u);
    bits = ((bits & 0x00FF00FFu) << 8u) | ((bits & 0xFF00FF00u) >> 8u);
    return double(bits) * 2.3283064365386963e-10;  // / 2^32
}

}  // namespace

std::vector<glm::vec2> computeBrdfTable(int size, int samples) {
    std::vector<glm::vec2> table(size_t(size) * size_t(size));
    for (int j = 0; j < size; ++j) {
        const double roughness = (j + 0.5) / size;
        const double a = roughness * roughness, a2 = a * a;
        for (int i = 0; i < size; ++i) {
            const double NoV = (i + 0.5) / size;
            const glm::dvec3 v(std::sqrt(1.0 - NoV * NoV), 0.0, NoV);  // n = +z
            double scale = 0.0, bias = 0.0;
            for (int k = 0; k < samples; ++k) {
                // GGX importance sample of the half vector: pdf(h) = D(h) (n.h).
                const double u1 = (k + 0.5) / samples, u2 = radicalInverse(uint32_t(k));
                const double phi = 2.0 * std::numbers::pi * u2;
                const double cosT = std::sqrt((1.0 - u1) / (1.0 + (a2 - 1.0) * u1));
                const double sinT = std::sqrt(1.0 - cosT * cosT);
                const glm::dvec3 h(sinT * std::cos(phi), sinT * std::sin(phi), cosT);
                const double VoH = glm::dot(v, h);
                const glm::dvec3 l = 2.0 * VoH * h - v;
                const double NoL = l.z, NoH = h.z;
                if (NoL <= 0.0 || VoH <= 0.0) continue;
                // f (n.l) / pdf(l) with pdf(l) = D (n.h) / (4 v.h) and f = D V F:
                // = 4 V (n.l) (v.h) / (n.h) x F; F = F0 (1 - Fc) + Fc.
                const double gv = NoL * std::sqrt(NoV * NoV * (1.0 - a2) + a2);
                const double gl = NoV * std::sqrt(NoL * NoL * (1.0 - a2) + a2);
                const double vis = 0.5 / (gv + gl);
                const double w = 4.0 * vis * NoL * VoH / NoH;
                const double fc = std::pow(1.0 - VoH, 5.0);
                scale += (1.0 - fc) * w;
                bias += fc * w;
            }
            table[size_t(j) * size_t(size) + size_t(i)] = glm::vec2(float(scale / samples), float(bias / samples));
        }
    }
    return table;
}

SceneRenderer::SceneRenderer(const ShadowSettings& shadows) : shadowSettings_(shadows) {
    if (shadows.size < 256 || shadows.size > 8192) throw std::invalid_argument("ShadowSettings::size not in [256, 8192]");
    if (!(shadows.halfExtentM > 0.0f)) throw std::invalid_argument("ShadowSettings::halfExtentM not > 0");
    const int n = 64;
    const std::vector<glm::vec2> table = computeBrdfTable(n, 512);
    brdfTable_ = GlName::texture(GL_TEXTURE_2D);
    glTextureStorage2D(brdfTable_.id(), 1, GL_RG32F, n, n);
    glTextureSubImage2D(brdfTable_.id(), 0, 0, 0, n, n, GL_RG, GL_FLOAT, table.data());
    glTextureParameteri(brdfTable_.id(), GL_TEXTURE_MIN_FILTER, GL_LINEAR);
    glTextureParameteri(brdfTable_.id(), GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    glTextureParameteri(brdfTable_.id(), GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glTextureParameteri(brdfTable_.id(), GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    program(false, {});
    depthProgram_ = buildProgram("host shadow depth", {{GL_VERTEX_SHADER, kDepthVertex}, {GL_FRAGMENT_SHADER, kDepthFragment}});
    // The shadow map: a depth texture compared in the lookup (sampler2DShadow), edges clamped.
    shadowMap_ = GlName::texture(GL_TEXTURE_2D);
    glTextureStorage2D(shadowMap_.id(), 1, GL_DEPTH_COMPONENT32F, shadows.size, shadows.size);
    glTextureParameteri(shadowMap_.id(), GL_TEXTURE_MIN_FILTER, GL_LINEAR);
    glTextureParameteri(shadowMap_.id(), GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    glTextureParameteri(shadowMap_.id(), GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glTextureParameteri(shadowMap_.id(), GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    glTextureParameteri(shadowMap_.id(), GL_TEXTURE_COMPARE_MODE, GL_COMPARE_REF_TO_TEXTURE);
    glTextureParameteri(shadowMap_.id(), GL_TEXTURE_COMPARE_FUNC, GL_LEQUAL);
    shadowFbo_ = GlName::framebuffer();
    glNamedFramebufferTexture(shadowFbo_.id(), GL_DEPTH_ATTACHMENT, shadowMap_.id(), 0);
    glNamedFramebufferDrawBuffer(shadowFbo_.id(), GL_NONE);
    glNamedFramebufferReadBuffer(shadowFbo_.id(), GL_NONE);
    if (glCheckNamedFramebufferStatus(shadowFbo_.id(), GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
        throw std::runtime_error("SceneRenderer: the shadow framebuffer is incomplete");
    checkGl("SceneRenderer()");
}

void SceneRenderer::renderShadows(const Scene& scene, const SceneLighting& lighting, const glm::vec3& centreWorld) {
    shadowLight_ = 0;
    if (!shadowSettings_.enabled) return;
    // The brighter of the two lights above the horizon (world y up is not assumed: the
    // horizon is the ENU z of the direction).
    auto up = [&](const DirectionalLight& l) { return (lighting.enuFromWorld * glm::dvec3(l.directionWorld)).z > 0.0; };
    auto lux = [](const DirectionalLight& l) { return glm::dot(l.illuminanceRgb, glm::vec3(0.2126f, 0.7152f, 0.0722f)); };
    const bool sun = up(lighting.sun) && lux(lighting.sun) > 0.0f;
    const bool moon = up(lighting.moon) && lux(lighting.moon) > 0.0f;
    if (!sun && !moon) return;
    shadowLight_ = sun && (!moon || lux(lighting.sun) >= lux(lighting.moon)) ? 1 : 2;
    const glm::vec3 l = glm::normalize((shadowLight_ == 1 ? lighting.sun : lighting.moon).directionWorld);

    // Light space: looking down the light onto the square about the centre, depth over 4 km.
    const float e = shadowSettings_.halfExtentM, reach = 2000.0f;
    const glm::vec3 helper = std::abs(l.y) > 0.99f ? glm::vec3(0.0f, 0.0f, -1.0f) : glm::vec3(0.0f, 1.0f, 0.0f);
    // A light-space frame fixed to the world origin, moved to the centre in whole texels (the
    // shadows' edges stay put as the camera moves), the centre 'reach' in front of it.
    const glm::mat4 view0 = glm::lookAt(l * reach, glm::vec3(0.0f), helper);
    const float texel = 2.0f * e / float(shadowSettings_.size);
    const glm::vec4 c = view0 * glm::vec4(centreWorld, 1.0f);
    const glm::vec2 snapped = texel * glm::floor(glm::vec2(c) / texel);
    const glm::mat4 view = glm::translate(glm::mat4(1.0f), glm::vec3(-snapped.x, -snapped.y, -reach - c.z)) * view0;
    shadowViewProjection_ = glm::ortho(-e, e, -e, e, 1.0f, 2.0f * reach) * view;

    GLint fb = 0, vp[4], clipOrigin = 0, clipDepth = 0, depthFunc = 0;
    glGetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &fb);
    glGetIntegerv(GL_VIEWPORT, vp);
    glGetIntegerv(GL_CLIP_ORIGIN, &clipOrigin);
    glGetIntegerv(GL_CLIP_DEPTH_MODE, &clipDepth);
    glGetIntegerv(GL_DEPTH_FUNC, &depthFunc);
    const GLboolean depthTest = glIsEnabled(GL_DEPTH_TEST), cull = glIsEnabled(GL_CULL_FACE);
    GLboolean depthMask = GL_TRUE;
    glGetBooleanv(GL_DEPTH_WRITEMASK, &depthMask);

    glBindFramebuffer(GL_FRAMEBUFFER, shadowFbo_.id());
    glViewport(0, 0, shadowSettings_.size, shadowSettings_.size);
    glClipControl(GL_LOWER_LEFT, GL_NEGATIVE_ONE_TO_ONE);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    glDepthMask(GL_TRUE);
    glDisable(GL_CULL_FACE);  // the terrain is one-sided: both sides cast
    glEnable(GL_POLYGON_OFFSET_FILL);
    glPolygonOffset(1.5f, 2.0f);
    const float one = 1.0f;
    glClearNamedFramebufferfv(shadowFbo_.id(), GL_DEPTH, 0, &one);
    glUseProgram(depthProgram_.id());
    glUniformMatrix4fv(glGetUniformLocation(depthProgram_.id(), "u_lightViewProjection"), 1, GL_FALSE, glm::value_ptr(shadowViewProjection_));
    const GLint uModel = glGetUniformLocation(depthProgram_.id(), "u_model");
    for (const auto& d : scene.draws()) {
        const auto& prim = scene.primitives()[size_t(d.primitive)];
        glUniformMatrix4fv(uModel, 1, GL_FALSE, glm::value_ptr(d.world));
        glBindVertexArray(prim.vao.id());
        glDrawElements(GL_TRIANGLES, prim.indexCount, GL_UNSIGNED_INT, nullptr);
    }
    glBindVertexArray(0);
    glDisable(GL_POLYGON_OFFSET_FILL);
    glBindFramebuffer(GL_FRAMEBUFFER, GLuint(fb));
    glViewport(vp[0], vp[1], vp[2], vp[3]);
    glClipControl(GLenum(clipOrigin), GLenum(clipDepth));
    glDepthFunc(GLenum(depthFunc));
    glDepthMask(depthMask);
    if (!depthTest) glDisable(GL_DEPTH_TEST);
    if (cull) glEnable(GL_CULL_FACE);
}

unsigned SceneRenderer::program(bool cloudShadow, const std::string& cloudGlsl) {
    GlName& p = cloudShadow ? programClouds_ : programPlain_;
    if (!p) {
        std::string fs = "#version 450 core\n";
        for (const auto& [name, text] : welkin::lightingGlslChunks()) fs += text + "\n";  // welkin_shIrradiance ...
        if (cloudShadow) fs += "#define HOST_CLOUD_SHADOW 1\n" + cloudGlsl + "\n";
        fs += kFragment;
        p = buildProgram(cloudShadow ? "host PBR (cloud shadow)" : "host PBR", {{GL_VERTEX_SHADER, kVertex}, {GL_FRAGMENT_SHADER, fs}});
    }
    return p.id();
}

void SceneRenderer::draw(const Scene& scene, const ViewParams& view, const SceneLighting& lighting) {
    const bool clouds = !lighting.cloudShadowGlsl.empty();
    const GLuint prog = program(clouds, lighting.cloudShadowGlsl);
    glUseProgram(prog);
    auto loc = [prog](const char* name) { return glGetUniformLocation(prog, name); };
    const glm::mat4 vp = view.projection * view.view;
    glUniformMatrix4fv(loc("u_viewProjection"), 1, GL_FALSE, glm::value_ptr(vp));
    glUniform3fv(loc("u_eye"), 1, glm::value_ptr(view.eyeWorld));
    glUniform3fv(loc("u_sunDir"), 1, glm::value_ptr(lighting.sun.directionWorld));
    glUniform3fv(loc("u_sunE"), 1, glm::value_ptr(lighting.sun.illuminanceRgb));
    glUniform3fv(loc("u_moonDir"), 1, glm::value_ptr(lighting.moon.directionWorld));
    glUniform3fv(loc("u_moonE"), 1, glm::value_ptr(lighting.moon.illuminanceRgb));
    glUniform2f(loc("u_cloudShadowOn"), lighting.sun.cloudShadow ? 1.0f : 0.0f, lighting.moon.cloudShadow ? 1.0f : 0.0f);
    const glm::mat4 toEnu(lighting.worldToEnuPoint);
    glUniformMatrix4fv(loc("u_worldToEnuPoint"), 1, GL_FALSE, glm::value_ptr(toEnu));
    glBindTextureUnit(kUnitBrdf, brdfTable_.id());
    glUniform1i(loc("u_shadowLight"), shadowLight_);
    glUniformMatrix4fv(loc("u_shadowViewProjection"), 1, GL_FALSE, glm::value_ptr(shadowViewProjection_));
    glUniform1f(loc("u_shadowTexel"), 2.0f * shadowSettings_.halfExtentM / float(shadowSettings_.size));
    glBindTextureUnit(kUnitShadow, shadowMap_.id());
    if (!lighting.sky) throw std::runtime_error("SceneRenderer::draw(): SceneLighting::sky is not set");
    welkin::bindLighting(prog, *lighting.sky, int(kUnitCube), lighting.enuFromWorld);
    if (clouds && lighting.bindCloudShadow) lighting.bindCloudShadow(prog);

    const GLint uModel = loc("u_model"), uNormal = loc("u_normalMatrix"), uBase = loc("u_baseColor"),
                uMetal = loc("u_metallic"), uRough = loc("u_roughness");
    for (const auto& d : scene.draws()) {
        const auto& prim = scene.primitives()[size_t(d.primitive)];
        const auto& mat = scene.materials()[size_t(prim.material)];
        const glm::mat3 normalMatrix = glm::transpose(glm::inverse(glm::mat3(d.world)));
        glUniformMatrix4fv(uModel, 1, GL_FALSE, glm::value_ptr(d.world));
        glUniformMatrix3fv(uNormal, 1, GL_FALSE, glm::value_ptr(normalMatrix));
        glUniform4fv(uBase, 1, glm::value_ptr(mat.baseColor));
        glUniform1f(uMetal, mat.metallic);
        glUniform1f(uRough, mat.roughness);
        glBindVertexArray(prim.vao.id());
        glDrawElements(GL_TRIANGLES, prim.indexCount, GL_UNSIGNED_INT, nullptr);
    }
    glBindVertexArray(0);
}

}  // namespace host
