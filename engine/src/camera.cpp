#include <welkin/camera.hpp>
#include <welkin/check.hpp>
#include <welkin/error.hpp>
#include <welkin/glsl_cpp.hpp>

#include <algorithm>
#include <cmath>
#include <numbers>

namespace welkin::glsl::dp::lighting_cube_shared {
#include "../shaders/lighting_cube.shared.glsl"
}  // namespace welkin::glsl::dp::lighting_cube_shared
namespace welkin::glsl::dp::camera_shared {
#include "../shaders/camera_projection.shared.glsl"
}  // namespace welkin::glsl::dp::camera_shared

namespace welkin {

namespace {
constexpr double kPi = std::numbers::pi;
constexpr double kHalfPi = kPi / 2;
}  // namespace

std::string_view toString(Projection p) {
    switch (p) {
        case Projection::Perspective: return "perspective";
        case Projection::Fisheye: return "fisheye";
        case Projection::Equirect: return "equirect";
        case Projection::CubeFace: return "cube";
    }
    return "?";
}

Projection parseProjection(std::string_view n) {
    if (n == "perspective") return Projection::Perspective;
    if (n == "fisheye") return Projection::Fisheye;
    if (n == "equirect") return Projection::Equirect;
    if (n == "cube") return Projection::CubeFace;
    throw Error("projection '" + std::string(n) + "' unknown (accepted: perspective, fisheye, equirect, cube)");
}

glm::dvec3 directionFromAzAlt(double az, double alt) { return glsl::dp::lighting_cube_shared::welkin_directionFromAzAlt(az, alt); }

glm::dvec2 azAltFromDirection(const glm::dvec3& d) {
    double h = std::hypot(d.x, d.y);
    double az = std::atan2(d.x, d.y);
    if (az < 0) az += 2 * kPi;
    return {az, std::atan2(d.z, h)};
}

void Camera::validate() const {
    // Angles get 1e-9 rad of slack: a caller converting exactly +-90 deg or +-360 deg may land
    // just outside.
    checkRange("Camera", "width", width, 1, 16384);
    checkRange("Camera", "height", height, 1, 16384);
    checkRange("Camera", "altitudeRad", altitudeRad, -kHalfPi - 1e-9, kHalfPi + 1e-9);
    checkRange("Camera", "azimuthRad", azimuthRad, -2 * kPi - 1e-9, 2 * kPi + 1e-9);
    checkOpenRange("Camera", "verticalFovRad", verticalFovRad, 0, kPi);
    checkRange("Camera", "cubeFace", cubeFace, 0, 5);
}

glm::dmat4 enuFromYUp(double metresPerUnit, const glm::dvec3& origin) {
    checkOpenRange("enuFromYUp()", "metresPerUnit", metresPerUnit, 0, kInfinity);
    // ENU x = host x, ENU y (north) = -host z, ENU z (up) = host y; columns are the images of the
    // host's axes.
    glm::dmat4 m(0.0);
    m[0] = glm::dvec4(metresPerUnit, 0, 0, 0);
    m[1] = glm::dvec4(0, 0, metresPerUnit, 0);
    m[2] = glm::dvec4(0, -metresPerUnit, 0, 0);
    m[3] = glm::dvec4(origin, 1);
    return m;
}

glm::dmat4 enuFromZUp(double metresPerUnit, const glm::dvec3& origin) {
    checkOpenRange("enuFromZUp()", "metresPerUnit", metresPerUnit, 0, kInfinity);
    glm::dmat4 m(metresPerUnit);
    m[3] = glm::dvec4(origin, 1);
    return m;
}

namespace {
bool finite(const glm::dmat4& m) {
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r)
            if (!std::isfinite(m[c][r])) return false;
    return true;
}
// The 3x3 part of `m` as a rotation times a uniform scale s > 0: returns s and writes the rotation
// (possibly a reflection) into `rot`; throws if it is not one (tolerance 1e-6 relative: float
// matrices a host computed in single precision pass).
double uniformScale(const glm::dmat3& m, glm::dmat3& rot, const char* what) {
    const double det = glm::determinant(m);
    const double s = std::cbrt(std::abs(det));
    if (!(s > 0) || !std::isfinite(s))
        throw Error(std::string("Camera::fromViewProjection(): ") + what + " is singular (determinant " + std::to_string(det) + ")");
    rot = m / s;
    const glm::dmat3 e = glm::transpose(rot) * rot;
    for (int c = 0; c < 3; ++c)
        for (int r = 0; r < 3; ++r)
            if (std::abs(e[c][r] - (c == r ? 1.0 : 0.0)) > 1e-5)
                throw Error(std::string("Camera::fromViewProjection(): ") + what + " is not a rotation with a uniform scale");
    return s;
}
}  // namespace

Camera Camera::fromViewProjection(const glm::dmat4& view, const glm::dmat4& projection, const glm::dmat4& worldToEnu,
                                  int width, int height, DepthMode depth) {
    const char* where = "Camera::fromViewProjection()";
    if (!finite(view)) throw Error(std::string(where) + ": view matrix is not finite");
    if (!finite(projection)) throw Error(std::string(where) + ": projection matrix is not finite");
    if (!finite(worldToEnu)) throw Error(std::string(where) + ": worldToEnu matrix is not finite");
    checkRange(where, "width", width, 1, 16384);
    checkRange(where, "height", height, 1, 16384);
    // The w row of a perspective projection depends on the view-space position; an orthographic
    // one's is (0, 0, 0, 1): it cannot show directions at infinity.
    const glm::dvec3 wRow(projection[0][3], projection[1][3], projection[2][3]);
    if (glm::length(wRow) < 1e-12) throw Error(std::string(where) + ": projection is orthographic (its w row is (0, 0, 0, 1)); the sky needs a perspective projection");
    glm::dmat3 viewRot, enuRot;
    uniformScale(glm::dmat3(view), viewRot, "view");
    const double metresPerUnit = uniformScale(glm::dmat3(worldToEnu), enuRot, "worldToEnu");
    Camera c;
    c.projection = Projection::Perspective;
    c.width = width;
    c.height = height;
    c.depth = depth;
    HostProjection h;
    // ENU direction -> host world direction (enuRot^T: a rotation's inverse) -> view space.
    h.viewFromEnu = viewRot * glm::transpose(enuRot);
    h.projection = projection;
    h.metresPerUnit = metresPerUnit;
    const glm::dvec4 eyeWorld = glm::inverse(view) * glm::dvec4(0, 0, 0, 1);
    h.eyeEnuMeters = glm::dvec3(worldToEnu * glm::dvec4(glm::dvec3(eyeWorld) / eyeWorld.w, 1.0));
    c.host = h;
    // The optical axis (basis()'s forward) as azimuth and altitude, and the vertical field of
    // view of the frustum's height at unit distance along it: informative (pixelAngle, stats).
    const glm::dvec2 aa = azAltFromDirection(c.basis()[2]);
    c.azimuthRad = aa.x;
    c.altitudeRad = aa.y;
    const double py = std::hypot(projection[0][1], projection[1][1], projection[2][1]);
    c.verticalFovRad = std::clamp(2 * std::atan(1.0 / std::max(py, 1e-9)), 1e-6, kPi - 1e-6);
    return c;
}

glm::dmat4 Camera::depthProjection(double nearUnits, double farUnits) const {
    if (host) return host->projection;
    // A perspective projection whose view-space z maps to NDC z = (A z + B) / -z, with NDC
    // zNear at z = -near and zFar at z = -far: B (1/n - 1/f) = zNear - zFar, A = B/n - zNear (for
    // f = inf: B = (zNear - zFar) n, A = -zFar). x and y are irrelevant to depth.
    const double lo = depth.zeroToOne ? 0.0 : -1.0;
    const double zNear = depth.reversedZ ? 1.0 : lo, zFar = depth.reversedZ ? lo : 1.0;
    const double n = nearUnits, f = farUnits;
    const double B = std::isinf(f) ? (zNear - zFar) * n : (zNear - zFar) * n * f / (f - n);
    const double A = B / n - zNear;
    glm::dmat4 p(1.0);
    p[2][2] = A;
    p[3][2] = B;
    p[2][3] = -1;
    p[3][3] = 0;
    return p;
}

glm::dmat3 Camera::basis() const {
    if (host) {
        // Rows of viewFromEnu are the view's axes in ENU: x right, y up, z backwards.
        const glm::dmat3 t = glm::transpose(host->viewFromEnu);
        const glm::dvec3 wRow(host->projection[0][3], host->projection[1][3], host->projection[2][3]);
        // The optical axis: clip w = wRow . v grows along it (forward = direction of wRow in view space).
        const glm::dvec3 f = glm::normalize(t * wRow);
        glm::dvec3 r = t[0] - glm::dot(t[0], f) * f;
        r = glm::length(r) > 1e-9 ? glm::normalize(r) : glm::normalize(glm::cross(f, t[1]));
        return glm::dmat3(r, glm::cross(r, f), f);
    }
    if (basisMemo.valid && basisMemo.azimuthRad == azimuthRad && basisMemo.altitudeRad == altitudeRad) return basisMemo.basis;
    glm::dvec3 f = directionFromAzAlt(azimuthRad, altitudeRad);
    // Horizontal right vector defined from the azimuth so it stays valid looking straight up.
    glm::dvec3 r{std::cos(azimuthRad), -std::sin(azimuthRad), 0.0};
    glm::dvec3 u = glm::cross(r, f);
    basisMemo = {azimuthRad, altitudeRad, glm::dmat3(r, u, f), true};
    return basisMemo.basis;
}

namespace {
// Cube axes (x east, y up, z south) <-> ENU, and the direction of a face texel coordinate (s, t)
// in [-1, 1], OpenGL cube-map convention: the shaders' text (lighting_cube.shared.glsl).
glm::dvec3 cubeToEnu(const glm::dvec3& c) { return glsl::dp::lighting_cube_shared::lighting_cubeToEnu(c); }
glm::dvec3 enuToCube(const glm::dvec3& e) { return glsl::dp::lighting_cube_shared::lighting_enuToCube(e); }
glm::dvec3 cubeDir(int face, double s, double t) { return glsl::dp::lighting_cube_shared::lighting_cubeDir(face, s, t); }
// The host camera's pinhole rows: clip = (a.d, b.d, f.d) for an ENU direction d, from the rows
// 0, 1 and 3 of the projection's 3x3 part applied to the view-space direction (w = 0: at infinity).
glm::dmat3 hostClipRows(const Camera& c) {
    const glm::dmat4& P = c.host->projection;
    const glm::dmat3 t = glm::transpose(c.host->viewFromEnu);  // view -> ENU; row vector r.v = (t r).d
    return glm::dmat3(t * glm::dvec3(P[0][0], P[1][0], P[2][0]), t * glm::dvec3(P[0][1], P[1][1], P[2][1]),
                      t * glm::dvec3(P[0][3], P[1][3], P[2][3]));
}
// Its inverse: an (unnormalised) ENU ray through NDC (x, y) is M (x, y, 1).
glm::dmat3 hostWorldFromClip(const Camera& c) { return glm::inverse(glm::transpose(hostClipRows(c))); }
}  // namespace

std::optional<glm::dvec3> Camera::directionAt(const glm::dvec2& p) const {
    const double w = width, h = height;
    switch (projection) {
        case Projection::Perspective: {
            if (host) {
                const glm::dvec2 ndc(2 * p.x / w - 1, 1 - 2 * p.y / h);
                return glm::normalize(hostWorldFromClip(*this) * glm::dvec3(ndc, 1.0));
            }
            double tanY = std::tan(verticalFovRad / 2), tanX = tanY * w / h;
            double x = (2 * p.x / w - 1) * tanX, y = (1 - 2 * p.y / h) * tanY;
            glm::dmat3 b = basis();
            return glm::normalize(b[2] + x * b[0] + y * b[1]);
        }
        case Projection::Fisheye: {
            double R = std::min(w, h) / 2;
            double dx = w / 2 - p.x, dy = h / 2 - p.y;  // dx = r sin(az), dy = r cos(az)
            double r = std::hypot(dx, dy);
            if (r > R) return std::nullopt;
            double alt = kHalfPi * (1 - r / R);
            double az = std::atan2(dx, dy);
            return directionFromAzAlt(az, alt);
        }
        case Projection::Equirect: {
            double az = 2 * kPi * p.x / w, alt = kHalfPi - kPi * p.y / h;
            return directionFromAzAlt(az, alt);
        }
        case Projection::CubeFace: {
            double s = 2 * p.x / w - 1, t = 2 * p.y / h - 1;
            return glm::normalize(cubeToEnu(cubeDir(cubeFace, s, t)));
        }
    }
    return std::nullopt;
}

std::optional<glm::dvec2> Camera::pixelOf(const glm::dvec3& dIn) const {
    const double w = width, h = height;
    glm::dvec3 d = glm::normalize(dIn);
    switch (projection) {
        case Projection::Perspective: {
            if (host) {
                const glm::dmat3 rows = hostClipRows(*this);  // columns a, b, f
                const double cw = glm::dot(rows[2], d);
                if (cw <= 0) return std::nullopt;
                return glm::dvec2((glm::dot(rows[0], d) / cw + 1) * w / 2, (1 - glm::dot(rows[1], d) / cw) * h / 2);
            }
            glm::dmat3 b = basis();
            double z = glm::dot(d, b[2]);
            if (z <= 0) return std::nullopt;
            double tanY = std::tan(verticalFovRad / 2), tanX = tanY * w / h;
            double x = glm::dot(d, b[0]) / z / tanX, y = glm::dot(d, b[1]) / z / tanY;
            return glm::dvec2((x + 1) * w / 2, (1 - y) * h / 2);
        }
        case Projection::Fisheye: {
            glm::dvec2 aa = azAltFromDirection(d);
            if (aa.y < 0) return std::nullopt;
            double R = std::min(w, h) / 2, r = (kHalfPi - aa.y) / kHalfPi * R;
            return glm::dvec2(w / 2 - r * std::sin(aa.x), h / 2 - r * std::cos(aa.x));
        }
        case Projection::Equirect: {
            glm::dvec2 aa = azAltFromDirection(d);
            return glm::dvec2(aa.x / (2 * kPi) * w, (kHalfPi - aa.y) / kPi * h);
        }
        case Projection::CubeFace: {
            glm::dvec3 c = enuToCube(d);
            // Project onto this face: the major axis must be the face's axis.
            const int axis = cubeFace / 2;
            const double sign = cubeFace % 2 == 0 ? 1.0 : -1.0;
            double ma = c[axis] * sign;
            if (ma <= 0 || ma < std::abs(c[(axis + 1) % 3]) - 1e-12 || ma < std::abs(c[(axis + 2) % 3]) - 1e-12)
                return std::nullopt;
            glm::dvec3 q = c / ma;  // on the face plane
            double s = 0, t = 0;
            switch (cubeFace) {
                case 0: s = -q.z; t = -q.y; break;
                case 1: s = q.z; t = -q.y; break;
                case 2: s = q.x; t = q.z; break;
                case 3: s = q.x; t = -q.z; break;
                case 4: s = q.x; t = -q.y; break;
                default: s = -q.x; t = -q.y; break;
            }
            return glm::dvec2((s + 1) * w / 2, (t + 1) * h / 2);
        }
    }
    return std::nullopt;
}

namespace {
// A pinhole projection (perspective, cube face) as three ENU vectors: clip = (a.d, b.d, f.d, f.d),
// so NDC = (a.d, b.d) / f.d. Mirrored by welkin_pinhole() in engine/shaders/camera.glsl.
struct Pinhole {
    glm::dvec3 a, b, f;
};
Pinhole pinholeOf(const Camera& c) {
    if (c.projection == Projection::Perspective && c.host) {
        const glm::dmat3 rows = hostClipRows(c);
        return {rows[0], rows[1], rows[2]};
    }
    if (c.projection == Projection::Perspective) {
        const glm::dmat3 m = c.basis();
        const double tanY = std::tan(c.verticalFovRad / 2), tanX = tanY * c.width / c.height;
        return {m[0] / tanX, m[1] / tanY, m[2]};
    }
    // Cube face: NDC x = s, NDC y = -t (pixel row 0 is t = -1, the top), with (s, t) the face
    // coordinates of pixelOf(), written in ENU (cube x = east, y = up, z = south).
    Pinhole p;
    glsl::dp::camera_shared::welkin_cubeFacePinhole(c.cubeFace, p.a, p.b, p.f);  // the shader's table
    return p;
}
glm::dvec3 checkedUnit(const glm::dvec3& d, const char* where) {
    const double n = glm::length(d);
    if (!(n > 0) || !std::isfinite(n)) throw Error(std::string(where) + ": direction has zero length or is not finite");
    return d / n;
}
}  // namespace

std::optional<glm::dvec4> Camera::clipFromDirection(const glm::dvec3& dIn, int copy) const {
    if (copy < 0 || copy > 1) throw Error("Camera::clipFromDirection(): copy " + std::to_string(copy) + " not in [0, 1]");
    const glm::dvec3 d = checkedUnit(dIn, "Camera::clipFromDirection()");
    if (!pixelOf(d)) return std::nullopt;
    if (copy == 1 && projection != Projection::Equirect) return std::nullopt;
    namespace sh = glsl::dp::camera_shared;  // the shader's text (camera_projection.shared.glsl)
    const glm::dvec2 size(width, height);
    switch (projection) {
        case Projection::Perspective:
        case Projection::CubeFace: {
            const Pinhole p = pinholeOf(*this);
            return sh::welkin_clipPinhole(p.a, p.b, p.f, d);
        }
        case Projection::Fisheye: return sh::welkin_clipFisheye(size, d);
        case Projection::Equirect: {
            glm::dvec4 clip = sh::welkin_clipEquirect(d);
            if (copy == 1) clip.x += clip.x >= 0 ? -2 : 2;
            return clip;
        }
    }
    return std::nullopt;
}

glm::dvec2 Camera::pixelFromClip(const glm::dvec4& c) const {
    if (!(c.w > 0)) throw Error("Camera::pixelFromClip(): w " + std::to_string(c.w) + " not > 0 (clipped away)");
    return {(c.x / c.w + 1) * width / 2, (1 - c.y / c.w) * height / 2};
}

std::optional<glm::dmat3x2> Camera::pixelJacobian(const glm::dvec3& dIn) const {
    const glm::dvec3 d = checkedUnit(dIn, "Camera::pixelJacobian()");
    if (!pixelOf(d)) return std::nullopt;
    namespace sh = glsl::dp::camera_shared;  // the shader's text (camera_projection.shared.glsl)
    const glm::dvec2 size(width, height);
    switch (projection) {
        case Projection::Perspective:
        case Projection::CubeFace: {
            const Pinhole p = pinholeOf(*this);
            return sh::welkin_jacobianPinhole(p.a, p.b, p.f, size, d);
        }
        case Projection::Fisheye: return sh::welkin_jacobianFisheye(size, d);
        case Projection::Equirect: return sh::welkin_jacobianEquirect(size, d);
    }
    return std::nullopt;
}

std::optional<glm::dvec2> Camera::pixelScale(const glm::dvec3& dIn) const {
    const glm::dvec3 d = checkedUnit(dIn, "Camera::pixelScale()");
    auto J = pixelJacobian(d);
    if (!J) return std::nullopt;
    return glsl::dp::camera_shared::welkin_pixelScaleOf(*J, d);  // the shader's text (camera_projection.shared.glsl)
}

double sceneDistanceMeters(const Camera& c, double d, const glm::dvec3& dir, const HostDepth& depth) {
    if (c.depth.reversedZ ? d <= 0.0 : d >= 1.0) return kInfinity;
    const double zNdc = c.depth.zeroToOne ? d : 2 * d - 1;
    const glm::dmat4 P = c.depthProjection(depth.nearM, depth.farM);
    const double z = (P[3][2] - zNdc * P[3][3]) / (zNdc * P[2][3] - P[2][2]);
    const glm::dvec3 vz = c.host ? glm::dvec3(c.host->viewFromEnu[0][2], c.host->viewFromEnu[1][2], c.host->viewFromEnu[2][2]) : -c.basis()[2];
    const double along = glm::dot(glm::normalize(dir), vz);
    return std::max(z / std::min(along, -1e-12), 0.0) * (c.host ? c.host->metresPerUnit : depth.metresPerUnit);
}

CameraBlock makeCameraBlock(const Camera& c, double seconds, const HostDepth& depth) {
    CameraBlock b{};
    glm::dmat3 m = c.basis();
    b.cameraToWorld = glm::mat4(glm::mat3(m));
    b.viewport = glm::vec4(float(c.width), float(c.height), 1.0f / float(c.width), 1.0f / float(c.height));
    b.projection = glm::vec4(float(int(c.projection)), float(std::tan(c.verticalFovRad / 2)),
                             float(c.width) / float(c.height), float(c.cubeFace));
    b.time = glm::vec4(float(seconds), 0, 0, 0);
    if (c.projection == Projection::Perspective || c.projection == Projection::CubeFace) {
        const Pinhole p = pinholeOf(c);
        b.clipRows = glm::mat4(glm::mat3(glm::dmat3(p.a, p.b, p.f)));
        b.worldFromClip = glm::mat4(glm::mat3(glm::inverse(glm::transpose(glm::dmat3(p.a, p.b, p.f)))));
    }
    const glm::dmat4 P = c.depthProjection(depth.nearM, depth.farM);
    b.depthProjection = glm::vec4(float(P[2][2]), float(P[3][2]), float(P[2][3]), float(P[3][3]));
    const double mpu = c.host ? c.host->metresPerUnit : depth.metresPerUnit;
    b.depthMode = glm::vec4(c.depth.reversedZ ? 1.0f : 0.0f, c.depth.zeroToOne ? 1.0f : 0.0f, float(mpu), 0.0f);
    // View space +z in ENU: the host's (row 2 of viewFromEnu), or backwards along the optical axis.
    const glm::dvec3 vz = c.host ? glm::dvec3(c.host->viewFromEnu[0][2], c.host->viewFromEnu[1][2], c.host->viewFromEnu[2][2]) : -m[2];
    b.viewZ = glm::vec4(glm::vec3(vz), 0.0f);
    b.eye = glm::vec4(glm::vec3(c.eyeEnuMeters()), 0.0f);
    return b;
}

}  // namespace welkin
