// Test helpers: load .glb bytes with tinygltf and flatten the default scene into world-space triangles,
// independently of the samples library's own code.
#pragma once

#include <tiny_gltf.h>

#include <glm/vec3.hpp>

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace probebake::samples::test {

// Loads a .glb from memory; on failure `error` is set and the model is empty.
tinygltf::Model load_glb(const std::vector<std::uint8_t>& bytes, std::string& error);
std::vector<std::uint8_t> read_file(const std::filesystem::path& path);

struct WorldTriangle {
  glm::vec3 a, b, c; // counter-clockwise = front
  int material = -1;
  std::string node;         // name of the node that placed it
  glm::vec3 normal() const; // unit geometric normal of the front face
  glm::vec3 centroid() const { return (a + b + c) / 3.0f; }
};

std::vector<WorldTriangle> world_triangles(const tinygltf::Model& model);

struct WorldBounds {
  glm::vec3 min, max;
};
WorldBounds bounds_of(const std::vector<WorldTriangle>& triangles);

// Every edge (by exact position) is used once in each direction: a closed, consistently oriented surface.
bool is_closed_and_oriented(const std::vector<WorldTriangle>& triangles);

// Names of nodes whose extras hold {"probebake": {"dynamic": true}}.
std::vector<std::string> dynamic_node_names(const tinygltf::Model& model);

// A fresh empty folder for one test.
std::filesystem::path fresh_folder(const std::string& name);

} // namespace probebake::samples::test
