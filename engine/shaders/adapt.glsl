// The eye's adaptation step (docs/eye.md; CPU twin: welkin/eye.hpp, eye.cpp), one text for its
// two callers: the meter's compute pass (meter.comp.glsl, a metered frame: the means and the new
// state in one dispatch) and the one-texel pass adapt.frag.glsl (a second tone map of the same
// frame: the stored meter, the settings of the moment). welkin_eyeStep(m, previous) returns
// (cone adaptation cd/m^2, rod adaptation scotopic cd/m^2, exposure, 1).
uniform int u_steady;         // 1: no previous state, or a still render: jump to the target
uniform float u_dt;           // seconds since the previous frame
uniform float u_coneTime;     // eye.cone_time_s
uniform float u_rodTime;      // eye.rod_time_s
uniform float u_min, u_max;   // eye.adaptation_min_cd_m2, eye.adaptation_max_cd_m2
uniform int u_eye;            // eye.adaptation: the eye's TVI model; 0: a camera's log-average
uniform float u_compensation; // exposure.compensation_ev
uniform float u_strength;     // eye.strength: log-mix of the camera's exposure (0) and the eye's (1)
uniform float u_kTvi;         // 0.104 * 10^-1.255
uniform float u_kappa;        // V'/Y of the sRGB white

// The cones' and rods' thresholds (welkin_coneThresholdLog10, welkin_rodThresholdLog10):
// eye_thresholds.shared.glsl, which eye.cpp compiles in double.
#include "eye_thresholds.shared.glsl"

float welkin_approach(float from, float to, float tau) {  // exponential in log luminance
    if (tau <= 0.0) return to;
    if (u_dt == 0.0) return from;
    return exp(mix(log(from), log(to), 1.0 - exp(-u_dt / tau)));
}

// The new state from the meter m (mean w ln Y, mean w, mean w ln V') and the previous state.
vec4 welkin_eyeStep(vec4 m, vec4 previous) {
    vec2 target = m.y > 0.0 ? exp(vec2(m.x, m.z) / m.y) : vec2(u_min);
    bool finiteTarget = !isnan(target.x) && !isnan(target.y) && !isinf(target.x) && !isinf(target.y);
    if (!finiteTarget) target = u_steady != 0 ? vec2(u_min) : previous.xy;  // a frame of NaN meters nothing
    target = clamp(target, vec2(u_min), vec2(u_max));
    vec2 s = target;
    if (u_steady == 0) {
        s.x = welkin_approach(previous.x, target.x, u_coneTime);
        s.y = welkin_approach(previous.y, target.y, target.y > previous.y ? u_coneTime : u_rodTime);  // light adaptation is fast
    }
    float exposure;
    if (u_eye != 0) {
        float cones = u_kTvi / exp2(welkin_coneThresholdLog10(s.x) * log2(10.0));
        float rods = u_kTvi * u_kappa / exp2(welkin_rodThresholdLog10(s.y) * log2(10.0));
        float camera = 1.0 / (1.2 * exp2(clamp(log2(s.x * 100.0 / 12.5), -20.0, 30.0)));
        exposure = exp(mix(log(camera), log(max(cones, rods)), u_strength));
    } else {
        // A camera: the log-average to 12.5 / (1.2 * 100), EV100 kept in [-20, 30].
        float ev = clamp(log2(s.x * 100.0 / 12.5), -20.0, 30.0);
        exposure = 1.0 / (1.2 * exp2(ev));
    }
    return vec4(s, exposure * exp2(u_compensation), 1.0);
}
