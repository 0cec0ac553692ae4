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
//   // A game's own camera: its view and projection matrices, a Y-up world in metres, reversed-Z
//   // depth with glClipControl(GL_LOWER_LEFT, GL_ZERO_TO_ONE) and an infinite far plane.
//   welkin::Camera host = welkin::Camera::fromViewProjection(view, projection, welkin::enuFromYUp(),
//                                                            1920, 1080, {.reversedZ = true, .zeroToOne = true});
//
// Projections:
//  - Perspective: looks at (azimuthRad, altitudeRad), vertical field of view verticalFovRad,
//    the zenith "up" (no roll); or, made by Camera::fromViewProjection(), the host's own pinhole
//    camera (any roll, asymmetric and off-axis frusta, infinite far planes): then `host` is set and
//    azimuthRad, altitudeRad and verticalFovRad describe its optical axis only.
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
#include <welkin/host_depth.hpp>

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

/// How the host's depth buffer is laid out: where the far plane is and the clip depth range
/// (glClipControl). welkin draws the sky at the far plane behind the host's geometry with GL_LEQUAL
/// (standard) or GL_GEQUAL (reversed-Z), and reads the host's depth texture this way.
struct DepthMode {
    bool reversedZ = false;  ///< far plane at window depth 0 (reversed-Z, depth cleared to 0); false: at 1
    bool zeroToOne = false;  ///< NDC depth in [0, 1] (glClipControl(..., GL_ZERO_TO_ONE)); false: OpenGL's [-1, 1]
    bool operator==(const DepthMode&) const = default;
};

/// Host world -> ENU (x east, y north, z up; metres relative to the observer) for a right-handed
/// Y-up host world with x east, y up and -z north (OpenGL, glTF, most engines).
/// `metresPerUnit` > 0 metres per host unit; `originEnuMeters`: where the host world's origin is in
/// ENU metres (a floating origin moves it, the sky stays put).
glm::dmat4 enuFromYUp(double metresPerUnit = 1.0, const glm::dvec3& originEnuMeters = glm::dvec3(0.0));
/// Host world -> ENU for a right-handed Z-up host world with x east, y north, z up (the ENU axes).
glm::dmat4 enuFromZUp(double metresPerUnit = 1.0, const glm::dvec3& originEnuMeters = glm::dvec3(0.0));

/// The host's own pinhole camera, as Camera::fromViewProjection() derived it from its matrices.
struct HostProjection {
    glm::dmat3 viewFromEnu{1.0};     ///< rotation: ENU direction -> host view space (orthonormal)
    glm::dmat4 projection{1.0};      ///< the host's projection matrix (view space -> clip), host units
    glm::dvec3 eyeEnuMeters{0.0};    ///< the eye's position, ENU metres relative to the observer
    double metresPerUnit = 1.0;      ///< metres per host unit (> 0)
};

struct Camera {
    Projection projection = Projection::Perspective;
    double azimuthRad = 0.0;               ///< view direction (perspective), [-2pi, 2pi]
    double altitudeRad = 0.35;             ///< view direction (perspective), [-pi/2, pi/2]
    double verticalFovRad = 1.0471975512;  ///< perspective vertical field of view, (0, pi)
    int cubeFace = 0;                      ///< CubeFace only, [0, 5]
    int width = 1280;                      ///< pixels, [1, 16384]
    int height = 720;                      ///< pixels, [1, 16384]
    DepthMode depth{};                     ///< the host's depth convention (renderInto, applyToScene)
    /// Set by fromViewProjection() (Projection::Perspective only): the host's matrices replace
    /// azimuthRad/altitudeRad/verticalFovRad for every mapping between pixels and directions.
    std::optional<HostProjection> host;
    /// Internal: basis() remembers its last result for the azimuth and altitude it was computed
    /// from (the elements ask for it dozens of times a frame; each time cost four sines and
    /// cosines). Recomputed whenever either angle differs; not used for a host camera.
    struct BasisMemo {
        double azimuthRad = 0.0, altitudeRad = 0.0;
        glm::dmat3 basis{0.0};
        bool valid = false;
    };
    mutable BasisMemo basisMemo{};

    /// The host's camera from its view matrix (host world -> view space, OpenGL convention: the
    /// camera looks down -z), its projection matrix (view -> clip: any perspective, off-axis or
    /// asymmetric, finite or infinite far plane, in the convention `depth` says) and `worldToEnu`
    /// (host world -> ENU metres relative to the observer: enuFromYUp(), enuFromZUp() or the
    /// host's own; rotation, uniform scale, translation). The view's translation only places the
    /// eye (eyeEnuMeters()): directions ignore it, so a floating origin costs no precision.
    /// Throws welkin::Error (one line) for a non-finite matrix, an orthographic projection (the
    /// sky is at infinity), a view or worldToEnu that is not a rotation with a uniform scale, or
    /// width/height not in [1, 16384].
    static Camera fromViewProjection(const glm::dmat4& view, const glm::dmat4& projection, const glm::dmat4& worldToEnu,
                                     int width, int height, DepthMode depth = {});
    /// The eye's position in ENU metres relative to the observer (0 unless made from host matrices).
    glm::dvec3 eyeEnuMeters() const { return host ? host->eyeEnuMeters : glm::dvec3(0.0); }
    /// The host's projection matrix, or for other cameras a standard OpenGL perspective with
    /// these near and far planes (host units; farUnits may be +inf) in the convention of `depth`:
    /// what the host's depth buffer is read with.
    glm::dmat4 depthProjection(double nearUnits, double farUnits) const;

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

/// Distance in metres from the eye to the host's geometry at window depth `windowDepth` (a texel of
/// the host's depth texture, [0, 1]) along the unit ENU direction `dir` of its pixel, read with
/// the host's projection (a camera from fromViewProjection()) or, for other cameras,
/// depthProjection(depth.nearM, depth.farM) with depth.metresPerUnit, in the camera's DepthMode;
/// +inf at the far plane. The CPU twin of GLSL welkin_sceneDistance() (engine/shaders/camera.glsl).
double sceneDistanceMeters(const Camera& camera, double windowDepth, const glm::dvec3& dir, const HostDepth& depth = {});

/// The per-frame camera block shared by every element's shaders (std140, binding gl::binding::kCameraUbo; see
/// engine/shaders/camera.glsl).
struct CameraBlock {
    glm::mat4 cameraToWorld;  ///< columns: right, up, forward (perspective: forward is the optical axis)
    glm::vec4 viewport;       ///< width, height, 1/width, 1/height (pixels)
    glm::vec4 projection;     ///< type (0..3), tan(fovY/2), aspect, cube face
    glm::vec4 time;           ///< seconds since the processor started, 0, 0, 0
    glm::mat4 clipRows;       ///< perspective: columns a, b, f with clip = (a.d, b.d, f.d, f.d) for an ENU direction d
    glm::mat4 worldFromClip;  ///< perspective: mat3 part, ENU ray = M (ndc.x, ndc.y, 1) (the inverse of clipRows' rows)
    glm::vec4 depthProjection;  ///< the host depth's projection: P[2][2], P[3][2], P[2][3], P[3][3] (glm [column][row])
    glm::vec4 depthMode;      ///< reversedZ (0/1), zeroToOne (0/1), metres per host unit, 0
    glm::vec4 viewZ;          ///< the host view space's +z axis in ENU (xyz): view-space z = |ray| (d . viewZ)
    glm::vec4 eye;            ///< the eye's position, ENU metres relative to the observer (xyz)
};
/// `depth`: how a camera not made from host matrices reads the host's depth buffer (its near and
/// far planes and units; ignored for host cameras, which use their own projection).
CameraBlock makeCameraBlock(const Camera& camera, double seconds, const HostDepth& depth = {});

}  // namespace welkin
