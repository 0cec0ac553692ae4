// The message of the welkin::Error a call throws, for tests of the one-line errors.
//
//   CHECK(test::errorOf([&] { CsvTable::parse("a\n3,x\n", "t.csv").numbers("a"); }) == "t.csv:2: ...");
//   CHECK(test::errorOf([] {}) == "(no error)");  // nothing thrown
#pragma once
#include <welkin/error.hpp>

#include <string>

namespace welkin::test {

// Calls f(); returns what() of the welkin::Error it throws, or "(no error)" when it returns.
// Other exceptions pass through (a test that gets one fails on it).
template <class F>
std::string errorOf(F&& f) {
    try {
        f();
    } catch (const Error& e) {
        return e.what();
    }
    return "(no error)";
}

}  // namespace welkin::test
