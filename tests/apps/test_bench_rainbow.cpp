// welkin bench rainbow: options checked before any table is built or frame rendered.
#include <catch2/catch.hpp>

#include "cli_runner.hpp"

#include <string>

using welkin::test::runCli;

TEST_CASE("welkin bench rainbow: bad options are one-line errors", "[cpu][cli][bench]") {
    struct Case {
        const char* args;
        const char* message;
    };
    for (Case c : {Case{"--repeats 0", "--repeats 0 not in [1, 1000]"}, Case{"--repeats 1001", "--repeats 1001 not in [1, 1000]"},
                   Case{"--qualities low,ultra", "--qualities: 'ultra' is not one of low, default, high"},
                   Case{"--csv /nonexistent-dir/x.csv", "--csv '/nonexistent-dir/x.csv': no directory '/nonexistent-dir'"}}) {
        const auto r = runCli(std::string("bench rainbow ") + c.args);
        INFO(c.args << " -> " << r.output);
        CHECK(r.status == 1);
        CHECK(r.output.find(std::string("welkin bench rainbow: ") + c.message) != std::string::npos);
        CHECK(r.output.find('\n') == r.output.size() - 1);  // one line
    }
}
