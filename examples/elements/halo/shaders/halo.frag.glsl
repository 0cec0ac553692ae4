// Halo element: a Gaussian ring around the Sun. Needs engine/camera.glsl and
// engine/composite.glsl before it.
uniform vec3 u_sun;     // unit vector to the Sun, world ENU
uniform float u_radius; // ring radius, radians
uniform float u_width;  // ring width (Gaussian sigma), radians
uniform vec3 u_peak;    // ring luminance at its crest, cd/m^2 per channel

void main() {
    vec3 dir;
    if (!welkin_viewDirection(welkin_pixel(), dir)) discard;  // outside a fisheye's circle
    float angle = acos(clamp(dot(dir, u_sun), -1.0, 1.0));
    float x = (angle - u_radius) / u_width;
    // Emits light and hides nothing: transmittance 1.
    welkin_output(u_peak * exp(-0.5 * x * x), vec3(1.0));
}
