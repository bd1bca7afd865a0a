// What an animated run reports (`probebake run --animate`, docs/RUNTIME.md "Animated runs"): one row per
// frame (CSV), a summary table per pass and phase of the motion (median, p95, worst), and SVG plots of the
// rows. Written by the driver itself, without libraries, so the runtime-only probebake-run has them too.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

#include "probebake/dynamic/animation.h"
#include "probebake/runtime/vocabulary.h"

namespace probebake::run {

using runtime::kFramePassNames;

struct FrameRow {
  int frame = 0;
  double angle_deg = 0.0;
  std::array<double, kFramePassNames.size()> pass_ms{}; // 0 for passes the frame did not run, -1 without timestamps
  double gpu_ms = 0.0;                                  // sum of the passes
  double cpu_ms = 0.0;
  int live_probes = 0;
  std::array<int, 9> processed{};     // leaf-queue entries by state, M0..M4, L0..L3
  std::optional<double> hit_fraction; // front hits / rays of the probes traced this frame
  int placed = 0, freed = 0, splits = 0, collapses = 0, failed = 0, deferred = 0, moved_objects = 0;
  int clusters_used = 0, cluster_capacity = 0, probes_used = 0, probe_capacity = 0, batches_used = 0,
      batch_capacity = 0;
  std::array<float, 3> camera{};     // --path: where the frame streamed around
  runtime::StreamStats stream;       // --path: the frame's cell streaming
  int traced = 0, unresolved = 0;    // probes light_trace traced, and of them those left unresolved (streaming)
  int load_window = 0, untraced = 0; // slots of the frame's load trace window, and slots it has still to reach
};

FrameRow frame_row(int frame, double angle_deg, const runtime::FrameStats& stats);
void write_frame_header(std::ostream& out);
void write_frame_row(std::ostream& out, const FrameRow& row);

// --path: one line per frame (resident cells and bytes, loads, drops, waiting cells, upload times), and
// the summary: the worst upload spike (the stream_upload pass's GPU time, and the host's numbering), the
// most bytes resident against the budget, loads and drops over the run.
std::string stream_frame_line(const FrameRow& row);
std::string stream_summary(const std::vector<FrameRow>& rows, std::uint64_t budget);

// This process's resident host memory now and at its peak (Linux VmRSS, VmHWM), in bytes; 0 where unknown.
struct HostMemory {
  std::uint64_t resident = 0, peak = 0;
};
HostMemory host_memory();
// "host memory: ..." for the streaming summary: after load and at the end.
std::string host_memory_line(HostMemory after_load, HostMemory at_end);
// --path --plots DIR: streaming.svg (resident and loaded KB per frame) and upload_times.svg (stream_upload
// GPU ms and host ms per frame). Returns the files written; throws std::runtime_error like write_plots.
std::vector<std::string> write_stream_plots(const std::string& folder, const std::vector<FrameRow>& rows);

// "before", "during", "after" (thesis), "turning", "still" (revolution), "moving", "still" (soak).
const char* motion_phase(dynamic::Animation animation, int frame);

// Per pass (over the frames that ran it) and for the frame's GPU total and host CPU: median, p95, worst and
// its frame, by phase and over all frames; a Markdown table.
// The worst frame against the median GPU time (the hitch measure: frame 0 and the load trace included), the
// frame the load trace ended (volumes with a light update), and with `frame_ms` > 0 the frames over that budget.
std::string frame_time_line(const std::vector<FrameRow>& rows, float frame_ms);
std::string summary_table(const std::vector<FrameRow>& rows, std::optional<dynamic::Animation> animation);

// "[########------------] 240/600 frames": `done` of `total` frames in a bar `width` characters wide.
std::string progress_bar(int done, int total, int width = 30);

// frame_times.svg (GPU ms per pass and total), probes.svg (live probes and pool use), leaf_states.svg
// (entries processed per state) in `folder`; the frames of motion shaded. Returns the files written, or
// throws std::runtime_error naming the file that could not be written.
std::vector<std::string> write_plots(const std::string& folder, const std::vector<FrameRow>& rows,
                                     dynamic::Animation animation);

} // namespace probebake::run
