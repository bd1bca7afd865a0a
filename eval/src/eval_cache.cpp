// The reference of `probebake eval`, computed once per (scene, points, seed, paths) and cached beside the
// scene.
#include <fmt/core.h>
#include <xxhash.h>

#include "eval_internal.h"
#include "probebake/formats/error.h"

namespace probebake::bake {
namespace {

constexpr char kCacheVersion[] = "probebake-reference-2"; // bump when the estimator or the receivers change

class Hasher {
public:
  Hasher() : state_(XXH3_createState()) { XXH3_64bits_reset(state_); }
  ~Hasher() { XXH3_freeState(state_); }
  Hasher(const Hasher&) = delete;
  Hasher& operator=(const Hasher&) = delete;

  template <class T>
  void add(const std::vector<T>& v) {
    add_value(v.size());
    if (!v.empty()) XXH3_64bits_update(state_, v.data(), v.size() * sizeof(T));
  }
  template <class T>
  void add_value(const T& value) {
    XXH3_64bits_update(state_, &value, sizeof(T));
  }
  std::uint64_t digest() const { return XXH3_64bits_digest(state_); }

private:
  XXH3_state_t* state_;
};

// Where the player is: the camera's position, when there is one.
std::vector<glm::vec3> receiver_anchors(const EvalSettings& s) {
  if (!s.camera) return {};
  return {s.camera->position};
}

} // namespace

std::uint64_t reference_hash(const scene::Scene& scene, int points, std::uint64_t seed, int paths, ReceiverMode mode,
                             std::span<const glm::vec3> anchors) {
  Hasher h;
  h.add_value(sizeof(kCacheVersion));
  for (char c : kCacheVersion) h.add_value(c);
  h.add(scene.positions);
  h.add(scene.triangles);
  h.add(scene.triangle_albedo);
  h.add(scene.triangle_emission);
  // Which triangles are double-sided (glTF doubleSided): it changes the transport and the receivers.
  std::vector<std::uint8_t> double_sided(scene.triangles.size());
  for (std::size_t t = 0; t < double_sided.size(); ++t) double_sided[t] = scene::is_double_sided(scene, t) ? 1 : 0;
  h.add(double_sided);
  h.add_value(scene.lights.size());
  for (const scene::Light& l : scene.lights) { // field by field: the struct holds a name and padding
    h.add_value(int(l.type));
    h.add_value(l.color);
    h.add_value(l.intensity);
    h.add_value(l.position);
    h.add_value(l.direction);
    h.add_value(l.range);
    h.add_value(l.inner_cone_angle);
    h.add_value(l.outer_cone_angle);
  }
  h.add_value(scene.sky.colour); // what paths that leave the scene see
  h.add(scene.sky.map.texels);
  h.add_value(points);
  h.add_value(seed);
  h.add_value(paths);
  h.add_value(int(mode));
  h.add(std::vector<glm::vec3>(anchors.begin(), anchors.end()));
  return h.digest();
}

namespace detail {

std::filesystem::path reference_cache_path(const std::filesystem::path& scene_path, std::uint64_t hash) {
  return scene_path.parent_path() / fmt::format("{}.reference.{:016x}.csv", scene_path.filename().string(), hash);
}

ReferencePoints cached_reference(const std::filesystem::path& scene_path, const scene::Scene& scene,
                                 const scene::RayScene& rays, const EvalSettings& s) {
  ReferencePoints r;
  const std::vector<glm::vec3> anchors = receiver_anchors(s);
  r.cache_file =
      reference_cache_path(scene_path, reference_hash(scene, s.points, s.seed, s.paths, s.receivers, anchors));
  if (s.use_cache && read_reference_csv(r.cache_file, r.points, r.values) && !r.points.empty()) {
    r.from_cache = true;
    return r;
  }
  const Receivers receivers = make_receivers(
      scene, rays, {.mode = s.receivers, .count = s.points, .seed = s.seed, .anchors = anchors, .threads = s.threads});
  r.points = receivers.points;
  r.viewpoints = receivers.viewpoints;
  if (r.points.empty())
    throw Error(ErrorKind::input, fmt::format("{}: no visible surface to sample ({} receivers)", scene_path.string(),
                                              receiver_mode_name(s.receivers)));
  r.values = reference_irradiance(scene, rays, r.points, {.paths = s.paths, .seed = s.seed, .threads = s.threads});
  if (s.use_cache) {
    try {
      write_reference_csv(r.cache_file, r.points, r.values);
      r.cache_written = true;
    } catch (const Error&) {
      // A read-only scene folder only means the next run computes the reference again.
    }
  }
  return r;
}

} // namespace detail
} // namespace probebake::bake
