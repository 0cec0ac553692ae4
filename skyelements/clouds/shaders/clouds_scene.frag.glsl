// Clouds::applyToScene(), ScenePass::Surfaces: the clouds' shadows over the host's scene, from its
// colour and depth (dual-source blending: dst = dst * T). The host lit its surfaces with the
// light at the observer (SkyLighting: the Sun's or the Moon's illuminance through the clouds'
// transmittance there, u_observerT); a surface point p under a cloud gets u_diffuse + u_direct *
// welkin_cloudShadow(p) instead of u_diffuse + u_direct * u_observerT on a horizontal surface,
// so its colour is scaled by the ratio (exact for horizontal Lambertian surfaces; for others the
// diffuse share differs, docs/embedding.md). Needs engine/camera.glsl, engine/composite.glsl and
// generators/clouds/cloud_shadow.glsl before it.
layout(binding = WELKIN_BINDING_SCENE_DEPTH) uniform sampler2D u_depth;
uniform float u_direct;     // the light's direct horizontal illuminance above the clouds, lux
uniform float u_diffuse;    // the diffuse horizontal illuminance under the clouds, lux
uniform float u_observerT;  // the clouds' transmittance towards the light at the observer

void main() {
    float d = texelFetch(u_depth, ivec2(gl_FragCoord.xy), 0).r;
    if (welkin_depthIsFar(d)) discard;  // the sky: not the host's surface
    vec3 dir;
    welkin_viewDirection(welkin_pixel(), dir);
    vec3 p = welkin_eye.xyz + dir * welkin_sceneDistance(d, dir);
    float s = welkin_cloudShadow(p);
    float T = (u_diffuse + u_direct * s) / max(u_diffuse + u_direct * u_observerT, 1e-6);
    // Not welkin_output(): its transmittance is clamped to 1, and a sunlit patch under a broken
    // deck is brighter than the observer's average (T > 1; float targets blend it unclamped).
    welkin_radiance = vec4(0.0, 0.0, 0.0, 1.0);
    welkin_transmittance = vec4(vec3(max(T, 0.0)), 1.0);
}
