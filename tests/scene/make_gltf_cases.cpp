// make-gltf-cases FOLDER: writes the glTF leniency cases and their README (tests/data/gltf-lenient).
#include <cstdio>
#include <filesystem>
#include <fstream>

#include "lenient_cases.h"

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: make-gltf-cases FOLDER\n");
    return 2;
  }
  const std::filesystem::path folder = argv[1];
  std::filesystem::create_directories(folder);
  const auto cases = probebake::test::lenient_cases();
  for (const auto& c : cases)
    std::ofstream(folder / c.file, std::ios::binary)
        .write(reinterpret_cast<const char*>(c.bytes.data()), std::streamsize(c.bytes.size()));
  std::ofstream(folder / "README.md", std::ios::binary) << probebake::test::lenient_cases_readme(cases);
  std::printf("%zu cases written to %s\n", cases.size(), folder.string().c_str());
  return 0;
}
