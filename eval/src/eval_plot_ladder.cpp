// `probebake eval --probes ... --plot`: relative RMSE against live probe count (log axis), one colour per
// placement method, the total error solid and the indirect error (the lookup alone) dashed.
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

// The ladder's rows of each method ("svo" sampler), in probe order.
std::map<std::string, std::vector<const EvalRow*>> curves(const EvalResult& result) {
  std::map<std::string, std::vector<const EvalRow*>> out;
  for (const EvalRow& r : result.rows)
    if (r.asked_probes > 0 && r.sampler == "svo")
      out[std::string(formats::placement_name(r.bake.placement))].push_back(&r);
  for (auto& [name, rows] : out)
    std::stable_sort(rows.begin(), rows.end(),
                     [](const EvalRow* a, const EvalRow* b) { return a->probes < b->probes; });
  return out;
}

Axes make_axes(const std::map<std::string, std::vector<const EvalRow*>>& lines) {
  Axes a;
  int lo = 1 << 30, hi = 1;
  double err = 0;
  for (const auto& [name, rows] : lines)
    for (const EvalRow* r : rows) {
      lo = std::min(lo, std::max(r->probes, 1));
      hi = std::max(hi, r->probes);
      err = std::max({err, r->relative_rmse, r->indirect_relative_rmse});
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

// One polyline with its points: the total error (solid) or the indirect error (dashed, hollow points).
std::string curve_svg(const Axes& a, const std::vector<const EvalRow*>& rows, const char* colour, bool indirect) {
  std::string path, points;
  for (const EvalRow* r : rows) {
    const double x = a.x(r->probes), y = a.y(indirect ? r->indirect_relative_rmse : r->relative_rmse);
    path += fmt::format("{} {:.1f} {:.1f}", path.empty() ? "M" : " L", x, y);
    points += fmt::format("<circle cx='{:.1f}' cy='{:.1f}' r='4' fill='{}' stroke='{}' stroke-width='1.5'/>\n", x, y,
                          indirect ? "white" : colour, colour);
  }
  return fmt::format("<path d='{}' fill='none' stroke='{}' stroke-width='1.5'{}/>\n", path, colour,
                     indirect ? " stroke-dasharray='5 3'" : "") +
         points;
}

std::string legend_svg(const std::map<std::string, std::vector<const EvalRow*>>& lines) {
  std::string s;
  double y = kTop + 14;
  const double x = kWidth - kRight - 200;
  std::size_t i = 0;
  for (const auto& [name, rows] : lines) {
    const char* colour = kColours[i++ % std::size(kColours)];
    s += fmt::format("<line x1='{}' y1='{}' x2='{}' y2='{}' stroke='{}' stroke-width='2'/>"
                     "<text x='{}' y='{}' font-size='11'>{} total</text>\n",
                     x, y, x + 24, y, colour, x + 30, y + 4, escape_xml(name));
    y += 16;
    s += fmt::format("<line x1='{}' y1='{}' x2='{}' y2='{}' stroke='{}' stroke-width='2' stroke-dasharray='5 3'/>"
                     "<text x='{}' y='{}' font-size='11'>{} indirect</text>\n",
                     x, y, x + 24, y, colour, x + 30, y + 4, escape_xml(name));
    y += 16;
  }
  return s;
}

} // namespace

std::string ladder_svg_plot(const EvalResult& result) {
  const auto lines = curves(result);
  const Axes axes = make_axes(lines);
  std::string svg =
      fmt::format("<svg xmlns='http://www.w3.org/2000/svg' width='{0}' height='{1}' viewBox='0 0 {0} {1}' "
                  "font-family='sans-serif'>\n<rect width='100%' height='100%' fill='white'/>\n",
                  kWidth, kHeight);
  svg +=
      fmt::format("<text x='{}' y='22' font-size='14' text-anchor='middle'>{}: error against probe count ({} points, "
                  "{} paths/point)</text>\n",
                  kWidth / 2, escape_xml(result.scene.filename().string()), result.points, result.paths);
  svg += plot_axes_svg(axes, "live probes (log scale)");
  std::size_t i = 0;
  for (const auto& [name, rows] : lines) {
    const char* colour = kColours[i++ % std::size(kColours)];
    svg += curve_svg(axes, rows, colour, false) + curve_svg(axes, rows, colour, true);
  }
  return svg + legend_svg(lines) + "</svg>\n";
}

} // namespace probebake::bake::detail
