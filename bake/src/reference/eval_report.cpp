// Text reports of `probebake eval`: Markdown table and CSV.
#include <fstream>
#include <system_error>

#include <fmt/core.h>

#include "probebake/bake/eval.h"
#include "probebake/formats/atomic_file.h"
#include "probebake/formats/error.h"

namespace probebake::bake {
namespace {

std::string placement_name(const BakeSettings& b) { return b.placement == Placement::grid ? "grid" : "octree"; }

std::string leak_cell(const EvalRow& r) {
  return r.leak_points > 0 ? fmt::format("{:.4g} ({})", r.leak_rmse, r.leak_points) : "-";
}

} // namespace

std::string eval_markdown_table(const EvalResult& result) {
  std::string out = fmt::format(
      "{}: {} points, {} paths/point, mean reference irradiance {:.4g} W/m^2, reference noise {:.2f}% ({})\n\n",
      result.scene.filename().string(), result.points, result.paths, result.mean_reference,
      100.0 * result.reference_noise,
      result.reference_from_cache ? "cached" : fmt::format("traced in {:.1f} s", result.reference_seconds));
  out += "| config | sampler | probes | bytes | bake s | ns/point | RMSE | rel. RMSE | bias | p95 | max | leak RMSE (points) | misses |\n";
  out += "|---|---|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|\n";
  for (const EvalRow& r : result.rows)
    out += fmt::format("| {} | {} | {} | {} | {:.3f} | {:.0f} | {:.4g} | {:.4f} | {:+.3f} | {:.4g} | {:.4g} | {} | {} |\n",
                       r.label, r.sampler, r.probes, r.file_bytes, r.bake_seconds, r.sample_ns, r.rmse, r.relative_rmse,
                       r.bias, r.p95,
                       r.max_error, leak_cell(r), r.misses);
  return out;
}

void write_text_file(const std::filesystem::path& path, const std::string& text) {
  write_file_atomically(path, std::string_view(text));
}

void write_eval_csv(const std::filesystem::path& path, const EvalResult& result) {
  std::string out = "label,sampler,placement,max_depth,grid,surfels,lattice,svo_depth,probes,file_bytes,bake_seconds,"
                    "sample_ns,rmse,relative_rmse,bias,p95,max_error,leak_rmse,leak_points,misses\n";
  for (const EvalRow& r : result.rows)
    out += fmt::format("{},{},{},{},{},{},{},{},{},{},{:.6g},{:.6g},{:.6g},{:.6g},{:.6g},{:.6g},{:.6g},{:.6g},{},{}\n", r.label,
                       r.sampler, placement_name(r.bake), r.bake.max_depth, r.bake.grid_resolution,
                       r.bake.surfels_per_probe, lattice_name(r.bake.lattice), r.bake.svo_depth, r.probes, r.file_bytes,
                       r.bake_seconds, r.sample_ns, r.rmse, r.relative_rmse, r.bias, r.p95, r.max_error, r.leak_rmse,
                       r.leak_points, r.misses);
  write_text_file(path, out);
}

} // namespace probebake::bake
