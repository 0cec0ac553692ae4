// Test cameras shared by the CPU and GL camera tests: the non-perspective projections.
#pragma once
#include <welkin/camera.hpp>

#include <utility>
#include <vector>

namespace welkin::test {

/// Appends a square and a wide fisheye, a 72x36 equirect and the six 32x32 cube faces.
inline void appendNonPerspectiveCameras(std::vector<Camera>& out) {
    for (auto [w, h] : {std::pair{48, 48}, std::pair{64, 40}}) {
        Camera c;
        c.projection = Projection::Fisheye;
        c.width = w;
        c.height = h;
        out.push_back(c);
    }
    Camera e;
    e.projection = Projection::Equirect;
    e.width = 72;
    e.height = 36;
    out.push_back(e);
    for (int f = 0; f < 6; ++f) {
        Camera c;
        c.projection = Projection::CubeFace;
        c.cubeFace = f;
        c.width = c.height = 32;
        out.push_back(c);
    }
}

}  // namespace welkin::test
