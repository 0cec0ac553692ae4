// The viewer panel's element switch (apps/welkin/scene_edit.hpp): on and off by name, in the
// default compositing order, errors as text.
#include <catch2/catch.hpp>

#include "elements_present.hpp"
#include "gl_test_context.hpp"
#include "scene_edit.hpp"

#include <welkin/elements/registry.hpp>

using namespace welkin;

#if defined(WELKIN_HAS_ELEMENT_planet) && defined(WELKIN_HAS_ELEMENT_grid)  // switched by name

namespace {
std::vector<std::string> names(const SkyProcessor& p) {
    std::vector<std::string> n;
    for (auto& e : p.elements()) n.push_back(e->name());
    return n;
}
// `list` in the registry's default compositing order.
std::vector<std::string> inKnownOrder(std::vector<std::string> list) {
    const auto known = elements::knownElements();
    std::sort(list.begin(), list.end(), [&](const std::string& a, const std::string& b) {
        return std::find(known.begin(), known.end(), a) < std::find(known.begin(), known.end(), b);
    });
    return list;
}
}  // namespace

TEST_CASE("the viewer's element switch keeps the compositing order and reports errors", "[gl][cli][view]") {
    test::glContext();
    SkyProcessor sky;
    sky.setCamera(Camera{.width = 16, .height = 8});
    for (const std::string& n : inKnownOrder({"sky", "planet"})) sky.add(elements::makeElement(n));
    sky.init();
    // On: "grid" goes where the registry's order puts it among the elements already there.
    CHECK(cli::setElementEnabled(sky, "grid", true).empty());
    CHECK(names(sky) == inKnownOrder({"sky", "planet", "grid"}));
    CHECK(cli::setElementEnabled(sky, "grid", true).empty());  // already on: unchanged
    CHECK(names(sky).size() == 3);
    // Off, then a frame renders without it; on again.
    CHECK(cli::setElementEnabled(sky, "sky", false).empty());
    CHECK(names(sky) == inKnownOrder({"planet", "grid"}));
    sky.renderFrame();
    CHECK(cli::setElementEnabled(sky, "sky", true).empty());
    CHECK(names(sky) == inKnownOrder({"sky", "planet", "grid"}));
    sky.renderFrame();
    // An unknown name: the registry's one-line error, the scene unchanged.
    const std::string e = cli::setElementEnabled(sky, "nosuch", true);
    CHECK_THAT(e, Catch::StartsWith("nosuch: unknown element 'nosuch'"));
    CHECK(names(sky).size() == 3);
    sky.release();
}
#endif
