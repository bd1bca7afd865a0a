// Per-input functions of the formats libFuzzer targets, shared by the fuzzers (fuzz_*.cpp, clang) and the
// regression test that replays tests/data/fuzz-regressions and the seeds (fuzz_regression_test.cpp, any
// compiler). Each returns normally or throws probebake::fuzz::PropertyViolation; probebake::Error never
// escapes, anything else escaping is a bug.
#pragma once

#include <cstddef>
#include <cstdint>

namespace probebake::fuzz {

void fuzz_one_probes_reader(const std::uint8_t* data, std::size_t size);
void fuzz_one_validator(const std::uint8_t* data, std::size_t size);

} // namespace probebake::fuzz
