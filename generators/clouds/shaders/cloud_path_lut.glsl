// Cloud-path LUT pass (compute, after cloud_density.glsl and cloud_path.glsl): texel (i, j) holds
// the (entry, exit) crossing of the cloud shell at mu = cloudPathMu(i / (W - 1)) and altitude
// cloudPathAltitude(j / (H - 1)). Evaluated in double: in float the discriminant near tangency
// loses ~1e-7 r^2 (4e6 m^2), tens of metres of distance; twin cpu::cloudPathTexel().
layout(local_size_x = 8, local_size_y = 8) in;
layout(rg32f, binding = WELKIN_BINDING_LUT_IMAGE) uniform writeonly image2D o_path;
uniform ivec2 u_size;
uniform double u_planetRadius, u_bottom, u_top;  // m (the layer's heights above the ground)

dvec2 cloudShellIntersectD(double R, double rb, double rt, double r, double mu) {
    double dR = (R - r) * (R + r) + r * r * mu * mu;
    double db = (rb - r) * (rb + r) + r * r * mu * mu;
    double dt = (rt - r) * (rt + r) + r * r * mu * mu;
    if (r < rb) {
        if (mu < 0.0 && dR >= 0.0 && r >= R) return dvec2(-1.0);
        return dvec2(-r * mu + sqrt(max(db, 0.0)), -r * mu + sqrt(max(dt, 0.0)));
    }
    if (r <= rt) {
        if (mu < 0.0 && db >= 0.0) return dvec2(0.0, -r * mu - sqrt(db));
        return dvec2(0.0, -r * mu + sqrt(max(dt, 0.0)));
    }
    if (mu >= 0.0 || dt < 0.0) return dvec2(-1.0);
    double entry = -r * mu - sqrt(dt);
    if (db >= 0.0) return dvec2(entry, -r * mu - sqrt(db));
    return dvec2(entry, -r * mu + sqrt(dt));
}

void main() {
    ivec2 t = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(t, u_size))) return;
    // The mapping's inverse in double (cloudPathMu, cloudPathAltitude of cloud_path.glsl).
    double x = double(t.x) / double(u_size.x - 1), y = double(t.y) / double(u_size.y - 1);
    double s = 2.0lf * x - 1.0lf;
    double mu = sign(s) * s * s;
    double b = double(u_bottom), tp = double(u_top), k = 3.0lf * y;
    double h = k < 1.0lf ? k * b : (k <= 2.0lf ? b + (k - 1.0lf) * (tp - b) : tp + (k - 2.0lf) * double(CLOUD_PATH_ABOVE_M));
    double R = double(u_planetRadius);
    imageStore(o_path, t, vec4(vec2(cloudShellIntersectD(R, R + double(u_bottom), R + double(u_top), R + h, mu)), 0.0, 0.0));
}
