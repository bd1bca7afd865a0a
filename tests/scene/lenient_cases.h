// The glTF leniency cases (docs/GLTF.md, "Accepted with a warning"): spec-valid files that other readers
// refuse, and the faults that stay refused. One small file each, generated here byte for byte and
// committed under tests/data/gltf-lenient (make-gltf-cases writes them; lenient_input_test checks both).
#pragma once

#include <string>
#include <vector>

namespace probebake::test {

enum class LenientOutcome { bakes, described, refused };

struct LenientCase {
  std::string file; // file name, .gltf or .glb
  std::string what; // the case, in words
  LenientOutcome outcome;
  std::vector<unsigned char> bytes;
  std::vector<std::string> warnings; // each a substring of one warning line, in order; none when empty
  std::string error;                 // refused: a substring of the one error line
};

std::vector<LenientCase> lenient_cases();
// tests/data/gltf-lenient/README.md: the table of cases and their outcomes.
std::string lenient_cases_readme(const std::vector<LenientCase>& cases);

} // namespace probebake::test
