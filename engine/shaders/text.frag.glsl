// Text: a glyph's coverage from the atlas (welkin/gl/text.hpp). Needs engine/camera.glsl and
// engine/composite.glsl before it. Emits radiance x coverage and hides what is behind by the
// coverage; nothing outside a fisheye's image circle.
layout(binding = WELKIN_BINDING_TEXT_ATLAS) uniform sampler2D u_atlas;
in vec2 v_uv;
flat in vec3 v_radiance;

void main() {
    vec3 dir;
    if (!welkin_viewDirection(welkin_pixel(), dir)) discard;
    float coverage = texture(u_atlas, v_uv).r;
    if (coverage <= 0.0) discard;
    welkin_output(v_radiance * coverage, vec3(1.0 - coverage));
}
