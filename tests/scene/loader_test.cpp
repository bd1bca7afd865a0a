// Scene loader on hand-built glTF: transforms, component types, sparse accessors, strips, materials,
// lights, dynamic flags, Draco and the Embree ray scene.
#include <cmath>

#include <draco/compression/encode.h>
#include <draco/mesh/triangle_soup_mesh_builder.h>
#include <gtest/gtest.h>

#include "mini_gltf.h"
#include "probebake/scene/ray_scene.h"
#include "probebake/scene/scene.h"

namespace probebake::test {
namespace {

const std::vector<glm::vec3> kQuad = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
const std::vector<std::uint32_t> kQuadIndices = {0, 1, 2, 0, 2, 3};

scene::Scene load_glb(const MiniGltf& g, const std::string& name) {
  const auto path = test_dir(name) / "scene.glb";
  g.write_glb(path);
  return scene::load_scene(path);
}

TEST(Loader, GlbAndGltfWithExternalAndDataUriBuffersAgree) {
  const MiniGltf g = MiniGltf::triangles(kQuad, kQuadIndices);
  const auto dir = test_dir("formats");
  g.write_glb(dir / "a.glb");
  g.write_gltf(dir / "b.gltf", "b.bin");
  g.write_gltf(dir / "c.gltf", "");
  for (const char* name : {"a.glb", "b.gltf", "c.gltf"}) {
    const scene::Scene s = scene::load_scene(dir / name);
    ASSERT_EQ(s.triangle_count(), 2u) << name;
    EXPECT_EQ(s.bounds.min, glm::vec3(0, 0, 0)) << name;
    EXPECT_EQ(s.bounds.max, glm::vec3(1, 1, 0)) << name;
    EXPECT_EQ(scene::triangle_normal(s, 0), glm::vec3(0, 0, 1)) << name;
  }
}

TEST(Loader, IndexComponentTypes) {
  for (int type : {5121, 5123, 5125}) {
    const scene::Scene s = load_glb(MiniGltf::triangles(kQuad, kQuadIndices, type), "index_types");
    ASSERT_EQ(s.triangle_count(), 2u);
    EXPECT_EQ(s.triangles[1], glm::uvec3(0, 2, 3));
  }
}

TEST(Loader, NonIndexedTriangles) {
  const std::vector<glm::vec3> soup = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {1, 0, 1}, {0, 1, 1}};
  const scene::Scene s = load_glb(MiniGltf::triangles(soup, {}), "soup");
  EXPECT_EQ(s.triangle_count(), 2u);
}

TEST(Loader, TrsHierarchyAndNegativeDeterminantFlipsWinding) {
  MiniGltf g = MiniGltf::triangles(kQuad, kQuadIndices);
  // root (translate +10 x) -> child (mirror in x via scale -1, uses the mesh)
  g.json["nodes"] = {{{"translation", {10, 0, 0}}, {"children", {1}}}, {{"scale", {-1, 1, 1}}, {"mesh", 0}}};
  const scene::Scene s = load_glb(g, "trs");
  ASSERT_EQ(s.triangle_count(), 2u);
  EXPECT_FLOAT_EQ(s.bounds.min.x, 9.0f);
  EXPECT_FLOAT_EQ(s.bounds.max.x, 10.0f);
  // The mirrored quad still faces +z because its winding was flipped.
  EXPECT_EQ(scene::triangle_normal(s, 0), glm::vec3(0, 0, 1));
}

TEST(Loader, MatrixTransformAndRotation) {
  MiniGltf g = MiniGltf::triangles(kQuad, kQuadIndices);
  // Column-major matrix: translate (0, 5, 0).
  g.json["nodes"][0]["matrix"] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 5, 0, 1};
  scene::Scene s = load_glb(g, "matrix");
  EXPECT_FLOAT_EQ(s.bounds.min.y, 5.0f);
  MiniGltf r = MiniGltf::triangles(kQuad, kQuadIndices);
  const float h = std::sqrt(0.5f); // 90 degrees about +x: +z normal -> -y
  r.json["nodes"][0]["rotation"] = {h, 0, 0, h};
  s = load_glb(r, "rotation");
  const glm::vec3 n = scene::triangle_normal(s, 0);
  EXPECT_NEAR(n.y, -1.0f, 1e-6f);
}

TEST(Loader, NormalizedShortPositionsAndSparseAccessor) {
  MiniGltf g = MiniGltf::triangles(kQuad, kQuadIndices);
  const std::int16_t shorts[] = {0, 0, 0, 32767, 0, 0, 32767, 32767, 0, 0, 32767, 0};
  const int view = g.add_view(shorts, sizeof(shorts));
  const int acc = g.add_accessor(view, 5122, 4, "VEC3", true);
  // Sparse: replace vertex 2 by (2, 2, 0) (as normalized shorts this is impossible, so use floats below).
  g.json["meshes"][0]["primitives"][0]["attributes"]["POSITION"] = acc;
  scene::Scene s = load_glb(g, "normalized");
  EXPECT_NEAR(s.bounds.max.x, 1.0f, 1e-6f);

  MiniGltf sp = MiniGltf::triangles(kQuad, kQuadIndices);
  const std::uint8_t which[] = {2};
  const float value[] = {2.0f, 3.0f, 0.0f};
  const int iv = sp.add_view(which, 1), vv = sp.add_view(value, sizeof(value));
  sp.json["accessors"][0]["sparse"] = {
      {"count", 1}, {"indices", {{"bufferView", iv}, {"componentType", 5121}}}, {"values", {{"bufferView", vv}}}};
  s = load_glb(sp, "sparse");
  EXPECT_EQ(s.bounds.max, glm::vec3(2, 3, 0));
}

TEST(Loader, StripsFansAndSkippedModes) {
  MiniGltf strip = MiniGltf::triangles(kQuad, {0, 1, 3, 2});
  strip.json["meshes"][0]["primitives"][0]["mode"] = 5;
  scene::Scene s = load_glb(strip, "strip");
  ASSERT_EQ(s.triangle_count(), 2u);
  for (std::size_t t = 0; t < 2; ++t) EXPECT_EQ(scene::triangle_normal(s, t), glm::vec3(0, 0, 1));
  MiniGltf fan = MiniGltf::triangles(kQuad, {0, 1, 2, 3});
  fan.json["meshes"][0]["primitives"][0]["mode"] = 6;
  s = load_glb(fan, "fan");
  EXPECT_EQ(s.triangle_count(), 2u);
  MiniGltf lines = MiniGltf::triangles(kQuad, kQuadIndices);
  lines.json["meshes"][0]["primitives"].push_back(lines.json["meshes"][0]["primitives"][0]);
  lines.json["meshes"][0]["primitives"][1]["mode"] = 1;
  s = load_glb(lines, "lines");
  EXPECT_EQ(s.triangle_count(), 2u);
  ASSERT_FALSE(s.warnings.empty());
  EXPECT_NE(s.warnings[0].find("LINES"), std::string::npos);
}

TEST(Loader, MaterialsLightsAndDynamicNodes) {
  MiniGltf g = MiniGltf::triangles(kQuad, kQuadIndices);
  g.json["materials"] = {{{"pbrMetallicRoughness", {{"baseColorFactor", {0.5, 0.25, 1.0, 1.0}}}},
                          {"emissiveFactor", {1.0, 0.5, 0.0}},
                          {"extensions", {{"KHR_materials_emissive_strength", {{"emissiveStrength", 4.0}}}}}}};
  g.json["meshes"][0]["primitives"][0]["material"] = 0;
  g.json["extensionsUsed"] = {"KHR_lights_punctual", "KHR_materials_emissive_strength"};
  g.json["extensions"]["KHR_lights_punctual"]["lights"] = {{{"type", "spot"}, {"spot", nlohmann::json::object()}},
                                                           {{"type", "directional"}, {"intensity", 3.0}}};
  g.json["nodes"][0]["extras"] = {{"probebake", {{"dynamic", true}}}};
  g.json["nodes"][0]["children"] = {1, 2};
  g.json["nodes"].push_back({{"translation", {0, 2, 0}}, {"extensions", {{"KHR_lights_punctual", {{"light", 0}}}}}});
  g.json["nodes"].push_back({{"extensions", {{"KHR_lights_punctual", {{"light", 1}}}}}});
  const scene::Scene s = load_glb(g, "materials");
  EXPECT_EQ(s.triangle_albedo[0], glm::vec3(0.5f, 0.25f, 1.0f));
  EXPECT_EQ(s.triangle_emission[0], glm::vec3(4.0f, 2.0f, 0.0f));
  ASSERT_EQ(s.lights.size(), 2u);
  EXPECT_EQ(s.lights[0].type, scene::LightType::spot);
  EXPECT_FLOAT_EQ(s.lights[0].intensity, 1.0f);                 // spec default
  EXPECT_NEAR(s.lights[0].outer_cone_angle, 0.7853982f, 1e-6f); // spec default pi/4
  EXPECT_EQ(s.lights[0].position, glm::vec3(0, 2, 0));
  EXPECT_EQ(s.lights[1].direction, glm::vec3(0, 0, -1));
  ASSERT_EQ(s.instances.size(), 1u);
  EXPECT_TRUE(s.instances[0].dynamic);
  const scene::SceneSummary summary = scene::summarize(s);
  EXPECT_EQ(summary.emissive_triangles, 2u);
  EXPECT_NEAR(summary.emissive_area, 1.0, 1e-9);
}

std::vector<unsigned char> encode_draco_quad() {
  draco::TriangleSoupMeshBuilder builder;
  builder.Start(2);
  const int pos = builder.AddAttribute(draco::GeometryAttribute::POSITION, 3, draco::DT_FLOAT32);
  for (int f = 0; f < 2; ++f) {
    const glm::vec3 a = kQuad[kQuadIndices[3 * f]], b = kQuad[kQuadIndices[3 * f + 1]],
                    c = kQuad[kQuadIndices[3 * f + 2]];
    builder.SetAttributeValuesForFace(pos, draco::FaceIndex(f), &a.x, &b.x, &c.x);
  }
  std::unique_ptr<draco::Mesh> mesh = builder.Finalize();
  draco::Encoder encoder;
  encoder.SetAttributeQuantization(draco::GeometryAttribute::POSITION, 14);
  draco::EncoderBuffer buffer;
  EXPECT_TRUE(encoder.EncodeMeshToBuffer(*mesh, &buffer).ok());
  return {buffer.data(), buffer.data() + buffer.size()};
}

MiniGltf draco_quad(const std::vector<unsigned char>& payload) {
  MiniGltf g = MiniGltf::triangles(kQuad, {});
  g.bin.clear();
  g.json["bufferViews"] = nlohmann::json::array();
  const int view = g.add_view(payload.data(), payload.size());
  g.json["accessors"] = {
      {{"componentType", 5126}, {"count", 4}, {"type", "VEC3"}, {"min", {0, 0, 0}}, {"max", {1, 1, 0}}},
      {{"componentType", 5125}, {"count", 6}, {"type", "SCALAR"}}};
  g.json["meshes"][0]["primitives"][0] = {
      {"attributes", {{"POSITION", 0}}},
      {"indices", 1},
      {"extensions", {{"KHR_draco_mesh_compression", {{"bufferView", view}, {"attributes", {{"POSITION", 0}}}}}}}};
  g.json["extensionsUsed"] = {"KHR_draco_mesh_compression"};
  g.json["extensionsRequired"] = {"KHR_draco_mesh_compression"};
  return g;
}

TEST(Loader, DracoPrimitiveDecodesToTheSameTriangles) {
  const scene::Scene s = load_glb(draco_quad(encode_draco_quad()), "draco");
  ASSERT_EQ(s.triangle_count(), 2u);
  EXPECT_NEAR(s.bounds.max.x, 1.0f, 1e-3f);
  EXPECT_EQ(scene::summarize(s).degenerate_triangles, 0u);
  double area = 0.0;
  for (std::size_t t = 0; t < 2; ++t) area += scene::triangle_area(s, t);
  EXPECT_NEAR(area, 1.0, 1e-3);
}

TEST(RayScene, HitsFrontAndBackFaces) {
  const scene::Scene s = load_glb(MiniGltf::triangles(kQuad, kQuadIndices), "rays");
  const scene::RayScene rays(s);
  auto front = rays.intersect({0.25f, 0.5f, 2.0f}, {0, 0, -1});
  ASSERT_TRUE(front.has_value());
  EXPECT_FLOAT_EQ(front->distance, 2.0f);
  EXPECT_FALSE(front->backface);
  auto back = rays.intersect({0.25f, 0.5f, -1.0f}, {0, 0, 1});
  ASSERT_TRUE(back.has_value());
  EXPECT_TRUE(back->backface);
  EXPECT_FALSE(rays.intersect({5, 5, 1}, {0, 0, -1}).has_value());
  EXPECT_TRUE(rays.occluded({0.5f, 0.5f, 1}, {0, 0, -1}, 0.0f, 2.0f));
  EXPECT_FALSE(rays.occluded({0.5f, 0.5f, 1}, {0, 0, -1}, 0.0f, 0.5f));
}

} // namespace
} // namespace probebake::test
