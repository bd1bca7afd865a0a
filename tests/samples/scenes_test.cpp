// Every scene kind: written .glb loads back through tinygltf with the expected triangles, materials,
// lights and bounds; output is deterministic.
#include "probebake/samples/scenes.h"

#include "gltf_readback.h"

#include <gtest/gtest.h>
#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iterator>

namespace ps = probebake::samples;
namespace pt = probebake::samples::test;

namespace {

struct Loaded {
  tinygltf::Model model;
  std::vector<pt::WorldTriangle> triangles;
};

Loaded load(const ps::SceneBuilder& scene) {
  std::string error;
  Loaded loaded{pt::load_glb(scene.to_glb(), error), {}};
  EXPECT_TRUE(error.empty()) << error;
  loaded.triangles = pt::world_triangles(loaded.model);
  return loaded;
}

const tinygltf::Material& material_named(const tinygltf::Model& model, const std::string& name) {
  const auto it =
      std::find_if(model.materials.begin(), model.materials.end(), [&](const auto& m) { return m.name == name; });
  if (it == model.materials.end()) throw std::runtime_error("no material " + name);
  return *it;
}

// Emitted radiance as a glTF reader computes it: emissiveFactor * KHR_materials_emissive_strength.
glm::dvec3 emission_of(const tinygltf::Material& m) {
  double strength = 1.0;
  const auto ext = m.extensions.find("KHR_materials_emissive_strength");
  if (ext != m.extensions.end()) strength = ext->second.Get("emissiveStrength").GetNumberAsDouble();
  return glm::dvec3(m.emissiveFactor[0], m.emissiveFactor[1], m.emissiveFactor[2]) * strength;
}

void expect_bounds(const std::vector<pt::WorldTriangle>& triangles, glm::vec3 min, glm::vec3 max, float tolerance) {
  const pt::WorldBounds b = pt::bounds_of(triangles);
  for (int i = 0; i < 3; ++i) {
    EXPECT_NEAR(b.min[i], min[i], tolerance) << "min axis " << i;
    EXPECT_NEAR(b.max[i], max[i], tolerance) << "max axis " << i;
  }
}

std::vector<pt::WorldTriangle> of_node(const std::vector<pt::WorldTriangle>& all, const std::string& node) {
  std::vector<pt::WorldTriangle> out;
  std::copy_if(all.begin(), all.end(), std::back_inserter(out), [&](const auto& t) { return t.node == node; });
  return out;
}

} // namespace

TEST(Cornell, ClassicBox) {
  const Loaded s = load(ps::cornell());
  EXPECT_EQ(s.triangles.size(), 32u);
  EXPECT_EQ(s.model.materials.size(), 4u);
  EXPECT_TRUE(s.model.lights.empty());
  expect_bounds(s.triangles, {-0.278f, 0.0f, -0.2796f}, {0.278f, 0.5488f, 0.2796f}, 1e-6f);
  const glm::dvec3 light = emission_of(material_named(s.model, "light"));
  EXPECT_NEAR(light.r, 17.0, 1e-9);
  EXPECT_NEAR(light.g, 12.0, 1e-9);
  EXPECT_NEAR(light.b, 4.0, 1e-9);
  EXPECT_NEAR(material_named(s.model, "red").pbrMetallicRoughness.baseColorFactor[0], 0.63, 1e-9);
  const glm::vec3 centre(0.0f, 0.2744f, 0.0f);
  for (const char* surface : {"floor", "ceiling", "back_wall", "red_wall", "green_wall", "light"}) {
    const auto triangles = of_node(s.triangles, surface);
    ASSERT_EQ(triangles.size(), 2u) << surface;
    for (const auto& t : triangles)
      EXPECT_GT(glm::dot(t.normal(), centre - t.centroid()), 0.0f) << surface << " faces the room";
  }
  EXPECT_LT(of_node(s.triangles, "red_wall")[0].centroid().x, -0.27f);  // red on the left (-X)
  EXPECT_GT(of_node(s.triangles, "green_wall")[0].centroid().x, 0.27f); // green on the right (+X)
  EXPECT_LT(of_node(s.triangles, "light")[0].normal().y, -0.99f);       // shines down
  EXPECT_EQ(of_node(s.triangles, "tall_block").size(), 10u);
  EXPECT_EQ(of_node(s.triangles, "short_block").size(), 10u);
}

TEST(Cornell, BlocksFaceOutward) {
  const Loaded s = load(ps::cornell());
  for (const char* block : {"short_block", "tall_block"}) {
    const auto triangles = of_node(s.triangles, block);
    glm::vec3 centre(0.0f);
    for (const auto& t : triangles) centre += t.centroid() / static_cast<float>(triangles.size());
    for (const auto& t : triangles) EXPECT_GT(glm::dot(t.normal(), t.centroid() - centre), 0.0f) << block;
  }
}

TEST(Cornell, WithModelReplacesTheTallBlock) {
  const auto folder = pt::fresh_folder("cornell_with");
  ps::SceneBuilder model("model");
  const ps::MaterialId m = model.add_material({"blue", {0.1f, 0.2f, 0.9f}, {}});
  ps::Transform far_away;
  far_away.translation = {10.0f, 5.0f, -3.0f};
  model.add_mesh_node("pillar", model.add_mesh("pillar", ps::box({-1, 0, -1}, {1, 4, 1}, ps::Facing::outward), m),
                      far_away);
  model.write_glb(folder / "pillar.glb");

  ps::CornellOptions options;
  options.with_model = folder / "pillar.glb";
  const Loaded s = load(ps::cornell(options));
  EXPECT_TRUE(of_node(s.triangles, "tall_block").empty());
  const auto placed = of_node(s.triangles, "model");
  ASSERT_EQ(placed.size(), 12u);
  EXPECT_EQ(s.triangles.size(), 34u);
  // Height limits the fit: 4 m -> 60% of the 0.5488 m box, standing on the floor, centred.
  expect_bounds(placed, {-0.08232f, 0.0f, -0.08232f}, {0.08232f, 0.6f * 0.5488f, 0.08232f}, 1e-5f);
  EXPECT_NEAR(material_named(s.model, "blue").pbrMetallicRoughness.baseColorFactor[2], 0.9, 1e-6);
}

TEST(Cornell, WithUnreadableModelIsAnInputError) {
  const auto folder = pt::fresh_folder("cornell_bad");
  std::ofstream(folder / "junk.glb") << "glTF but not really";
  for (const auto& path : {folder / "missing.glb", folder / "junk.glb", folder}) {
    ps::CornellOptions options;
    options.with_model = path;
    try {
      (void)ps::cornell(options);
      ADD_FAILURE() << "no error for " << path;
    } catch (const probebake::Error& e) {
      EXPECT_EQ(e.kind(), probebake::ErrorKind::input) << e.what();
    }
  }
}

namespace {

probebake::ErrorKind import_error(const std::filesystem::path& path) {
  ps::SceneBuilder scene;
  try {
    (void)scene.add_model(path, "model");
  } catch (const probebake::Error& e) {
    return e.kind();
  }
  return probebake::ErrorKind::internal; // "no error" marker: never what an import reports
}

} // namespace

// Only the whole file may load; every prefix is refused as unreadable input, without crashing.
TEST(ModelImport, EveryTruncationIsRefused) {
  const auto folder = pt::fresh_folder("import_prefixes");
  const std::vector<std::uint8_t> bytes = ps::triangle().to_glb();
  for (std::size_t length = 0; length < bytes.size(); ++length) {
    std::ofstream(folder / "cut.glb", std::ios::binary)
        .write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(length));
    EXPECT_EQ(import_error(folder / "cut.glb"), probebake::ErrorKind::input) << "length " << length;
  }
}

TEST(ModelImport, AccessorPastItsBufferIsRefused) {
  const auto folder = pt::fresh_folder("import_bad_accessor");
  std::vector<std::uint8_t> bytes = ps::triangle().to_glb();
  std::string text(bytes.begin(), bytes.end());
  const std::size_t at = text.find("\"count\":3"); // the POSITION accessor
  ASSERT_NE(at, std::string::npos);
  text[at + 8] = '9';
  std::ofstream(folder / "bad.glb", std::ios::binary) << text;
  EXPECT_EQ(import_error(folder / "bad.glb"), probebake::ErrorKind::input);
}

TEST(Cornell, WithDracoModelFromSharedScenes) {
  const std::filesystem::path draco = std::filesystem::path(PROBEBAKE_SHARED_SCENES) / "box_draco" / "Box_Draco.glb";
  if (!std::filesystem::exists(draco)) GTEST_SKIP() << "shared scenes not available";
  ps::CornellOptions options;
  options.with_model = draco;
  const Loaded s = load(ps::cornell(options));
  EXPECT_EQ(of_node(s.triangles, "model").size(), 12u);
}

TEST(Furnace, ClosedInwardBox) {
  for (int subdivisions : {1, 3}) {
    ps::FurnaceOptions options;
    options.albedo = 0.99f;
    options.emission = 5.0f;
    options.subdivisions = subdivisions;
    const Loaded s = load(ps::furnace(options));
    EXPECT_EQ(s.triangles.size(), static_cast<std::size_t>(12 * subdivisions * subdivisions));
    EXPECT_TRUE(pt::is_closed_and_oriented(s.triangles));
    for (const auto& t : s.triangles) EXPECT_LT(glm::dot(t.normal(), t.centroid()), 0.0f) << "faces inward";
    expect_bounds(s.triangles, glm::vec3(-0.5f), glm::vec3(0.5f), 0.0f);
    ASSERT_EQ(s.model.materials.size(), 1u);
    EXPECT_NEAR(s.model.materials[0].pbrMetallicRoughness.baseColorFactor[1], 0.99, 1e-9);
    EXPECT_NEAR(emission_of(s.model.materials[0]).g, 5.0, 1e-9);
    EXPECT_TRUE(s.model.lights.empty());
  }
}

TEST(Furnace, EmissionEncoding) {
  for (float emission : {0.0f, 1e-6f, 0.5f, 1.0f, 2.0f, 1e6f}) {
    ps::FurnaceOptions options;
    options.emission = emission;
    const Loaded s = load(ps::furnace(options));
    const tinygltf::Material& m = s.model.materials.at(0);
    const bool uses_strength = m.extensions.count("KHR_materials_emissive_strength") != 0;
    EXPECT_EQ(uses_strength, emission > 1.0f) << emission;
    for (double f : m.emissiveFactor) EXPECT_LE(f, 1.0);
    EXPECT_NEAR(emission_of(m).r, emission, 1e-6 * std::max(1.0f, emission));
    const bool listed = std::count(s.model.extensionsUsed.begin(), s.model.extensionsUsed.end(),
                                   "KHR_materials_emissive_strength") == 1;
    EXPECT_EQ(listed, uses_strength);
  }
}

TEST(Leak, TwoClosedRoomsAndOneLight) {
  ps::LeakOptions options;
  options.wall_thickness = 0.02f;
  const Loaded s = load(ps::leak(options));
  EXPECT_EQ(s.triangles.size(), 24u);
  const auto lit = of_node(s.triangles, "room_lit");
  const auto dark = of_node(s.triangles, "room_dark");
  EXPECT_TRUE(pt::is_closed_and_oriented(lit));
  EXPECT_TRUE(pt::is_closed_and_oriented(dark));
  EXPECT_NEAR(pt::bounds_of(dark).min.x - pt::bounds_of(lit).max.x, 0.02f, 1e-6f); // the wall
  ASSERT_EQ(s.model.lights.size(), 1u);
  EXPECT_EQ(s.model.lights[0].type, "point");
  const auto light_node =
      std::find_if(s.model.nodes.begin(), s.model.nodes.end(), [](const auto& n) { return n.name == "light"; });
  ASSERT_NE(light_node, s.model.nodes.end());
  EXPECT_LT(light_node->translation.at(0), pt::bounds_of(lit).max.x);
  EXPECT_GT(light_node->translation.at(0), pt::bounds_of(lit).min.x);
  expect_bounds(s.triangles, {-3.01f, 0.0f, -1.5f}, {3.01f, 2.5f, 1.5f}, 1e-6f);
}

TEST(PlaneLight, PlaneAndPointLight) {
  ps::PlaneLightOptions options;
  options.size = 4.0f;
  options.height = 2.0f;
  options.intensity = 50.0f;
  const Loaded s = load(ps::plane_light(options));
  EXPECT_EQ(s.triangles.size(), 2u);
  for (const auto& t : s.triangles) EXPECT_NEAR(t.normal().y, 1.0f, 1e-6f);
  expect_bounds(s.triangles, {-2.0f, 0.0f, -2.0f}, {2.0f, 0.0f, 2.0f}, 0.0f);
  ASSERT_EQ(s.model.lights.size(), 1u);
  EXPECT_EQ(s.model.lights[0].intensity, 50.0);
  const auto& node = s.model.nodes.at(1);
  EXPECT_EQ(node.translation, (std::vector<double>{0.0, 2.0, 0.0}));
  EXPECT_EQ(node.extensions.at("KHR_lights_punctual").Get("light").GetNumberAsInt(), 0);
}

TEST(Rooms, LargeDeterministicScene) {
  const ps::SceneBuilder scene = ps::rooms();
  const std::vector<std::uint8_t> bytes = scene.to_glb();
  EXPECT_EQ(bytes, ps::rooms().to_glb());
  std::string error;
  const tinygltf::Model model = pt::load_glb(bytes, error);
  ASSERT_TRUE(error.empty()) << error;
  const auto triangles = pt::world_triangles(model);
  EXPECT_GE(triangles.size(), 500000u);
  EXPECT_EQ(triangles.size(), scene.triangle_count());
  EXPECT_EQ(triangles.size(), 16u * (7844u + 72u * 20u * 20u) + 2u * 6u);
  EXPECT_EQ(model.lights.size(), 16u);
  EXPECT_EQ(pt::dynamic_node_names(model).size(), 16u);
  EXPECT_NE(ps::rooms({16, 20, 2}).to_glb(), bytes); // the seed matters
}

TEST(Rooms, SmallGridBounds) {
  const Loaded s = load(ps::rooms({4, 2, 7}));
  EXPECT_EQ(s.triangles.size(), 4u * (7844u + 72u * 4u) + 2u * 2u);
  expect_bounds(s.triangles, {-3.0f, 0.0f, -3.0f}, {9.2f, 3.0f, 9.2f}, 1e-5f);
}

// --windows: three rooms on a 2 x 2 grid (rooms 0 and 1 in the first row, room 2 alone in the second) get a 3 x 1 m
// window in each wall that faces out of the grid: 2 + 3 + 3 of them, 192 triangles each.
TEST(Rooms, WindowsOpenOnlyTheOuterWalls) {
  ps::RoomsOptions options{3, 2, 7};
  const std::size_t closed = load(ps::rooms(options)).triangles.size();
  options.windows = true;
  const Loaded s = load(ps::rooms(options));
  EXPECT_EQ(closed, 3u * (7844u + 72u * 4u) + 2u);
  EXPECT_EQ(s.triangles.size(), closed - 8u * 192u);
  // Room 0's wall cells whose centre is in the window rectangle of a wall plane (x or z = `at`).
  const auto in_window = [&](bool x_plane, float at) {
    return std::count_if(s.triangles.begin(), s.triangles.end(), [&](const pt::WorldTriangle& t) {
      const glm::vec3 c = t.centroid();
      const float plane = x_plane ? c.x : c.z, along = x_plane ? c.z : c.x;
      return std::abs(plane - at) < 1e-4f && std::abs(along) < 1.5f && c.y > 1.0f && c.y < 2.0f;
    });
  };
  EXPECT_EQ(in_window(false, -3.0f), 0); // -Z: the grid's edge
  EXPECT_EQ(in_window(true, -3.0f), 0);  // -X: the grid's edge
  EXPECT_EQ(in_window(true, 3.0f), 192); // +X: room 1 is beside it
}

TEST(EdgeCases, OneTriangle) {
  const Loaded s = load(ps::triangle());
  ASSERT_EQ(s.triangles.size(), 1u);
  EXPECT_NEAR(s.triangles[0].normal().y, 1.0f, 1e-6f);
  EXPECT_EQ(s.model.lights.size(), 1u);
}

TEST(EdgeCases, EmptyScene) {
  const Loaded s = load(ps::empty());
  EXPECT_TRUE(s.triangles.empty());
  EXPECT_TRUE(s.model.meshes.empty());
  EXPECT_TRUE(s.model.buffers.empty());
  ASSERT_EQ(s.model.scenes.size(), 1u);
  EXPECT_EQ(s.model.asset.version, "2.0");
}

TEST(Determinism, EveryKindTwiceSameBytes) {
  EXPECT_EQ(ps::cornell().to_glb(), ps::cornell().to_glb());
  EXPECT_EQ(ps::furnace().to_glb(), ps::furnace().to_glb());
  EXPECT_EQ(ps::leak().to_glb(), ps::leak().to_glb());
  EXPECT_EQ(ps::plane_light().to_glb(), ps::plane_light().to_glb());
  EXPECT_EQ(ps::triangle().to_glb(), ps::triangle().to_glb());
  EXPECT_EQ(ps::empty().to_glb(), ps::empty().to_glb());
}

TEST(Builder, DynamicFlagAndPlacement) {
  ps::SceneBuilder scene = ps::triangle();
  scene.set_dynamic(ps::NodeId{0});
  ps::Transform placement;
  placement.scale = glm::vec3(1000.0f);
  placement.translation = glm::vec3(1e6f, 0.0f, 0.0f);
  scene.wrap_roots("placement", placement);
  const Loaded s = load(scene);
  EXPECT_EQ(pt::dynamic_node_names(s.model), std::vector<std::string>{"triangle"});
  expect_bounds(s.triangles, {1e6f, 0.0f, -1000.0f}, {1e6f + 1000.0f, 0.0f, 0.0f}, 0.1f);
  EXPECT_EQ(scene.bounds().max.x, 1e6f + 1000.0f);
}

TEST(Builder, SpotAndDirectionalLightsPointAlongTheirDirection) {
  ps::SceneBuilder scene("lights");
  ps::Light spot;
  spot.type = ps::LightType::spot;
  spot.inner_cone_angle = 0.2f;
  spot.outer_cone_angle = 0.5f;
  ps::Light sun;
  sun.type = ps::LightType::directional;
  sun.intensity = 2000.0f;
  scene.add_light_node("spot", scene.add_light(spot), {0, 2, 0}, {1, 0, 0});
  scene.add_light_node("sun", scene.add_light(sun), {0, 0, 0}, {0, 0, 1}); // opposite to glTF's -Z
  const Loaded s = load(scene);
  ASSERT_EQ(s.model.lights.size(), 2u);
  EXPECT_EQ(s.model.lights[0].type, "spot");
  EXPECT_NEAR(s.model.lights[0].spot.outerConeAngle, 0.5, 1e-7);
  EXPECT_EQ(s.model.lights[1].type, "directional");
  for (std::size_t i = 0; i < 2; ++i) {
    const auto& r = s.model.nodes[i].rotation;
    ASSERT_EQ(r.size(), 4u);
    const glm::quat q(static_cast<float>(r[3]), static_cast<float>(r[0]), static_cast<float>(r[1]),
                      static_cast<float>(r[2]));
    const glm::vec3 shines = q * glm::vec3(0, 0, -1);
    EXPECT_NEAR(glm::dot(shines, i == 0 ? glm::vec3(1, 0, 0) : glm::vec3(0, 0, 1)), 1.0f, 1e-5f);
  }
}

TEST(Builder, RejectsBadInput) {
  auto kind_of = [](auto&& make) {
    try {
      (void)make();
    } catch (const probebake::Error& e) {
      return e.kind();
    }
    return probebake::ErrorKind::internal; // "no error" marker: never thrown here
  };
  EXPECT_EQ(kind_of([] { return ps::furnace({1.5f, 1.0f, 1.0f, 1}); }), probebake::ErrorKind::usage);
  EXPECT_EQ(kind_of([] { return ps::furnace({0.5f, std::nanf(""), 1.0f, 1}); }), probebake::ErrorKind::usage);
  EXPECT_EQ(kind_of([] { return ps::furnace({0.5f, -1.0f, 1.0f, 1}); }), probebake::ErrorKind::usage);
  EXPECT_EQ(kind_of([] { return ps::rooms({0, 20, 1}); }), probebake::ErrorKind::usage);
  EXPECT_EQ(kind_of([] { return ps::leak({0.0f, 100.0f, 1}); }), probebake::ErrorKind::usage);
  EXPECT_EQ(kind_of([] {
              ps::SceneBuilder s;
              return s.add_mesh("nothing", ps::MeshData{}, s.add_material({}));
            }),
            probebake::ErrorKind::usage);
}

TEST(Output, AtomicWriteAndUnwritablePath) {
  const auto folder = pt::fresh_folder("output");
  const ps::SceneBuilder scene = ps::furnace();
  scene.write_glb(folder / "furnace.glb");
  EXPECT_EQ(pt::read_file(folder / "furnace.glb"), scene.to_glb());
  scene.write_glb(folder / "furnace.glb"); // replaces an existing file
  EXPECT_EQ(std::distance(std::filesystem::directory_iterator(folder), std::filesystem::directory_iterator()), 1);
  try {
    scene.write_glb(folder / "no" / "such" / "folder.glb");
    ADD_FAILURE() << "no error";
  } catch (const probebake::Error& e) {
    EXPECT_EQ(e.kind(), probebake::ErrorKind::output);
  }
}
