// glTF sides flipped (make-scene convert --flip): every triangle's winding reversed, every NORMAL (and
// morph-target NORMAL delta) negated and every material doubleSided. By the glTF spec the result is the
// same scene as the input: a doubleSided surface is lit on both sides with the normal facing the viewer,
// so what was the front is now the back of a double-sided surface. Primitives without a material get a
// copy of the default material with doubleSided. Triangle strips and fans become triangle lists; points
// and lines are left as they are; TANGENT is left as it is. Everything else (lights, cameras, nodes,
// materials' other properties, textures, extras) is carried over; the output is one .glb with external
// and data-URI buffers and images embedded. Inputs that use Draco or meshopt compression are refused
// (give the uncompressed original).
// Errors: probebake::Error (input: unreadable or unsupported file).
#pragma once

#include <cstdint>
#include <filesystem>
#include <vector>

namespace probebake::samples {

// A .glb or .gltf (external files resolved against `base_dir`) -> the flipped scene as .glb bytes.
std::vector<std::uint8_t> flip_sides_gltf(const std::vector<std::uint8_t>& input,
                                          const std::filesystem::path& base_dir);
// The same for a file.
std::vector<std::uint8_t> flip_sides_file(const std::filesystem::path& path);

} // namespace probebake::samples
