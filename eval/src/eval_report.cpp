// Text reports of `probebake eval`: Markdown table and CSV.
#include <fstream>
#include <system_error>

#include <fmt/core.h>

#include "probebake/eval/eval.h"
#include "probebake/formats/atomic_file.h"
#include "probebake/formats/error.h"
#include "probebake/formats/placement_kind.h"

namespace probebake::bake {
namespace {

std::string leak_cell(const EvalRow& r) {
  return r.leak_points > 0 ? fmt::format("{:.4g} ({})", r.leak_rmse, r.leak_points) : "-";
}

// The ladder rung and how the configuration meets it, e.g. "128 (max depth)"; "-" outside a ladder.
std::string asked_cell(const EvalRow& r) {
  return r.asked_probes > 0 ? fmt::format("{} ({})", r.asked_probes, r.budget_by) : "-";
}

// Float, l2 and l1 probes' lookup bytes ("float" alone where the compact codes are not measured).
std::string lookup_bytes_cell(const EvalRow& r) {
  if (r.l2_lookup_bytes == 0) return std::to_string(r.lookup_bytes);
  return fmt::format("{} / {} / {}", r.lookup_bytes, r.l2_lookup_bytes, r.l1_lookup_bytes);
}

// A measure that is -1 where not measured.
std::string optional_cell(double value) { return value < 0 ? "-" : fmt::format("{:.4f}", value); }

} // namespace

std::string eval_markdown_table(const EvalResult& result) {
  const bool image = result.image_pixels > 0;
  std::string out = fmt::format(
      "{}: {} {} receivers{}, {} paths/point, mean reference irradiance {:.4g} W/m^2, reference noise {:.2f}% ({})\n",
      result.scene.filename().string(), result.points, result.receivers,
      result.viewpoints > 0 ? fmt::format(" from {} viewpoints", result.viewpoints) : "", result.paths,
      result.mean_reference, 100.0 * result.reference_noise,
      result.reference_from_cache ? "cached" : fmt::format("traced in {:.1f} s", result.reference_seconds));
  out += fmt::format("indirect (reference minus its direct part): mean {:.4g} W/m^2, noise {:.2f}%; direct_irradiance "
                     "against the traced direct part: relative RMSE {:.4f}, bias {:+.4f}\n",
                     result.mean_indirect_reference, 100.0 * result.indirect_noise, result.direct_relative_rmse,
                     result.direct_bias);
  if (image)
    out += fmt::format("camera: {} image receivers, mean reference {:.4g} W/m^2; HDR-FLIP at {} exposures from {:+.2f} "
                       "to {:+.2f}\n",
                       result.image_pixels, result.image_mean_reference, result.image_flip_exposures.count,
                       result.image_flip_exposures.start, result.image_flip_exposures.stop);
  out += "\n| config | sampler | asked | probes | bytes | lookup bytes float / l2 / l1 | bake s | ns/point | RMSE | "
         "rel. RMSE | "
         "indirect rel. RMSE | "
         "rel. median | rel. p95 | bias | p95 | max | leak RMSE (points) | coverage | seam p99 | l2 code err | l1 code "
         "err |";
  out += image ? " image rel. RMSE | image mean err | image FLIP |\n" : "\n";
  out += "|---|---|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|";
  out += image ? "--:|--:|--:|\n" : "\n";
  for (const EvalRow& r : result.rows) {
    out += fmt::format(
        "| {} | {} | {} | {} | {} | {} | {:.3f} | {:.0f} | {:.4g} | {:.4f} | {:.4f} | {:.4f} | {:.4f} | {:+.3f} | "
        "{:.4g} | {:.4g} | {} | {:.3f} | {} | {} | {} |",
        r.label, r.sampler, asked_cell(r), r.probes, r.file_bytes, lookup_bytes_cell(r), r.bake_seconds, r.sample_ns,
        r.rmse, r.relative_rmse, r.indirect_relative_rmse, r.relative_median, r.relative_p95, r.bias, r.p95,
        r.max_error, leak_cell(r), r.coverage, optional_cell(r.seam_p99), optional_cell(r.l2_codec_error),
        optional_cell(r.l1_codec_error));
    out += image ? fmt::format(" {:.4f} | {:.4g} | {:.4f} |\n", r.image_relative_rmse, r.image_mean_error,
                               r.image_flip_mean)
                 : "\n";
  }
  return out;
}

void write_text_file(const std::filesystem::path& path, const std::string& text) {
  write_file_atomically(path, std::string_view(text));
}

void write_eval_csv(const std::filesystem::path& path, const EvalResult& result) {
  std::string out =
      "label,sampler,placement,max_depth,grid,surfels,lattice,svo_depth,probes,file_bytes,bake_seconds,"
      "sample_ns,rmse,relative_rmse,bias,p95,max_error,leak_rmse,leak_points,misses,coverage,"
      "relative_median,relative_p95,image_relative_rmse,image_mean_error,asked_probes,budget_by,"
      "indirect_rmse,indirect_relative_rmse,seam_p99,image_flip_mean,lookup_bytes,l2_codec_error,l1_codec_error,"
      "l2_relative_rmse,l1_relative_rmse,l2_lookup_bytes,l1_lookup_bytes\n";
  for (const EvalRow& r : result.rows)
    out += fmt::format(
        "{},{},{},{},{},{},{},{},{},{},{:.6g},{:.6g},{:.6g},{:.6g},{:.6g},{:.6g},{:.6g},{:.6g},{},{},{:.6g},{:.6g},"
        "{:.6g},{:.6g},{:.6g},{},{},{:.6g},{:.6g},{:.6g},{:.6g},{},{:.6g},{:.6g},{:.6g},{:.6g},{},{}\n",
        r.label, r.sampler, formats::placement_name(r.bake.placement), r.bake.max_depth, r.bake.grid_resolution,
        r.bake.surfels_per_probe, lattice_name(r.bake.lattice), r.bake.svo_depth, r.probes, r.file_bytes,
        r.bake_seconds, r.sample_ns, r.rmse, r.relative_rmse, r.bias, r.p95, r.max_error, r.leak_rmse, r.leak_points,
        r.misses, r.coverage, r.relative_median, r.relative_p95, r.image_relative_rmse, r.image_mean_error,
        r.asked_probes, r.budget_by, r.indirect_rmse, r.indirect_relative_rmse, r.seam_p99, r.image_flip_mean,
        r.lookup_bytes, r.l2_codec_error, r.l1_codec_error, r.l2_relative_rmse, r.l1_relative_rmse, r.l2_lookup_bytes,
        r.l1_lookup_bytes);
  write_text_file(path, out);
}

} // namespace probebake::bake
