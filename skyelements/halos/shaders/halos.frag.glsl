// The Halos element's pass (contract in welkin/elements/halos.hpp). Needs engine/camera.glsl,
// engine/composite.glsl and generators/clouds' cloud_density.glsl before it.
// Frame: ENU at the observer's ground point, metres; planet centre at (0, 0, -R).
layout(binding = WELKIN_BINDING_HALOS_TABLE) uniform sampler2D u_haloTable;  // (azimuth, elevation) at the light's elevation, 1/sr

uniform vec3 u_light;        // unit vector to the light (Sun or Moon), ENU
uniform vec3 u_E;            // the light's illuminance at the observer, lux per channel
uniform vec3 u_lightX;       // unit horizontal vector towards the light's azimuth (turned by the table's lag)
uniform vec3 u_lightY;       // up x u_lightX
uniform vec3 u_lightZ;       // u_lightX x u_lightY: up, when the table holds the current light's elevation
uniform float u_tauUser;     // vertical optical depth of the user's crystal layer
uniform float u_tauCirrus;   // halos.cirrus_fraction x the cirrus' optical depth at density 1 (0: no cirrus)
uniform float u_h;           // observer height above the ground, m
uniform float u_R;           // planet radius, m
uniform float u_layerH;      // the crystal layer's height above the ground, m

const float HALOS_PI = 3.14159265358979;

#include "halos_layer.shared.glsl"

void main() {
    vec3 dir;
    if (!welkin_viewDirection(welkin_pixel(), dir)) discard;
    // Where the ray crosses the layer's sphere (from below: upwards; from above: downwards).
    float r = u_R + u_h, rc = u_R + u_layerH, mu = dir.z;
    float d = halos_layerDistance(r, rc, mu);  // halos_layer.shared.glsl, as layerFactor() in halos.cpp
    if (d <= 0.0) discard;
    // Hidden by the ground (the planet's sphere) before the layer?
    float gDisc = r * r * (mu * mu - 1.0) + u_R * u_R;
    if (mu < 0.0 && gDisc >= 0.0 && -r * mu - sqrt(gDisc) < d) discard;
    vec3 p = vec3(0.0, 0.0, u_h) + dir * d;
    vec3 up = normalize(p + vec3(0.0, 0.0, u_R));
    float slant = 1.0 / max(abs(dot(up, dir)), 0.1);
    float tauCirrus = u_tauCirrus > 0.0 ? u_tauCirrus * cirrusDensity(p.xy) : 0.0;
    float tau = (u_tauUser + tauCirrus) * slant;
    // The table's coordinates: the direction's elevation and its azimuth from the light's, in the
    // table's frame (while a refill is under way turned about u_lightY by the table's lag in
    // elevation, so that its light lands on the current one: Halos::doRender; else x, y, up).
    vec3 q = vec3(dot(dir, u_lightX), dot(dir, u_lightY), dot(dir, u_lightZ));
    float el = asin(clamp(q.z, -1.0, 1.0));
    float az = atan(abs(q.y), q.x);
    vec3 phase = texture(u_haloTable, vec2(az / HALOS_PI, el / HALOS_PI + 0.5)).rgb;
    vec3 L = u_E * phase * (1.0 - exp(-tau));
    welkin_output(L, vec3(exp(-u_tauUser * slant)));
}
