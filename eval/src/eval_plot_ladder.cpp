// Error curves of `probebake eval` on a log x axis, one colour per method:
// - `--probes ... --plot`: relative RMSE against live probe count, the total error solid and the indirect
//   error (the lookup alone) dashed;
// - `--bytes-plot`: relative RMSE with the l2 probe code against the lookup's bytes (issue #41's quality per
//   byte), every row a point and each method's Pareto front (no cheaper row is as good) a line.
#include <algorithm>
#include <cmath>
#include <map>

#include <fmt/core.h>

#include "eval_internal.h"
#include "probebake/formats/placement_kind.h"

namespace probebake::bake::detail {
namespace {

constexpr double kWidth = kPlotWidth, kHeight = kPlotHeight, kRight = kPlotRight, kTop = kPlotTop;
constexpr const char* kColours[] = {"#1f77b4", "#d62728", "#2ca02c", "#9467bd", "#ff7f0e", "#8c564b"};
using Axes = PlotAxes;

// What a curve plots: its x value, its error and which rows it takes.
struct CurveKind {
  bool bytes = false; // x = l2 lookup bytes (all scored rows, grid engine a method of its own), else probes
  double x(const EvalRow& r) const { return bytes ? double(r.l2_lookup_bytes) : double(r.probes); }
  double error(const EvalRow& r, bool indirect) const {
    return bytes ? r.l2_relative_rmse : indirect ? r.indirect_relative_rmse : r.relative_rmse;
  }
};

// The rows of each method, in x order: the ladder's ("svo" sampler), or every row with l2 bytes.
std::map<std::string, std::vector<const EvalRow*>> curves(const EvalResult& result, const CurveKind& kind) {
  std::map<std::string, std::vector<const EvalRow*>> out;
  for (const EvalRow& r : result.rows) {
    if (kind.bytes ? r.l2_lookup_bytes > 0 : r.asked_probes > 0 && r.sampler == "svo")
      out[r.sampler == "grid" ? std::string("grid engine") : std::string(formats::placement_name(r.bake.placement))]
          .push_back(&r);
  }
  for (auto& [name, rows] : out)
    std::stable_sort(rows.begin(), rows.end(),
                     [&](const EvalRow* a, const EvalRow* b) { return kind.x(*a) < kind.x(*b); });
  return out;
}

Axes make_axes(const std::map<std::string, std::vector<const EvalRow*>>& lines, const CurveKind& kind) {
  Axes a;
  double lo = 1e300, hi = 1;
  double err = 0;
  for (const auto& [name, rows] : lines)
    for (const EvalRow* r : rows) {
      lo = std::min(lo, std::max(kind.x(*r), 1.0));
      hi = std::max(hi, kind.x(*r));
      err = std::max({err, kind.error(*r, false), kind.error(*r, true)});
    }
  if (lo > hi) return a;
  a.log_lo = std::floor(std::log10(lo));
  a.log_hi = std::max(std::ceil(std::log10(hi)), a.log_lo + 1);
  if (std::isfinite(err) && err > 0) {
    const double step = nice_step(err * 1.05);
    a.y_max = std::ceil(err * 1.05 / step) * step;
  }
  return a;
}

// One polyline with its points: the total error (solid) or the indirect error (dashed, hollow points). With
// bytes the line joins only the Pareto front: rows better than every cheaper row.
std::string curve_svg(const Axes& a, const std::vector<const EvalRow*>& rows, const CurveKind& kind, const char* colour,
                      bool indirect) {
  std::string path, points;
  double best = 1e300;
  for (const EvalRow* r : rows) {
    const double x = a.x(kind.x(*r)), y = a.y(kind.error(*r, indirect));
    const bool front = !kind.bytes || kind.error(*r, indirect) < best;
    best = std::min(best, kind.error(*r, indirect));
    if (front) path += fmt::format("{} {:.1f} {:.1f}", path.empty() ? "M" : " L", x, y);
    points += fmt::format("<circle cx='{:.1f}' cy='{:.1f}' r='4' fill='{}' stroke='{}' stroke-width='1.5'/>\n", x, y,
                          indirect ? "white" : colour, colour);
  }
  return fmt::format("<path d='{}' fill='none' stroke='{}' stroke-width='1.5'{}/>\n", path, colour,
                     indirect ? " stroke-dasharray='5 3'" : "") +
         points;
}

std::string legend_svg(const std::map<std::string, std::vector<const EvalRow*>>& lines, const CurveKind& kind) {
  std::string s;
  double y = kTop + 14;
  const double x = kWidth - kRight - 200;
  std::size_t i = 0;
  for (const auto& [name, rows] : lines) {
    const char* colour = kColours[i++ % std::size(kColours)];
    s += fmt::format("<line x1='{}' y1='{}' x2='{}' y2='{}' stroke='{}' stroke-width='2'/>"
                     "<text x='{}' y='{}' font-size='11'>{}{}</text>\n",
                     x, y, x + 24, y, colour, x + 30, y + 4, escape_xml(name), kind.bytes ? "" : " total");
    y += 16;
    if (kind.bytes) continue; // one curve per method
    s += fmt::format("<line x1='{}' y1='{}' x2='{}' y2='{}' stroke='{}' stroke-width='2' stroke-dasharray='5 3'/>"
                     "<text x='{}' y='{}' font-size='11'>{} indirect</text>\n",
                     x, y, x + 24, y, colour, x + 30, y + 4, escape_xml(name));
    y += 16;
  }
  return s;
}

std::string curve_plot(const EvalResult& result, const CurveKind& kind) {
  const auto lines = curves(result, kind);
  const Axes axes = make_axes(lines, kind);
  std::string svg =
      fmt::format("<svg xmlns='http://www.w3.org/2000/svg' width='{0}' height='{1}' viewBox='0 0 {0} {1}' "
                  "font-family='sans-serif'>\n<rect width='100%' height='100%' fill='white'/>\n",
                  kWidth, kHeight);
  svg += fmt::format("<text x='{}' y='22' font-size='14' text-anchor='middle'>{}: {} ({} points, "
                     "{} paths/point)</text>\n",
                     kWidth / 2, escape_xml(result.scene.filename().string()),
                     kind.bytes ? "error against lookup bytes, l2 probes" : "error against probe count", result.points,
                     result.paths);
  svg += plot_axes_svg(axes, kind.bytes ? "lookup bytes (log scale)" : "live probes (log scale)");
  std::size_t i = 0;
  for (const auto& [name, rows] : lines) {
    const char* colour = kColours[i++ % std::size(kColours)];
    svg += curve_svg(axes, rows, kind, colour, false);
    if (!kind.bytes) svg += curve_svg(axes, rows, kind, colour, true);
  }
  return svg + legend_svg(lines, kind) + "</svg>\n";
}

} // namespace

std::string ladder_svg_plot(const EvalResult& result) { return curve_plot(result, CurveKind{false}); }

} // namespace probebake::bake::detail

namespace probebake::bake {

std::string eval_bytes_svg_plot(const EvalResult& result) {
  return detail::curve_plot(result, detail::CurveKind{true});
}

} // namespace probebake::bake
