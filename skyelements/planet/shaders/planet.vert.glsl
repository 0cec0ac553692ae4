// Planet: one screen quad around a body (and, in equirect, its twin across the seam). Needs
// engine/camera.glsl before it. A disk's quad covers its apparent radius at the largest local
// pixel scale plus 2 px; a PSF's covers 4 sigma of the Gaussian. See planet.frag.glsl. Needs
// atmosphere/point_perceptual.glsl before it (render.point_sources = perceptual).
uniform vec3 u_centre;      // unit direction to the body's centre, ENU
uniform float u_sinRadius;  // sin of the apparent angular radius as drawn
uniform int u_kind;         // 0 Sun, 1 Moon, 2 planet disk, 3 PSF, 4 corona
uniform int u_copies;       // 2 in equirect (the seam twin), else 1
uniform float u_psfSigma;   // PSF sigma, px
uniform vec3 u_flux;        // disk: radiance scale (cd/m^2); PSF: illuminance (lux), per channel
uniform int u_ppPoint;      // 1: a perceptual point (PSF only; the uniforms below are set)
uniform float u_ppEyeLux;   // illuminance at the eye, lux (after extinction)
uniform float u_ppLaterT;   // luminance transmittance the Sky applies after this element (1: none)
uniform float u_ppDiskCdM2; // the disk's mean luminance at the eye: the point's peak stays under it
uniform vec3 u_ppColour;    // colour, luminance 1
uniform float u_ppFwhmPx;   // FWHM at the eye's threshold, px

out vec2 v_offset;            // pixels from the body's centre (x right, y down)
flat out vec3 v_flux;         // disk: u_flux; PSF: illuminance / pixel solid angle
flat out float v_pixelAngle;  // the largest angle a pixel spans near the body, rad
flat out vec4 v_pp;           // perceptual point: peak radiance (cd/m^2, RGB), sigma (px); 0: none

void main() {
    const vec2 corner[6] = vec2[6](vec2(-1, -1), vec2(1, -1), vec2(1, 1), vec2(-1, -1), vec2(1, 1), vec2(-1, 1));
    vec4 clip = welkin_clipFromDirectionWrapped(u_centre, gl_InstanceID % u_copies);
    vec2 s = welkin_pixelScale(u_centre);  // (smallest, largest) px per radian
    if (clip.w <= 0.0 || s.x <= 0.0) {
        gl_Position = WELKIN_CLIP_INVISIBLE;
        return;
    }
    float halfPx;
    v_pp = vec4(0.0);
    if (u_kind == 3 && u_ppPoint == 1) {
        // The eye's threshold against the sky behind the body (welkin/point_source.hpp): not seen,
        // not drawn; seen, a Gaussian of peak C B (at the eye) besides the physical PSF.
        float B = pp_background(u_centre);
        vec2 fc = pp_point(u_ppEyeLux, B, u_ppFwhmPx);
        if (fc.x <= 0.0) {
            gl_Position = WELKIN_CLIP_INVISIBLE;
            return;
        }
        v_pp = vec4(u_ppColour * min(fc.y * B, u_ppDiskCdM2) / max(u_ppLaterT, 1e-6), fc.x / WELKIN_GAUSSIAN_FWHM_PER_SIGMA);
    }
    if (u_kind == 3) {
        halfPx = 4.0 * max(u_psfSigma, v_pp.w);
        v_flux = u_flux * (s.x * s.y);  // divided by the pixel's solid angle 1 / (s.x s.y) sr
    } else {
        halfPx = asin(min(u_sinRadius, 1.0)) * s.y * 1.05 + 2.0;
        v_flux = u_flux;
    }
    v_pixelAngle = 1.0 / s.x;
    v_offset = halfPx * corner[gl_VertexID];
    gl_Position = welkin_clipOffset(clip, v_offset);
}
