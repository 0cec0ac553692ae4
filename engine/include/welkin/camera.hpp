// Camera and projections. Directions are in the world ENU frame (x east, y north, z up); pixel
// coordinates have their origin at the top-left corner of the image, y downwards, and the centre
// of pixel (i, j) at (i + 0.5, j + 0.5).
//
//   welkin::Camera cam;
//   cam.projection = welkin::Projection::Fisheye;
//   cam.width = cam.height = 512;
//   glm::dvec3 east = welkin::directionFromAzAlt(glm::radians(90.0), 0.0);  // east horizon
//   auto px = cam.pixelOf(east);
//   // -> (0, 256): east is on the left of an all-sky image seen from below
//   auto clip = cam.clipFromDirection(east);  // gl_Position (nullopt: not visible); pixelFromClip(*clip) == *px
//   auto ppr = cam.pixelScale(east);          // (2R/pi, R) = (163, 256) pixels per radian there
//
// Projections:
//  - Perspective: looks at (azimuthRad, altitudeRad), vertical field of view verticalFovRad,
//    the zenith "up" (no roll).
//  - Fisheye: equidistant all-sky, zenith at the centre, horizon on the inscribed circle of
//    radius min(W, H)/2, north up, east left: r = (pi/2 - alt)/(pi/2) * R,
//    x = W/2 - r sin(az), y = H/2 - r cos(az).
//  - Equirect: u = az / 2pi (north at the left edge, through east), v = (pi/2 - alt)/pi (zenith
//    on the top row).
//  - CubeFace: one face of a cube map in OpenGL face order (+X, -X, +Y, -Y, +Z, -Z) with cube
//    axes x = east, y = up, z = south; face texel rows as GL stores them (row 0 is t = -1).
//
// Both ways: directionAt() maps a pixel to a direction (the fragment side, like GLSL
// welkin_viewDirection), pixelOf() and clipFromDirection() map a direction to a pixel (the vertex
// side, like GLSL welkin_clipFromDirection). All three use continuous pixel coordinates: pixel
// (i, j) covers [i, i+1) x [j, j+1) and its centre, where a fragment is shaded, is (i + 0.5, j + 0.5).
// A clip position maps to pixelOf() through the viewport transform of a viewport equal to the
// camera (pixelFromClip()). Perspective and cube faces are pinhole projections, linear in the
// direction (lines between two directions clip correctly); fisheye and equirect are not (subdivide
// lines, and split them at the equirect seam).
#pragma once
#include <glm/glm.hpp>

#include <optional>
#include <string>
#include <string_view>

namespace welkin {

enum class Projection { Perspective, Fisheye, Equirect, CubeFace };

std::string_view toString(Projection p);
/// "perspective", "fisheye", "equirect", "cube"; throws welkin::Error listing the accepted names.
Projection parseProjection(std::string_view name);

/// Unit vector (ENU) for azimuth (from north through east) and altitude, radians.
glm::dvec3 directionFromAzAlt(double azimuthRad, double altitudeRad);
/// Azimuth in [0, 2pi) and altitude in [-pi/2, pi/2] of a (not necessarily unit) ENU vector.
glm::dvec2 azAltFromDirection(const glm::dvec3& dir);

struct Camera {
    Projection projection = Projection::Perspective;
    double azimuthRad = 0.0;               ///< view direction (perspective), [-2pi, 2pi]
    double altitudeRad = 0.35;             ///< view direction (perspective), [-pi/2, pi/2]
    double verticalFovRad = 1.0471975512;  ///< perspective vertical field of view, (0, pi)
    int cubeFace = 0;                      ///< CubeFace only, [0, 5]
    int width = 1280;                      ///< pixels, [1, 16384]
    int height = 720;                      ///< pixels, [1, 16384]

    /// Throws welkin::Error naming the first member out of range.
    void validate() const;
    /// World direction (unit) through a pixel position, or nullopt outside the image circle of
    /// a fisheye.
    std::optional<glm::dvec3> directionAt(const glm::dvec2& pixel) const;
    /// Pixel position of a world direction, or nullopt if not visible (behind a perspective
    /// camera, below the fisheye horizon, off the cube face).
    std::optional<glm::dvec2> pixelOf(const glm::dvec3& direction) const;
    /// Perspective basis as columns (right, up, forward), world ENU.
    glm::dmat3 basis() const;

    /// Clip-space position (gl_Position) of a world direction (any non-zero length): with a
    /// viewport equal to the camera, its fragment lands on the pixel whose directionAt() is that
    /// direction, at pixelFromClip(clip) == pixelOf(direction). z = w (the far plane, like the
    /// fullscreen pass). nullopt exactly when pixelOf() is (not visible). Perspective:
    /// (right.d / tanX, up.d / tanY, fwd.d, fwd.d), outside [-w, w] off the frame; cube face:
    /// the same with the face's axes and tan 45 deg; fisheye and equirect: w = 1.
    /// `copy` 1 (equirect only, else nullopt) is the twin across the seam at azimuth 0/2pi: x
    /// shifted by -2w if x >= 0, +2w otherwise, so a sprite that straddles the seam is drawn
    /// whole by drawing both copies. Throws welkin::Error on a zero or non-finite direction or
    /// copy not in [0, 1].
    std::optional<glm::dvec4> clipFromDirection(const glm::dvec3& direction, int copy = 0) const;
    /// Viewport transform for a viewport equal to the camera: ((x/w + 1) W/2, (1 - y/w) H/2),
    /// pixels, origin top-left, y down. Throws welkin::Error if w <= 0 (clipped away).
    glm::dvec2 pixelFromClip(const glm::dvec4& clip) const;
    /// d(pixel)/d(direction) at a visible direction: a small displacement `delta` (radians) of
    /// the unit direction, perpendicular to it, moves the pixel position (x right, y down) by
    /// J * delta pixels; J * direction = 0. Equirect: the horizontal scale W / (2pi cos alt) is
    /// capped at cos alt >= 1e-6 (it is infinite at the poles). nullopt when pixelOf() is.
    std::optional<glm::dmat3x2> pixelJacobian(const glm::dvec3& direction) const;
    /// Local pixel scale at a visible direction: (smallest, largest) pixels per radian over the
    /// directions of displacement (the singular values of pixelJacobian()). A sprite of angular
    /// radius a covers at least a * x and at most a * y pixels in any direction. nullopt when
    /// pixelOf() is.
    std::optional<glm::dvec2> pixelScale(const glm::dvec3& direction) const;
};

/// The per-frame camera block shared by every element's shaders (std140, binding gl::binding::kCameraUbo; see
/// engine/shaders/camera.glsl).
struct CameraBlock {
    glm::mat4 cameraToWorld;  ///< columns: right, up, forward (perspective)
    glm::vec4 viewport;       ///< width, height, 1/width, 1/height (pixels)
    glm::vec4 projection;     ///< type (0..3), tan(fovY/2), aspect, cube face
    glm::vec4 time;           ///< seconds since the processor started, 0, 0, 0
};
CameraBlock makeCameraBlock(const Camera& camera, double seconds);

}  // namespace welkin
