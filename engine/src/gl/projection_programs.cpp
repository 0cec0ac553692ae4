#include <welkin/error.hpp>
#include <welkin/gl/projection_programs.hpp>

namespace welkin::gl {

const Program& ProjectionPrograms::get(Projection projection) {
    if (!recipe_) throw Error("ProjectionPrograms::get(): no recipe (default-constructed)");
    const int i = static_cast<int>(projection);
    if (i < 0 || i >= int(programs_.size())) throw Error("ProjectionPrograms::get(): projection " + std::to_string(i) + " not in [0, 3]");
    if (!programs_[i]) {
        ProgramBuilder b = *recipe_;
        b.define("WELKIN_PROJECTION", i);
        programs_[i] = b.build();
    }
    return programs_[i];
}

void ProjectionPrograms::buildAll() {
    for (Projection p : {Projection::Perspective, Projection::Fisheye, Projection::Equirect, Projection::CubeFace}) get(p);
}

void ProjectionPrograms::releasePrograms() {
    for (auto& p : programs_) p = {};
}

}  // namespace welkin::gl
