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

// The check on `root` with scripts/twins-allowed.txt holding `list`.
welkin::test::CliResult checkWith(const std::string& root, const std::string& list) {
    write(root + "/scripts/twins-allowed.txt", list);
    return runScript(root, "--check");
}

// A small tree of its own (the script reads the folders beside its scripts/ folder), with the
// script copied in.
std::string scratchTree(const char* name) {
    const std::string root = welkin::test::scratchDir(name);
    REQUIRE(std::system(("mkdir -p '" + root + "'/scripts '" + root + "'/engine/shaders '" + root + "'/engine/src '" + root +
                         "'/generators '" + root + "'/skyelements '" + root + "'/apps '" + root + "'/examples")
                            .c_str()) == 0);
    REQUIRE(std::system(("cp '" WELKIN_SOURCE_DIR "/scripts/twins-check.sh' '" + root + "/scripts/'").c_str()) == 0);
    return root;
}

}  // namespace

TEST_CASE("Twins check: no function of the tree is copied between a shader and C++ unexplained", "[cpu][docs]") {
    const auto r = runScript(WELKIN_SOURCE_DIR, "--check");
    INFO(r.output);
    CHECK(r.status == 0);
    CHECK_THAT(r.output, Catch::Contains("in all: new 0, pending 0"));
}

TEST_CASE("Twins check: a new copy fails, a shared function and a stale listing are told apart", "[cpu][docs]") {
    const std::string root = scratchTree("twins-check");
    write(root + "/engine/shaders/a.glsl",
          "float atm_opticalThing(float x) {\n    return x;\n}\nvoid main() {\n}\nvec3 onlyInGlsl(vec3 v) { return v; }\n");
    write(root + "/engine/shaders/b.shared.glsl", "real sharedOne(real x) { return x; }\n");
    write(root + "/engine/src/a.cpp",
          "double opticalThing(double x) {\n    return x;\n}\nint main() {\n    return sharedOne(1.0) > 0 ? 0 : 1;\n}\n"
          "glm::dvec3 onlyInCpp(const glm::dvec3& v) { return v; }\ndouble sharedOne(double x) { return x; }\n");
    SECTION("unlisted: both names are new copies, --check fails naming the way out") {
        const auto r = checkWith(root, "# nothing allowed\n");
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
        const auto r = checkWith(root, "opticalThing pending a copy\nsharedOne wrapper calls the shared one\n");
        INFO(r.output);
        CHECK(r.status == 0);
        CHECK_THAT(r.output, Catch::Contains("wrapper 1,") && Catch::Contains("pending 1,") && Catch::Contains("new 0)"));
    }
    SECTION("a listed name no longer duplicated fails: the list stays true") {
        const auto r = checkWith(root, "opticalThing pending a copy\nsharedOne wrapper calls it\ngoneAway pending moved already\n");
        INFO(r.output);
        CHECK(r.status == 1);
        CHECK_THAT(r.output, Catch::Contains("'goneaway' is in scripts/twins-allowed.txt but no longer defined in both"));
    }
    SECTION("an unknown kind is refused") {
        const auto r = checkWith(root, "opticalThing copied because\n");
        INFO(r.output);
        CHECK(r.status == 2);
        CHECK_THAT(r.output, Catch::Contains("'opticalThing' has kind 'copied'"));
    }
}

TEST_CASE("Twins check: a copy under another name is found by its literals and its expressions' shape", "[cpu][docs]") {
    const std::string root = scratchTree("twins-check-copies");
    // The copies (a)-(c) of issue 24's last pass, planted: a fit's constant and a texel's set-up
    // inside main() (no function of their own, so no name to compare), written again in C++ with
    // other variable names, std::, double and a 1.0f.
    write(root + "/engine/shaders/pass.glsl",
          "void main() {\n    float sigma = fwhm / 2.35482;  // a Gaussian\n"
          "    float nu = clamp(sinV * sinS * cos(az) + mu * u_muS, -1.0, 1.0);\n"
          "    float tiny = a * b + c;\n}\n");
    write(root + "/engine/src/twin.cpp",
          "void twin() {\n    const double s = w / 2.35482;\n"
          "    double nu = std::clamp(sv * ss * std::cos(phi) + m * mS, -1.0f, 1.0);\n"
          "    double tiny = p * q + r;\n}\n");
    // The same text in a shared file is one source: not counted.
    write(root + "/engine/shaders/one.shared.glsl", "real k(real x) { return x * 1.2345678 + sqrt(x) * sin(x) * cos(x) / x; }\n");
    write(root + "/engine/src/one.cpp", "double f(double x) { return x * 1.2345678 + std::sqrt(x) * std::sin(x) * std::cos(x) / x; }\n");
    SECTION("unlisted: --check fails on the literal and on the expression, not on the small ones or the shared file") {
        const auto r = checkWith(root, "# nothing allowed\n");
        INFO(r.output);
        CHECK(r.status == 1);
        CHECK_THAT(r.output, Catch::Contains("2.35482") && Catch::Contains("clamp(v*v*cos(v)+v*v,-1.0,1.0)"));
        CHECK_THAT(r.output, Catch::Contains("literals of >= 5 digits in a shader and C++: 1 ") &&
                                 Catch::Contains("expressions of one shape in a shader and C++: 1 ") && Catch::Contains("in all: new 2,"));
        CHECK_THAT(r.output, !Catch::Contains("1.2345678") && !Catch::Contains("v*v+v "));
    }
    SECTION("listed: the check passes and counts them by kind") {
        const auto r = checkWith(root, "2.35482 pending a copy\nclamp(v*v*cos(v)+v*v,-1.0,1.0) pending a copy too\n");
        INFO(r.output);
        CHECK(r.status == 0);
        CHECK_THAT(r.output, Catch::Contains("in all: new 0, pending 2"));
    }
}
