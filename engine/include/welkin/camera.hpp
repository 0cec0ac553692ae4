// Camera and projections. Directions are in the world ENU frame (x east, y north, z up); pixel
// coordinates have their origin at the top-left corner of the image, y downwards, and the centre
// of pixel (i, j) at (i + 0.5, j + 0.5).
//
//   welkin::Camera cam;
//   cam.projection = welkin::Projection::Fisheye;
//   cam.width = cam.height = 512;
//   auto px = cam.pixelOf(welkin::directionFromAzAlt(glm::radians(90.0), 0.0));  // east horizon
//   // -> (0, 256): east is on the left of an all-sky image seen from below
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
};

/// The per-frame camera block shared by every element's shaders (std140, binding 0; see
/// engine/shaders/camera.glsl).
struct CameraBlock {
    glm::mat4 cameraToWorld;  ///< columns: right, up, forward (perspective)
    glm::vec4 viewport;       ///< width, height, 1/width, 1/height (pixels)
    glm::vec4 projection;     ///< type (0..3), tan(fovY/2), aspect, cube face
    glm::vec4 time;           ///< seconds since the processor started, 0, 0, 0
};
CameraBlock makeCameraBlock(const Camera& camera, double seconds);

}  // namespace welkin
