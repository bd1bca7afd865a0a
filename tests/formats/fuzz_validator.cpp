// libFuzzer target for the validator (validate_file on any bytes, validate on what the reader decodes); the
// checks are in fuzz_validator_entry.cpp. Seeds: tests/data/golden, tests/data/fuzz/validator.
//   fuzz_validator -dict=tests/formats/fuzz_probes_reader.dict -max_total_time=60 CORPUS tests/data/golden
#include "fuzz_entries.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  probebake::fuzz::fuzz_one_validator(data, size);
  return 0;
}
