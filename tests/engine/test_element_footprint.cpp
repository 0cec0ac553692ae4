// What outside its folder names each element (scripts/element-footprint-static.py, issue 24
// item 2): in this tree no element but the Sky is needed by a file outside its folder; a scratch
// tree shows that the script tells a needed element (an unguarded #include) from a guarded use, a
// citation in a comment and a documentation link, so the tree's "needs none" can fail.
#include <catch2/catch.hpp>

#include "cli_runner.hpp"

#include <cstdlib>
#include <fstream>
#include <string>

namespace {

welkin::test::CliResult runFootprint(const std::string& args) {
    return welkin::test::runShell("python3 '" WELKIN_SOURCE_DIR "/scripts/element-footprint-static.py' " + args + " 2>&1");
}

void write(const std::string& path, const std::string& text) {
    std::ofstream f(path);
    f << text;
    REQUIRE(f.good());
}

}  // namespace

TEST_CASE("Element footprint: no element but the Sky is needed outside its folder", "[cpu][docs]") {
    const auto r = runFootprint("--check --root '" WELKIN_SOURCE_DIR "'");
    INFO(r.output);
    CHECK(r.status == 0);
    // It read the tree's element folders (the Sky is always there) and found no needed element.
    CHECK_THAT(r.output, Catch::Contains("\nsky: "));
    CHECK_THAT(r.output, !Catch::Contains("other than the Sky are needed"));
}

TEST_CASE("Element footprint: needed, guarded, cited and linked are told apart", "[cpu][docs]") {
    const std::string root = welkin::test::scratchDir("element-footprint");
    REQUIRE(std::system(("rm -rf '" + root + "' && mkdir -p '" + root + "/skyelements/e/src' '" + root +
                         "/skyelements/e/include/welkin/elements' '" + root + "/tests' '" + root + "/docs' '" + root +
                         "/skyelements/f/src'").c_str()) == 0);
    write(root + "/skyelements/e/include/welkin/elements/e.hpp", "#pragma once\n");
    write(root + "/skyelements/e/src/e.cpp", "#include <welkin/elements/e.hpp>\n");
    write(root + "/skyelements/f/src/f.cpp", "int f() { return 1; }\n");
    write(root + "/docs/page.md", "See [E](../skyelements/e/README.md).\n");
    write(root + "/tests/cited.cpp", "// measured in skyelements/e/README.md\nint x = 0;\n");
    write(root + "/tests/guarded.cpp", "#ifdef WELKIN_HAS_ELEMENT_e\n#include <welkin/elements/e.hpp>\n#endif\n");
    write(root + "/tests/key.cpp", "const char* d = \"see skyelements/e/README.md, Model\";\n");
    SECTION("guarded, cited and linked uses: e needs none") {
        const auto r = runFootprint("--check --root '" + root + "'");
        INFO(r.output);
        CHECK(r.status == 0);
        CHECK_THAT(r.output, Catch::Contains("e: needs none; guarded uses 1, cited in comments 2, linked from docs 1"));
        CHECK_THAT(r.output, Catch::Contains("f: needs none; guarded uses 0, cited in comments 0, linked from docs 0"));
    }
    SECTION("an unguarded include makes e needed, named with its line") {
        write(root + "/tests/needs.cpp", "// uses E\n#include <welkin/elements/e.hpp>\n");
        const auto r = runFootprint("--check --root '" + root + "'");
        INFO(r.output);
        CHECK(r.status == 1);
        CHECK_THAT(r.output, Catch::Contains("e: needed by 1 file(s)"));
        CHECK_THAT(r.output, Catch::Contains("needs    tests/needs.cpp:2"));
        // Without --check it reports and exits 0.
        CHECK(runFootprint("--root '" + root + "'").status == 0);
    }
    SECTION("a build line naming its folder outside a comment makes it needed") {
        write(root + "/tests/CMakeLists.txt", "# skyelements/e/ is cited here\nadd_library(x ${ROOT}/skyelements/e/src/e.cpp)\n");
        const auto r = runFootprint("--check --root '" + root + "'");
        INFO(r.output);
        CHECK(r.status == 1);
        CHECK_THAT(r.output, Catch::Contains("needs    tests/CMakeLists.txt:2"));
    }
    SECTION("bad arguments: one line, exit 2") {
        const auto r = runFootprint("--root '" + root + "/nope'");
        CHECK(r.status == 2);
        CHECK_THAT(r.output, Catch::Contains("--root '" + root + "/nope': not a folder"));
    }
}
