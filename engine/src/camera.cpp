#include <welkin/camera.hpp>
#include <welkin/check.hpp>
#include <welkin/error.hpp>

#include <cmath>
#include <numbers>

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

glm::dvec3 directionFromAzAlt(double az, double alt) {
    double c = std::cos(alt);
    return {c * std::sin(az), c * std::cos(az), std::sin(alt)};
}

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

glm::dmat3 Camera::basis() const {
    glm::dvec3 f = directionFromAzAlt(azimuthRad, altitudeRad);
    // Horizontal right vector defined from the azimuth so it stays valid looking straight up.
    glm::dvec3 r{std::cos(azimuthRad), -std::sin(azimuthRad), 0.0};
    glm::dvec3 u = glm::cross(r, f);
    return glm::dmat3(r, u, f);
}

namespace {
// Cube axes (x east, y up, z south) -> ENU.
glm::dvec3 cubeToEnu(const glm::dvec3& c) { return {c.x, -c.z, c.y}; }
glm::dvec3 enuToCube(const glm::dvec3& e) { return {e.x, e.z, -e.y}; }
// Direction of a face texel coordinate (s, t) in [-1, 1], OpenGL cube-map convention.
glm::dvec3 cubeDir(int face, double s, double t) {
    switch (face) {
        case 0: return {1, -t, -s};
        case 1: return {-1, -t, s};
        case 2: return {s, 1, t};
        case 3: return {s, -1, -t};
        case 4: return {s, -t, 1};
        default: return {-s, -t, -1};
    }
}
}  // namespace

std::optional<glm::dvec3> Camera::directionAt(const glm::dvec2& p) const {
    const double w = width, h = height;
    switch (projection) {
        case Projection::Perspective: {
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
    if (c.projection == Projection::Perspective) {
        const glm::dmat3 m = c.basis();
        const double tanY = std::tan(c.verticalFovRad / 2), tanX = tanY * c.width / c.height;
        return {m[0] / tanX, m[1] / tanY, m[2]};
    }
    // Cube face: NDC x = s, NDC y = -t (pixel row 0 is t = -1, the top), with (s, t) the face
    // coordinates of pixelOf(), written in ENU (cube x = east, y = up, z = south).
    switch (c.cubeFace) {
        case 0: return {{0, 1, 0}, {0, 0, 1}, {1, 0, 0}};    // +X east
        case 1: return {{0, -1, 0}, {0, 0, 1}, {-1, 0, 0}};  // -X west
        case 2: return {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};    // +Y up
        case 3: return {{1, 0, 0}, {0, -1, 0}, {0, 0, -1}};  // -Y down
        case 4: return {{1, 0, 0}, {0, 0, 1}, {0, -1, 0}};   // +Z south
        default: return {{-1, 0, 0}, {0, 0, 1}, {0, 1, 0}};  // -Z north
    }
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
    const double w = width, h = height;
    glm::dvec4 clip(0, 0, 1, 1);
    switch (projection) {
        case Projection::Perspective:
        case Projection::CubeFace: {
            const Pinhole p = pinholeOf(*this);
            const double fw = glm::dot(p.f, d);
            clip = {glm::dot(p.a, d), glm::dot(p.b, d), fw, fw};
            break;
        }
        case Projection::Fisheye: {
            // pixel = (W/2, H/2) - r (sin az, cos az), r = theta / (pi/2) * R (theta from the zenith).
            const double R = std::min(w, h) / 2, hor = std::hypot(d.x, d.y);
            const double r = std::atan2(hor, d.z) / kHalfPi * R;
            const glm::dvec2 sc = hor > 0 ? glm::dvec2(d.x, d.y) / hor : glm::dvec2(0.0);
            clip.x = -2 * r * sc.x / w;
            clip.y = 2 * r * sc.y / h;
            break;
        }
        case Projection::Equirect: {
            const glm::dvec2 aa = azAltFromDirection(d);
            clip.x = aa.x / kPi - 1;
            clip.y = aa.y / kHalfPi;
            if (copy == 1) clip.x += clip.x >= 0 ? -2 : 2;
            break;
        }
    }
    return clip;
}

glm::dvec2 Camera::pixelFromClip(const glm::dvec4& c) const {
    if (!(c.w > 0)) throw Error("Camera::pixelFromClip(): w " + std::to_string(c.w) + " not > 0 (clipped away)");
    return {(c.x / c.w + 1) * width / 2, (1 - c.y / c.w) * height / 2};
}

std::optional<glm::dmat3x2> Camera::pixelJacobian(const glm::dvec3& dIn) const {
    const glm::dvec3 d = checkedUnit(dIn, "Camera::pixelJacobian()");
    if (!pixelOf(d)) return std::nullopt;
    const double w = width, h = height;
    // J = sum of outer products (pixel displacement per radian) x (unit tangent), as rows jx, jy.
    glm::dvec3 jx(0.0), jy(0.0);
    switch (projection) {
        case Projection::Perspective:
        case Projection::CubeFace: {
            // NDC = (a.d, b.d) / f.d; pixel = ((NDC.x + 1) W/2, (1 - NDC.y) H/2).
            const Pinhole p = pinholeOf(*this);
            const double fw = glm::dot(p.f, d), nx = glm::dot(p.a, d) / fw, ny = glm::dot(p.b, d) / fw;
            jx = (w / 2) * (p.a - nx * p.f) / fw;
            jy = -(h / 2) * (p.b - ny * p.f) / fw;
            break;
        }
        case Projection::Fisheye: {
            // Radially k = R/(pi/2) pixels per radian; along the azimuth k theta / sin(theta).
            const double R = std::min(w, h) / 2, k = R / kHalfPi, hor = std::hypot(d.x, d.y);
            const double theta = std::atan2(hor, d.z);
            const glm::dvec2 s = hor > 0 ? glm::dvec2(d.x, d.y) / hor : glm::dvec2(0.0, 1.0);
            const double g = hor > 1e-8 ? theta / hor : 1.0;  // theta / sin(theta) -> 1 at the zenith
            const glm::dvec3 eTheta(d.z * s.x, d.z * s.y, -hor), eAz(s.y, -s.x, 0.0);
            const glm::dvec2 pTheta = -k * s, pAz = -k * g * glm::dvec2(s.y, -s.x);
            jx = pTheta.x * eTheta + pAz.x * eAz;
            jy = pTheta.y * eTheta + pAz.y * eAz;
            break;
        }
        case Projection::Equirect: {
            // x = az W/(2pi), y = (pi/2 - alt) H/pi; one radian along the azimuth circle is
            // 1/cos(alt) radians of azimuth.
            const double hor = std::hypot(d.x, d.y);
            const glm::dvec2 s = hor > 0 ? glm::dvec2(d.x, d.y) / hor : glm::dvec2(0.0, 1.0);
            const glm::dvec3 eAz(s.y, -s.x, 0.0), eAlt(-d.z * s.x, -d.z * s.y, hor);
            jx = w / (2 * kPi * std::max(hor, 1e-6)) * eAz;
            jy = -h / kPi * eAlt;
            break;
        }
    }
    glm::dmat3x2 J;  // 3 columns (ENU components) of 2 rows (pixel x, y)
    for (int c = 0; c < 3; ++c) J[c] = glm::dvec2(jx[c], jy[c]);
    return J;
}

std::optional<glm::dvec2> Camera::pixelScale(const glm::dvec3& dIn) const {
    const glm::dvec3 d = checkedUnit(dIn, "Camera::pixelScale()");
    auto J = pixelJacobian(d);
    if (!J) return std::nullopt;
    // The 2x2 map M = J (t1 t2) in a tangent frame at d; with M = (a b; c e) its singular values
    // are (sqrt((a+e)^2 + (c-b)^2) +- sqrt((a-e)^2 + (c+b)^2)) / 2 (no difference of squares),
    // the smallest taken as |det M| / largest. Mirrors welkin_pixelScale().
    const glm::dvec3 t1 = glm::normalize(glm::cross(std::abs(d.z) < 0.9 ? glm::dvec3(0, 0, 1) : glm::dvec3(1, 0, 0), d));
    const glm::dvec3 t2 = glm::cross(d, t1);
    const glm::dvec2 m1 = *J * t1, m2 = *J * t2;
    const double a = m1.x, c = m1.y, b = m2.x, e = m2.y;
    const double sMax = (std::hypot(a + e, c - b) + std::hypot(a - e, c + b)) / 2;
    return glm::dvec2(sMax > 0 ? std::abs(a * e - b * c) / sMax : 0.0, sMax);
}

CameraBlock makeCameraBlock(const Camera& c, double seconds) {
    CameraBlock b{};
    glm::dmat3 m = c.basis();
    b.cameraToWorld = glm::mat4(glm::mat3(m));
    b.viewport = glm::vec4(float(c.width), float(c.height), 1.0f / float(c.width), 1.0f / float(c.height));
    b.projection = glm::vec4(float(int(c.projection)), float(std::tan(c.verticalFovRad / 2)),
                             float(c.width) / float(c.height), float(c.cubeFace));
    b.time = glm::vec4(float(seconds), 0, 0, 0);
    return b;
}

}  // namespace welkin
