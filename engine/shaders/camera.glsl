// The per-frame camera block (welkin::CameraBlock, std140, binding 0) and the view direction of
// a pixel in the world ENU frame (x east, y north, z up). Mirrors welkin::Camera::directionAt().
layout(std140, binding = 0) uniform WelkinCamera {
    mat4 welkin_cameraToWorld;  // columns: right, up, forward
    vec4 welkin_viewport;       // width, height, 1/width, 1/height (pixels)
    vec4 welkin_projection;     // type (0 perspective, 1 fisheye, 2 equirect, 3 cube), tan(fovY/2), aspect, face
    vec4 welkin_time;           // seconds since start
};

const float WELKIN_PI = 3.14159265358979;

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

// Pixel position with the origin at the top-left corner, y downwards (image convention).
vec2 welkin_pixel() { return vec2(gl_FragCoord.x, welkin_viewport.y - gl_FragCoord.y); }

vec3 welkin_directionFromAzAlt(float az, float alt) {
    float c = cos(alt);
    return vec3(c * sin(az), c * cos(az), sin(alt));
}

// Unit world direction through `pixel`; returns false outside a fisheye's image circle.
bool welkin_viewDirection(vec2 pixel, out vec3 dir) {
    vec2 size = welkin_viewport.xy;
    int type = welkin_projectionType();
    dir = vec3(0.0, 0.0, 1.0);
    if (type == 0) {
        float tanY = welkin_projection.y, tanX = tanY * welkin_projection.z;
        float x = (2.0 * pixel.x / size.x - 1.0) * tanX;
        float y = (1.0 - 2.0 * pixel.y / size.y) * tanY;
        mat3 b = mat3(welkin_cameraToWorld);
        dir = normalize(b[2] + x * b[0] + y * b[1]);
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
