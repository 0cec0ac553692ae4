// Uses the installed library: CPU parts only, so it runs anywhere.
#include <welkin/camera.hpp>
#include <welkin/elements/registry.hpp>
#include <welkin/generators/reference_sky.hpp>
#include <welkin/time.hpp>
#include <welkin/vars.hpp>

#include <cstdio>

int main() {
    welkin::SkyVars vars = welkin::SkyVars::earth();
    auto t = welkin::UtcInstant::parse("2026-06-21T12:00:00+02:00");
    welkin::Camera cam;
    cam.projection = welkin::Projection::Fisheye;
    cam.width = cam.height = 512;
    auto px = cam.pixelOf(welkin::directionFromAzAlt(0.0, 0.0));
    welkin::atmosphere::ReferenceOptions::fast().validate();  // links welkin::reference (throws if out of range)
    std::printf("welkin consumer: %s, north horizon at (%.1f, %.1f), %zu elements known\n", t.toIso().c_str(), px->x,
                px->y, welkin::elements::knownElements().size());
    return px && px->y == 0.0 ? 0 : 1;
}
