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

constexpr double kWidth = 760, kHeight = 480, kLeft = 70, kRight = 20, kTop = 40, kBottom = 60;
constexpr const char* kColours[] = {"#1f77b4", "#d62728", "#2ca02c", "#9467bd", "#ff7f0e", "#8c564b"};

struct Axes {
  double log_lo = 0, log_hi = 1, y_max = 1;
  double x(int probes) const {
    const double l = std::log10(std::max(probes, 1));
    return kLeft + (l - log_lo) / (log_hi - log_lo) * (kWidth - kLeft - kRight);
  }
  double y(double error) const { return kHeight - kBottom - std::min(error, y_max) / y_max * (kHeight - kTop - kBottom); }
};

// The ladder's rows of each method ("svo" sampler), in probe order.
std::map<std::string, std::vector<const EvalRow*>> curves(const EvalResult& result) {
  std::map<std::string, std::vector<const EvalRow*>> out;
  for (const EvalRow& r : result.rows)
    if (r.asked_probes > 0 && r.sampler == "svo") out[std::string(formats::placement_name(r.bake.placement))].push_back(&r);
  for (auto& [name, rows] : out)
    std::stable_sort(rows.begin(), rows.end(), [](const EvalRow* a, const EvalRow* b) { return a->probes < b->probes; });
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

std::string axes_svg(const Axes& a) {
  std::string s;
  const double x0 = kLeft, x1 = kWidth - kRight, y0 = kHeight - kBottom, y1 = kTop;
  s += fmt::format("<rect x='{}' y='{}' width='{}' height='{}' fill='none' stroke='#444'/>\n", x0, y1, x1 - x0, y0 - y1);
  for (int d = int(a.log_lo); d <= int(a.log_hi); ++d)
    for (double m : {1.0, 2.0, 5.0}) {
      const double v = m * std::pow(10.0, d);
      if (std::log10(v) > a.log_hi + 1e-9) continue;
      const double x = a.x(int(v));
      s += fmt::format("<line x1='{:.1f}' y1='{}' x2='{:.1f}' y2='{}' stroke='#ddd'/>\n", x, y0, x, y1);
      s += fmt::format("<text x='{:.1f}' y='{}' font-size='11' text-anchor='middle'>{:g}</text>\n", x, y0 + 16, v);
    }
  const double step = nice_step(a.y_max);
  for (double v = 0; v <= a.y_max + step * 1e-6; v += step) {
    s += fmt::format("<line x1='{}' y1='{:.1f}' x2='{}' y2='{:.1f}' stroke='#ddd'/>\n", x0, a.y(v), x1, a.y(v));
    s += fmt::format("<text x='{}' y='{:.1f}' font-size='11' text-anchor='end'>{:g}</text>\n", x0 - 6, a.y(v) + 4, v);
  }
  s += fmt::format("<text x='{}' y='{}' font-size='13' text-anchor='middle'>live probes (log scale)</text>\n",
                   (x0 + x1) / 2, kHeight - 18);
  s += fmt::format("<text x='16' y='{}' font-size='13' text-anchor='middle' transform='rotate(-90 16 {})'>"
                   "relative RMSE of irradiance</text>\n", (y0 + y1) / 2, (y0 + y1) / 2);
  return s;
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
                     indirect ? " stroke-dasharray='5 3'" : "") + points;
}

std::string legend_svg(const std::map<std::string, std::vector<const EvalRow*>>& lines) {
  std::string s;
  double y = kTop + 14;
  const double x = kWidth - kRight - 200;
  std::size_t i = 0;
  for (const auto& [name, rows] : lines) {
    const char* colour = kColours[i++ % std::size(kColours)];
    s += fmt::format("<line x1='{}' y1='{}' x2='{}' y2='{}' stroke='{}' stroke-width='2'/>"
                     "<text x='{}' y='{}' font-size='11'>{} total</text>\n", x, y, x + 24, y, colour, x + 30, y + 4, escape_xml(name));
    y += 16;
    s += fmt::format("<line x1='{}' y1='{}' x2='{}' y2='{}' stroke='{}' stroke-width='2' stroke-dasharray='5 3'/>"
                     "<text x='{}' y='{}' font-size='11'>{} indirect</text>\n", x, y, x + 24, y, colour, x + 30, y + 4, escape_xml(name));
    y += 16;
  }
  return s;
}

} // namespace

std::string ladder_svg_plot(const EvalResult& result) {
  const auto lines = curves(result);
  const Axes axes = make_axes(lines);
  std::string svg = fmt::format("<svg xmlns='http://www.w3.org/2000/svg' width='{0}' height='{1}' viewBox='0 0 {0} {1}' "
                                "font-family='sans-serif'>\n<rect width='100%' height='100%' fill='white'/>\n",
                                kWidth, kHeight);
  svg += fmt::format("<text x='{}' y='22' font-size='14' text-anchor='middle'>{}: error against probe count ({} points, "
                     "{} paths/point)</text>\n",
                     kWidth / 2, escape_xml(result.scene.filename().string()), result.points, result.paths);
  svg += axes_svg(axes);
  std::size_t i = 0;
  for (const auto& [name, rows] : lines) {
    const char* colour = kColours[i++ % std::size(kColours)];
    svg += curve_svg(axes, rows, colour, false) + curve_svg(axes, rows, colour, true);
  }
  return svg + legend_svg(lines) + "</svg>\n";
}

} // namespace probebake::bake::detail
