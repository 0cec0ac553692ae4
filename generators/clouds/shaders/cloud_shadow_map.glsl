// The cloud shadow map pass (fragment, one texel per fragment); C++:
// cpu::cloudShadowTransmittance() (generators/clouds/src/cloud_shadow.cpp; the model is in
// cloud_shadow.hpp). Needs cloud_density.glsl (the shared density, its block and textures) before
// it. Positions: ENU metres relative to the observer's ground point (cloud_density.glsl's frame).
uniform ivec2 u_size;     // map texels
uniform float u_extent;   // m, side of the mapped square
uniform float u_cirrusTau;  // optical depth of the cirrus at relative density 1 (kCirrusOpticalDepth)
uniform vec3 u_light;     // unit, ENU, z >= 0
uniform int u_steps;
uniform bool u_hasClouds; // the weather map and the base noise are bound
uniform bool u_hasCurl;   // the curl noise (the cirrus) is bound
out vec4 o_shadow;

// The column's optical depth, cld_shadowOpticalDepth(): cloud_shadow.shared.glsl, which
// cloud_shadow.cpp compiles in double.
#include "cloud_shadow.shared.glsl"

void main() {
    vec2 xy = (gl_FragCoord.xy / vec2(u_size) - 0.5) * u_extent;
    float tau = cld_shadowOpticalDepth(xy, u_light, cld_radii, cld_shape, u_steps, u_hasClouds, u_hasCurl, u_cirrusTau);
    o_shadow = vec4(exp(-tau), 0.0, 0.0, 1.0);
}
