// One source for the GPU maths and its CPU twin (issue 24 item 3): scripts/twins-check.sh lists the
// functions defined both in a shader and in C++; with --check it fails on a name that
// scripts/twins-allowed.txt does not explain (docs/architecture.md, "One source").
#include <catch2/catch.hpp>

#include "cli_runner.hpp"

#include <cstdlib>
#include <fstream>
#include <string>

namespace {

welkin::test::CliResult runScript(const std::string& root, const std::string& args) {
    return welkin::test::runShell("bash '" + root + "/scripts/twins-check.sh' " + args + " 2>&1");
}

void write(const std::string& path, const std::string& text) {
    std::ofstream f(path);
    f << text;
    REQUIRE(f.good());
}

}  // namespace

TEST_CASE("Twins check: no function of the tree is copied between a shader and C++ unexplained", "[cpu][docs]") {
    const auto r = runScript(WELKIN_SOURCE_DIR, "--check");
    INFO(r.output);
    CHECK(r.status == 0);
    CHECK_THAT(r.output, Catch::Contains("new 0)"));
}

TEST_CASE("Twins check: a new copy fails, a shared function and a stale listing are told apart", "[cpu][docs]") {
    // A small tree of its own: the script reads the folders beside its scripts/ folder.
    const std::string root = welkin::test::scratchDir("twins-check");
    REQUIRE(std::system(("mkdir -p '" + root + "'/scripts '" + root + "'/engine/shaders '" + root + "'/engine/src '" + root +
                         "'/generators '" + root + "'/skyelements '" + root + "'/apps '" + root + "'/examples")
                            .c_str()) == 0);
    REQUIRE(std::system(("cp '" WELKIN_SOURCE_DIR "/scripts/twins-check.sh' '" + root + "/scripts/'").c_str()) == 0);
    write(root + "/engine/shaders/a.glsl",
          "float atm_opticalThing(float x) {\n    return x;\n}\nvoid main() {\n}\nvec3 onlyInGlsl(vec3 v) { return v; }\n");
    write(root + "/engine/shaders/b.shared.glsl", "real sharedOne(real x) { return x; }\n");
    write(root + "/engine/src/a.cpp",
          "double opticalThing(double x) {\n    return x;\n}\nint main() {\n    return sharedOne(1.0) > 0 ? 0 : 1;\n}\n"
          "glm::dvec3 onlyInCpp(const glm::dvec3& v) { return v; }\ndouble sharedOne(double x) { return x; }\n");
    SECTION("unlisted: both names are new copies, --check fails naming the way out") {
        write(root + "/scripts/twins-allowed.txt", "# nothing allowed\n");
        const auto r = runScript(root, "--check");
        INFO(r.output);
        CHECK(r.status == 1);
        // atm_opticalThing and opticalThing are one name (prefix and case dropped); main is left out.
        CHECK_THAT(r.output, Catch::Contains("opticalthing") && Catch::Contains("[new]"));
        CHECK_THAT(r.output, Catch::Contains("sharedone"));
        CHECK_THAT(r.output, !Catch::Contains("onlyin") && !Catch::Contains("main "));
        CHECK_THAT(r.output, Catch::Contains("duplicated names: 2 ") && Catch::Contains("new 2)"));
        CHECK_THAT(r.output, Catch::Contains("*.shared.glsl"));
    }
    SECTION("listed with their kinds: the check passes and counts them") {
        write(root + "/scripts/twins-allowed.txt", "opticalThing pending a copy\nsharedOne wrapper calls the shared one\n");
        const auto r = runScript(root, "--check");
        INFO(r.output);
        CHECK(r.status == 0);
        CHECK_THAT(r.output, Catch::Contains("wrapper 1,") && Catch::Contains("pending 1,") && Catch::Contains("new 0)"));
    }
    SECTION("a listed name no longer duplicated fails: the list stays true") {
        write(root + "/scripts/twins-allowed.txt",
              "opticalThing pending a copy\nsharedOne wrapper calls it\ngoneAway pending moved already\n");
        const auto r = runScript(root, "--check");
        INFO(r.output);
        CHECK(r.status == 1);
        CHECK_THAT(r.output, Catch::Contains("'goneaway' is in scripts/twins-allowed.txt but no longer defined in both"));
    }
    SECTION("an unknown kind is refused") {
        write(root + "/scripts/twins-allowed.txt", "opticalThing copied because\n");
        const auto r = runScript(root, "--check");
        INFO(r.output);
        CHECK(r.status == 2);
        CHECK_THAT(r.output, Catch::Contains("'opticalThing' has kind 'copied'"));
    }
}
