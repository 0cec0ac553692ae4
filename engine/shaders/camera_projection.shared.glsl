// The camera's projection from a direction to clip space and its derivatives, one source for GLSL
// (camera.glsl includes it: welkin_clipFromDirection(), welkin_pixelJacobian(),
// welkin_pixelScale() pass the camera block) and C++ (camera.cpp compiles it in double:
// Camera::clipFromDirection(), pixelJacobian(), pixelScale() pass the Camera's values). Directions
// are ENU (x east, y north, z up); pixels x right, y down; `size` the image's (width, height).

const real WELKIN_PI = 3.14159265358979;

// A cube face as a pinhole (OpenGL face order; NDC = (s, -t) in the face coordinates of
// welkin_viewDirection()): clip = (a.d, b.d, f.d, f.d) for an ENU direction d.
void welkin_cubeFacePinhole(int face, OUT(vec3) a, OUT(vec3) b, OUT(vec3) f) {
    if (face == 0) { a = vec3(0.0, 1.0, 0.0); b = vec3(0.0, 0.0, 1.0); f = vec3(1.0, 0.0, 0.0); }        // +X east
    else if (face == 1) { a = vec3(0.0, -1.0, 0.0); b = vec3(0.0, 0.0, 1.0); f = vec3(-1.0, 0.0, 0.0); } // -X west
    else if (face == 2) { a = vec3(1.0, 0.0, 0.0); b = vec3(0.0, 1.0, 0.0); f = vec3(0.0, 0.0, 1.0); }   // +Y up
    else if (face == 3) { a = vec3(1.0, 0.0, 0.0); b = vec3(0.0, -1.0, 0.0); f = vec3(0.0, 0.0, -1.0); } // -Y down
    else if (face == 4) { a = vec3(1.0, 0.0, 0.0); b = vec3(0.0, 0.0, 1.0); f = vec3(0.0, -1.0, 0.0); }  // +Z south
    else { a = vec3(-1.0, 0.0, 0.0); b = vec3(0.0, 0.0, 1.0); f = vec3(0.0, 1.0, 0.0); }                 // -Z north
}

// ---- From a direction to clip space ----------------------------------------------------------
// Pinhole (perspective, cube face): linear in the direction; w = f.d <= 0 behind the camera.
vec4 welkin_clipPinhole(vec3 a, vec3 b, vec3 f, vec3 dir) {
    real w = dot(f, dir);
    return vec4(dot(a, dir), dot(b, dir), w, w);
}
// Fisheye, a direction at or above the horizon: pixel = size/2 - r (sin az, cos az), r = theta /
// (pi/2) * R, theta from the zenith, R = min(size) / 2.
vec4 welkin_clipFisheye(vec2 size, vec3 dir) {
    real h = length(vec2(dir.x, dir.y));
    real R = 0.5 * min(size.x, size.y);
    real r = atan(h, dir.z) / (0.5 * WELKIN_PI) * R;
    vec2 sc = h > 0.0 ? vec2(dir.x, dir.y) / h : vec2(0.0);
    return vec4(-2.0 * r * sc.x / size.x, 2.0 * r * sc.y / size.y, 1.0, 1.0);
}
// Equirect: x = az/pi - 1, y = alt/(pi/2) (atan(0, 0) is undefined in GLSL: azimuth 0 at the poles).
vec4 welkin_clipEquirect(vec3 dir) {
    real h = length(vec2(dir.x, dir.y));
    real az = h > 0.0 ? atan(dir.x, dir.y) : 0.0;
    if (az < 0.0) az += 2.0 * WELKIN_PI;
    real alt = atan(dir.z, h);
    return vec4(az / WELKIN_PI - 1.0, alt / (0.5 * WELKIN_PI), 1.0, 1.0);
}

// ---- d(pixel)/d(direction) at a unit direction d (3 columns, 2 rows) ------------------------
// Pinhole: NDC = (a.d, b.d) / f.d; pixel = ((NDC.x + 1) W/2, (1 - NDC.y) H/2).
mat3x2 welkin_jacobianPinhole(vec3 a, vec3 b, vec3 f, vec2 size, vec3 d) {
    real fw = dot(f, d);
    vec3 jx = 0.5 * size.x * (a - dot(a, d) / fw * f) / fw;
    vec3 jy = -0.5 * size.y * (b - dot(b, d) / fw * f) / fw;
    return transpose(mat2x3(jx, jy));
}
// Fisheye: radially k = R/(pi/2) pixels per radian; along the azimuth k theta / sin(theta). Zero
// below the horizon.
mat3x2 welkin_jacobianFisheye(vec2 size, vec3 d) {
    real h = length(vec2(d.x, d.y));
    vec2 s = h > 0.0 ? vec2(d.x, d.y) / h : vec2(0.0, 1.0);  // (sin az, cos az)
    vec3 eAz = vec3(s.y, -s.x, 0.0);                          // unit tangent towards increasing azimuth
    if (d.z < 0.0) return mat3x2(0.0);
    real k = 0.5 * min(size.x, size.y) / (0.5 * WELKIN_PI);
    real theta = atan(h, d.z);
    real g = h > 1e-4 ? theta / h : 1.0;  // theta / sin(theta); the error below 1e-4 is < 2e-9
    vec3 eTheta = vec3(d.z * s.x, d.z * s.y, -h);  // towards increasing zenith angle
    return outerProduct(-k * s, eTheta) + outerProduct(-k * g * vec2(s.y, -s.x), eAz);
}
// Equirect: x = az W/(2pi), y = (pi/2 - alt) H/pi; one radian along the azimuth circle is 1/cos(alt)
// radians of azimuth (the horizontal scale capped at cos alt >= 1e-6).
mat3x2 welkin_jacobianEquirect(vec2 size, vec3 d) {
    real h = length(vec2(d.x, d.y));
    vec2 s = h > 0.0 ? vec2(d.x, d.y) / h : vec2(0.0, 1.0);
    vec3 eAz = vec3(s.y, -s.x, 0.0);
    vec3 eAlt = vec3(-d.z * s.x, -d.z * s.y, h);
    return outerProduct(vec2(size.x / (2.0 * WELKIN_PI * max(h, 1e-6)), 0.0), eAz) +
           outerProduct(vec2(0.0, -size.y / WELKIN_PI), eAlt);
}

// (smallest, largest) pixels per radian at `dir` from its Jacobian J: the singular values of the
// 2x2 map M = J (t1 t2) in a tangent frame at dir; with M = (a b; c e) they are (sqrt((a+e)^2 +
// (c-b)^2) +- sqrt((a-e)^2 + (c+b)^2)) / 2, the difference of squares avoided (float: it would lose
// half the digits of a nearly isotropic scale), and the smallest taken as |det M| / largest.
vec2 welkin_pixelScaleOf(mat3x2 J, vec3 dir) {
    vec3 d = normalize(dir);
    vec3 t1 = normalize(cross(abs(d.z) < 0.9 ? vec3(0.0, 0.0, 1.0) : vec3(1.0, 0.0, 0.0), d));
    vec3 t2 = cross(d, t1);
    vec2 m1 = J * t1, m2 = J * t2;  // columns of M
    real a = m1.x, c = m1.y, b = m2.x, e = m2.y;
    real sMax = 0.5 * (length(vec2(a + e, c - b)) + length(vec2(a - e, c + b)));
    return vec2(sMax > 0.0 ? abs(a * e - b * c) / sMax : 0.0, sMax);
}
