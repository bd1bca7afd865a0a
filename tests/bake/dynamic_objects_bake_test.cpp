// Dynamic objects in the loader and the bake (format 1.3): nodes marked by glTF extras or by name become
// objects whose triangles the bake stores in their own frame, with their own BVH, after the static ones;
// at rest they are exactly the scene's triangles; posed scenes move only them.
#include <algorithm>
#include <vector>

#include <gtest/gtest.h>
#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include "bake_test_util.h"
#include "probebake/bake/gpu_scene.h"
#include "probebake/dynamic/animation.h"
#include "probebake/formats/error.h"
#include "probebake/formats/probes_file.h"
#include "probebake/formats/trace_mesh.h"
#include "probebake/formats/validate.h"
#include "probebake/samples/scenes.h"

namespace probebake::test {
namespace {

samples::SceneBuilder dynamic_cornell() {
  samples::CornellOptions options;
  options.dynamic = true;
  return samples::cornell(options);
}

formats::ProbeVolume bake_volume(const scene::Scene& scene) {
  bake::BakeSettings settings = test_settings();
  return bake::bake(scene, settings).volume;
}

// World-space corners of a stored face under a pose.
std::array<glm::vec3, 3> corners(const formats::ProbeVolume& v, std::size_t face, const glm::mat4& pose) {
  std::array<glm::vec3, 3> out;
  for (int k = 0; k < 3; ++k) {
    const gpu::TraceVertex& p = v.trace_vertices[v.trace_faces[face].vertex[k]];
    out[std::size_t(k)] = glm::vec3(pose * glm::vec4(p.x, p.y, p.z, 1.0f));
  }
  return out;
}

// The scene triangle whose corners are within 1e-5 of `world`, or -1.
int scene_triangle_at(const scene::Scene& scene, const std::array<glm::vec3, 3>& world) {
  for (std::size_t t = 0; t < scene.triangles.size(); ++t) {
    bool same = true;
    for (int k = 0; k < 3; ++k)
      same = same && glm::length(world[std::size_t(k)] - scene.positions[scene.triangles[t][k]]) < 1e-5f;
    if (same) return int(t);
  }
  return -1;
}

TEST(DynamicObjectsBake, BlocksAreObjectsWhoseRestTrianglesAreTheScenes) {
  const scene::Scene scene = load_generated(dynamic_cornell(), "cornell-dynamic");
  ASSERT_EQ(scene.dynamic_objects.size(), 2u); // short and tall block
  const formats::ProbeVolume v = bake_volume(scene);
  ASSERT_EQ(v.dynamic_objects.size(), 2u);
  EXPECT_TRUE(formats::validate(v).valid());
  int object_triangles = 0;
  for (const gpu::DynamicObject& o : v.dynamic_objects) {
    EXPECT_EQ(o.triangle_count, 10); // a block without its bottom face
    object_triangles += o.triangle_count;
    const glm::mat4 rest = dynamic::rest_pose(o);
    for (int t = o.first_triangle; t < o.first_triangle + o.triangle_count; ++t) {
      const int source = scene_triangle_at(scene, corners(v, std::size_t(t), rest));
      ASSERT_GE(source, 0) << t;
      const glm::vec3 normal = formats::face_geometry(v, std::size_t(t)).normal;
      EXPECT_LT(glm::length(glm::mat3(rest) * normal - scene::triangle_normal(scene, std::size_t(source))), 1e-5f);
    }
  }
  // The static tree holds the other triangles, the objects' trees follow it.
  EXPECT_EQ(v.dynamic_objects[0].first_triangle, int(scene.triangles.size()) - object_triangles);
  EXPECT_EQ(v.dynamic_objects[0].bvh_root, 1); // tree 1 + o
  EXPECT_EQ(v.dynamic_objects[1].bvh_root, 2);
  EXPECT_EQ(v.dynamic_objects[1].bvh_node_count, v.trace_trees[2].node_count);
  EXPECT_EQ(v.lighting->dynamic_objects, 2);
}

TEST(DynamicObjectsBake, RoundTripsAndStaticScenesHaveNoObjects) {
  const formats::ProbeVolume v = bake_volume(load_generated(dynamic_cornell(), "cornell-dynamic"));
  const std::vector<std::uint8_t> bytes = formats::write_probes(v);
  EXPECT_EQ(formats::parse_container(bytes, "dynamic").header.version_minor, formats::kEmitterGroupsMinor);
  const formats::ProbeVolume back = formats::read_probes(bytes, "dynamic");
  ASSERT_EQ(back.dynamic_objects.size(), 2u);
  EXPECT_EQ(formats::write_probes(back), bytes);
  // Without dynamic nodes: no objects, only the static tree.
  const formats::ProbeVolume plain = bake_volume(load_generated(samples::cornell(), "cornell-static"));
  EXPECT_TRUE(plain.dynamic_objects.empty());
  EXPECT_EQ(plain.trace_trees.size(), 1u);
}

TEST(DynamicObjectsBake, NodesNamedOnTheCommandLineAreDynamicAndUnknownNamesAreRefused) {
  const std::filesystem::path file = write_generated(samples::cornell(), "cornell-names");
  scene::LoadOptions options;
  options.dynamic_nodes = {"short_block"};
  const scene::Scene scene = scene::load_scene(file, options);
  ASSERT_EQ(scene.dynamic_objects.size(), 1u);
  EXPECT_EQ(scene.dynamic_objects[0].name, "short_block");
  options.dynamic_nodes = {"no_such_node"};
  try {
    scene::load_scene(file, options);
    FAIL() << "an unknown name was accepted";
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), ErrorKind::input);
    EXPECT_NE(std::string(e.what()).find("no_such_node"), std::string::npos) << e.what();
  }
}

TEST(DynamicObjectsBake, PosedScenesMoveOnlyTheObjects) {
  const scene::Scene scene = load_generated(dynamic_cornell(), "cornell-dynamic");
  std::vector<glm::mat4> poses;
  for (const scene::DynamicObject& o : scene.dynamic_objects)
    poses.push_back(glm::translate(glm::mat4(1.0f), glm::vec3(0.05f, 0.0f, 0.0f)) * o.world_from_object);
  const scene::Scene moved = scene::posed(scene, poses);
  std::vector<bool> in_object(scene.positions.size(), false);
  for (const scene::Instance& i : scene.instances)
    for (std::uint32_t t = i.first_triangle; t < i.first_triangle + i.triangle_count; ++t)
      for (int k = 0; k < 3; ++k) in_object[scene.triangles[t][k]] = i.dynamic_object >= 0;
  for (std::size_t p = 0; p < scene.positions.size(); ++p) {
    const glm::vec3 expected = scene.positions[p] + (in_object[p] ? glm::vec3(0.05f, 0.0f, 0.0f) : glm::vec3(0.0f));
    EXPECT_LT(glm::length(moved.positions[p] - expected), 1e-6f) << p;
  }
  EXPECT_THROW(scene::posed(scene, std::vector<glm::mat4>(1)), Error);
}

TEST(DynamicObjectsBake, EmissiveObjectsAreRefusedWhileEmittersAreAreaLights) {
  scene::LoadOptions options;
  options.dynamic_nodes = {"light"};
  const scene::Scene scene = scene::load_scene(write_generated(samples::cornell(), "cornell-emissive"), options);
  try {
    bake_volume(scene);
    FAIL() << "an emissive dynamic node was baked";
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), ErrorKind::input);
    EXPECT_NE(std::string(e.what()).find("emissive"), std::string::npos) << e.what();
  }
}

} // namespace
} // namespace probebake::test
