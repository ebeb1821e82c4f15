#pragma once
// Errors thrown at API boundaries. The message is one line that names the file, key, GL call or
// shader file:line and says what was expected; the CLI prints it as is and exits non-zero.
#include <stdexcept>
#include <string>

namespace forest {

// A failure of the program or the machine (GL call, driver, I/O).
class Error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Bad input from the user: a file, key or value that is malformed or out of range.
class InputError : public Error {
 public:
  using Error::Error;
};

// Formats "what: strerror(errno)" for a failed system call.
std::string systemErrorMessage(const std::string& what);

}  // namespace forest
