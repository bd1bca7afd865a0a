// Per-input function of the glTF loader's libFuzzer target, shared by the fuzzer (fuzz_scene_loader.cpp,
// clang) and the regression test (fuzz_regression_test.cpp, any compiler). Returns normally or throws
// probebake::fuzz::PropertyViolation; probebake::Error never escapes, anything else escaping is a bug.
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>

namespace probebake::fuzz {

void fuzz_one_scene_loader(const std::uint8_t* data, std::size_t size);

// The scratch folder the loader's inputs resolve against: scene/ (the base directory, holding only
// buffer.bin) and outside.bin beside it, which no input may read. $PROBEBAKE_FUZZ_SCRATCH, or a folder of
// this process under the temp directory removed at exit.
const std::filesystem::path& fuzz_scratch_folder();

} // namespace probebake::fuzz
