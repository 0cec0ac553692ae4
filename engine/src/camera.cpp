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
