// Constellations: an antialiased line (see constellations.vert.glsl). Needs engine/camera.glsl
// and engine/composite.glsl before it. Emits u_radiance x coverage, hides what is behind by it.
uniform vec3 u_radiance;  // cd/m^2 per channel at full coverage
in float v_across;
flat in float v_halfWidth;

void main() {
    vec3 dir;
    if (!welkin_viewDirection(welkin_pixel(), dir)) discard;  // outside a fisheye's circle
    // Box filter of the line's cross-section over one pixel.
    // A line thinner than a pixel gets dimmer rather than thinner (peak coverage = its width).
    float coverage = clamp(min(v_halfWidth + 0.5 - abs(v_across), 2.0 * v_halfWidth), 0.0, 1.0);
    if (coverage <= 0.0) discard;
    welkin_output(u_radiance * coverage, vec3(1.0 - coverage));
}
