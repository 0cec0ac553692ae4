// The eye's adaptation, one texel (docs/eye.md; CPU twin: welkin/eye.hpp, eye.cpp): reads the
// meter (meter.comp.glsl: one texel, the means of w ln Y, w and w ln V') and the previous state, writes
// (cone adaptation cd/m^2, rod adaptation scotopic cd/m^2, exposure, 1). On the GPU so that the
// tone map never waits for a read-back.
layout(binding = WELKIN_BINDING_LOG_LUM_TEXTURE) uniform sampler2D u_logLum;
layout(binding = WELKIN_BINDING_EYE_STATE_TEXTURE) uniform sampler2D u_previous;
in vec2 v_ndc;
out vec4 o_state;
// welkin_eyeStep() and its uniforms: adapt.glsl, the chunk before this one.
void main() { o_state = welkin_eyeStep(texelFetch(u_logLum, ivec2(0), 0), texelFetch(u_previous, ivec2(0), 0)); }
