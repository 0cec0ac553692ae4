// Reading the cloud-path LUT (after cloud_density.glsl): (entry, exit) distances in m of the view
// ray through the cloud layer, from altitude h (m) with cos(view zenith) mu. exit <= entry: no
// crossing.
// The mapping (cloudPathX, cloudPathMu, cloudPathY, cloudPathAltitude, CLOUD_PATH_ABOVE_M):
// cloud_path.shared.glsl, which cloud_path_lut.cpp compiles in double.
#include "cloud_path.shared.glsl"
layout(binding = WELKIN_BINDING_CLOUD_PATH_LUT) uniform sampler2D u_cloudPathLut;

vec2 cloudPathLookup(float h, float mu) {
    vec2 size = vec2(textureSize(u_cloudPathLut, 0));
    vec2 xy = vec2(cloudPathX(mu), cloudPathY(h, cld_radii.y - cld_radii.x, cld_radii.z - cld_radii.x));
    return textureLod(u_cloudPathLut, (xy * (size - 1.0) + 0.5) / size, 0.0).rg;
}
