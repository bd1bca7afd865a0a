// Command line of probebake-run (a plain argv parser: the tool links only the runtime and formats).
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "probebake/dynamic/animation.h"
#include "probebake/runtime/runtime.h"

namespace probebake::run {

// --depth-cycle LOW:HIGH:PERIOD: the memory update on; every PERIOD frames the max depth alternates between
// HIGH (first) and LOW, with every leaf marked changed in that frame.
struct DepthCycle {
  int low = 1, high = 3, period = 50;
};

// --orbit-light I:RADIUS:PERIOD: the file's punctual light I circles about the vertical (Y) axis, one turn
// every PERIOD frames, on a horizontal circle of RADIUS metres that passes through its baked position (frame
// 0; the centre is RADIUS along -X from it). A directional light's direction turns instead. I = `all`:
// every light of the file, each on its own circle.
struct LightOrbit {
  static constexpr int kEveryLight = -1; // `all`: every light on its own circle
  int light = 0;
  float radius = 0.0f;
  int period = 1;
};

// --budget BYTES --path PATH.csv: stream cells around a camera that follows the path, one frame per row
// (runtime::StreamingOptions; docs/RUNTIME.md "Streaming cells").
struct StreamRun {
  std::uint64_t budget = 0;      // --budget: device bytes for the resident cells' tracing blocks
  std::uint64_t max_upload = 0;  // --max-upload: bytes copied per frame at most (0 = no limit)
  std::string path;              // --path: frame,x,y,z
  float radius = 20.0f;          // --radius: metres around the camera
  int max_joining = 0;           // --max-joining: probes of arrived cells lit (traced) per frame at most
  float keep_margin = 0.0f;      // --keep-margin: metres beyond the radius within which resident cells stay
  int max_lit = 0;               // --max-lit: probes with light records at once (0 = every probe)
  float light_reach = 0.0f;      // --light-reach: StreamingOptions::light_reach
  bool background_reads = false; // --background-reads: StreamingOptions::read_in_background
};

struct RunOptions {
  std::string input;               // .probes file
  int frames = 1;                  // >= 1
  std::optional<std::string> csv;  // per-frame, per-pass times
  bool validate = false;           // validate the live state after every frame
  bool vulkan_validation = false;  // VK_LAYER_KHRONOS_validation with synchronization validation
  std::string device;              // device name filter
  int samples = 0;                 // irradiance lookups after the frames (random points in the root cube)
  bool compare_all_probes = false; // also time the thesis's all-probe loop on the same points
  bool light_update = true;        // run the light update when the file has the lighting sections
  float hysteresis = 0.9f;         // runtime::UploadOptions::hysteresis, [0, 1)
  formats::ShCodec probe_code = formats::ShCodec::float32; // runtime::UploadOptions::probe_code
  std::optional<glm::vec3> load_focus;       // runtime::UploadOptions::load_focus (--path: its first point)
  std::optional<DepthCycle> depth_cycle;     // run the memory update with this max-depth schedule
  std::optional<LightOrbit> orbit_light;     // move one punctual light every frame (FrameInputs::lights)
  std::optional<float> day_cycle;            // seconds of a day at 60 frames a second (FrameInputs::sky, the sun)
  std::optional<int> switch_emitters;        // frames between switches of every emitter (FrameInputs::emitters)
  std::optional<dynamic::Animation> animate; // pose the file's dynamic objects per frame (dynamic/animation.h)
  bool memory_update = false;            // runtime::UploadOptions::memory_update (implied by --depth-cycle, --animate)
  bool no_memory_update = false;         // --no-memory-update: off even with --animate (moved objects re-trace the
                                         // probes whose rays cross them; light_mark_moved)
  std::vector<int> animated_objects;     // --objects LIST: the objects --animate moves (empty: all)
  std::optional<int> max_depth;          // FrameInputs::max_depth in frame 0 (memory update)
  std::optional<int> pool_probes;        // --pool-probes: runtime::MemoryPools::free_probes (memory update)
  runtime::FrameLimits limits;           // per-frame limits of the memory and light updates
  std::optional<std::string> plots;      // folder for SVG plots of the per-frame table (--animate, --path)
  std::optional<StreamRun> stream;       // --budget and --path (both or neither)
  bool verbose = false;                  // one line per frame even without --csv
  std::string program = "probebake-run"; // prefix of error messages
  // Called after every frame with the frame index (0-based), for the CLI's pictures and error against the
  // reference; a Status that is not ok ends the run with its exit code.
  std::function<runtime::Status(int frame, runtime::Volume& volume)> after_frame;
};

// Parses argv; on error or --help returns nullopt and sets `message` (usage text or the error) and
// `exit_code` (0 for --help, 1 for a usage error).
std::optional<RunOptions> parse_run_options(int argc, char** argv, std::string& message, int& exit_code);

} // namespace probebake::run
