// Streaming cells (UploadOptions::streaming, issue #15) on generated closed rooms, under the validation
// layer: with every cell resident the volume lights exactly as the whole file does; with some resident, the
// probes whose cell and neighbouring cells are resident light exactly as the whole file does and the others
// keep the file's irradiance; along a camera path back and forth the resident bytes stay within the budget
// and the live state (every resident cell's block numbered back to the file's bytes) is valid every frame.
#include <algorithm>
#include <array>
#include <chrono>
#include <cstdio>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <optional>
#include <set>
#include <thread>
#include <utility>
#include <vector>

#include <glm/common.hpp>

#include "probebake/probe_index/lookup.h"
#include "probebake/formats/cell_file.h"
#include "probebake/formats/cells.h"
#include "probebake/formats/container.h"
#include "probebake/formats/probes_file.h"
#include "probebake/memory_types.h"
#include "probebake/runtime_types.h"
#include "probebake/samples/scenes.h"
#include "memory_reference.h"
#include "run_cli.h"
#include "runtime_test_util.h"

namespace probebake::test {
namespace {

class StreamingTest : public RuntimeTest {};

// Eight closed rooms (6.2 m with their walls) baked to max depth 5 in cells at least 6.5 m wide, so that the
// faces of a probe's room lie in its cell and the neighbouring ones.
const formats::ProbeVolume& streamed_rooms() {
  static const formats::ProbeVolume v = [] {
    bake::BakeSettings s;
    s.max_depth = 5;
    s.surfels_per_probe = 64;
    s.svo_depth = 5;
    s.lighting.rays = 64;
    s.cell_size = 6.5f;
    return bake_with(samples::rooms({.count = 8, .detail = 2}), "rooms8", s);
  }();
  return v;
}

std::uint64_t tracing_bytes_of_cells(const formats::ProbeVolume& v) {
  std::uint64_t total = 0;
  for (const formats::CellTracing& t : v.cell_tracing) total += formats::cell_tracing_bytes(t);
  return total;
}

// A frame that streamed every cell of `v` but record `refused`, which stream_refusals() names with `reason`.
void expect_one_refusal(runtime::Volume& volume, const runtime::FrameStats& frame, const formats::ProbeVolume& v,
                        std::size_t refused, const std::string& reason = "") {
  EXPECT_EQ(frame.streaming.refused_cells, 1);
  EXPECT_EQ(frame.streaming.loaded_cells, int(v.cells.size()) - 1);
  const std::vector<std::string> refusals = volume.stream_refusals();
  ASSERT_EQ(refusals.size(), 1u);
  EXPECT_NE(refusals[0].find("cells[" + std::to_string(refused) + "]"), std::string::npos) << refusals[0];
  EXPECT_NE(refusals[0].find(reason), std::string::npos) << refusals[0];
}

bool same_irradiance(const gpu::Probe& a, const gpu::Probe& b) {
  return std::memcmp(a.irradiance_sh, b.irradiance_sh, sizeof(a.irradiance_sh)) == 0;
}

runtime::UploadOptions streaming_options(std::uint64_t budget, std::uint64_t max_upload = 0, int max_joining = 0,
                                         int max_lit = 0) {
  runtime::UploadOptions options;
  options.streaming = {budget, max_upload, max_joining, 0.0f, max_lit};
  return options;
}

// `v` uploaded whole, and streamed with a budget of twice its cells' tracing bytes.
std::pair<runtime::Result<runtime::Volume>, runtime::Result<runtime::Volume>>
upload_whole_and_streamed(runtime::Context& context, const formats::ProbeVolume& v) {
  return {runtime::Volume::upload(context, v),
          runtime::Volume::upload(context, v, streaming_options(2 * tracing_bytes_of_cells(v)))};
}

// Where the middle byte of one of a cell's ranges lies in the file at `path`.
std::uint64_t file_offset_in(const std::string& path, formats::SectionType section, const formats::CellRange& range) {
  const formats::ContainerView view = formats::parse_container(formats::read_file_bytes(path), path);
  for (const formats::SectionEntry& e : view.sections)
    if (e.type == static_cast<std::uint32_t>(section)) return e.offset + range.byte_offset + range.byte_size / 2;
  return 0;
}

// Flips bits of one byte in place: a volume that keeps the file open reads the change (a new file written
// to the path would be another inode, which it does not read).
void flip_byte(const std::string& path, std::uint64_t offset, char bits) {
  std::fstream file(path, std::ios::in | std::ios::out | std::ios::binary);
  file.seekg(std::streamoff(offset));
  const char byte = char(file.get() ^ bits);
  file.seekp(std::streamoff(offset));
  file.put(byte);
}

TEST_F(StreamingTest, EveryCellResidentLightsExactlyAsTheWholeFile) {
  const formats::ProbeVolume& v = streamed_rooms();
  ASSERT_FALSE(v.cell_tracing.empty());
  auto [whole, streamed] = upload_whole_and_streamed(context(), v);
  ASSERT_TRUE(whole.ok()) << whole.status().message;
  ASSERT_TRUE(streamed.ok()) << streamed.status().message;
  ASSERT_TRUE(streamed.value().stream_around(glm::vec3(0.0f), 1e6f).ok());
  for (int f = 0; f < 3; ++f) {
    auto a = whole.value().run_frame();
    auto b = streamed.value().run_frame();
    ASSERT_TRUE(a.ok() && b.ok()) << b.status().message;
    EXPECT_EQ(b.value().light.lit_probes, a.value().light.lit_probes);
    if (f == 0) {
      EXPECT_EQ(b.value().streaming.resident_cells, int(v.cells.size()));
    }
  }
  ASSERT_TRUE(streamed.value().validate_live().ok()) << streamed.value().validate_live().message;
  auto a = whole.value().read_back(), b = streamed.value().read_back();
  ASSERT_TRUE(a.ok() && b.ok());
  for (std::size_t i = 0; i < v.probes.size(); ++i)
    ASSERT_TRUE(same_irradiance(a.value().probes[i], b.value().probes[i])) << "probe " << i;
}

TEST_F(StreamingTest, ResidentNeighbourhoodsLightExactlyAndTheRestKeepTheFilesIrradiance) {
  const formats::ProbeVolume& v = streamed_rooms();
  auto [whole, streamed] = upload_whole_and_streamed(context(), v);
  ASSERT_TRUE(whole.ok() && streamed.ok());
  // The camera at the first live probe, the radius about two cells.
  const auto first = std::find_if(v.probes.begin(), v.probes.end(), [](const gpu::Probe& p) { return p.link != 0; });
  ASSERT_NE(first, v.probes.end());
  const float cell = v.info.root_size / float(formats::cells_per_axis(v.cell_depth));
  ASSERT_TRUE(streamed.value().stream_around(first->position, 12.0f).ok());
  ASSERT_TRUE(whole.value().run_frame().ok());
  ASSERT_TRUE(streamed.value().run_frame().ok());
  const std::vector<int> resident = streamed.value().resident_cells();
  const std::set<int> resident_set(resident.begin(), resident.end());
  const int n = formats::cells_per_axis(v.cell_depth);
  // A room with its walls is 6.4 m wide: its faces lie within `reach` cells of any probe inside it.
  const int reach = int(std::ceil(6.4f / cell));
  const auto neighbourhood_resident = [&](int c) {
    const int x = c % n, y = c / n % n, z = c / (n * n);
    for (int dz = -reach; dz <= reach; ++dz)
      for (int dy = -reach; dy <= reach; ++dy)
        for (int dx = -reach; dx <= reach; ++dx) {
          const int cx = x + dx, cy = y + dy, cz = z + dz;
          if (cx < 0 || cy < 0 || cz < 0 || cx >= n || cy >= n || cz >= n) continue;
          const int neighbour = cx + n * (cy + n * cz);
          const bool has_record = std::any_of(v.cells.begin(), v.cells.end(),
                                              [&](const formats::Cell& r) { return r.cell_index == neighbour; });
          if (has_record && !resident_set.count(neighbour)) return false;
        }
    return true;
  };
  auto a = whole.value().read_back(), b = streamed.value().read_back();
  ASSERT_TRUE(a.ok() && b.ok());
  int exact = 0, kept = 0, between = 0, between_lit = 0;
  for (std::size_t i = 0; i < v.probes.size(); ++i) {
    if (v.probes[i].link == 0) continue;
    const int c = formats::cell_of_point(v.info, v.cell_depth, v.probes[i].position);
    if (!resident_set.count(c)) {
      ASSERT_TRUE(same_irradiance(b.value().probes[i], v.probes[i]))
          << "probe " << i << " of a cell out of range changed";
      ++kept;
    } else if (neighbourhood_resident(c)) {
      ASSERT_TRUE(same_irradiance(b.value().probes[i], a.value().probes[i])) << "probe " << i << " of cell " << c;
      ++exact;
    } else {
      // Beside cells that are out: lit exactly as the whole file when none of its rays crossed one, else it
      // keeps the file's irradiance (RECORD_SLOT_UNRESOLVED); never lit through a missing cell.
      const bool lit_exactly = same_irradiance(b.value().probes[i], a.value().probes[i]);
      ASSERT_TRUE(lit_exactly || same_irradiance(b.value().probes[i], v.probes[i]))
          << "probe " << i << " lit through a cell that is out";
      ++between;
      between_lit += lit_exactly ? 1 : 0;
    }
  }
  // Lookups at every live probe: a result says kSampleNotLit exactly when a probe of its SVO stencil is not
  // lit: it lies in a cell that is out, or it is unresolved (it kept the file's irradiance where the whole
  // file's changed). Every resident cell's probes have records here: no join limit.
  const auto not_lit_probe = [&](int p) {
    const std::size_t i = std::size_t(p);
    if (!resident_set.count(formats::cell_of_point(v.info, v.cell_depth, v.probes[i].position))) return true;
    return !same_irradiance(b.value().probes[i], a.value().probes[i]) &&
           same_irradiance(b.value().probes[i], v.probes[i]);
  };
  std::vector<glm::vec3> positions, normals;
  for (const gpu::Probe& p : v.probes)
    if (p.link != 0) positions.push_back(p.position), normals.push_back(glm::vec3(0.0f, 1.0f, 0.0f));
  std::vector<std::uint32_t> flags, whole_flags;
  runtime::SampleStats sampled, whole_sampled;
  ASSERT_TRUE(
      streamed.value().sample_irradiance(positions, normals, &sampled, runtime::SampleMethod::svo, &flags).ok());
  ASSERT_TRUE(whole.value()
                  .sample_irradiance(positions, normals, &whole_sampled, runtime::SampleMethod::svo, &whole_flags)
                  .ok());
  std::size_t expected_not_lit = 0;
  for (std::size_t i = 0; i < positions.size(); ++i) {
    const probe_index::BlendedLookup lookup = probe_index::blended_lookup(v, positions[i], normals[i]);
    bool out = false;
    for (int l = 0; l < lookup.count; ++l) {
      const probe_index::ProbeStencil s =
          probe_index::leaf_stencil(v, lookup.leaves[std::size_t(l)], positions[i], normals[i]);
      for (int k = 0; k < 4; ++k) out = out || (s.probes[k] >= 0 && not_lit_probe(s.probes[k]));
    }
    ASSERT_EQ((flags[i] & runtime::kSampleNotLit) != 0, out) << "lookup " << i;
    ASSERT_EQ(whole_flags[i] & runtime::kSampleNotLit, 0u) << "the whole file lights every probe";
    expected_not_lit += out ? 1 : 0;
  }
  EXPECT_EQ(sampled.not_lit, expected_not_lit);
  // The game's include reads the same slots (sample_irradiance.glsl, PROBEBAKE_BINDING_RECORD_SLOTS).
  EXPECT_EQ(streamed.value().buffers().record_slots.size, v.probes.size() * sizeof(std::int32_t));
  EXPECT_NE(streamed.value().buffers().record_slots.buffer, VK_NULL_HANDLE);
  EXPECT_EQ(whole.value().buffers().record_slots.buffer, VK_NULL_HANDLE) << "only with streaming";
  EXPECT_GT(sampled.not_lit, 0u);
  EXPECT_LT(sampled.not_lit, positions.size());
  std::printf("[streaming] %zu of %zu lookups at the probes say that a probe of theirs is not lit\n", sampled.not_lit,
              positions.size());
  std::printf("[streaming] %d live probes, cells of %.2f m: %zu of %zu cells resident: %d probes lit exactly as the "
              "whole file, %d kept the file's "
              "irradiance, %d beside cells that are out (%d of them lit as the whole file, the others unresolved)\n",
              live_probe_count(v), double(cell), resident.size(), v.cells.size(), exact, kept, between, between_lit);
  EXPECT_GT(exact, 0);
  EXPECT_GT(kept, 0);
}

// No seam between cells, with or without light_reach. Around one probe of the eight rooms, at radii from 4 to
// 20 m, each streamed volume runs one frame like the whole file: every probe is lit bit for bit as the whole
// file or keeps the file's irradiance. Without a reach, a probe whose rays cross a neighbouring cell that is
// out is left unresolved (bvh_trace.glsl's null leaves) and keeps its irradiance, where it used to be lit
// through the missing walls; the reach of a room (6.4 m with its walls) keeps such probes out of the light
// list instead, and so lights fewer probes.
TEST_F(StreamingTest, NoProbeIsLitThroughACellThatIsOutWithOrWithoutALightReach) {
  const formats::ProbeVolume& v = streamed_rooms();
  auto whole = runtime::Volume::upload(context(), v);
  ASSERT_TRUE(whole.ok());
  ASSERT_TRUE(whole.value().run_frame().ok());
  auto a = whole.value().read_back();
  ASSERT_TRUE(a.ok());
  const auto first = std::find_if(v.probes.begin(), v.probes.end(), [](const gpu::Probe& p) { return p.link != 0; });
  struct Lit {
    int exact = 0, seams = 0, unresolved = 0;
  };
  const auto light_at = [&](float reach, float radius) {
    runtime::UploadOptions options = streaming_options(2 * tracing_bytes_of_cells(v));
    options.streaming.light_reach = reach;
    auto streamed = runtime::Volume::upload(context(), v, options); // from the file, one frame like `whole`
    EXPECT_TRUE(streamed.ok()) << streamed.status().message;
    EXPECT_TRUE(streamed.value().stream_around(first->position, radius).ok());
    auto stats = streamed.value().run_frame();
    EXPECT_TRUE(stats.ok());
    auto b = streamed.value().read_back();
    EXPECT_TRUE(b.ok());
    EXPECT_TRUE(streamed.value().validate_live().ok());
    Lit lit;
    lit.unresolved = stats.value().light.unresolved_probes;
    for (std::size_t i = 0; i < v.probes.size(); ++i) {
      if (v.probes[i].link == 0) continue;
      if (same_irradiance(b.value().probes[i], a.value().probes[i]))
        ++lit.exact;
      else if (!same_irradiance(b.value().probes[i], v.probes[i]))
        ++lit.seams;
    }
    return lit;
  };
  int unresolved = 0, lit_with = 0;
  for (const float radius : {4.0f, 6.0f, 8.0f, 10.0f, 12.0f, 16.0f, 20.0f}) {
    const Lit without = light_at(0.0f, radius), with = light_at(6.4f, radius);
    std::printf("[streaming] radius %2.0f m: without a light reach %3d probes lit as the whole file, %2d left "
                "unresolved, %d seams; "
                "with 6.4 m %3d lit, %d unresolved, %d seams\n",
                double(radius), without.exact, without.unresolved, without.seams, with.exact, with.unresolved,
                with.seams);
    EXPECT_EQ(without.seams, 0) << "radius " << radius;
    EXPECT_EQ(with.seams, 0) << "radius " << radius;
    EXPECT_GE(without.exact, with.exact) << "radius " << radius << ": the reach only holds probes back";
    unresolved += without.unresolved, lit_with += with.exact;
  }
  EXPECT_GT(unresolved, 0) << "the scene has no ray crossing a cell that is out";
  EXPECT_GT(lit_with, 0);
  runtime::UploadOptions bad = streaming_options(1 << 20);
  bad.streaming.light_reach = -1.0f;
  EXPECT_EQ(runtime::Volume::upload(context(), v, bad).status().code, runtime::StatusCode::invalid_argument);
}

// Unresolved probes are traced again once cells arrive, at most max_joining_probes list places a frame:
// around one probe some are left unresolved; when every cell is in, each frame traces at most the joining
// probes and one retry window, and after one pass over the list every probe is lit (none keeps its light).
TEST_F(StreamingTest, UnresolvedProbesAreRetriedWithinTheJoinBudgetOnceTheirCellsArrive) {
  const formats::ProbeVolume& v = streamed_rooms();
  constexpr int kJoining = 8;
  auto streamed = runtime::Volume::upload(context(), v, streaming_options(2 * tracing_bytes_of_cells(v), 0, kJoining));
  ASSERT_TRUE(streamed.ok()) << streamed.status().message;
  const auto first = std::find_if(v.probes.begin(), v.probes.end(), [](const gpu::Probe& p) { return p.link != 0; });
  int unresolved = 0, frames = 0, retraced = 0;
  const auto settle = [&] {
    for (int f = 0;; ++f) {
      auto stats = streamed.value().run_frame();
      EXPECT_TRUE(stats.ok());
      EXPECT_LE(stats.value().light.traced_probes, 2 * kJoining)
          << "frame " << frames << ": the joining probes and one retry window";
      unresolved += stats.value().light.unresolved_probes, retraced += stats.value().light.traced_probes, ++frames;
      if (stats.value().streaming.joining_probes == 0 && stats.value().streaming.waiting_cells == 0) return;
      ASSERT_LT(f, 400);
    }
  };
  ASSERT_TRUE(streamed.value().stream_around(first->position, 6.0f).ok());
  settle();
  EXPECT_GT(unresolved, 0) << "around one probe, some rays cross cells that are out";
  const int unresolved_around_one = unresolved;
  ASSERT_TRUE(streamed.value().stream_around(first->position, 2.0f * v.info.root_size).ok());
  settle();
  const int live = live_probe_count(v);
  for (int f = 0; f <= live / kJoining; ++f) settle(); // the retry windows pass over the whole list
  auto last = streamed.value().run_frame();
  ASSERT_TRUE(last.ok());
  EXPECT_EQ(last.value().light.lit_probes, live) << "every probe is lit: none keeps its light as unresolved";
  EXPECT_EQ(last.value().light.traced_probes, 0) << "the retries are over";
  EXPECT_TRUE(streamed.value().validate_live().ok());
  std::printf(
      "[streaming] around one probe %d probes left unresolved; with every cell in, %d traces in %d frames (at most %d "
      "a frame), then %d of %d probes lit\n",
      unresolved_around_one, retraced, frames, 2 * kJoining, last.value().light.lit_probes, live);
}

// A light change after cells dropped: the relight's shadow rays that cross a cell that is out leave their
// probe unresolved too. With every cell resident for three frames the streamed volume is the whole file bit
// for bit; then, in one frame, cells around all but one probe drop and every light moves 0.4 m down: each
// probe is lit as the whole file is or keeps its irradiance, none is lit through a cell that dropped.
TEST_F(StreamingTest, ALightChangeLightsNoProbeThroughACellThatDropped) {
  const formats::ProbeVolume& v = streamed_rooms();
  auto [whole, streamed] = upload_whole_and_streamed(context(), v);
  ASSERT_TRUE(whole.ok() && streamed.ok());
  const auto first = std::find_if(v.probes.begin(), v.probes.end(), [](const gpu::Probe& p) { return p.link != 0; });
  ASSERT_TRUE(streamed.value().stream_around(first->position, 2.0f * v.info.root_size).ok());
  for (int f = 0; f < 3; ++f) ASSERT_TRUE(whole.value().run_frame().ok() && streamed.value().run_frame().ok());
  auto before = streamed.value().read_back();
  ASSERT_TRUE(before.ok());
  std::vector<gpu::PunctualLight> lights(whole.value().lights().begin(), whole.value().lights().end());
  ASSERT_FALSE(lights.empty());
  for (gpu::PunctualLight& light : lights) light.position.y -= 0.4f;
  runtime::FrameInputs moved;
  moved.lights = lights;
  ASSERT_TRUE(streamed.value().stream_around(first->position, 8.0f).ok());
  auto a_frame = whole.value().run_frame(moved);
  auto b_frame = streamed.value().run_frame(moved);
  ASSERT_TRUE(a_frame.ok() && b_frame.ok()) << b_frame.status().message;
  EXPECT_GT(b_frame.value().streaming.dropped_cells, 0);
  auto a = whole.value().read_back(), b = streamed.value().read_back();
  ASSERT_TRUE(a.ok() && b.ok());
  int exact = 0, kept = 0, seams = 0;
  for (std::size_t i = 0; i < v.probes.size(); ++i) {
    if (v.probes[i].link == 0) continue;
    ASSERT_FALSE(same_irradiance(a.value().probes[i], before.value().probes[i]))
        << "probe " << i << ": the lights moved";
    if (same_irradiance(b.value().probes[i], a.value().probes[i]))
      ++exact;
    else if (same_irradiance(b.value().probes[i], before.value().probes[i]))
      ++kept;
    else
      ++seams;
  }
  std::printf(
      "[streaming] lights moved as cells dropped: %d probes lit as the whole file, %d kept their irradiance (%d left "
      "unresolved by the relight), %d seams\n",
      exact, kept, b_frame.value().light.unresolved_probes, seams);
  EXPECT_EQ(seams, 0);
  EXPECT_GT(exact, 0);
  EXPECT_GT(b_frame.value().light.unresolved_probes, 0) << "no shadow ray crossed a cell that dropped";
  EXPECT_TRUE(streamed.value().validate_live().ok());
}

TEST_F(StreamingTest, CameraPathKeepsTheBudgetAndAValidLiveStateEveryFrame) {
  const formats::ProbeVolume& v = streamed_rooms();
  const std::uint64_t all = tracing_bytes_of_cells(v), budget = all * 2 / 5;
  constexpr int kJoining = 8; // probes that start being lit (and traced) per frame
  constexpr int kLit = 40;    // probes with light records at once
  auto streamed = runtime::Volume::upload(context(), v, streaming_options(budget, budget / 4, kJoining, kLit));
  ASSERT_TRUE(streamed.ok()) << streamed.status().message;
  const glm::vec3 lo = v.info.root_min, hi = v.info.root_min + v.info.root_size;
  const float radius = 0.3f * v.info.root_size;
  int loads = 0, drops = 0, waits = 0, joined = 0, unplaced = 0, moved = 0;
  std::uint64_t worst_upload = 0;
  const int frames = 24;
  for (int f = 0; f < frames; ++f) {
    const float t = f < frames / 2 ? float(f) / float(frames / 2 - 1) : float(frames - 1 - f) / float(frames / 2 - 1);
    const glm::vec3 camera = glm::mix(lo, hi, glm::vec3(t, 0.5f, 1.0f - t));
    ASSERT_TRUE(streamed.value().stream_around(camera, radius).ok());
    auto stats = streamed.value().run_frame();
    ASSERT_TRUE(stats.ok()) << stats.status().message;
    const runtime::StreamStats& s = stats.value().streaming;
    ASSERT_TRUE(s.active);
    ASSERT_LE(s.resident_bytes, budget) << "frame " << f;
    ASSERT_LE(s.joined_probes, kJoining) << "frame " << f;
    ASSERT_LE(stats.value().light.traced_probes, 2 * kJoining)
        << "frame " << f << ": only joining probes and one retry window trace";
    ASSERT_LE(stats.value().light.lit_probes, kLit) << "frame " << f << ": only probes with records are lit";
    loads += s.loaded_cells, drops += s.dropped_cells, waits += s.waiting_cells, joined += s.joined_probes;
    unplaced += s.unplaced_cells, moved += s.moved_cells;
    worst_upload = std::max(worst_upload, s.loaded_bytes);
    const runtime::Status live = streamed.value().validate_live();
    ASSERT_TRUE(live.ok()) << "frame " << f << ": " << live.message;
  }
  std::printf(
      "[streaming] %d frames, budget %llu of %llu bytes: %d loads, %d drops, %d waits, %d without a free run, %d "
      "blocks moved to compact the arena, %d probes joined, largest frame upload %llu bytes\n",
      frames, static_cast<unsigned long long>(budget), static_cast<unsigned long long>(all), loads, drops, waits,
      unplaced, moved, joined, static_cast<unsigned long long>(worst_upload));
  // A load that finds the arena fragmented compacts it (validate_live above compares every resident block,
  // moved or not, with the file's bytes at its place): none waits.
  EXPECT_EQ(unplaced, 0);
  EXPECT_GT(moved, 0) << "the path never fragmented the arena";
  // A still camera: the waiting probes join, kJoining a frame, and then nothing more traces.
  int still = 0;
  for (;; ++still) {
    auto stats = streamed.value().run_frame();
    ASSERT_TRUE(stats.ok());
    if (stats.value().streaming.joining_probes == 0 && stats.value().streaming.waiting_cells == 0) break;
    ASSERT_LT(still, 200);
  }
  for (int f = 0; f <= kLit / kJoining; ++f) ASSERT_TRUE(streamed.value().run_frame().ok()); // the last retry windows
  auto settled = streamed.value().run_frame();
  ASSERT_TRUE(settled.ok());
  EXPECT_EQ(settled.value().light.traced_probes, 0);
  EXPECT_GT(joined, kJoining) << "joins spread over frames";
  EXPECT_GT(drops, 0);
  EXPECT_GT(loads, int(v.cells.size()) / 2) << "the way back loads dropped cells again";
  EXPECT_FALSE(streamed.value().set_stream_budget(budget + 1).ok());
  EXPECT_FALSE(streamed.value().stream_around(glm::vec3(NAN), 1.0f).ok());
}

// Volume::load with streaming reads each cell from disk when it arrives (formats/cell_file.h): the result
// equals the in-memory upload's bit for bit. A cell whose bytes change on disk after the load is refused
// with its name, never uploaded and never asked for again; the other cells stream on.
TEST_F(StreamingTest, LoadedFileStreamsCellsFromDiskAndRefusesACellChangedSinceLoad) {
  const formats::ProbeVolume& v = streamed_rooms();
  const std::string path = temp_path("stream-from-disk.probes");
  formats::write_probes_file(path, v);
  const runtime::UploadOptions options = streaming_options(2 * tracing_bytes_of_cells(v));
  auto from_disk = runtime::Volume::load(context(), path, options);
  auto in_memory = runtime::Volume::upload(context(), v, options);
  ASSERT_TRUE(from_disk.ok()) << from_disk.status().message;
  ASSERT_TRUE(in_memory.ok());
  for (runtime::Volume* volume : {&from_disk.value(), &in_memory.value()}) {
    ASSERT_TRUE(volume->stream_around(glm::vec3(0.0f), 1e6f).ok());
    for (int f = 0; f < 2; ++f) ASSERT_TRUE(volume->run_frame().ok());
  }
  EXPECT_EQ(from_disk.value().resident_cells().size(), v.cells.size());
  ASSERT_TRUE(from_disk.value().validate_live().ok()) << from_disk.value().validate_live().message;
  auto a = from_disk.value().read_back(), b = in_memory.value().read_back();
  ASSERT_TRUE(a.ok() && b.ok());
  for (std::size_t i = 0; i < v.probes.size(); ++i)
    ASSERT_TRUE(same_irradiance(a.value().probes[i], b.value().probes[i])) << "probe " << i;

  // A second load, then one byte of a cell's faces changes on disk before the camera reaches it.
  auto later = runtime::Volume::load(context(), path, options);
  ASSERT_TRUE(later.ok());
  std::size_t damaged = 0;
  while (v.cell_tracing[damaged].trace_faces.count == 0) ++damaged;
  const std::uint64_t offset =
      file_offset_in(path, formats::SectionType::trace_faces, v.cell_tracing[damaged].trace_faces);
  flip_byte(path, offset, 0x01);
  ASSERT_TRUE(later.value().stream_around(glm::vec3(0.0f), 1e6f).ok());
  auto first = later.value().run_frame();
  ASSERT_TRUE(first.ok()) << first.status().message;
  expect_one_refusal(later.value(), first.value(), v, damaged);
  const std::vector<int> resident = later.value().resident_cells();
  EXPECT_EQ(std::count(resident.begin(), resident.end(), v.cells[damaged].cell_index), 0);
  EXPECT_EQ(resident.size(), v.cells.size() - 1);
  auto second = later.value().run_frame();
  ASSERT_TRUE(second.ok());
  EXPECT_EQ(second.value().streaming.refused_cells + second.value().streaming.loaded_cells, 0)
      << "a refused cell is not retried";
  // With the byte back the file reads as validated again: the live state checks out, the refused cell's
  // word the null leaf.
  flip_byte(path, offset, 0x01);
  EXPECT_TRUE(later.value().validate_live().ok()) << later.value().validate_live().message;
}

// A file whose container and checksums are sound (the writer's) but where one cell's face uses another
// cell's vertex. The whole-file load refuses it. The streaming load of a 1.7 file reads no cell (cell_file.h),
// so it loads, reading only the global part, and refuses that cell when it arrives, by name and invariant,
// while every other cell loads. Written as 1.6 (no global checksums) the file is read whole once, its cells'
// tracing validated in place in the mapping, and refused at load as before.
TEST_F(StreamingTest, ACellWhoseTracingReachesIntoAnotherIsRefusedWhenItArrives) {
  formats::ProbeVolume v = streamed_rooms();
  std::size_t a = 0;
  while (v.cell_tracing[a].trace_faces.count == 0) ++a;
  std::size_t b = a + 1;
  while (v.cell_tracing[b].trace_vertices.count == 0) ++b;
  v.trace_faces[v.cell_tracing[a].trace_faces.first].vertex[2] = v.cell_tracing[b].trace_vertices.first;
  const std::string leak = "cell_tracing[" + std::to_string(a) + "]: cell_tracing: trace face";
  const std::string path = temp_path("stream-leak.probes");
  formats::write_probes_file(path, v);
  auto whole = runtime::Volume::load(context(), path, streaming_options(0));
  ASSERT_FALSE(whole.ok());
  EXPECT_EQ(whole.status().code, runtime::StatusCode::invalid_volume);
  EXPECT_NE(whole.status().message.find(leak), std::string::npos) << whole.status().message;

  const formats::OpenedCellFile opened = formats::CellFile::open(path);
  EXPECT_TRUE(opened.cells_unread);
  EXPECT_EQ(opened.bytes_read, std::filesystem::file_size(path) - tracing_bytes_of_cells(v)); // the global part, once
  auto streamed = runtime::Volume::load(context(), path, streaming_options(2 * tracing_bytes_of_cells(v)));
  ASSERT_TRUE(streamed.ok()) << streamed.status().message;
  ASSERT_TRUE(streamed.value().stream_around(glm::vec3(0.0f), 1e6f).ok());
  auto frame = streamed.value().run_frame();
  ASSERT_TRUE(frame.ok()) << frame.status().message;
  expect_one_refusal(streamed.value(), frame.value(), v, a, leak);

  v.cell_checksums = formats::cell_checksums_of(v), v.cell_global_checksums.clear(); // written as 1.6
  formats::write_probes_file(path, v);
  EXPECT_FALSE(formats::CellFile::open(path).cells_unread);
  auto older = runtime::Volume::load(context(), path, streaming_options(2 * tracing_bytes_of_cells(v)));
  ASSERT_FALSE(older.ok());
  EXPECT_NE(older.status().message.find(leak), std::string::npos) << older.status().message;
}

// read_in_background: the first frame asks for every cell with faces and loads none of them (their bytes
// are read on the reader's thread); they arrive in later frames, the live state valid at every one. A cell
// damaged on disk is refused from the background thread as from the frame's own read.
TEST_F(StreamingTest, BackgroundReadsArriveInLaterFramesAndRefuseADamagedCell) {
  const formats::ProbeVolume& v = streamed_rooms();
  const std::string path = temp_path("stream-background.probes");
  formats::write_probes_file(path, v);
  runtime::UploadOptions options = streaming_options(2 * tracing_bytes_of_cells(v));
  options.streaming.read_in_background = true;
  auto volume = runtime::Volume::load(context(), path, options);
  ASSERT_TRUE(volume.ok()) << volume.status().message;
  std::size_t damaged = 0, with_faces = 0;
  for (const formats::CellTracing& t : v.cell_tracing) with_faces += t.trace_faces.count > 0 ? 1 : 0;
  while (v.cell_tracing[damaged].trace_faces.count == 0) ++damaged;
  const std::uint64_t offset =
      file_offset_in(path, formats::SectionType::trace_vertices, v.cell_tracing[damaged].trace_vertices);
  flip_byte(path, offset, 0x40);
  ASSERT_TRUE(volume.value().stream_around(glm::vec3(0.0f), 1e6f).ok());
  int loaded = 0, refused = 0, frames = 0;
  for (;; ++frames) {
    ASSERT_LT(frames, 400) << "the cells never arrived";
    auto stats = volume.value().run_frame();
    ASSERT_TRUE(stats.ok()) << stats.status().message;
    const runtime::StreamStats& s = stats.value().streaming;
    if (frames == 0) {
      EXPECT_EQ(std::size_t(s.reading_cells), with_faces) << "no cell with faces is read inside the frame";
      EXPECT_EQ(std::size_t(s.loaded_cells), v.cells.size() - with_faces);
    }
    loaded += s.loaded_cells, refused += s.refused_cells;
    if (s.reading_cells == 0 && s.joining_probes == 0 && frames > 0) break;
    if (s.reading_cells > 0) std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  EXPECT_EQ(refused, 1);
  EXPECT_EQ(std::size_t(loaded), v.cells.size() - 1);
  ASSERT_EQ(volume.value().stream_refusals().size(), 1u);
  EXPECT_NE(volume.value().stream_refusals()[0].find("cells[" + std::to_string(damaged) + "]"), std::string::npos);
  EXPECT_EQ(volume.value().resident_cells().size(), v.cells.size() - 1);
  std::printf("[streaming] background reads: %zu cells with faces arrived within %d frames, one refused\n", with_faces,
              frames);
  // The rest of the file is intact: every resident cell's block equals its bytes. (The damaged cell's
  // section checksum now fails, so the whole file is compared only after restoring it.)
  flip_byte(path, offset, 0x40);
  EXPECT_TRUE(volume.value().validate_live().ok()) << volume.value().validate_live().message;
}

// probebake-run --budget --path: a line per frame and the summary with the worst upload spike.
TEST_F(StreamingTest, RunToolStreamsAlongAPathAndReportsTheWorstUploadSpike) {
  const std::string probes = temp_path("stream-rooms.probes"), path = temp_path("stream-path.csv"),
                    csv = temp_path("stream.csv");
  const formats::ProbeVolume& v = streamed_rooms();
  formats::write_probes_file(probes, v);
  {
    std::ofstream out(path);
    out << "frame,x,y,z\n";
    for (int f = 0; f < 6; ++f) {
      const glm::vec3 p = v.info.root_min + v.info.root_size * glm::vec3(0.2f + 0.12f * float(f), 0.5f, 0.5f);
      out << f << ',' << p.x << ',' << p.y << ',' << p.z << '\n';
    }
  }
  const std::uint64_t budget = tracing_bytes_of_cells(v) / 2;
  const CliResult r = run_cli(test::quoted(std::filesystem::path(probes)) + " --budget " + std::to_string(budget) +
                              " --path " + test::quoted(std::filesystem::path(path)) +
                              " --radius 8 --max-joining 16 --keep-margin 2 --validate --vk-validation --csv " +
                              test::quoted(std::filesystem::path(csv)));
  EXPECT_EQ(r.exit_code, 0) << r.out << r.err;
  EXPECT_NE(r.out.find("frame 5 at ("), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("streaming: worst upload spike "), std::string::npos) << r.out;
  // The summary counts the frames whose line says a load found no free run in the arena.
  const std::string waits_key = " frames with a load waiting for a free run";
  const std::size_t waits_at = r.out.find(waits_key);
  ASSERT_NE(waits_at, std::string::npos) << r.out;
  const std::size_t number_at = r.out.rfind("; ", waits_at);
  ASSERT_NE(number_at, std::string::npos);
  int unplaced_frames = 0;
  for (std::size_t at = r.out.find(" without a free run)"); at != std::string::npos;
       at = r.out.find(" without a free run)", at + 1))
    ++unplaced_frames;
  EXPECT_EQ(std::stoi(r.out.substr(number_at + 2, waits_at - number_at - 2)), unplaced_frames) << r.out;
  EXPECT_NE(r.out.find("| stream_upload | all |"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("validation messages: 0"), std::string::npos) << r.out;
  std::ifstream rows(csv);
  int lines = 0;
  std::string header;
  for (std::string line; std::getline(rows, line); ++lines) {
    if (lines == 0) header = line;
    EXPECT_EQ(std::count(line.begin(), line.end(), ','), std::count(header.begin(), header.end(), ',')) << line;
  }
  EXPECT_EQ(lines, 1 + 6);
  EXPECT_NE(header.find(",waiting_cells,reading_cells,refused_cells,upload_cpu_ms"), std::string::npos) << header;
  // The same path read in the background, probes lit only with the rooms around them resident.
  const CliResult background = run_cli(test::quoted(std::filesystem::path(probes)) + " --budget " +
                                       std::to_string(budget) + " --path " + test::quoted(std::filesystem::path(path)) +
                                       " --radius 8 --background-reads --light-reach 6.4 --validate --vk-validation");
  EXPECT_EQ(background.exit_code, 0) << background.out << background.err;
  EXPECT_NE(background.out.find(" being read)"), std::string::npos) << background.out;
  EXPECT_NE(background.out.find("host memory: "), std::string::npos) << background.out;
  EXPECT_NE(background.out.find("validation messages: 0"), std::string::npos) << background.out;
  EXPECT_EQ(run_cli(test::quoted(std::filesystem::path(probes)) + " --budget 1M --path " +
                    test::quoted(std::filesystem::path(path)) + " --light-reach -1")
                .exit_code,
            1);
  const CliResult missing = run_cli(test::quoted(std::filesystem::path(probes)) + " --budget 1M");
  EXPECT_EQ(missing.exit_code, 1) << "--budget needs --path";
  const CliResult bad_path = run_cli(test::quoted(std::filesystem::path(probes)) + " --budget 1M --path " +
                                     test::quoted(std::filesystem::path(probes)));
  EXPECT_EQ(bad_path.exit_code, 2) << bad_path.err;
}

// max_lit_probes sizes the light records (64 B per ray and probe, 12 more for the tracked light) and the
// gathered irradiance (27 floats per probe) for that many probes instead of every probe of the file.
TEST_F(StreamingTest, LitProbeCapSizesTheLightRecords) {
  const formats::ProbeVolume& v = streamed_rooms();
  const std::uint64_t budget = tracing_bytes_of_cells(v);
  const auto device_bytes = [&](int max_lit) {
    const std::uint64_t before = context().memory_stats().live_bytes;
    auto volume = runtime::Volume::upload(context(), v, streaming_options(budget, 0, 0, max_lit));
    EXPECT_TRUE(volume.ok()) << volume.status().message;
    return context().memory_stats().live_bytes - before;
  };
  const std::uint64_t all = device_bytes(0), capped = device_bytes(32);
  const std::uint64_t per_probe =
      std::uint64_t(v.lighting->rays) * (sizeof(gpu::LightRecord) + 12) + gpu::PROBE_SH_FLOATS * sizeof(float);
  std::printf("[streaming] light records for every one of %zu probe slots: %llu bytes on the device; for 32: %llu\n",
              v.probes.size(), static_cast<unsigned long long>(all), static_cast<unsigned long long>(capped));
  EXPECT_EQ(all - capped, (v.probes.size() - 32) * per_probe);
}

// Frames that re-measure every leaf in `box` (if any) twice, then run until the memory update has no work left (at
// most `frames`); returns the measures left unresolved over all of them, or -1 when a frame failed or the
// tree never settled.
int settle_streamed(runtime::Volume& volume, std::optional<runtime::Box> box, int frames = 40) {
  int unresolved = 0;
  for (int f = 1; f <= frames; ++f) {
    runtime::FrameInputs in;
    if (f <= 2 && box) in.changed_boxes = {*box};
    auto stats = volume.run_frame(in);
    if (!stats.ok()) return ADD_FAILURE() << stats.status().message, -1;
    const runtime::MemoryUpdateStats& m = stats.value().memory;
    unresolved += m.unresolved_measures;
    const bool busy = m.splits + m.collapses + m.probes_placed + m.probes_freed + m.deferred > 0 ||
                      m.processed[std::size_t(gpu::LEAF_L1_PLACE_SURFELS)] > 0;
    if (f > 3 && !busy) return unresolved;
  }
  return ADD_FAILURE() << "not settled after " << frames << " frames", -1;
}

// The octant path of cell `cell` (grid index at `depth`), as path_of() writes a node's.
std::string cell_path(int cell, int depth) {
  const int n = 1 << depth, x = cell % n, y = cell / n % n, z = cell / (n * n);
  std::string path;
  for (int level = depth - 1; level >= 0; --level)
    path += char('0' + (((x >> level) & 1) | (((y >> level) & 1) << 1) | (((z >> level) & 1) << 2)));
  return path;
}

// The node at `path` of the volume's tree, or -1 when a leaf ends the path before.
int node_at(const formats::ProbeVolume& v, const std::string& path) {
  int node = 0;
  for (char c : path) {
    const int meta = v.octree[std::size_t(node)];
    if (meta <= 0) return -1;
    node = meta + 1 + (c - '0');
  }
  return node;
}

// Whether a tree's leaf at `leaf` lies strictly below `path`.
bool below(const std::string& leaf, const std::string& path) {
  return leaf.size() > path.size() && leaf.compare(0, path.size(), path) == 0;
}

// The octant path of every probe's leaf in `v` ("" for a probe in no leaf).
std::vector<std::string> probe_paths(const formats::ProbeVolume& v) {
  std::vector<std::string> paths(v.probes.size());
  std::vector<std::pair<int, std::string>> stack{{0, ""}};
  while (!stack.empty()) {
    const auto [node, path] = stack.back();
    stack.pop_back();
    const int value = v.octree[std::size_t(node)];
    if (value < 0) paths[std::size_t(~value)] = path;
    if (value > 0)
      for (int o = 0; o < 8; ++o) stack.emplace_back(value + 1 + o, path + char('0' + o));
  }
  return paths;
}

// The cell of each probe of `v`: the cell its leaf lies in, or -1 for a leaf above the cell depth.
std::vector<int> probe_cells(const formats::ProbeVolume& v) {
  std::map<std::string, int> cell_at;
  const int n = 1 << v.cell_depth;
  for (int cell = 0; cell < n * n * n; ++cell) cell_at.emplace(cell_path(cell, v.cell_depth), cell);
  const std::vector<std::string> paths = probe_paths(v);
  std::vector<int> cells(paths.size(), -1);
  for (std::size_t p = 0; p < paths.size(); ++p)
    if (paths[p].size() >= std::size_t(v.cell_depth))
      cells[p] = cell_at.at(paths[p].substr(0, std::size_t(v.cell_depth)));
  return cells;
}

// Per SVO leaf of `v`, the cells whose probes its bake stencil names (a seat of each carries the leaf).
std::vector<std::set<int>> stencil_cells(const formats::ProbeVolume& v) {
  const std::vector<int> cells = probe_cells(v);
  std::vector<std::set<int>> named(v.svo_leaves.size());
  for (std::size_t leaf = 0; leaf < named.size(); ++leaf)
    for (int k = 0; k < gpu::SVO_PROBES_PER_LEAF; ++k) {
      const int probe = v.svo_leaves[leaf].probes[k];
      if (probe >= 0 && cells[std::size_t(probe)] >= 0) named[leaf].insert(cells[std::size_t(probe)]);
    }
  return named;
}

// The cells of `v` that `chosen` picks whose subtree in `live` differs from the file's (leaf for leaf, probe
// for probe).
template <class Chosen>
std::vector<int> cells_unlike_the_file(const formats::ProbeVolume& live, const formats::ProbeVolume& v, Chosen chosen) {
  const Canonical file = canonical(v), now = canonical(live);
  const auto subtree = [](const Canonical& tree, const std::string& path) {
    std::map<std::string, std::tuple<bool, float, float, float, int>> out;
    for (const auto& [leaf, value] : tree.leaves)
      if (below(leaf, path) || leaf == path) out.emplace(leaf, value);
    return out;
  };
  std::vector<int> unlike;
  for (const formats::Cell& cell : v.cells) {
    const std::string path = cell_path(cell.cell_index, v.cell_depth);
    if (chosen(cell.cell_index) && subtree(now, path) != subtree(file, path)) unlike.push_back(cell.cell_index);
  }
  return unlike;
}

// Of the cells of `v` that `chosen` picks, how many have the file's subtree in `live`; each one that does not
// is a test failure naming `when`.
template <class Chosen>
int cells_with_file_subtrees(const formats::ProbeVolume& live, const formats::ProbeVolume& v, Chosen chosen,
                             const char* when) {
  const std::vector<int> unlike = cells_unlike_the_file(live, v, chosen);
  for (int cell : unlike) ADD_FAILURE() << when << ": cell " << cell << " differs from the file";
  return int(std::count_if(v.cells.begin(), v.cells.end(),
                           [&](const formats::Cell& c) { return chosen(c.cell_index); })) -
         int(unlike.size());
}

// The SVO leaves whose bake stencils name a probe of the cells `arrived` picks and whose every probe lies in a
// cell that has the file's subtree in `live` (or above the cells): a seat restores each of those, whichever
// cells they cross. Counts them, those that name probes of more than one cell, and those that hold the bake's
// stencil in `live` (the same weights, bit for bit, on probes at the file's positions).
struct StencilCount {
  int leaves = 0, crossing = 0, held = 0;
};
template <class Arrived>
StencilCount bake_stencils_in(const formats::ProbeVolume& live, const formats::ProbeVolume& v, Arrived arrived) {
  const std::vector<int> unlike_cells = cells_unlike_the_file(live, v, [](int) { return true; });
  const std::set<int> unlike(unlike_cells.begin(), unlike_cells.end());
  const std::vector<std::set<int>> named = stencil_cells(v);
  StencilCount count;
  for (std::size_t leaf = 0; leaf < named.size(); ++leaf) {
    const auto& cells = named[leaf];
    if (std::none_of(cells.begin(), cells.end(), arrived) ||
        std::any_of(cells.begin(), cells.end(), [&](int cell) { return unlike.count(cell) != 0; }))
      continue;
    ++count.leaves;
    count.crossing += cells.size() > 1 ? 1 : 0;
    const gpu::SvoLeaf& file = v.svo_leaves[leaf];
    const gpu::SvoLeaf& now = live.svo_leaves[leaf];
    bool same = std::memcmp(&now.weights, &file.weights, sizeof(file.weights)) == 0;
    for (int k = 0; k < 4 && same; ++k) {
      if ((file.probes[k] < 0) != (now.probes[k] < 0))
        same = false;
      else if (file.probes[k] >= 0)
        same = live.probes[std::size_t(now.probes[k])].position == v.probes[std::size_t(file.probes[k])].position;
    }
    count.held += same ? 1 : 0;
  }
  return count;
}

// The memory update with streaming: the probe tree follows the cells through the memory update's pools. The
// upload holds every cell's subtree collapsed to the cell's node, a leaf whose probe holds the mean irradiance
// of the probes it replaced; the first frame seats the resident cells' file subtrees from the pools. Measures
// that cross a cell that is out decide nothing (MemoryUpdateStats::unresolved_measures). When every cell is in,
// each arrived cell gets the file's subtree from the pools; out (the GPU collapses it as the upload did) and
// in again, the same.
TEST_F(StreamingTest, TheProbeTreeFollowsTheCellsThroughTheMemoryUpdatesPools) {
  const formats::ProbeVolume& v = streamed_rooms();
  runtime::UploadOptions streamed_options = streaming_options(2 * tracing_bytes_of_cells(v));
  streamed_options.memory_update = true;
  // Pools that never run dry: in a dry pool which M1 gets a probe follows thread order
  // (docs/RUNTIME_INTERNALS.md, Departures).
  streamed_options.pools.free_probes = 4096;
  auto streamed = runtime::Volume::upload(context(), v, streamed_options);
  ASSERT_TRUE(streamed.ok()) << streamed.status().message;
  ASSERT_TRUE(streamed.value().runs_memory_update());
  const auto first = std::find_if(v.probes.begin(), v.probes.end(), [](const gpu::Probe& p) { return p.link != 0; });
  ASSERT_TRUE(streamed.value().stream_around(first->position, 6.0f).ok());

  // Frame 1: every cell that is out and has a subtree in the file is collapsed to its node; those in are seated.
  auto frame = streamed.value().run_frame();
  ASSERT_TRUE(frame.ok()) << frame.status().message;
  std::set<int> resident;
  for (int c : streamed.value().resident_cells()) resident.insert(c);
  const Canonical file = canonical(v);
  const formats::ProbeVolume collapsed = streamed.value().read_back().value();
  int cells = 0, freed = 0;
  for (const formats::Cell& cell : v.cells) {
    if (resident.count(cell.cell_index)) continue;
    const std::string path = cell_path(cell.cell_index, v.cell_depth);
    std::array<double, gpu::PROBE_SH_FLOATS> sum{};
    int probes = 0;
    for (const auto& [leaf, value] : file.leaves) {
      if (!below(leaf, path) || !std::get<0>(value)) continue;
      const gpu::Probe& p = v.probes[std::size_t(~v.octree[std::size_t(node_at(v, leaf))])];
      for (int k = 0; k < gpu::PROBE_SH_FLOATS; ++k) sum[std::size_t(k)] += p.irradiance_sh[k];
      ++probes;
    }
    if (probes == 0) continue;
    const int node = node_at(collapsed, path);
    ASSERT_GE(node, 0) << "cell " << cell.cell_index;
    ASSERT_LT(collapsed.octree[std::size_t(node)], 0) << "cell " << cell.cell_index << " is not a leaf with a probe";
    const gpu::Probe& mean = collapsed.probes[std::size_t(~collapsed.octree[std::size_t(node)])];
    for (int k = 0; k < gpu::PROBE_SH_FLOATS; ++k)
      ASSERT_NEAR(mean.irradiance_sh[k], sum[std::size_t(k)] / probes,
                  1e-5 * (1.0 + std::abs(sum[std::size_t(k)] / probes)))
          << "cell " << cell.cell_index << " coefficient " << k;
    ++cells, freed += probes - 1;
  }
  ASSERT_GT(cells, 0);
  EXPECT_EQ(frame.value().memory.cells_collapsed, 0); // the upload collapsed them
  EXPECT_EQ(frame.value().memory.failed_allocations, 0);
  ASSERT_TRUE(streamed.value().validate_live().ok()) << streamed.value().validate_live().message;
  const auto in_cells = [&](int cell) { return resident.count(cell) != 0; };
  EXPECT_EQ(cells_with_file_subtrees(collapsed, v, in_cells, "first frame"), int(resident.size()));

  // A box 12 m wide around the camera measured again until the tree settles: nothing decided through a cell
  // that is out, so the collapsed cells stay single leaves.
  const runtime::Box box{first->position - glm::vec3(6.0f), first->position + glm::vec3(6.0f)};
  const int unresolved = settle_streamed(streamed.value(), box);
  ASSERT_GT(unresolved, 0);
  const Canonical boxed = canonical(streamed.value().read_back().value());
  int single = 0;
  for (const formats::Cell& cell : v.cells) {
    if (resident.count(cell.cell_index)) continue;
    const std::string path = cell_path(cell.cell_index, v.cell_depth);
    for (const auto& [leaf, value] : boxed.leaves)
      ASSERT_FALSE(below(leaf, path)) << "cell " << cell.cell_index << " grew";
    single += boxed.leaves.count(path) ? 1 : 0;
  }
  EXPECT_GE(single, cells);

  // Every cell in: each arrived cell gets the file's subtree back from the pools, leaf for leaf and probe for
  // probe; out and in again, the same.
  const auto out_cells = [&](int cell) { return resident.count(cell) == 0; };
  StencilCount stencils;
  for (int round = 0; round < 2; ++round) {
    ASSERT_TRUE(streamed.value().stream_around(first->position, 1e6f).ok());
    auto in = streamed.value().run_frame();
    ASSERT_TRUE(in.ok()) << in.status().message;
    EXPECT_EQ(in.value().memory.failed_allocations, 0);
    const formats::ProbeVolume live = streamed.value().read_back().value();
    const int seated = cells_with_file_subtrees(live, v, out_cells, round == 0 ? "first return" : "second return");
    stencils = bake_stencils_in(live, v, out_cells); // the SVO leaves naming their probes
    ASSERT_GT(stencils.crossing, 0);
    EXPECT_EQ(stencils.held, stencils.leaves) << (round == 0 ? "first return" : "second return");
    ASSERT_TRUE(streamed.value().validate_live().ok()) << streamed.value().validate_live().message;
    if (round == 1) {
      std::printf(
          "[streaming] memory update: %d cells collapsed to their node (%d probes fewer); %d measures "
          "unresolved around one room; twice out and in, each of the %d cells that were out has the file's subtree, "
          "and the %d SVO leaves naming their probes (%d of them probes of other cells too) the bake's stencils\n",
          cells, freed, unresolved, seated, stencils.leaves, stencils.crossing);
      break;
    }
    ASSERT_TRUE(streamed.value().stream_around(first->position, 6.0f).ok());
    auto out_again = streamed.value().run_frame();
    ASSERT_TRUE(out_again.ok());
    EXPECT_EQ(out_again.value().memory.cells_collapsed, cells);
    EXPECT_EQ(out_again.value().memory.probes_freed, freed);
    ASSERT_TRUE(streamed.value().validate_live().ok()) << streamed.value().validate_live().message;
  }
}

// The memory update with streaming sizes its pools by the budget: the upload holds every cell collapsed and
// room for what the budget lets be resident at once (streaming::most_resident), fewer probe slots, and so
// fewer light records, than the whole file's memory update. Stepping from cell to cell, every arrival is
// seated from those pools (no failed allocation, the file's subtree leaf for leaf) and the live state is valid.
TEST_F(StreamingTest, ABudgetSizesTheMemoryUpdatesPoolsAndEveryArrivalSeatsFromThem) {
  const formats::ProbeVolume& v = streamed_rooms();
  std::uint64_t largest = 0;
  for (const formats::CellTracing& t : v.cell_tracing) largest = std::max(largest, formats::cell_tracing_bytes(t));
  runtime::UploadOptions streamed_options = streaming_options(2 * largest + 4096); // two cells or so at a time
  streamed_options.memory_update = true;
  runtime::UploadOptions whole_options;
  whole_options.memory_update = true;
  const auto upload = [&](const runtime::UploadOptions& options, std::uint64_t& bytes) {
    const std::uint64_t before = context().memory_stats().live_bytes;
    auto volume = runtime::Volume::upload(context(), v, options);
    EXPECT_TRUE(volume.ok()) << volume.status().message;
    bytes = context().memory_stats().live_bytes - before;
    return volume;
  };
  std::uint64_t whole_bytes = 0, streamed_bytes = 0;
  int whole_capacity = 0;
  {
    auto whole = upload(whole_options, whole_bytes);
    ASSERT_TRUE(whole.ok());
    auto frame = whole.value().run_frame();
    ASSERT_TRUE(frame.ok()) << frame.status().message;
    whole_capacity = frame.value().probe_capacity;
  }
  // The same streamed upload with a pool as large as the whole file's: what the pool sizing alone saves (the
  // whole file's bytes also hold its whole tracing).
  std::uint64_t whole_pool_bytes = 0;
  {
    runtime::UploadOptions whole_pool = streamed_options;
    whole_pool.pools.free_probes = whole_capacity;
    ASSERT_TRUE(upload(whole_pool, whole_pool_bytes).ok());
  }
  auto streamed = upload(streamed_options, streamed_bytes);
  ASSERT_TRUE(streamed.ok());
  int steps = 0, capacity = 0, most_live = 0;
  for (const formats::Cell& cell : v.cells) {
    if (cell.probes.count == 0) continue;
    const glm::vec3 centre = 0.5f * (cell.bounds_min + cell.bounds_max);
    ASSERT_TRUE(streamed.value().stream_around(centre, 0.5f).ok());
    auto frame = streamed.value().run_frame();
    ASSERT_TRUE(frame.ok()) << frame.status().message;
    ASSERT_EQ(frame.value().memory.failed_allocations, 0) << "cell " << cell.cell_index;
    std::set<int> resident;
    for (int c : streamed.value().resident_cells()) resident.insert(c);
    ASSERT_TRUE(resident.count(cell.cell_index)) << "cell " << cell.cell_index;
    const auto in_cells = [&](int c) { return resident.count(c) != 0; };
    ASSERT_EQ(cells_with_file_subtrees(streamed.value().read_back().value(), v, in_cells, "walk"),
              int(resident.size()));
    ASSERT_TRUE(streamed.value().validate_live().ok()) << streamed.value().validate_live().message;
    capacity = frame.value().probe_capacity;
    most_live = std::max(most_live, frame.value().live_probes);
    ++steps;
  }
  ASSERT_GT(steps, 2);
  std::printf(
      "[streaming] memory update on a budget of %llu bytes: %d probe slots (at most %d live over %d cells) and "
      "%llu device bytes (%llu with a pool as large as the whole file's), against %d slots and %llu bytes for the "
      "whole file's (%zu probes)\n",
      static_cast<unsigned long long>(streamed_options.streaming.budget_bytes), capacity, most_live, steps,
      static_cast<unsigned long long>(streamed_bytes), static_cast<unsigned long long>(whole_pool_bytes),
      whole_capacity, static_cast<unsigned long long>(whole_bytes), v.probes.size());
  EXPECT_LT(capacity, whole_capacity);
  EXPECT_LT(streamed_bytes, whole_bytes);
  EXPECT_LT(streamed_bytes, whole_pool_bytes);
}

// The ints a cell's seat passes behind MemoryFrame: its clusters (9 words each), probes (36 each) and the SVO
// leaves naming its probes (an index each), or 0 when its node is a leaf above the cell depth.
std::uint64_t seat_ints_of(const formats::ProbeVolume& v, int cell_index) {
  const int root = formats::cell_root_node(v, v.cell_depth, cell_index);
  if (root < 0) return 0;
  std::uint64_t ints = 0;
  for (const std::set<int>& cells : stencil_cells(v)) ints += cells.count(cell_index) ? 1 : 0;
  std::vector<int> stack{root};
  while (!stack.empty()) {
    const int value = v.octree[std::size_t(stack.back())];
    stack.pop_back();
    if (value < 0) ints += 36;
    if (value <= 0) continue;
    ints += 9;
    for (int o = 0; o < 8; ++o) stack.push_back(value + 1 + o);
  }
  return ints;
}

// StreamingOptions::max_seat_bytes bounds the file subtrees passed to the GPU per frame. With every cell
// arriving at once, the arrivals are seated over several frames, each with the file's subtree; the one cell
// larger than the limit alone grows back by measures instead. The live state is valid after every frame.
TEST_F(StreamingTest, TheSeatLimitSpreadsArrivalsOverFramesAndALargerCellGrowsByMeasures) {
  const formats::ProbeVolume& v = streamed_rooms();
  std::vector<std::pair<std::uint64_t, int>> seats; // (ints, cell index), largest first
  for (const formats::Cell& cell : v.cells) seats.emplace_back(seat_ints_of(v, cell.cell_index), cell.cell_index);
  std::sort(seats.rbegin(), seats.rend());
  ASSERT_GT(seats[0].first, seats[1].first);
  const int largest = seats[0].second;
  runtime::UploadOptions options = streaming_options(2 * tracing_bytes_of_cells(v));
  options.memory_update = true;
  options.pools.free_probes = 4096;
  options.streaming.max_seat_bytes = 4 * (8 + seats[0].first) - 4; // one int short of the largest cell's seat
  auto streamed = runtime::Volume::upload(context(), v, options);
  ASSERT_TRUE(streamed.ok()) << streamed.status().message;
  ASSERT_TRUE(streamed.value().stream_around(glm::vec3(0.0f), 1e6f).ok());
  const auto others = [&](int cell) { return cell != largest; };
  const int cells = int(v.cells.size()) - 1;
  std::vector<int> seated_by_frame;
  for (int frame = 0; frame < 40; ++frame) {
    auto stats = streamed.value().run_frame();
    ASSERT_TRUE(stats.ok()) << stats.status().message;
    ASSERT_EQ(stats.value().memory.failed_allocations, 0);
    ASSERT_TRUE(streamed.value().validate_live().ok()) << streamed.value().validate_live().message;
    const int seated = cells - int(cells_unlike_the_file(streamed.value().read_back().value(), v, others).size());
    seated_by_frame.push_back(seated);
    if (seated == cells) break;
  }
  ASSERT_GT(seated_by_frame.size(), 1u) << "every arrival fitted one frame's seat data";
  EXPECT_LT(seated_by_frame.front(), cells);
  ASSERT_EQ(seated_by_frame.back(), cells) << "not every cell seated within 40 frames";
  const formats::ProbeVolume live = streamed.value().read_back().value();
  EXPECT_EQ(cells_with_file_subtrees(live, v, others, "seated"), cells);
  const StencilCount stencils = bake_stencils_in(live, v, others);
  ASSERT_GT(stencils.crossing, 0);
  EXPECT_EQ(stencils.held, stencils.leaves);
  // The largest cell was measured again instead: its node, a leaf at upload, splits as the geometry asks.
  ASSERT_GE(settle_streamed(streamed.value(), std::nullopt), 0);
  const std::string path = cell_path(largest, v.cell_depth);
  int leaves = 0;
  for (const auto& [leaf, value] : canonical(streamed.value().read_back().value()).leaves)
    leaves += below(leaf, path) ? 1 : 0;
  EXPECT_GT(leaves, 1) << "cell " << largest << " did not grow";
  ASSERT_TRUE(streamed.value().validate_live().ok()) << streamed.value().validate_live().message;
  std::printf("[streaming] seat data of %llu bytes a frame: %d cells seated over %zu frames (%d in the first); cell %d "
              "(%llu bytes) grew by measures to %d leaves\n",
              static_cast<unsigned long long>(options.streaming.max_seat_bytes), cells, seated_by_frame.size(),
              seated_by_frame.front(), largest, static_cast<unsigned long long>(4 * (8 + seats[0].first)), leaves);
}

TEST_F(StreamingTest, RefusesVolumesItCannotStream) {
  formats::ProbeVolume v = streamed_rooms();
  v.cell_tracing.clear();
  auto refused = runtime::Volume::upload(context(), v, streaming_options(1 << 20));
  ASSERT_FALSE(refused.ok());
  EXPECT_EQ(refused.status().code, runtime::StatusCode::unsupported) << refused.status().message;
  runtime::UploadOptions no_light = streaming_options(1 << 20);
  no_light.light_update = false;
  auto unlit = runtime::Volume::upload(context(), streamed_rooms(), no_light);
  ASSERT_FALSE(unlit.ok());
  EXPECT_EQ(unlit.status().code, runtime::StatusCode::invalid_argument);
  auto plain = runtime::Volume::upload(context(), streamed_rooms());
  ASSERT_TRUE(plain.ok());
  EXPECT_EQ(plain.value().stream_around(glm::vec3(0.0f), 1.0f).code, runtime::StatusCode::invalid_argument);
  for (std::uint64_t seat_bytes : {std::uint64_t(31), std::uint64_t(4) * gpu::MEMORY_SEAT_INTS + 1}) {
    runtime::UploadOptions bad_seat = streaming_options(1 << 20);
    bad_seat.memory_update = true;
    bad_seat.streaming.max_seat_bytes = seat_bytes;
    auto refused_seat = runtime::Volume::upload(context(), streamed_rooms(), bad_seat);
    ASSERT_FALSE(refused_seat.ok()) << seat_bytes;
    EXPECT_EQ(refused_seat.status().code, runtime::StatusCode::invalid_argument) << refused_seat.status().message;
  }
}

// A grid's lattice names the file's probes, not the streamed slots: with streaming the grid sampler is refused,
// a game gets no lattice buffer, and the live volume (read back without the lattice) validates.
TEST_F(StreamingTest, AGridStreamsWithoutItsLattice) {
  const formats::ProbeVolume& grid = baked_cornell_grid();
  ASSERT_FALSE(grid.grid_lattice.empty());
  ASSERT_FALSE(grid.cell_tracing.empty());
  auto streamed = runtime::Volume::upload(context(), grid, streaming_options(2 * tracing_bytes_of_cells(grid)));
  ASSERT_TRUE(streamed.ok()) << streamed.status().message;
  ASSERT_TRUE(streamed->stream_around(glm::vec3(0.0f, 0.2f, 0.0f), 10.0f).ok());
  for (int frame = 0; frame < 3; ++frame) ASSERT_TRUE(streamed->run_frame().ok());
  EXPECT_EQ(streamed->buffers().grid_lattice.buffer, VK_NULL_HANDLE);
  const std::vector<glm::vec3> positions{glm::vec3(0.0f, 0.2f, 0.0f)}, normals{glm::vec3(0.0f, 1.0f, 0.0f)};
  EXPECT_EQ(streamed->sample_irradiance(positions, normals, nullptr, runtime::SampleMethod::grid).status().code,
            runtime::StatusCode::unsupported);
  formats::ValidationReport report;
  const runtime::Status live = streamed->validate_live(&report);
  EXPECT_TRUE(live.ok()) << live.message
                         << (report.violations.empty() ? "" : formats::format_violation(report.violations[0]));
}

} // namespace
} // namespace probebake::test
