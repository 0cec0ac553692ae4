// Stars: the PSF of one star (see stars.vert.glsl). Needs engine/camera.glsl and
// engine/composite.glsl before it. Emits radiance, hides nothing (transmittance 1).
in vec2 v_offset;
flat in vec3 v_flux;
flat in vec3 v_shape;
flat in float v_haloR2;
flat in vec4 v_pp;

void main() {
    vec3 dir;
    if (!welkin_viewDirection(welkin_pixel(), dir)) discard;  // outside a fisheye's circle
    float r2 = dot(v_offset, v_offset);
    float sigma = v_shape.x, a = v_shape.y, g = v_shape.z;
    // Per pixel^2: the Gaussian core (integral 1) and the Moffat beta = 2 halo, truncated at 8a
    // (integral 1 - 1/65 inside; divided by it so the halo's integral is 1).
    float w = (1.0 - g) * exp(-0.5 * r2 / (sigma * sigma)) / (2.0 * WELKIN_PI * sigma * sigma);
    if (g > 0.0 && r2 < v_haloR2) {
        float q = 1.0 + r2 / (a * a);
        w += g / (WELKIN_PI * a * a * (64.0 / 65.0) * q * q);
    }
    vec3 L = v_flux * w;
    // Perceptual mode: the point as the eye sees it, where it is brighter than the physical PSF.
    if (v_pp.w > 0.0) L = max(L, v_pp.rgb * exp(-0.5 * r2 / (v_pp.w * v_pp.w)));
    welkin_output(L, vec3(1.0));
}
