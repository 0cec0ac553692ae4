// Test support shared by element tests that check drawn lines and labels against the astronomy:
// the night of 2026-08-12 22:00 UTC over Malta (35.9 N, 14.5 E), its CPU reference of apparent
// places, a fisheye camera, and a luminance read that is 0 outside the image.
//
//   welkin::test::MaltaSky sky = welkin::test::maltaSky();
//   glm::dvec3 enu = sky.apparent(icrsDirection);    // refracted, 1013.25 hPa, 10 C
//   welkin::test::atMalta(processor, welkin::test::fisheye(128));
#pragma once
#include <welkin/astro/frames.hpp>
#include <welkin/astro/timescales.hpp>
#include <welkin/camera.hpp>
#include <welkin/image.hpp>
#include <welkin/processor.hpp>
#include <welkin/time.hpp>

#include <numbers>

namespace welkin::test {

inline constexpr double kMaltaLatRad = 35.9 * std::numbers::pi / 180.0, kMaltaLonRad = 14.5 * std::numbers::pi / 180.0;
inline const UtcInstant kMaltaNight = UtcInstant::parse("2026-08-12T22:00:00Z");

/// Luminance (Rec. 709 weights) of pixel (x, y); 0 outside the image.
inline double lum(const Image& img, int x, int y) {
    if (x < 0 || y < 0 || x >= img.width || y >= img.height) return 0.0;
    return 0.2126 * img.at(x, y, 0) + 0.7152 * img.at(x, y, 1) + 0.0722 * img.at(x, y, 2);
}

/// The CPU reference of a J2000 direction's apparent place: the astronomy's observer frame (its
/// own code path, not the processor's keys), then astro::refraction at the default 1013.25 hPa, 10 C.
struct MaltaSky {
    astro::ObserverFrame frame;
    glm::dvec3 apparent(const glm::dvec3& icrs) const {
        const astro::Topocentric t = astro::topocentricFromIcrs(frame, icrs);
        return directionFromAzAlt(t.azimuthRad, t.altitudeRad);
    }
};

inline MaltaSky maltaSky() {
    const astro::Site site{kMaltaLatRad, kMaltaLonRad, 0.0};
    return MaltaSky{astro::observerFrame(site, astro::timeScales(kMaltaNight), astro::Path::Fast)};
}

inline Camera fisheye(int size) {
    Camera cam;
    cam.projection = Projection::Fisheye;
    cam.width = cam.height = size;
    return cam;
}

inline void atMalta(SkyProcessor& p, const Camera& cam) {
    p.setObserver({.latitudeRad = kMaltaLatRad, .longitudeRad = kMaltaLonRad, .heightMeters = 0});
    p.setTime(kMaltaNight);
    p.setCamera(cam);
}

}  // namespace welkin::test
