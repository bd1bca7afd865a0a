// Property checks of the fuzz entry functions (tests/*/fuzz_*_entry.cpp). A failed check throws
// PropertyViolation, which is not a probebake::Error: under libFuzzer it escapes LLVMFuzzerTestOneInput and
// ends in std::terminate (a crash with the message), under GoogleTest it fails the regression test.
#pragma once

#include <stdexcept>
#include <string>

namespace probebake::fuzz {

class PropertyViolation : public std::logic_error {
public:
  using std::logic_error::logic_error;
};

inline void check(bool condition, const std::string& what) {
  if (!condition) throw PropertyViolation("fuzz property violated: " + what);
}

} // namespace probebake::fuzz
