#include "run_report.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <optional>
#include <span>
#include <stdexcept>
#include <string_view>
#include <utility>

namespace probebake::run {
namespace {

constexpr const char* kStateNames[9] = {"m0", "m1", "m2", "m3", "m4", "l0", "l1", "l2", "l3"};

std::string number(double v, int precision = 4) {
  char text[48];
  std::snprintf(text, sizeof(text), "%.*g", precision, v);
  return text;
}

// ---- Summary ---------------------------------------------------------------------------------------------
struct Stat {
  double median = 0, p95 = 0, worst = 0;
  int worst_frame = 0;
};

Stat stat_of(std::vector<std::pair<double, int>> values) {
  std::sort(values.begin(), values.end());
  Stat s;
  s.median = values[values.size() / 2].first;
  s.p95 = values[std::min(values.size() - 1, values.size() * 95 / 100)].first;
  s.worst = values.back().first, s.worst_frame = values.back().second;
  return s;
}

// ---- SVG line plots --------------------------------------------------------------------------------------
constexpr double kWidth = 900, kHeight = 420, kLeft = 70, kRight = 170, kTop = 36, kBottom = 50;
constexpr const char* kColours[] = {"#1f77b4", "#d62728", "#2ca02c", "#9467bd", "#ff7f0e",
                                    "#8c564b", "#e377c2", "#7f7f7f", "#17becf"};

struct Series {
  std::string name;
  std::vector<double> values; // one per row
};

double nice_step(double max) {
  const double raw = max / 5.0, power = std::pow(10.0, std::floor(std::log10(raw)));
  for (double m : {1.0, 2.0, 5.0, 10.0})
    if (raw <= m * power) return m * power;
  return 10.0 * power;
}

std::string line_plot(const std::string& title, const std::string& y_title, const std::vector<FrameRow>& rows,
                      const std::vector<Series>& series, std::optional<dynamic::Animation> animation) {
  const double x_max = std::max(1, rows.back().frame), x0 = kLeft, x1 = kWidth - kRight, y0 = kHeight - kBottom,
               y1 = kTop;
  double y_max = 0.0;
  for (const Series& s : series)
    for (double v : s.values) y_max = std::max(y_max, std::isfinite(v) ? v : 0.0);
  const double step = nice_step(y_max > 0.0 ? y_max * 1.05 : 1.0);
  y_max = std::ceil((y_max > 0.0 ? y_max * 1.05 : 1.0) / step) * step;
  const auto x = [&](double f) { return x0 + (x1 - x0) * f / x_max; };
  const auto y = [&](double v) { return y0 - (y0 - y1) * std::clamp(v, 0.0, y_max) / y_max; };
  std::string svg = "<svg xmlns='http://www.w3.org/2000/svg' width='" + number(kWidth) + "' height='" +
                    number(kHeight) + "' font-family='sans-serif'>\n<rect width='100%' height='100%' fill='white'/>\n";
  // Frames in motion, shaded (the phases that are not still).
  for (std::size_t i = 0; animation && i < rows.size();) {
    const std::string phase = motion_phase(*animation, rows[i].frame);
    std::size_t j = i;
    while (j < rows.size() && motion_phase(*animation, rows[j].frame) == phase) ++j;
    if (phase == "during" || phase == "turning" || phase == "moving")
      svg += "<rect x='" + number(x(rows[i].frame), 6) + "' y='" + number(y1) + "' width='" +
             number(x(rows[j - 1].frame) - x(rows[i].frame), 6) + "' height='" + number(y0 - y1) +
             "' fill='#f2efe6'/>\n";
    i = j;
  }
  svg += "<rect x='" + number(x0) + "' y='" + number(y1) + "' width='" + number(x1 - x0) + "' height='" +
         number(y0 - y1) + "' fill='none' stroke='#444'/>\n";
  for (double v = 0.0; v <= y_max + step * 1e-6; v += step) {
    svg += "<line x1='" + number(x0) + "' x2='" + number(x1) + "' y1='" + number(y(v), 6) + "' y2='" + number(y(v), 6) +
           "' stroke='#ddd'/>\n";
    svg += "<text x='" + number(x0 - 6) + "' y='" + number(y(v) + 4, 6) + "' font-size='11' text-anchor='end'>" +
           number(v) + "</text>\n";
  }
  const double x_step = nice_step(x_max);
  for (double f = 0.0; f <= x_max + 1e-9; f += x_step)
    svg += "<text x='" + number(x(f), 6) + "' y='" + number(y0 + 16) + "' font-size='11' text-anchor='middle'>" +
           number(f) + "</text>\n";
  svg += "<text x='" + number((x0 + x1) / 2) + "' y='" + number(kHeight - 12) +
         "' font-size='13' text-anchor='middle'>frame</text>\n";
  svg += "<text x='16' y='" + number((y0 + y1) / 2) +
         "' font-size='13' text-anchor='middle' transform='rotate(-90 16 " + number((y0 + y1) / 2) + ")'>" + y_title +
         "</text>\n";
  svg += "<text x='" + number(kWidth / 2) + "' y='22' font-size='14' text-anchor='middle'>" + title + "</text>\n";
  for (std::size_t k = 0; k < series.size(); ++k) {
    std::string points;
    for (std::size_t i = 0; i < rows.size(); ++i)
      if (std::isfinite(series[k].values[i]))
        points += number(x(rows[i].frame), 6) + "," + number(y(series[k].values[i]), 6) + " ";
    const char* colour = kColours[k % std::size(kColours)];
    svg += "<polyline fill='none' stroke='" + std::string(colour) + "' stroke-width='1.2' points='" + points + "'/>\n";
    svg += "<text x='" + number(x1 + 10) + "' y='" + number(y1 + 14 + 16 * double(k)) + "' font-size='12' fill='" +
           colour + "'>" + series[k].name + "</text>\n";
  }
  return svg + "</svg>\n";
}

Series series_of(const std::string& name, const std::vector<FrameRow>& rows,
                 const std::function<double(const FrameRow&)>& value) {
  Series s{name, {}};
  for (const FrameRow& r : rows) s.values.push_back(value(r));
  return s;
}

// Each (file name, SVG text) into `folder` (created); the paths written, or std::runtime_error naming the file.
std::vector<std::string> write_svgs(const std::string& folder,
                                    std::span<const std::pair<std::string, std::string>> plots) {
  std::error_code ec;
  std::filesystem::create_directories(folder, ec);
  std::vector<std::string> written;
  for (const auto& [file, svg] : plots) {
    const std::string path = (std::filesystem::path(folder) / file).string();
    std::ofstream out(path);
    if (!(out << svg) || !out.flush()) throw std::runtime_error(path + ": cannot be written");
    written.push_back(path);
  }
  return written;
}

} // namespace

FrameRow frame_row(int frame, double angle_deg, const runtime::FrameStats& stats) {
  FrameRow row;
  row.frame = frame;
  row.angle_deg = angle_deg;
  for (const runtime::PassTime& pass : stats.passes)
    for (std::size_t k = 0; k < kFramePassNames.size(); ++k)
      if (pass.name == kFramePassNames[k]) row.pass_ms[k] = pass.gpu_ms, row.gpu_ms += std::max(0.0, pass.gpu_ms);
  row.cpu_ms = stats.cpu_ms;
  row.live_probes = stats.live_probes;
  const runtime::MemoryUpdateStats& m = stats.memory;
  row.processed = m.processed;
  const runtime::LightStats& l = stats.light;
  const int rays = l.front_hits + l.backface_hits + l.misses;
  if (rays > 0) row.hit_fraction = double(l.front_hits) / double(rays);
  row.placed = m.probes_placed, row.freed = m.probes_freed, row.splits = m.splits, row.collapses = m.collapses;
  row.failed = m.failed_allocations, row.deferred = m.deferred, row.moved_objects = l.moved_objects;
  row.clusters_used = m.cluster_capacity - m.free_clusters, row.cluster_capacity = m.cluster_capacity;
  row.probes_used = m.probe_capacity - m.free_probes, row.probe_capacity = m.probe_capacity;
  row.batches_used = m.batch_capacity - m.free_batches, row.batch_capacity = m.batch_capacity;
  row.stream = stats.streaming;
  row.traced = l.traced_probes, row.unresolved = l.unresolved_probes;
  row.load_window = l.load_window, row.untraced = l.untraced_slots;
  return row;
}

std::string frame_time_line(const std::vector<FrameRow>& rows, float frame_ms) {
  if (rows.empty()) return {};
  std::vector<std::pair<double, int>> frames;
  int over = 0, loaded = -1;
  bool loads = false; // a light update traced records: frame 0 at once, or windows
  for (const FrameRow& r : rows) {
    frames.push_back({r.gpu_ms, r.frame});
    if (frame_ms > 0.0f && r.gpu_ms > double(frame_ms)) ++over;
    loads = loads || r.load_window > 0;
    if (loaded < 0 && loads && r.untraced == 0) loaded = r.frame;
  }
  const Stat s = stat_of(std::move(frames));
  char line[320];
  int n = std::snprintf(line, sizeof(line),
                        "frame gpu ms: median %.3f, frame 0 %.3f, worst %.3f (frame %d) = %.2fx the median", s.median,
                        rows.front().gpu_ms, s.worst, s.worst_frame, s.median > 0.0 ? s.worst / s.median : 0.0);
  if (loads)
    n += loaded < 0 ? std::snprintf(line + n, sizeof(line) - std::size_t(n),
                                    "; load trace not finished (%d slots left)", rows.back().untraced)
                    : std::snprintf(line + n, sizeof(line) - std::size_t(n), "; load trace done in frame %d", loaded);
  if (frame_ms > 0.0f)
    std::snprintf(line + n, sizeof(line) - std::size_t(n), "; %d of %zu frames over the %.3f ms budget", over,
                  rows.size(), double(frame_ms));
  return std::string(line) + "\n";
}

void write_frame_header(std::ostream& out) {
  out << "frame,angle_deg";
  for (const char* pass : kFramePassNames) out << ',' << pass << "_ms";
  out << ",gpu_ms,cpu_ms,live_probes";
  for (const char* state : kStateNames) out << ',' << state;
  out << ",surfel_hit_fraction,probes_placed,probes_freed,splits,merges,failed_allocations,deferred,moved_objects,"
         "clusters_used,cluster_capacity,probes_used,probe_capacity,batches_used,batch_capacity,camera_x,camera_y,"
         "camera_z,"
         "resident_cells,resident_bytes,loaded_cells,loaded_bytes,dropped_cells,waiting_cells,reading_cells,refused_"
         "cells,"
         "upload_cpu_ms\n";
}

void write_frame_row(std::ostream& out, const FrameRow& r) {
  out << r.frame << ',' << number(r.angle_deg, 6);
  for (double ms : r.pass_ms) out << ',' << number(ms, 6);
  out << ',' << number(r.gpu_ms, 6) << ',' << number(r.cpu_ms, 6) << ',' << r.live_probes;
  for (int n : r.processed) out << ',' << n;
  out << ',' << (r.hit_fraction ? number(*r.hit_fraction, 6) : std::string());
  out << ',' << r.placed << ',' << r.freed << ',' << r.splits << ',' << r.collapses << ',' << r.failed << ','
      << r.deferred << ',' << r.moved_objects << ',' << r.clusters_used << ',' << r.cluster_capacity << ','
      << r.probes_used << ',' << r.probe_capacity << ',' << r.batches_used << ',' << r.batch_capacity;
  for (float c : r.camera) out << ',' << number(c, 6);
  const runtime::StreamStats& s = r.stream;
  out << ',' << s.resident_cells << ',' << s.resident_bytes << ',' << s.loaded_cells << ',' << s.loaded_bytes << ','
      << s.dropped_cells << ',' << s.waiting_cells << ',' << s.reading_cells << ',' << s.refused_cells << ','
      << number(s.upload_cpu_ms, 6) << '\n';
}

const char* motion_phase(dynamic::Animation animation, int frame) {
  switch (animation) {
  case dynamic::Animation::thesis: return frame < 200 ? "before" : (frame <= 350 ? "during" : "after");
  case dynamic::Animation::revolution: return frame % 200 < 150 ? "turning" : "still";
  case dynamic::Animation::soak: {
    const int f = frame % 10000;
    return f < 50 || f >= 9950 ? "still" : "moving";
  }
  }
  return "all";
}

std::string summary_table(const std::vector<FrameRow>& rows, std::optional<dynamic::Animation> animation) {
  if (rows.empty()) return "";
  // "all", then the phases in the order the motion meets them.
  std::vector<std::pair<std::string, std::vector<const FrameRow*>>> phases{{"all", {}}};
  for (const FrameRow& r : rows) {
    phases[0].second.push_back(&r);
    if (!animation) continue;
    const std::string phase = motion_phase(*animation, r.frame);
    auto it = std::find_if(phases.begin() + 1, phases.end(), [&](const auto& p) { return p.first == phase; });
    if (it == phases.end()) it = phases.insert(phases.end(), {phase, {}});
    it->second.push_back(&r);
  }
  std::string table = "| pass | phase | frames | median ms | p95 ms | worst ms (frame) | worst / median "
                      "|\n|---|---|--:|--:|--:|--:|--:|\n";
  // A pass counts in the frames that ran it (0 ms: not run, e.g. light_trace in most frames).
  const auto add = [&](const std::string& name, const std::function<double(const FrameRow&)>& value, bool every_frame) {
    for (const auto& [phase, members] : phases) {
      std::vector<std::pair<double, int>> values;
      for (const FrameRow* r : members)
        if (every_frame || value(*r) != 0.0) values.push_back({value(*r), r->frame});
      if (values.empty() || (phase != "all" && phases.size() == 2)) continue; // one phase: "all" says it
      const Stat s = stat_of(values);
      table += "| " + name + " | " + phase + " | " + std::to_string(values.size()) + " | " + number(s.median) + " | " +
               number(s.p95) + " | " + number(s.worst) + " (" + std::to_string(s.worst_frame) + ") | " +
               (s.median > 0 ? number(s.worst / s.median, 3) : "-") + " |\n";
    }
  };
  for (std::size_t k = 0; k < kFramePassNames.size(); ++k) {
    const bool ran = std::any_of(rows.begin(), rows.end(), [&](const FrameRow& r) { return r.pass_ms[k] != 0.0; });
    if (ran)
      add(
          kFramePassNames[k], [k](const FrameRow& r) { return r.pass_ms[k]; }, false);
  }
  add(
      "gpu total", [](const FrameRow& r) { return r.gpu_ms; }, true);
  add(
      "host cpu", [](const FrameRow& r) { return r.cpu_ms; }, true);
  return table;
}

// The column of a pass in FrameRow::pass_ms, by its name in the pass table (a name not there does not build);
// the streaming report reads these two.
consteval std::size_t pass_column(std::string_view name) {
  for (std::size_t k = 0; k < kFramePassNames.size(); ++k)
    if (std::string_view(kFramePassNames[k]) == name) return k;
  throw "not a pass of the pass table";
}
constexpr std::size_t kStreamUploadPass = pass_column("stream_upload"), kLightTracePass = pass_column("light_trace");

std::string stream_frame_line(const FrameRow& r) {
  const runtime::StreamStats& s = r.stream;
  char line[512];
  std::snprintf(line, sizeof(line),
                "frame %d at (%.2f, %.2f, %.2f): %d cells resident, %llu bytes; loaded %d (%llu bytes), dropped %d, "
                "waiting %d%s%s%s, "
                "%d probes joined (%d waiting); upload gpu %.3f ms, host %.3f ms; light_trace %.3f ms (%d traced, %d "
                "unresolved)%s\n",
                r.frame, double(r.camera[0]), double(r.camera[1]), double(r.camera[2]), s.resident_cells,
                static_cast<unsigned long long>(s.resident_bytes), s.loaded_cells,
                static_cast<unsigned long long>(s.loaded_bytes), s.dropped_cells, s.waiting_cells,
                s.reading_cells > 0 ? (" (" + std::to_string(s.reading_cells) + " being read)").c_str() : "",
                s.unplaced_cells > 0 ? (" (" + std::to_string(s.unplaced_cells) + " without a free run)").c_str() : "",
                s.moved_cells > 0 ? (" (" + std::to_string(s.moved_cells) + " moved to compact the arena)").c_str()
                                  : "",
                s.joined_probes, s.joining_probes, std::max(0.0, r.pass_ms[kStreamUploadPass]), s.upload_cpu_ms,
                std::max(0.0, r.pass_ms[kLightTracePass]), r.traced, r.unresolved,
                s.refused_cells > 0 ? "; REFUSED a cell (below)" : "");
  return line;
}

std::string stream_summary(const std::vector<FrameRow>& rows, std::uint64_t budget) {
  const FrameRow* worst_gpu = nullptr;
  const FrameRow* worst_host = nullptr;
  std::uint64_t most = 0, loaded = 0;
  int loads = 0, drops = 0, traced = 0, unresolved = 0, most_traced = 0, unplaced_frames = 0, moved = 0;
  for (const FrameRow& r : rows) {
    traced += r.traced, unresolved += r.unresolved, most_traced = std::max(most_traced, r.traced);
    unplaced_frames += r.stream.unplaced_cells > 0 ? 1 : 0;
    moved += r.stream.moved_cells;
    if (!worst_gpu || r.pass_ms[kStreamUploadPass] > worst_gpu->pass_ms[kStreamUploadPass]) worst_gpu = &r;
    if (!worst_host || r.stream.upload_cpu_ms > worst_host->stream.upload_cpu_ms) worst_host = &r;
    most = std::max(most, r.stream.resident_bytes);
    loads += r.stream.loaded_cells, drops += r.stream.dropped_cells, loaded += r.stream.loaded_bytes;
  }
  if (!worst_gpu) return "";
  char line[512];
  std::snprintf(
      line, sizeof(line),
      "streaming: worst upload spike %.3f ms GPU (frame %d, %llu bytes), %.3f ms host (frame %d); at most %llu of "
      "%llu bytes resident; %d loads (%llu bytes), %d drops over %zu frames; %d probe traces (at most %d a frame), "
      "%d left unresolved; %d frames with a load waiting for a free run, %d blocks moved to compact the arena\n",
      std::max(0.0, worst_gpu->pass_ms[kStreamUploadPass]), worst_gpu->frame,
      static_cast<unsigned long long>(worst_gpu->stream.loaded_bytes), worst_host->stream.upload_cpu_ms,
      worst_host->frame, static_cast<unsigned long long>(most), static_cast<unsigned long long>(budget), loads,
      static_cast<unsigned long long>(loaded), drops, rows.size(), traced, most_traced, unresolved, unplaced_frames,
      moved);
  return line;
}

HostMemory host_memory() {
  HostMemory memory;
  std::ifstream status("/proc/self/status");
  std::string line;
  const auto kilobytes = [&](std::string_view key) -> std::optional<std::uint64_t> {
    if (line.rfind(key, 0) != 0) return std::nullopt;
    return std::strtoull(line.c_str() + key.size(), nullptr, 10) * 1024u;
  };
  while (std::getline(status, line)) {
    if (auto v = kilobytes("VmRSS:")) memory.resident = *v;
    if (auto v = kilobytes("VmHWM:")) memory.peak = *v;
  }
  return memory;
}

std::string host_memory_line(HostMemory after_load, HostMemory at_end) {
  if (at_end.resident == 0) return "host memory: unknown on this system\n";
  const auto mb = [](std::uint64_t bytes) { return double(bytes) / (1024.0 * 1024.0); };
  char line[200];
  std::snprintf(line, sizeof(line), "host memory: %.1f MB resident after load, %.1f MB at the end, peak %.1f MB\n",
                mb(after_load.resident), mb(at_end.resident), mb(at_end.peak));
  return line;
}

std::vector<std::string> write_stream_plots(const std::string& folder, const std::vector<FrameRow>& rows) {
  const std::vector<Series> bytes = {
      series_of("resident KB", rows, [](const FrameRow& r) { return double(r.stream.resident_bytes) / 1024.0; }),
      series_of("loaded KB", rows, [](const FrameRow& r) { return double(r.stream.loaded_bytes) / 1024.0; })};
  const std::vector<Series> times = {
      series_of("stream_upload GPU", rows,
                [](const FrameRow& r) { return std::max(0.0, r.pass_ms[kStreamUploadPass]); }),
      series_of("host numbering", rows, [](const FrameRow& r) { return r.stream.upload_cpu_ms; })};
  const std::pair<std::string, std::string> plots[] = {
      {"streaming.svg", line_plot("streaming: resident and loaded bytes per frame", "KB", rows, bytes, std::nullopt)},
      {"upload_times.svg", line_plot("streaming: upload time per frame", "ms", rows, times, std::nullopt)}};
  return write_svgs(folder, plots);
}

std::string progress_bar(int done, int total, int width) {
  const int filled = total > 0 ? int(std::int64_t(width) * std::clamp(done, 0, total) / total) : width;
  return "[" + std::string(std::size_t(filled), '#') + std::string(std::size_t(width - filled), '-') + "] " +
         std::to_string(done) + "/" + std::to_string(total) + " frames";
}

std::vector<std::string> write_plots(const std::string& folder, const std::vector<FrameRow>& rows,
                                     dynamic::Animation animation) {
  std::vector<Series> times;
  for (std::size_t k = 0; k < kFramePassNames.size(); ++k)
    if (std::any_of(rows.begin(), rows.end(), [&](const FrameRow& r) { return r.pass_ms[k] > 0.0; }))
      times.push_back(series_of(kFramePassNames[k], rows, [k](const FrameRow& r) { return r.pass_ms[k]; }));
  times.push_back(series_of("gpu total", rows, [](const FrameRow& r) { return r.gpu_ms; }));
  const std::vector<Series> probes = {
      series_of("live probes", rows, [](const FrameRow& r) { return double(r.live_probes); }),
      series_of("probe slots used", rows, [](const FrameRow& r) { return double(r.probes_used); }),
      series_of("clusters used", rows, [](const FrameRow& r) { return double(r.clusters_used); })};
  std::vector<Series> states;
  for (std::size_t s = 0; s < 9; ++s)
    states.push_back(series_of(kStateNames[s], rows, [s](const FrameRow& r) { return double(r.processed[s]); }));
  const std::string name = dynamic::to_string(animation);
  const std::pair<std::string, std::string> plots[] = {
      {"frame_times.svg", line_plot(name + ": GPU time per pass and frame", "GPU ms", rows, times, animation)},
      {"probes.svg", line_plot(name + ": live probes and pool use", "count", rows, probes, animation)},
      {"leaf_states.svg",
       line_plot(name + ": leaf-queue entries processed per state", "entries", rows, states, animation)}};
  return write_svgs(folder, plots);
}

} // namespace probebake::run
