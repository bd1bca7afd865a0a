// make-scene convert --flip: the flipped file has every triangle reversed, every NORMAL negated, every
// material double-sided, and everything else (positions, lights, cameras, textures) as it was; read back
// through tinygltf (generated scenes) and through probebake's loader (shared scenes).
#include "probebake/samples/flip_gltf.h"
#include "probebake/samples/meshopt_gltf.h"
#include "probebake/samples/scenes.h"

#include "probebake/scene/scene.h"
#include "probebake/formats/error.h"

#include "gltf_readback.h"

#include <gtest/gtest.h>
#include <glm/geometric.hpp>

#include <cstring>
#include <fstream>

namespace ps = probebake::samples;
namespace pt = probebake::samples::test;
namespace scene = probebake::scene;

namespace {

tinygltf::Model load(const std::vector<std::uint8_t>& bytes) {
  std::string error;
  tinygltf::Model model = pt::load_glb(bytes, error);
  EXPECT_TRUE(error.empty()) << error;
  return model;
}

// The NORMAL values of every primitive, in mesh and primitive order (float VEC3 only, as both writers use).
std::vector<glm::vec3> normals(const tinygltf::Model& model) {
  std::vector<glm::vec3> out;
  for (const tinygltf::Mesh& mesh : model.meshes)
    for (const tinygltf::Primitive& p : mesh.primitives) {
      const auto it = p.attributes.find("NORMAL");
      if (it == p.attributes.end()) continue;
      const tinygltf::Accessor& a = model.accessors.at(std::size_t(it->second));
      EXPECT_EQ(a.componentType, TINYGLTF_COMPONENT_TYPE_FLOAT);
      const tinygltf::BufferView& v = model.bufferViews.at(std::size_t(a.bufferView));
      const std::size_t stride = v.byteStride ? v.byteStride : 12;
      for (std::size_t i = 0; i < a.count; ++i) {
        glm::vec3 n;
        std::memcpy(&n, &model.buffers.at(std::size_t(v.buffer)).data.at(v.byteOffset + a.byteOffset + i * stride), 12);
        out.push_back(n);
      }
    }
  return out;
}

void expect_reversed(const std::vector<pt::WorldTriangle>& original, const std::vector<pt::WorldTriangle>& flipped) {
  ASSERT_EQ(original.size(), flipped.size());
  for (std::size_t i = 0; i < original.size(); ++i) {
    EXPECT_EQ(flipped[i].a, original[i].a) << i;
    EXPECT_EQ(flipped[i].b, original[i].c) << i;
    EXPECT_EQ(flipped[i].c, original[i].b) << i;
    EXPECT_EQ(flipped[i].material, original[i].material) << i;
    EXPECT_LT(glm::distance(flipped[i].normal(), -original[i].normal()), 1e-5f) << i;
  }
}

TEST(Flip, GeneratedCornellReversedNegatedAndDoubleSided) {
  const std::vector<std::uint8_t> bytes = ps::cornell().to_glb();
  const tinygltf::Model original = load(bytes);
  const tinygltf::Model flipped = load(ps::flip_sides_gltf(bytes, "."));
  expect_reversed(pt::world_triangles(original), pt::world_triangles(flipped));
  ASSERT_EQ(flipped.materials.size(), original.materials.size()); // every primitive had a material
  for (std::size_t m = 0; m < flipped.materials.size(); ++m) {
    EXPECT_FALSE(original.materials[m].doubleSided);
    EXPECT_TRUE(flipped.materials[m].doubleSided) << flipped.materials[m].name;
    EXPECT_EQ(flipped.materials[m].emissiveFactor, original.materials[m].emissiveFactor);
    EXPECT_EQ(flipped.materials[m].pbrMetallicRoughness.baseColorFactor,
              original.materials[m].pbrMetallicRoughness.baseColorFactor);
  }
  const std::vector<glm::vec3> n0 = normals(original), n1 = normals(flipped);
  ASSERT_EQ(n0.size(), n1.size());
  ASSERT_FALSE(n0.empty());
  for (std::size_t i = 0; i < n0.size(); ++i) EXPECT_EQ(n1[i], -n0[i]) << i;
  EXPECT_EQ(flipped.lights.size(), original.lights.size());
  EXPECT_EQ(flipped.nodes.size(), original.nodes.size());
}

TEST(Flip, TwiceGivesTheOriginalTriangles) {
  const std::vector<std::uint8_t> bytes = ps::plane_light().to_glb();
  const tinygltf::Model original = load(bytes);
  const tinygltf::Model twice = load(ps::flip_sides_gltf(ps::flip_sides_gltf(bytes, "."), "."));
  const auto a = pt::world_triangles(original), b = pt::world_triangles(twice);
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a[i].a, b[i].a);
    EXPECT_EQ(a[i].b, b[i].b);
    EXPECT_EQ(a[i].c, b[i].c);
  }
  EXPECT_EQ(normals(twice), normals(original));
}

TEST(Flip, FlippedAndMeshoptCompressedLoadsTheSameTriangles) {
  const std::vector<std::uint8_t> flipped = ps::flip_sides_gltf(ps::cornell().to_glb(), ".");
  const auto folder = pt::fresh_folder("flip_meshopt");
  std::ofstream(folder / "flipped.glb", std::ios::binary)
      .write(reinterpret_cast<const char*>(flipped.data()), std::streamsize(flipped.size()));
  const std::vector<std::uint8_t> packed = ps::meshopt_compress_gltf(flipped, folder);
  std::ofstream(folder / "packed.glb", std::ios::binary)
      .write(reinterpret_cast<const char*>(packed.data()), std::streamsize(packed.size()));
  const scene::Scene a = scene::load_scene(folder / "flipped.glb");
  const scene::Scene b = scene::load_scene(folder / "packed.glb");
  // meshoptimizer's index codec may rotate a triangle's vertices (never its winding).
  ASSERT_EQ(a.triangles.size(), b.triangles.size());
  EXPECT_EQ(a.positions, b.positions);
  for (std::size_t t = 0; t < a.triangles.size(); ++t) {
    const glm::uvec3 x = a.triangles[t], y = b.triangles[t];
    EXPECT_TRUE(y == x || y == glm::uvec3(x.y, x.z, x.x) || y == glm::uvec3(x.z, x.x, x.y)) << t;
  }
  for (std::size_t t = 0; t < b.triangles.size(); ++t) EXPECT_TRUE(scene::is_double_sided(b, t)) << t;
}

TEST(Flip, CompressedInputIsRefused) {
  const auto folder = pt::fresh_folder("flip_compressed");
  const std::vector<std::uint8_t> packed = ps::meshopt_compress_gltf(ps::triangle().to_glb(), folder);
  try {
    ps::flip_sides_gltf(packed, folder);
    FAIL() << "a meshopt input was flipped";
  } catch (const probebake::Error& e) {
    EXPECT_EQ(e.kind(), probebake::ErrorKind::input);
    EXPECT_NE(std::string(e.what()).find("uncompressed original"), std::string::npos) << e.what();
  }
}

// A shared scene through probebake's own loader (.gltf, external .bin, PNG textures, punctual lights):
// positions, lights, textures and instances carried over.
void expect_flipped_shared(const std::filesystem::path& path) {
  if (!std::filesystem::exists(path)) GTEST_SKIP() << "shared scenes not available";
  const scene::Scene original = scene::load_scene(path);
  const std::vector<std::uint8_t> bytes = ps::flip_sides_file(path);
  const auto folder = pt::fresh_folder("flip_shared_" + path.stem().string());
  std::ofstream(folder / "flipped.glb", std::ios::binary)
      .write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
  const scene::Scene flipped = scene::load_scene(folder / "flipped.glb");
  ASSERT_EQ(flipped.triangles.size(), original.triangles.size());
  EXPECT_EQ(flipped.positions.size(), original.positions.size());
  for (std::size_t t = 0; t < original.triangles.size(); ++t) {
    const glm::uvec3 a = original.triangles[t], b = flipped.triangles[t];
    ASSERT_EQ(flipped.positions[b.x], original.positions[a.x]) << t;
    ASSERT_EQ(flipped.positions[b.y], original.positions[a.z]) << t;
    ASSERT_EQ(flipped.positions[b.z], original.positions[a.y]) << t;
    EXPECT_TRUE(scene::is_double_sided(flipped, t)) << t;
    // Textures embedded, the same texels (the per-triangle average visits its sample points in another
    // order: float rounding only).
    EXPECT_LT(glm::distance(flipped.triangle_albedo[t], original.triangle_albedo[t]), 1e-6f) << t;
    EXPECT_LT(glm::distance(flipped.triangle_emission[t], original.triangle_emission[t]),
              1e-6f * (1.0f + glm::length(original.triangle_emission[t])))
        << t;
  }
  EXPECT_EQ(flipped.lights.size(), original.lights.size());
  EXPECT_EQ(flipped.cameras.size(), original.cameras.size());
  EXPECT_EQ(flipped.instances.size(), original.instances.size());
}

TEST(Flip, SharedCornellBoxBjsWithTextures) {
  expect_flipped_shared(std::filesystem::path(PROBEBAKE_SHARED_SCENES) / "cornellbox_bjs" /
                        "cornellBox-2.80-Eevee-gltf.gltf");
}

TEST(Flip, SharedSphereLightsWithPunctualLights) {
  expect_flipped_shared(std::filesystem::path(PROBEBAKE_SHARED_SCENES) / "sphere_lights" / "sphere_lights.gltf");
}

} // namespace
