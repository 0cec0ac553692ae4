// The shared CSV reader and writer (csv.hpp): quoting, comments, header lookup, numbers, and
// errors that name the file, the line and the column.
#include <catch2/catch.hpp>

#include "error_of.hpp"

#include "cli_runner.hpp"

#include <welkin/csv.hpp>
#include <welkin/error.hpp>

#include <cmath>
#include <fstream>
#include <limits>
#include <string>

using namespace welkin;

namespace {

using test::errorOf;

}  // namespace

TEST_CASE("CSV reader: quoted fields, comments, header lookup", "[cpu][csv]") {
    // Line numbers: 1 comment, 2 blank, 3 header, 4 row, 5 comment, 6-7 row with a newline in a
    // quoted field, 8 blank with spaces, 9 row (CRLF).
    const std::string text =
        "# a comment before the header\n"
        "\n"
        "name, x ,\"y, in m\"\n"
        "\"Vega, the harp star\",1.5,+2\n"
        "  # an indented comment\n"
        "\"two\nlines\",-3e2,\"say \"\"hi\"\"\"\n"
        "   \n"
        "  plain  ,nan,  \"  kept  \"  \r\n";
    const CsvTable t = CsvTable::parse(text, "mem.csv");
    REQUIRE(t.header() == std::vector<std::string>{"name", "x", "y, in m"});
    CHECK(t.headerLine() == 3);
    REQUIRE(t.rowCount() == 3);
    CHECK(t.column("x") == 1);
    CHECK(t.column("y, in m") == 2);
    CHECK_FALSE(t.findColumn("X"));  // exact names unless caseInsensitiveColumns
    CHECK(CsvTable::parse(text, "mem.csv", {.caseInsensitiveColumns = true}).findColumn("X") == std::optional<std::size_t>(1));

    CHECK(t.row(0).text("name") == "Vega, the harp star");
    CHECK(t.row(0).number("x") == 1.5);
    CHECK(t.row(0).number(2) == 2.0);  // a leading '+'
    CHECK(t.row(0).line() == 4);
    CHECK(t.row(1).text(0) == "two\nlines");
    CHECK(t.row(1).number("x") == -300.0);
    CHECK(t.row(1).text(2) == "say \"hi\"");
    CHECK(t.row(1).line() == 6);
    CHECK(t.row(2).line() == 9);
    CHECK(t.row(2).text("name") == "plain");      // unquoted: spaces around dropped
    CHECK(t.row(2).text(2) == "  kept  ");        // quoted: kept verbatim, no '\r'
    CHECK(std::isnan(t.row(2).number("x")));      // the writer's NaN reads back
    const std::vector<double> x = t.numbers("x");
    REQUIRE(x.size() == 3);
    CHECK(x[1] == -300.0);
    int n = 0;
    for (const CsvRow& r : t) n += int(r.size());
    CHECK(n == 9);
}

TEST_CASE("CSV reader: errors name the file, the line and the column", "[cpu][csv]") {
    const std::string ok = "a,b\n1,2\n";
    CHECK(errorOf([&] { CsvTable::parse(ok + "3,abc\n", "t.csv").numbers("b"); }) == "t.csv:3: column 2 'b': 'abc' is not a number");
    CHECK(errorOf([&] { CsvTable::parse(ok + "3,1.5x\n", "t.csv").row(1).number(1); }) ==
          "t.csv:3: column 2 'b': '1.5x' is not a number");
    CHECK(errorOf([&] { CsvTable::parse(ok + "3,\n", "t.csv").row(1).number("b"); }) == "t.csv:3: column 2 'b': empty, expected a number");
    CHECK(CsvTable::parse(ok + "3,\n", "t.csv").row(1).numberOr("b", -1.0) == -1.0);
    CHECK(errorOf([&] { CsvTable::parse(ok + "3,4,5\n", "t.csv"); }) == "t.csv:3: expected 2 fields, found 3");
    CHECK(CsvTable::parse(ok + "3,4,5\n", "t.csv", {.sameFieldCount = false}).row(1).size() == 3);
    CHECK(errorOf([&] { CsvTable::parse("# c\n" + ok, "t.csv").column("c"); }) == "t.csv:2: no column 'c' (columns: a, b)");
    CHECK(errorOf([&] { CsvTable::parse(ok + "\"3,4\n5,6\n", "t.csv"); }) == "t.csv:3: unterminated quote");
    CHECK(errorOf([&] { CsvTable::parse(ok + "3,4\"5\"\n", "t.csv"); }) == "t.csv:3: field 2: '\"' inside an unquoted field");
    CHECK(errorOf([&] { CsvTable::parse(ok + "\"3\"x,4\n", "t.csv"); }) == "t.csv:3: field 1: text after the closing '\"'");
    CHECK(errorOf([&] { CsvTable::load("/nonexistent/welkin.csv"); }) == "/nonexistent/welkin.csv: cannot open");
    const CsvTable empty = CsvTable::parse("# only a comment\n\n", "e.csv");
    CHECK(empty.header().empty());
    CHECK(empty.rowCount() == 0);
}

TEST_CASE("CSV writer: quoting and exact numbers read back by the reader", "[cpu][csv]") {
    const std::string path = test::scratchDir("csv") + "/w.csv";
    const double third = 1.0 / 3.0, tiny = 1.234567890123e-300;
    {
        CsvWriter w(path, {"name", "value", "n"});
        w.comment("two\nlines of comment");
        w.row("plain", third, 7);
        w.row("a, \"quoted\" name", tiny, -1);
        w.row("#not a comment", std::numeric_limits<double>::quiet_NaN(), 0);
        w.row(" padded ", 0.1f, std::size_t(3));
        CHECK(errorOf([&] { w.row("too", "few"); }) == "CsvWriter: '" + path + "': row of 2 fields, header has 3");
        w.close();
    }
    const CsvTable t = CsvTable::load(path);
    REQUIRE(t.rowCount() == 4);
    CHECK(t.headerLine() == 3);  // after the two comment lines
    CHECK(t.row(0).number("value") == third);  // shortest round-trip form: bit-exact
    CHECK(t.row(1).text("name") == "a, \"quoted\" name");
    CHECK(t.row(1).number("value") == tiny);
    CHECK(t.row(1).number("n") == -1.0);
    CHECK(t.row(2).text("name") == "#not a comment");
    CHECK(std::isnan(t.row(2).number("value")));
    CHECK(t.row(3).text("name") == " padded ");
    CHECK(float(t.row(3).number("value")) == 0.1f);
    CHECK(errorOf([] { CsvWriter("/nonexistent/dir/w.csv", {"a"}); }) == "CsvWriter: cannot write '/nonexistent/dir/w.csv'");
}
