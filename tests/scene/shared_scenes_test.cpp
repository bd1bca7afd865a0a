// The real third-party scenes of ../shared/scenes (when present, as in CI): triangle counts and bounds as
// listed in its README, and each Draco twin equal to its plain scene within quantization.
#include <fstream>
#include <map>
#include <regex>
#include <sstream>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include "probebake/scene/scene.h"

namespace probebake::test {
namespace {

const std::filesystem::path kScenes = PROBEBAKE_SHARED_SCENES;

struct SceneRow {
  std::string folder, file;
  std::size_t triangles = 0;
  bool has_bounds = false;
  glm::vec3 min{0.0f}, max{0.0f};
};

// Rows of the README table: | scene | file | source | license | tris | lights | textures | Draco | bbox |
std::vector<SceneRow> readme_rows() {
  std::ifstream in(kScenes / "README.md");
  std::vector<SceneRow> rows;
  const std::regex bbox(R"(\(([-\d.]+),([-\d.]+),([-\d.]+)\)\.\.\(([-\d.]+),([-\d.]+),([-\d.]+)\))");
  for (std::string line; std::getline(in, line);) {
    std::vector<std::string> cells;
    std::stringstream ss(line);
    for (std::string cell; std::getline(ss, cell, '|');) cells.push_back(cell);
    if (cells.size() < 10) continue;
    auto trim = [](std::string s) {
      s.erase(0, s.find_first_not_of(' '));
      s.erase(s.find_last_not_of(' ') + 1);
      return s;
    };
    SceneRow row{trim(cells[1]), trim(cells[2])};
    if (row.folder == "scene" || row.folder.starts_with("---")) continue;
    row.file = row.file.substr(0, row.file.find(' '));
    row.triangles = std::stoul(trim(cells[5]));
    std::smatch m;
    const std::string box = cells[9];
    if (std::regex_search(box, m, bbox)) {
      row.has_bounds = true;
      row.min = {std::stof(m[1]), std::stof(m[2]), std::stof(m[3])};
      row.max = {std::stof(m[4]), std::stof(m[5]), std::stof(m[6])};
    } else if (box.find("unit cube") != std::string::npos) {
      row.has_bounds = true;
      row.min = glm::vec3(-0.5f);
      row.max = glm::vec3(0.5f);
    }
    rows.push_back(row);
  }
  return rows;
}

std::filesystem::path scene_file(const SceneRow& row) {
  for (const auto& entry : std::filesystem::directory_iterator(kScenes / row.folder)) {
    const auto ext = entry.path().extension();
    if (ext == ".gltf" || ext == ".glb") return entry.path();
  }
  return {};
}

class SharedScenes : public ::testing::Test {
protected:
  void SetUp() override {
    if (!std::filesystem::exists(kScenes / "README.md")) GTEST_SKIP() << "no ../shared/scenes here";
  }
};

TEST_F(SharedScenes, TriangleCountsAndBoundsMatchTheReadme) {
  const auto rows = readme_rows();
  ASSERT_GE(rows.size(), 7u);
  for (const SceneRow& row : rows) {
    const scene::Scene s = scene::load_scene(scene_file(row));
    EXPECT_EQ(s.triangle_count(), row.triangles) << row.folder;
    if (!row.has_bounds) continue;
    const float tolerance = 0.01f * glm::length(row.max - row.min); // the README rounds its bounds
    for (int a = 0; a < 3; ++a) {
      EXPECT_NEAR(s.bounds.min[a], row.min[a], tolerance) << row.folder << " axis " << a;
      EXPECT_NEAR(s.bounds.max[a], row.max[a], tolerance) << row.folder << " axis " << a;
    }
  }
}

std::vector<glm::vec3> centroids(const scene::Scene& s) {
  std::vector<glm::vec3> c;
  for (const auto& t : s.triangles) c.push_back((s.positions[t.x] + s.positions[t.y] + s.positions[t.z]) / 3.0f);
  return c;
}

TEST_F(SharedScenes, DracoTwinsEqualTheirPlainScenes) {
  const std::map<std::string, std::string> twins = {{"cornell_box_draco", "cornell_box"},
                                                    {"cornellbox_bjs_draco", "cornellbox_bjs"}};
  const auto rows = readme_rows();
  auto find = [&](const std::string& folder) {
    for (const auto& r : rows)
      if (r.folder == folder) return scene_file(r);
    return std::filesystem::path{};
  };
  for (const auto& [draco_name, plain_name] : twins) {
    const scene::Scene draco = scene::load_scene(find(draco_name));
    const scene::Scene plain = scene::load_scene(find(plain_name));
    ASSERT_EQ(draco.triangle_count(), plain.triangle_count()) << draco_name;
    // Draco quantizes positions (14 bits by default in gltf-transform): 2^-12 of the extent is generous.
    const float tolerance = glm::length(plain.bounds.max - plain.bounds.min) / 4096.0f;
    const auto a = centroids(draco), b = centroids(plain);
    std::size_t unmatched = 0;
    for (const glm::vec3& p : a) {
      float best = 1e30f;
      for (const glm::vec3& q : b) best = std::min(best, glm::length(p - q));
      unmatched += best > tolerance ? 1 : 0;
    }
    EXPECT_EQ(unmatched, 0u) << draco_name << " tolerance " << tolerance;
    double area_a = 0, area_b = 0;
    for (std::size_t t = 0; t < a.size(); ++t) {
      area_a += scene::triangle_area(draco, t);
      area_b += scene::triangle_area(plain, t);
    }
    EXPECT_NEAR(area_a, area_b, 1e-3 * area_b) << draco_name;
  }
}

} // namespace
} // namespace probebake::test
