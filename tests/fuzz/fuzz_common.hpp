// Shared by the libFuzzer targets (docs/fuzzing.md). Each target feeds the bytes to one parser;
// welkin::Error is the parser's documented answer to bad input and is swallowed, anything else
// (another exception, a crash, a sanitizer report, a failed FUZZ_CHECK) is a finding.
#pragma once
#include <welkin/error.hpp>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <string_view>

// A property every accepted input must have; aborts (a libFuzzer crash) with the condition.
#define FUZZ_CHECK(cond)                                                                   \
    do {                                                                                   \
        if (!(cond)) {                                                                     \
            std::fprintf(stderr, "FUZZ_CHECK failed: %s (%s:%d)\n", #cond, __FILE__, __LINE__); \
            std::abort();                                                                  \
        }                                                                                  \
    } while (0)

namespace welkin::fuzz {

inline std::string text(const uint8_t* data, size_t size) { return std::string(reinterpret_cast<const char*>(data), size); }

// Runs f(); a welkin::Error (the documented rejection) returns false, success true. With
// `oneLine`, the message must be one line (the file parsers quote one line of their input; the
// options quote the user's whole text, which may itself hold a newline).
template <class F>
bool accepts(F&& f, bool oneLine = true) {
    try {
        f();
        return true;
    } catch (const welkin::Error& e) {
        const std::string_view what = e.what();
        FUZZ_CHECK(!what.empty());  // a rejection says why
        if (oneLine) FUZZ_CHECK(what.find('\n') == std::string_view::npos);
        return false;
    }
}

}  // namespace welkin::fuzz
