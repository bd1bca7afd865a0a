// Errors: exceptions with context inside the libraries, one exit code per kind at the CLI boundary.
// The message is one line: "<file>: <place>: <reason>" where a file and place are known.
#pragma once

#include <stdexcept>
#include <string>

namespace probebake {

// Values are the CLI exit codes (README, "Exit codes").
enum class ErrorKind : int {
  usage = 1,    // bad command-line arguments
  input = 2,    // a file is missing, unreadable, truncated or invalid
  output = 3,   // an output file could not be written
  internal = 4, // a bug or an unexpected failure of a dependency
};

class Error : public std::runtime_error {
public:
  Error(ErrorKind kind, const std::string& message) : std::runtime_error(message), kind_(kind) {}
  ErrorKind kind() const noexcept { return kind_; }
  int exit_code() const noexcept { return static_cast<int>(kind_); }

private:
  ErrorKind kind_;
};

// "<path>: <reason>" as an input error.
[[noreturn]] inline void throw_input_error(const std::string& path, const std::string& reason) {
  throw Error(ErrorKind::input, path + ": " + reason);
}

} // namespace probebake
