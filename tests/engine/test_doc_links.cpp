// The documentation's links: every relative link and image in the tracked Markdown files points
// at a file that exists, and file.md#heading at a heading it has (scripts/check-doc-links.py).
// Element pages live in their folders (skyelements/<name>/README.md), so pages link across
// folders; this keeps those links whole when pages and images move.
#include <catch2/catch.hpp>

#include "cli_runner.hpp"

#include <cstdlib>
#include <fstream>
#include <string>

namespace {

welkin::test::CliResult runCheck(const std::string& root) {
    return welkin::test::runShell("python3 '" WELKIN_SOURCE_DIR "/scripts/check-doc-links.py' '" + root + "' 2>&1");
}

void write(const std::string& path, const std::string& text) {
    std::ofstream f(path);
    f << text;
    REQUIRE(f.good());
}

}  // namespace

TEST_CASE("Doc links: every relative link and image of the tree's Markdown resolves", "[cpu][docs]") {
    const auto r = runCheck(WELKIN_SOURCE_DIR);
    INFO(r.output);
    CHECK(r.status == 0);
    CHECK_THAT(r.output, Catch::Contains(" 0 broken link(s)"));
    // The check read the tree's pages (not an empty list): the README, docs/ and the element pages.
    CHECK_THAT(r.output, !Catch::Contains(" 0 Markdown files"));
}

TEST_CASE("Doc links: a missing file, a missing heading and links in code are told apart", "[cpu][docs]") {
    // A tree of its own (not a git checkout: the script then reads every *.md under it).
    const std::string root = welkin::test::scratchDir("doc-links");
    REQUIRE(std::system(("rm -rf '" + root + "' && mkdir -p '" + root + "/docs/images' '" + root + "/skyelements/e'").c_str()) == 0);
    write(root + "/docs/images/a.png", "x");
    write(root + "/skyelements/e/README.md", "# The E element\n\n## Its `e.key` (bool)\n\nText.\n");
    const std::string good = "# Index\n\n![a](images/a.png) [E](../skyelements/e/README.md#its-ekey-bool) [top](#index)\n"
                             "[web](https://example.org/x.md) `[not a link](nowhere.md)`\n```\n[in a fence](nowhere.md)\n```\n";
    SECTION("all resolve") {
        write(root + "/docs/index.md", good);
        const auto r = runCheck(root);
        INFO(r.output);
        CHECK(r.status == 0);
        CHECK_THAT(r.output, Catch::Contains("2 Markdown files, 0 broken"));
    }
    SECTION("a missing file and a missing heading each fail, with file and line") {
        write(root + "/docs/index.md", good + "\n![b](images/b.png)\n[E](../skyelements/e/README.md#its-e-key)\n");
        const auto r = runCheck(root);
        INFO(r.output);
        CHECK(r.status == 1);
        CHECK_THAT(r.output, Catch::Contains("docs/index.md:9: images/b.png: no such file"));
        CHECK_THAT(r.output, Catch::Contains("docs/index.md:10: ../skyelements/e/README.md#its-e-key: no heading"));
        CHECK_THAT(r.output, Catch::Contains("2 broken link(s)"));
    }
    SECTION("a link into an element folder that is not in the tree is counted apart, one into a present folder is not") {
        write(root + "/docs/index.md", good + "\n[gone](../skyelements/gone/README.md) [half](../skyelements/e/missing.md)\n");
        const auto r = runCheck(root);
        INFO(r.output);
        CHECK(r.status == 1);  // e is present: its missing page is broken
        CHECK_THAT(r.output, Catch::Contains("../skyelements/e/missing.md: no such file"));
        CHECK_THAT(r.output, Catch::Contains("1 broken link(s), 1 into element folders not in this tree"));
    }
}
