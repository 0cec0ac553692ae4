// welkin::Error: the one exception type the library throws for bad input and failed GL work.
//
//   try { vars.get(keys::sunDirection); }
//   catch (const welkin::Error& e) { std::cerr << e.what() << '\n'; }   // one line, names the problem
#pragma once
#include <stdexcept>
#include <string>

namespace welkin {

/// Thrown on precondition violations, GL failures and I/O errors. what() is a single line that
/// names the function or argument and, for ranges, the accepted range.
class Error : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

}  // namespace welkin
