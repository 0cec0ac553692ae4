// The Halos element's real-time display: one fetch of the table at the interpolated coordinates
// (halos_grid.vert.glsl). Needs engine/composite.glsl before it.
layout(binding = WELKIN_BINDING_HALOS_TABLE) uniform sampler2D u_haloTable;  // (azimuth, elevation) at the light's elevation, 1/sr
uniform vec3 u_E;                // the light's illuminance at the observer, lux per channel
uniform float u_below;           // 1: the observer is under the layer (the ground hides it below the horizon)
noperspective in vec4 v_coord;
noperspective in vec2 v_layer;

void main() {
    if (u_below > 0.5 && v_coord.w < 0.0) discard;
    const float PI = 3.14159265358979;
    // |phi| from the signed azimuth that is continuous here (near the light's side or the far side).
    float a = abs(v_coord.x) < 0.5 * PI ? abs(v_coord.x) : PI - abs(v_coord.y);
    vec3 phase = texture(u_haloTable, vec2(a / PI, v_coord.z / PI + 0.5)).rgb;
    welkin_output(u_E * phase * v_layer.x, vec3(v_layer.y));
}
