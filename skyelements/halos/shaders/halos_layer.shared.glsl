// The crystal layer's crossing, one source for the Halos pass (halos.frag.glsl includes it) and
// the table's C++ (layerFactor() in halos.cpp compiles it in double, welkin/glsl_cpp.hpp).
//
// The distance along a ray of cos zenith mu from radius r (planet centre to observer) to where it
// crosses the layer's sphere of radius rc: upwards from below the layer, downwards from above it;
// -1.0 when the ray misses the sphere. A distance <= 0 means no crossing ahead.
real halos_layerDistance(real r, real rc, real mu) {
    real disc = r * r * mu * mu - (r - rc) * (r + rc);
    if (disc < 0.0) return -1.0;
    return r < rc ? -r * mu + sqrt(disc) : -r * mu - sqrt(disc);
}
