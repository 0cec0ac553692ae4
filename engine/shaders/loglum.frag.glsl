// Log-luminance of the HDR image for automatic exposure: writes (w ln Y, w, w ln V') so that the
// mean over a mip chain gives the weighted log-averages of the photopic luminance Y and of the
// scotopic luminance V' (Larson et al. 1997, the rods' adaptation; welkin/eye.hpp); w = 0 outside
// the camera's image (fisheye) and where nothing emits light (Y below 1e-7 cd/m^2, far below the
// faintest night sky), so an empty background does not drag the exposure down.
layout(binding = WELKIN_BINDING_HDR_TEXTURE) uniform sampler2D u_hdr;
in vec2 v_ndc;
out vec4 o_logLum;
void main() {
    vec2 uv = 0.5 * v_ndc + 0.5;  // same relative position in the HDR image
    vec2 pixel = vec2(uv.x, 1.0 - uv.y) * welkin_viewport.xy;
    vec3 dir;
    vec3 c = texture(u_hdr, uv).rgb;
    float X = dot(c, vec3(0.4124, 0.3576, 0.1805));
    float Y = dot(c, vec3(0.2126, 0.7152, 0.0722));
    float Z = dot(c, vec3(0.0193, 0.1192, 0.9505));
    float V = X > 0.0 ? Y * (1.33 * (1.0 + (Y + Z) / X) - 1.68) : 0.0;
    float w = (welkin_viewDirection(pixel, dir) && Y > 1e-7) ? 1.0 : 0.0;
    o_logLum = vec4(w * log(max(Y, 1e-7)), w, w * log(max(V, 1e-7)), 1.0);
}
