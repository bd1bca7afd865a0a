#include "lenient_cases.h"

#include <cstring>
#include <fstream>

#include <fmt/core.h>

#include "mini_gltf.h"
#include "probebake/common/enum_names.h"

namespace probebake::test {
namespace {

using nlohmann::json;
using Bytes = std::vector<unsigned char>;

// A closed room (the unit cube, double-sided grey walls) lit by a point light at its centre: small enough to
// bake in a second at depth 2.
MiniGltf room() {
  const std::vector<glm::vec3> corners = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0},
                                          {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
  const std::vector<std::uint32_t> faces = {0, 2, 1, 0, 3, 2, 4, 5, 6, 4, 6, 7, 0, 1, 5, 0, 5, 4,
                                            3, 6, 2, 3, 7, 6, 0, 4, 7, 0, 7, 3, 1, 2, 6, 1, 6, 5};
  MiniGltf g = MiniGltf::triangles(corners, faces);
  g.json["materials"] = {{{"doubleSided", true}, {"pbrMetallicRoughness", {{"baseColorFactor", {0.7, 0.7, 0.7, 1}}}}}};
  g.json["meshes"][0]["primitives"][0]["material"] = 0;
  g.json["extensionsUsed"] = {"KHR_lights_punctual"};
  g.json["extensions"] = {{"KHR_lights_punctual", {{"lights", {{{"type", "point"}, {"intensity", 5}}}}}}};
  g.json["nodes"].push_back(
      {{"name", "light"}, {"translation", {0.5, 0.5, 0.5}}, {"extensions", {{"KHR_lights_punctual", {{"light", 0}}}}}});
  g.json["scenes"][0]["nodes"] = {0, 1};
  return g;
}

Bytes gltf_bytes(const MiniGltf& g) { return g.gltf_text(); } // the buffer as a data URI: one file per case

Bytes text_bytes(const std::string& text) { return Bytes(text.begin(), text.end()); }

void put_u32(Bytes& bytes, std::size_t at, std::uint32_t v) { std::memcpy(&bytes[at], &v, 4); }
std::uint32_t get_u32(const Bytes& bytes, std::size_t at) {
  std::uint32_t v;
  std::memcpy(&v, &bytes[at], 4);
  return v;
}

// A GLB chunk of `size` bytes of `fill`, type `type` (four characters), appended after the chunk at `after`
// (0: after the JSON chunk, 1: after the BIN chunk); the header's length follows.
Bytes with_extra_chunk(Bytes glb, int after, const char* type, std::size_t size) {
  std::size_t at = 12 + 8 + get_u32(glb, 12);
  if (after == 1) at += 8 + get_u32(glb, at);
  Bytes chunk(8 + size, 0xAB);
  put_u32(chunk, 0, std::uint32_t(size));
  std::memcpy(&chunk[4], type, 4);
  glb.insert(glb.begin() + std::ptrdiff_t(at), chunk.begin(), chunk.end());
  put_u32(glb, 8, std::uint32_t(glb.size()));
  return glb;
}

// Every integer in the tree written as a float (1 as 1.0), extras included.
void floats_for_integers(json& value) {
  if (value.is_number_integer()) value = value.get<double>();
  if (value.is_array() || value.is_object())
    for (json& element : value) floats_for_integers(element);
}

LenientCase bakes(std::string file, std::string what, Bytes bytes, std::vector<std::string> warnings = {}) {
  return {std::move(file), std::move(what), LenientOutcome::bakes, std::move(bytes), std::move(warnings), {}};
}

LenientCase refused(std::string file, std::string what, Bytes bytes, std::string error) {
  return {std::move(file), std::move(what), LenientOutcome::refused, std::move(bytes), {}, std::move(error)};
}

std::vector<LenientCase> accessor_cases() {
  std::vector<LenientCase> cases;
  MiniGltf g = room();
  g.add_accessor(0, 5126, 1, "NotaVEC3");
  cases.push_back(bakes("unused_accessor_unknown_type.gltf",
                        "an accessor `type` from a later version that no primitive uses", gltf_bytes(g),
                        {"accessors[2].type: unknown value 'NotaVEC3' in an unused accessor"}));
  g = room();
  g.add_accessor(0, 5127, 1, "VEC3");
  cases.push_back(bakes("unused_accessor_unknown_component_type.gltf",
                        "an unknown `componentType` in an unused accessor", gltf_bytes(g),
                        {"accessors[2].componentType: unknown value '5127' in an unused accessor"}));
  g = room();
  g.json["accessors"][0]["type"] = "NotaVEC3";
  cases.push_back(refused("used_accessor_unknown_type.gltf", "POSITION read through an accessor of an unknown `type`",
                          gltf_bytes(g), "accessors[0].type: 'NotaVEC3' is not a glTF 2.0 accessor type"));
  g = room();
  g.json["meshes"][0]["primitives"][0]["attributes"]["POSITION"] = 7;
  cases.push_back(refused("missing_position_accessor.gltf", "POSITION names an accessor that is not there",
                          gltf_bytes(g), "accessor 7 does not exist"));
  g = room();
  json j = g.json;
  floats_for_integers(j);
  g.json = j;
  cases.push_back(
      bakes("integral_floats.gltf", "every integer written as a float (`\"byteLength\": 1.0`)", gltf_bytes(g)));
  return cases;
}

std::vector<LenientCase> glb_cases() {
  std::vector<LenientCase> cases;
  const Bytes glb = room().glb();
  Bytes tail = glb;
  tail.insert(tail.end(), {1, 2, 3});
  cases.push_back(bakes("glb_bytes_after_length.glb", "3 bytes after the header's declared length", tail,
                        {"glb: 3 bytes after the declared length"}));
  Bytes inside = glb;
  inside.insert(inside.end(), {0, 0, 0, 0});
  put_u32(inside, 8, std::uint32_t(inside.size()));
  cases.push_back(bakes("glb_bytes_after_last_chunk.glb", "4 bytes inside the declared length after the last chunk",
                        inside, {"glb: 4 bytes after the last chunk"}));
  cases.push_back(bakes("glb_unknown_chunk.glb", "a chunk of unknown type after the BIN chunk",
                        with_extra_chunk(glb, 1, "XTRA", 16), {"glb: chunk 2: unknown type 'XTRA' skipped"}));
  cases.push_back(bakes("glb_unknown_chunk_before_bin.glb", "a chunk of unknown type between the JSON and BIN chunks",
                        with_extra_chunk(glb, 0, "XTRA", 4), {"glb: chunk 1: unknown type 'XTRA' skipped"}));
  Bytes long_chunk = glb;
  const std::size_t bin = 12 + 8 + get_u32(glb, 12);
  put_u32(long_chunk, bin, get_u32(glb, bin) + 64);
  cases.push_back(refused("glb_chunk_past_end.glb", "a BIN chunk longer than the file", long_chunk,
                          fmt::format("glb: chunk 1: {} bytes are longer than the file", get_u32(long_chunk, bin))));
  Bytes truncated(glb.begin(), glb.end() - 8);
  cases.push_back(
      refused("glb_truncated.glb", "a file shorter than its header's declared length", truncated, "truncated"));
  return cases;
}

std::vector<LenientCase> unused_data_cases() {
  std::vector<LenientCase> cases;
  MiniGltf g = room();
  g.json["buffers"].push_back({{"uri", "data:application/gltf-buffer,0"}, {"byteLength", 1}});
  LenientCase described =
      bakes("unused_buffer_not_base64.glb", "an unused buffer whose data URI is not base64", g.glb());
  described.outcome = LenientOutcome::described;
  cases.push_back(described);
  g = room();
  g.json["images"] = {{{"uri", "data:image/png,not-base64"}}};
  cases.push_back(
      bakes("unused_image_not_base64.gltf", "an image no texture uses, whose data URI is not base64", gltf_bytes(g)));
  g = room();
  g.json["buffers"][0]["uri"] = "data:application/gltf-buffer,0";
  cases.push_back(refused("used_buffer_not_base64.gltf", "the buffer the mesh reads is a data URI that is not base64",
                          text_bytes(g.json.dump(1)), "buffers[0].uri: data URI is not base64"));
  g = room();
  g.json["cameras"] = {{{"type", "fisheye"}}};
  g.json["nodes"].push_back({{"camera", 0}, {"translation", {0.5, 0.5, 0.9}}});
  g.json["scenes"][0]["nodes"].push_back(2);
  cases.push_back(bakes("camera_unknown_type.gltf", "a node's camera of a type from a later version", gltf_bytes(g),
                        {"cameras[0].type: unknown value 'fisheye', camera not used"}));
  g = room();
  g.json["extensions"]["KHR_lights_punctual"]["lights"].push_back({{"type", "area"}, {"intensity", 1}});
  g.json["nodes"].push_back({{"extensions", {{"KHR_lights_punctual", {{"light", 1}}}}}});
  g.json["scenes"][0]["nodes"].push_back(2);
  cases.push_back(bakes("light_unknown_type.gltf", "a node's light of a type from a later version", gltf_bytes(g),
                        {"nodes[2]: light 1 of unknown type 'area' skipped"}));
  g = room();
  g.json["meshes"].push_back({{"primitives", {{{"attributes", {{"POSITION", 0}}}, {"mode", 7}}}}});
  g.json["nodes"].push_back({{"mesh", 1}});
  g.json["scenes"][0]["nodes"].push_back(2);
  cases.push_back(bakes("primitive_unknown_mode.gltf", "a primitive of a mode from a later version", gltf_bytes(g),
                        {"meshes[1].primitives[0]: unknown mode 7 skipped"}));
  return cases;
}

// The outcome column of the cases' README.
constexpr EnumName<LenientOutcome> kOutcomeNames[] = {
    {LenientOutcome::bakes, "bakes"},
    {LenientOutcome::described, "`info` describes it, and it bakes"},
    {LenientOutcome::refused, "refused"},
};

} // namespace

std::vector<LenientCase> lenient_cases() {
  std::vector<LenientCase> cases = accessor_cases();
  for (auto& c : glb_cases()) cases.push_back(std::move(c));
  for (auto& c : unused_data_cases()) cases.push_back(std::move(c));
  return cases;
}

std::string lenient_cases_readme(const std::vector<LenientCase>& cases) {
  std::string text =
      "# glTF leniency cases\n\n"
      "Written by `build/tests/scene/make-gltf-cases tests/data/gltf-lenient` (tests/scene/lenient_cases.cpp);\n"
      "tests/scene/lenient_input_test.cpp checks that these files are what it writes and that each has its\n"
      "outcome. docs/GLTF.md says what is accepted with a warning and what is refused.\n\n"
      "| file | case | outcome | warning or error (a part of the line) |\n|---|---|---|---|\n";
  for (const LenientCase& c : cases) {
    std::string said = c.outcome == LenientOutcome::refused ? c.error : "";
    for (const std::string& w : c.warnings) said += (said.empty() ? "" : "; ") + w;
    text += fmt::format("| `{}` | {} | {} | {} |\n", c.file, c.what, name_in(kOutcomeNames, c.outcome, ""),
                        said.empty() ? "none" : "`" + said + "`");
  }
  return text;
}

} // namespace probebake::test
