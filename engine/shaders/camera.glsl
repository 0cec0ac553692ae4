// The per-frame camera block (welkin::CameraBlock, std140, binding WELKIN_BINDING_CAMERA_UBO) and
// the camera's projection both ways, in the world ENU frame (x east, y north, z up):
//  - fragment side: welkin_viewDirection(welkin_pixel(), dir), the direction through a pixel
//    (mirrors welkin::Camera::directionAt());
//  - vertex side: gl_Position = welkin_clipFromDirection(dir) puts a vertex on the pixel whose
//    view direction is `dir` (mirrors welkin::Camera::clipFromDirection()), and
//    welkin_pixelJacobian() / welkin_pixelScale() give the local pixels per radian there.
// Pixel coordinates are continuous, origin top-left, y down; the centre of pixel (i, j), where
// its fragment is shaded, is (i + 0.5, j + 0.5). The viewport must equal the camera's size (the
// processor sets it).
layout(std140, binding = WELKIN_BINDING_CAMERA_UBO) uniform WelkinCamera {
    mat4 welkin_cameraToWorld;  // columns: right, up, forward
    vec4 welkin_viewport;       // width, height, 1/width, 1/height (pixels)
    vec4 welkin_projection;     // type (0 perspective, 1 fisheye, 2 equirect, 3 cube), tan(fovY/2), aspect, face
    vec4 welkin_time;           // seconds since start
    mat4 welkin_clipRows;       // perspective: columns a, b, f; clip = (a.d, b.d, f.d, f.d) for an ENU direction d
    mat4 welkin_worldFromClip;  // perspective: ENU ray = mat3(M) * vec3(ndc.xy, 1)
    vec4 welkin_depthProjection;  // the host depth's projection P[2][2], P[3][2], P[2][3], P[3][3]
    vec4 welkin_depthMode;      // reversedZ (0/1), zeroToOne (0/1), metres per host unit, 0
    vec4 welkin_viewZ;          // the host view space's +z axis, ENU
    vec4 welkin_eye;            // the eye, ENU metres from the observer
};

// The camera's projection. A program built with WELKIN_PROJECTION defined (0..3, see
// welkin::gl::ProjectionPrograms) compiles only that projection's code: llvmpipe, like most GPU
// compilers for divergent code, otherwise evaluates every branch of the projection switch.
int welkin_projectionType() {
#ifdef WELKIN_PROJECTION
    return WELKIN_PROJECTION;
#else
    return int(welkin_projection.x + 0.5);
#endif
}

#ifdef WELKIN_FRAGMENT_SHADER
// Pixel position with the origin at the top-left corner, y downwards (image convention).
vec2 welkin_pixel() { return vec2(gl_FragCoord.x, welkin_viewport.y - gl_FragCoord.y); }
#endif

// welkin_directionFromAzAlt(az, alt): lighting_cube.shared.glsl (camera.cpp's directionFromAzAlt()
// compiles it in double).
#include "lighting_cube.shared.glsl"
// WELKIN_PI, the projections from a direction to clip space and their Jacobians:
// camera_projection.shared.glsl (camera.cpp compiles it in double for Camera::clipFromDirection(),
// pixelJacobian(), pixelScale()).
#include "camera_projection.shared.glsl"

// Unit world direction through `pixel`; returns false outside a fisheye's image circle.
bool welkin_viewDirection(vec2 pixel, out vec3 dir) {
    vec2 size = welkin_viewport.xy;
    int type = welkin_projectionType();
    dir = vec3(0.0, 0.0, 1.0);
    if (type == 0) {
        // Any pinhole camera (welkin's, or the host's from its matrices: roll, off-axis frusta).
        vec2 ndc = vec2(2.0 * pixel.x / size.x - 1.0, 1.0 - 2.0 * pixel.y / size.y);
        dir = normalize(mat3(welkin_worldFromClip) * vec3(ndc, 1.0));
        return true;
    }
    if (type == 1) {
        float R = 0.5 * min(size.x, size.y);
        vec2 d = 0.5 * size - pixel;  // (r sin az, r cos az)
        float r = length(d);
        if (r > R) return false;
        float alt = 0.5 * WELKIN_PI * (1.0 - r / R);
        // (sin az, cos az) = d / r: no atan, sin or cos of the azimuth (llvmpipe evaluates every
        // projection's branch, so each transcendental here costs every pixel of every element).
        vec2 sc = r > 0.0 ? d / r : vec2(0.0, 1.0);
        float c = cos(alt);
        dir = vec3(sc.x * c, sc.y * c, sin(alt));
        return true;
    }
    if (type == 2) {
        float az = 2.0 * WELKIN_PI * pixel.x / size.x;
        float alt = 0.5 * WELKIN_PI - WELKIN_PI * pixel.y / size.y;
        dir = welkin_directionFromAzAlt(az, alt);
        return true;
    }
    // Cube face (OpenGL order, cube axes x east, y up, z south).
    float s = 2.0 * pixel.x / size.x - 1.0, t = 2.0 * pixel.y / size.y - 1.0;
    int face = int(welkin_projection.w + 0.5);
    vec3 c;
    if (face == 0) c = vec3(1.0, -t, -s);
    else if (face == 1) c = vec3(-1.0, -t, s);
    else if (face == 2) c = vec3(s, 1.0, t);
    else if (face == 3) c = vec3(s, -1.0, -t);
    else if (face == 4) c = vec3(s, -t, 1.0);
    else c = vec3(-s, -t, -1.0);
    dir = normalize(vec3(c.x, -c.z, c.y));
    return true;
}

// Angular size of one pixel at the image centre, radians (for antialiasing widths).
float welkin_pixelAngle() {
    int type = welkin_projectionType();
    vec2 size = welkin_viewport.xy;
    if (type == 0) return 2.0 * welkin_projection.y / size.y;
    if (type == 1) return WELKIN_PI / min(size.x, size.y);
    if (type == 2) return WELKIN_PI / size.y;
    return 2.0 / size.y;
}

// ---- Vertex side: from a direction to clip space ----------------------------------------------

// The clip position of a direction that is not visible in the projection (below a fisheye's
// horizon): w < 0, so the clipper rejects it, and any vertex derived from it by
// welkin_clipOffset(), whatever the depth-clamp state.
const vec4 WELKIN_CLIP_INVISIBLE = vec4(0.0, 0.0, 0.0, -1.0);

// Pinhole projections (0 perspective, 3 cube face) as three ENU vectors: clip = (a.d, b.d, f.d,
// f.d), NDC = (a.d, b.d) / f.d. Mirrors pinholeOf() in engine/src/camera.cpp (the cube faces:
// welkin_cubeFacePinhole(), shared).
void welkin_pinhole(out vec3 a, out vec3 b, out vec3 f) {
    if (welkin_projectionType() == 0) {
        a = welkin_clipRows[0].xyz;
        b = welkin_clipRows[1].xyz;
        f = welkin_clipRows[2].xyz;
        return;
    }
    welkin_cubeFacePinhole(int(welkin_projection.w + 0.5), a, b, f);
}

// gl_Position for a world direction (any non-zero length): its fragment lands on the pixel whose
// welkin_viewDirection() is `dir`. z = w: the far plane, like the fullscreen pass (drawn behind a
// host's geometry with GL_LEQUAL). A direction the projection does not show is clipped:
//  - perspective and cube face (pinhole, linear in `dir`): w = forward.d <= 0 behind the camera
//    or the face, |x| or |y| > w off the frame or face; a line between two directions is
//    clipped exactly (it is a straight line in these projections);
//  - fisheye: WELKIN_CLIP_INVISIBLE below the horizon, else w = 1;
//  - equirect: every direction is visible, w = 1; x in [-1, 1) from azimuth 0 to 2pi (the seam
//    at the left and right edges, see welkin_clipFromDirectionWrapped()).
// Fisheye and equirect are not linear in the direction: subdivide lines (a few pixels per
// segment) and drop segments with an invisible end or that cross the equirect seam.
vec4 welkin_clipFromDirection(vec3 dir) {
    int type = welkin_projectionType();
    if (type == 0 || type == 3) {
        vec3 a, b, f;
        welkin_pinhole(a, b, f);
        return welkin_clipPinhole(a, b, f, dir);
    }
    if (type == 1) {
        if (dir.z < 0.0) return WELKIN_CLIP_INVISIBLE;
        return welkin_clipFisheye(welkin_viewport.xy, dir);
    }
    return welkin_clipEquirect(dir);
}

// Copy 0 is welkin_clipFromDirection(dir). Copy 1 is, in equirect, its twin across the seam at
// azimuth 0/2pi (x shifted by -2w in the right half, +2w in the left half), and elsewhere
// WELKIN_CLIP_INVISIBLE. A sprite that may straddle the seam is drawn whole by drawing both
// copies, e.g. with 2 instances and copy = gl_InstanceID % 2. Use quads (triangles), not wide
// GL_POINTS: GL discards a point whose centre is outside the clip volume, so the twin of a point
// sprite would never be drawn.
vec4 welkin_clipFromDirectionWrapped(vec3 dir, int copy) {
    vec4 c = welkin_clipFromDirection(dir);
    if (copy == 0) return c;
    if (welkin_projectionType() != 2) return WELKIN_CLIP_INVISIBLE;
    c.x += c.x >= 0.0 ? -2.0 * c.w : 2.0 * c.w;
    return c;
}

// Moves a clip position by `pixels` (x right, y down) on the screen: the corners of a sprite quad.
vec4 welkin_clipOffset(vec4 clip, vec2 pixels) {
    return vec4(clip.xy + pixels * vec2(2.0, -2.0) * welkin_viewport.zw * clip.w, clip.zw);
}

// d(pixel)/d(direction) at a visible direction (3 columns, 2 rows): a small displacement `delta`
// (radians) of the unit direction, perpendicular to it, moves the pixel (x right, y down) by
// welkin_pixelJacobian(dir) * delta pixels. Equirect: the horizontal scale W / (2pi cos alt) is
// capped at cos alt >= 1e-6. Zero for an invisible fisheye direction. Mirrors
// welkin::Camera::pixelJacobian().
mat3x2 welkin_pixelJacobian(vec3 dirIn) {
    vec3 d = normalize(dirIn);
    int type = welkin_projectionType();
    if (type == 0 || type == 3) {
        vec3 a, b, f;
        welkin_pinhole(a, b, f);
        return welkin_jacobianPinhole(a, b, f, welkin_viewport.xy, d);
    }
    if (type == 1) return welkin_jacobianFisheye(welkin_viewport.xy, d);
    return welkin_jacobianEquirect(welkin_viewport.xy, d);
}

// (smallest, largest) pixels per radian at a visible direction, over the directions of a small
// displacement (the singular values of welkin_pixelJacobian(): welkin_pixelScaleOf(), shared). A
// sprite of angular radius a spans between a * x and a * y pixels from its centre: e.g. a point
// size that keeps an angular diameter is 2a * y, and max(2a * x, 1.0) keeps at least one pixel.
vec2 welkin_pixelScale(vec3 dir) { return welkin_pixelScaleOf(welkin_pixelJacobian(dir), dir); }

// ---- The host's depth buffer -------------------------------------------------------------------

// True when window depth `d` (a texel of the host's depth texture) is the far plane: nothing was
// drawn there (the camera's DepthMode: 1 standard, 0 reversed-Z).
bool welkin_depthIsFar(float d) {
    return welkin_depthMode.x > 0.5 ? d <= 0.0 : d >= 1.0;
}

// Distance in metres from the eye to the host's geometry at window depth `d` along the unit ENU
// direction `dir` of its pixel, read with the host's projection (Camera::fromViewProjection) or,
// for other cameras, a perspective with HostDepth's near and far planes, in the camera's
// DepthMode. Returns a huge value (1e30) at the far plane. Mirrors welkin::sceneDistanceMeters().
float welkin_sceneDistance(float d, vec3 dir) {
    if (welkin_depthIsFar(d)) return 1e30;
    float zNdc = welkin_depthMode.y > 0.5 ? d : 2.0 * d - 1.0;
    vec4 P = welkin_depthProjection;  // ndc = (P.x z + P.y) / (P.z z + P.w), z view-space
    float z = (P.y - zNdc * P.w) / (zNdc * P.z - P.x);
    float along = dot(dir, welkin_viewZ.xyz);  // view-space z per unit of distance (< 0 in front)
    return max(z / min(along, -1e-6), 0.0) * welkin_depthMode.z;
}
