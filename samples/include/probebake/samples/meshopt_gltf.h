// glTF geometry rewritten through meshoptimizer's encoder (EXT_meshopt_compression), as gltfpack -cc writes
// it: every vertex attribute and index accessor of a triangle primitive becomes a compressed bufferView
// (ATTRIBUTES, TRIANGLES, or INDICES for other topologies) in the GLB's BIN chunk, backed by a uri-less
// fallback buffer; the extension is required. Lossless except NORMAL, which goes through the OCTAHEDRAL
// filter (16-bit; the bake does not read normals), so the bake of the output equals the bake of the input.
// External and data-URI images are embedded in the BIN chunk unchanged.
// Errors: probebake::Error (input: unreadable or unsupported file, e.g. Draco; output: unwritable).
#pragma once

#include <cstdint>
#include <filesystem>
#include <vector>

namespace probebake::samples {

// A .glb or .gltf (external files resolved against `base_dir`) -> meshopt-compressed .glb bytes.
std::vector<std::uint8_t> meshopt_compress_gltf(const std::vector<std::uint8_t>& input,
                                                const std::filesystem::path& base_dir);
// The same for a file.
std::vector<std::uint8_t> meshopt_compress_file(const std::filesystem::path& path);

} // namespace probebake::samples
