// Transmittance LUT pass (fragment): exp(-optical depth) from (h, mu) to the top of the
// atmosphere; twin of cpu::transmittanceToTop(). Needs atmosphere.glsl before it.
uniform int u_steps;
uniform ivec2 u_size;  // LUT size, texels
out vec4 o_transmittance;

vec3 transmittanceToTop(float h, float mu, int steps) {
    float d = distanceToTop(h, mu);
    float p = atm_perigeeFraction(h, mu, d);
    vec3 depth = vec3(0.0);
    for (int i = 0; i < steps; ++i) {
        float s0 = float(i) / float(steps), s1 = float(i + 1) / float(steps), sm = (float(i) + 0.5) / float(steps);
        float dt = d * (atm_warp(s1, p) - atm_warp(s0, p));
        depth += atm_extinction(heightAt(h, mu, d * atm_warp(sm, p))) * dt;
    }
    return exp(-depth);
}

void main() {
    vec2 size = vec2(u_size);
    vec2 hm = transmittanceHMu(gl_FragCoord.xy / size, size);
    o_transmittance = vec4(transmittanceToTop(hm.x, hm.y, u_steps), 1.0);
}
