// One program per camera projection, built on first use from a recipe with WELKIN_PROJECTION
// defined (0 perspective, 1 fisheye, 2 equirect, 3 cube face), so engine/camera.glsl compiles
// only that projection's code. llvmpipe (and GPUs for divergent code) otherwise evaluates every
// branch of the projection switch on every pixel (measured on llvmpipe: about a sixth of a
// fisheye sky frame at 1280x720; docs/writing-an-element.md).
//
//   welkin::gl::ProjectionPrograms programs(welkin::gl::ProgramBuilder("Mine")
//       .fullscreenVertex()
//       .fragment("engine/camera.glsl", welkin::gl::engineShader("camera.glsl"))
//       .fragment("mine.frag", text));
//   // in doRender(ctx):
//   const welkin::gl::Program& p = programs.get(ctx.camera.projection);  // compiles once per projection
//   p.use();
//
// A program compiled for one projection must only draw with a camera of that projection; get()
// takes care of it. The first get() for a projection compiles (tens to hundreds of ms on llvmpipe).
#pragma once
#include <welkin/camera.hpp>
#include <welkin/gl/shader.hpp>

#include <array>
#include <optional>

namespace welkin::gl {

class ProjectionPrograms {
public:
    ProjectionPrograms() = default;
    /// `recipe` must include engine/camera.glsl; WELKIN_PROJECTION is added per variant.
    explicit ProjectionPrograms(ProgramBuilder recipe) : recipe_(std::move(recipe)) {}
    ProjectionPrograms(const ProjectionPrograms&) = delete;
    ProjectionPrograms& operator=(const ProjectionPrograms&) = delete;
    ProjectionPrograms(ProjectionPrograms&&) = default;
    ProjectionPrograms& operator=(ProjectionPrograms&&) = default;

    /// The program for `projection`, compiled on first use. Throws welkin::Error like
    /// ProgramBuilder::build() (naming the label, file and line), or if there is no recipe.
    const Program& get(Projection projection);
    /// True when the program for `projection` is compiled (get() will not compile it); false for
    /// a projection outside [0, 3].
    bool built(Projection projection) const {
        const int i = static_cast<int>(projection);
        return i >= 0 && i < int(programs_.size()) && bool(programs_[i]);
    }
    /// Compiles every variant now (e.g. to keep compilation out of timed frames).
    void buildAll();
    /// True once a recipe is set.
    explicit operator bool() const { return recipe_.has_value(); }
    /// Frees the compiled programs (needs the context current); the recipe stays.
    void releasePrograms();

private:
    std::optional<ProgramBuilder> recipe_;
    std::array<Program, 4> programs_;
};

}  // namespace welkin::gl
