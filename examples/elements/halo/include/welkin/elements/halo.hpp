// Halo: the 22-degree ice-crystal halo around the Sun, the template for writing an element.
// Copy this folder to skyelements/halo/ (or rename it, and the names inside) and rebuild: the
// registry is generated from the folders, so `welkin render --elements sky,halo` and
// `--var halo.radius_rad=46deg` work with no other file changed (docs/writing-an-element.md).
//
//   processor.add(std::make_unique<welkin::elements::Halo>());          // options as keys:
//   processor.vars().set(welkin::elements::halokeys::radius, 0.80);     // the 46-degree halo, rad
//   // command line: welkin render --elements sky,halo --var halo.width_rad=1deg --out h.png
//
// Physics, kept simple: a Gaussian ring of angular radius halo.radius_rad and width (sigma)
// halo.width_rad around the Sun, whose luminance is halo.gain_per_sr times the Sun's illuminance
// at the observer (the shared lights: illuminance above the air times the transmittance), so the
// halo dims and reddens with the Sun and vanishes at night without a fade curve. It emits light
// and hides nothing (transmittance 1). Real halos: Tape, "Atmospheric Halos" (1994).
#pragma once
#include <welkin/element.hpp>
#include <welkin/gl/projection_programs.hpp>

namespace welkin::elements {

namespace halokeys {
inline constexpr double kDeg = 0.017453292519943295;
inline const Key<double> radius{"halo.radius_rad", Range{1 * kDeg, 90 * kDeg}, "angular radius of the ring around the Sun"};
inline const Key<double> width{"halo.width_rad", Range{0.05 * kDeg, 10 * kDeg}, "width (Gaussian sigma) of the ring"};
inline const Key<double> gain{"halo.gain_per_sr", Range{0, 1}, "ring luminance per lux of sunlight at the observer", "1/sr"};
}  // namespace halokeys

class Halo final : public SkyElement {
public:
    Halo();

private:
    void doInit(InitContext& ctx) override;
    void doRender(const FrameContext& ctx) override;
    void doRelease() override;

    gl::ProjectionPrograms programs_;  // one per camera projection, compiled on first use
};

}  // namespace welkin::elements
